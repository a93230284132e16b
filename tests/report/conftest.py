"""Fixtures of the report tests: a fake campaign (built once) and an HTML page parser."""
from __future__ import annotations

from html.parser import HTMLParser

import pytest

from .fake_campaign import build


@pytest.fixture(scope="session")
def campaign_dir(tmp_path_factory):
    """The fake campaign of :mod:`fake_campaign` (read-only: copy it before damaging it)."""
    return build(tmp_path_factory.mktemp("report"))


class Page(HTMLParser):
    """Tables (header + rows of cell texts), images, tags, headings and notes of a page."""

    def __init__(self, text: str):
        super().__init__(convert_charrefs=True)
        self.tables: list[dict] = []
        self.images: list[dict[str, str]] = []
        self.tags: list[str] = []
        self.headings: list[str] = []
        self.notes: list[str] = []
        self._cell = None
        self._heading = None
        self._in_notes = 0
        self._li = None
        self.feed(text)
        self.close()

    def handle_starttag(self, tag, attrs):
        attrs = dict(attrs)
        self.tags.append(tag)
        if tag == "table":
            section = self.headings[-1] if self.headings else ""
            self.tables.append({"id": attrs.get("id"), "section": section, "header": [],
                                "rows": []})
        elif tag == "tr":
            self._row = []
        elif tag in ("td", "th"):
            self._cell = ""
        elif tag == "img":
            self.images.append(attrs)
        elif tag in ("h1", "h2", "h3"):
            self._heading = ""
        elif tag == "div" and attrs.get("class") == "notes":
            self._in_notes += 1
        elif tag == "li" and self._in_notes:
            self._li = ""

    def handle_endtag(self, tag):
        if tag in ("td", "th"):
            self._row.append(self._cell.strip())
            self._cell = None
        elif tag == "tr":
            table = self.tables[-1]
            if table["header"]:
                table["rows"].append(self._row)
            else:
                table["header"] = self._row
        elif tag in ("h1", "h2", "h3"):
            self.headings.append(self._heading.strip())
            self._heading = None
        elif tag == "li" and self._li is not None:
            self.notes.append(self._li.strip())
            self._li = None
        elif tag == "div" and self._in_notes:
            self._in_notes -= 1

    def handle_data(self, data):
        if self._cell is not None:
            self._cell += data
        if self._heading is not None:
            self._heading += data
        if self._li is not None:
            self._li += data

    def table(self, header_start: list[str], section: str = "") -> dict:
        """The first table whose header starts with ``header_start`` (below heading
        ``section`` if given)."""
        for table in self.tables:
            if table["header"][:len(header_start)] == header_start and \
                    (not section or table["section"] == section):
                return table
        raise AssertionError(f"no table with header {header_start} in '{section}'")

    def rows_by_first(self, table: dict) -> dict[str, dict[str, str]]:
        """Rows of a table as {first cell: {column: text}}."""
        return {row[0]: dict(zip(table["header"], row, strict=False)) for row in table["rows"]}


@pytest.fixture
def parse():
    return Page


@pytest.fixture(scope="session")
def model_dir(tmp_path_factory):
    """A copy of the shipped thesis-realistic model whose card claims the feature version this
    tree computes (the shipped card may lag while feature code changes; the report tests are
    about the page, not about that version)."""
    import json
    import shutil

    from slam_predict.features.plan import version_of
    from slam_predict.learn.store import default_models_dir

    source = default_models_dir() / "thesis-realistic"
    if not (source / "card.json").is_file():
        pytest.skip(f"shipped model missing: {source}")
    target = tmp_path_factory.mktemp("models") / "thesis-realistic"
    shutil.copytree(source, target)
    card = json.loads((target / "card.json").read_text())
    card["feature_version"] = version_of(card.get("feature_config") or {})
    (target / "card.json").write_text(json.dumps(card, indent=2) + "\n")
    return target
