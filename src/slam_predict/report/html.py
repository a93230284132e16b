"""Minimal HTML building blocks for the self-contained report page.

Everything is inline: one ``<style>`` block, images as ``data:image/png;base64`` URIs, no
script and no external resource, so the page can be mailed or archived as one file. Every text
that comes from the data passes through :func:`esc`.
"""
from __future__ import annotations

import base64
import html
import math
from collections.abc import Iterable, Sequence

STYLE = """
body{font-family:system-ui,-apple-system,"Segoe UI",Roboto,sans-serif;margin:1.5em auto;
max-width:1200px;padding:0 1em;color:#222;line-height:1.4}
h1{border-bottom:2px solid #444}h2{border-bottom:1px solid #aaa;margin-top:2em}
div.table{overflow-x:auto;max-width:100%;margin:.6em 0}
table{border-collapse:collapse;font-size:.9em}
th,td{border:1px solid #bbb;padding:.25em .5em}th{background:#eee;text-align:left}
td.num{text-align:right;font-variant-numeric:tabular-nums;white-space:nowrap}
tr.best td{font-weight:bold}
.notes{background:#fff6e0;border-left:4px solid #e0a000;padding:.4em 1em;margin:.6em 0}
.notes li{margin:.15em 0}
figure{margin:1em 0}figcaption{font-size:.9em;color:#444}
img{max-width:100%;height:auto;border:1px solid #ddd}
code{background:#f3f3f3;padding:0 .2em}
dl.kv{display:grid;grid-template-columns:max-content auto;gap:.2em 1em}dl.kv dt{font-weight:bold}
dl.kv dd{margin:0}
"""
MISSING = "—"


def esc(value) -> str:
    """HTML-escaped text of any value."""
    return html.escape(str(value), quote=True)


def number(value, digits: int = 3) -> str:
    """A fixed-point number, or an em dash for None / NaN / non-numbers."""
    try:
        value = float(value)
    except (TypeError, ValueError):
        return MISSING
    if not math.isfinite(value):
        return MISSING
    return f"{value:.{digits}f}"


class Cell:
    """A table cell: text (escaped) or ready-made HTML, optionally numeric (right-aligned)."""

    def __init__(self, text: str, numeric: bool = False, raw: bool = False):
        self.text, self.numeric, self.raw = text, numeric, raw

    def render(self, tag: str = "td") -> str:
        cls = ' class="num"' if self.numeric else ""
        return f"<{tag}{cls}>{self.text if self.raw else esc(self.text)}</{tag}>"


def num_cell(value, digits: int = 3) -> Cell:
    """A right-aligned number cell (see :func:`number`)."""
    return Cell(number(value, digits), numeric=True)


def table(header: Sequence[str], rows: Iterable[Sequence], caption: str = "",
          table_id: str = "", row_classes: Sequence[str] | None = None) -> str:
    """An HTML table in a horizontally scrolling box; cells are :class:`Cell` objects or plain
    values (escaped)."""
    attr = f' id="{esc(table_id)}"' if table_id else ""
    parts = [f'<div class="table"><table{attr}>']  # the div scrolls a table wider than the page
    if caption:
        parts.append(f"<caption>{esc(caption)}</caption>")
    parts.append("<thead><tr>" + "".join(f"<th>{esc(h)}</th>" for h in header) + "</tr></thead>")
    parts.append("<tbody>")
    for i, row in enumerate(rows):
        cls = row_classes[i] if row_classes and row_classes[i] else ""
        cells = "".join((c if isinstance(c, Cell) else Cell(str(c))).render() for c in row)
        parts.append(f'<tr class="{esc(cls)}">{cells}</tr>' if cls else f"<tr>{cells}</tr>")
    parts.append("</tbody></table></div>")
    return "\n".join(parts)


def image(png: bytes, alt: str, caption: str = "") -> str:
    """A figure with the PNG embedded as a base64 data URI."""
    data = base64.b64encode(png).decode("ascii")
    cap = f"<figcaption>{esc(caption)}</figcaption>" if caption else ""
    return (f'<figure><img alt="{esc(alt)}" src="data:image/png;base64,{data}">{cap}'
            "</figure>")


def notes(items: Sequence[str], title: str = "Notes") -> str:
    """A highlighted list of remarks (missing pieces, warnings); empty string if none."""
    if not items:
        return ""
    lis = "".join(f"<li>{esc(item)}</li>" for item in items)
    return f'<div class="notes"><strong>{esc(title)}</strong><ul>{lis}</ul></div>'


def key_values(pairs: Iterable[Sequence]) -> str:
    """A definition list of (key, value) pairs (values escaped)."""
    body = "".join(f"<dt>{esc(k)}</dt><dd>{esc(v)}</dd>" for k, v in pairs)
    return f'<dl class="kv">{body}</dl>'


def section(title: str, body: str, level: int = 2, anchor: str = "") -> str:
    """A heading followed by its body HTML."""
    attr = f' id="{esc(anchor)}"' if anchor else ""
    return f"<section{attr}><h{level}>{esc(title)}</h{level}>\n{body}\n</section>"


def details(summary: str, body: str) -> str:
    """A collapsible block (no script needed)."""
    return f"<details><summary>{esc(summary)}</summary>{body}</details>"


def page(title: str, body: str) -> str:
    """The complete HTML document."""
    return ("<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
            f"<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">"
            f"<title>{esc(title)}</title><style>{STYLE}</style></head>\n<body>\n"
            f"<h1>{esc(title)}</h1>\n{body}\n</body></html>\n")
