"""Small wording helpers shared by the library's log lines and the CLI's output."""
from __future__ import annotations


def plural(count: int, noun: str, plural_form: str | None = None) -> str:
    """``'1 run'``, ``'2 runs'``: ``count`` with the noun in the right number."""
    word = noun if count == 1 else (plural_form or noun + "s")
    return f"{count} {word}"
