"""Tokens of a Stage 4 world file, with ``include`` files spliced in.

Lexical rules follow Stage's worldfile.cc: ``#`` starts a comment to the end of the line; a word
starts with a letter and continues with letters, digits and ``. - _ [ ]`` (so ``point[0]`` is one
word); a number is a run of ``+ - . 0-9`` (no exponent: Stage reads ``1e-3`` as ``1`` followed by
a word); a string is ``"..."`` on one line, without escapes; ``( ) [ ]`` are punctuation.

``include "f.inc"`` is expanded while lexing, as Stage does. A relative name is looked up beside
the including file first, then beside the top-level world file (Stage's own rule), so include
trees that work in Stage work here too. Include cycles are an error.
"""
from __future__ import annotations

import os
from collections.abc import Sequence
from dataclasses import dataclass

from slam_predict.errors import InputError

WORD, NUMBER, STRING, OPEN, CLOSE, TUPLE_OPEN, TUPLE_CLOSE = (
    "word", "number", "string", "(", ")", "[", "]")
_NUMBER_CHARS = set("+-.0123456789")
_WORD_CHARS = set(".-_[]")
_PUNCT = {"(": OPEN, ")": CLOSE, "[": TUPLE_OPEN, "]": TUPLE_CLOSE}


@dataclass(frozen=True)
class Token:
    """One token: kind, text (strings without quotes), the file and 1-based line it came from."""

    kind: str
    text: str
    path: str
    line: int


def _read_text(path: str, included_from: Token | None) -> str:
    if not os.path.isfile(path):
        if included_from is None:
            raise InputError("world file not found", path)
        raise InputError(f"included file '{included_from.text}' not found (looked for {path})",
                         included_from.path, included_from.line)
    try:
        with open(path, "rb") as handle:
            data = handle.read()
    except OSError as exc:
        raise InputError(f"cannot read world file ({exc.strerror})", path) from None
    if b"\0" in data:
        raise InputError("not a text world file (binary content)", path)
    return data.decode("utf-8", errors="replace")


def _scan(text: str, path: str) -> list[Token]:
    """Split one file's text into tokens (comments and white space dropped)."""
    tokens: list[Token] = []
    i, line, n = 0, 1, len(text)
    while i < n:
        ch = text[i]
        if ch == "\r" or ch == "\n":
            i += 2 if text[i:i + 2] in ("\r\n", "\n\r") else 1
            line += 1
        elif ch in " \t\f\v":
            i += 1
        elif ch == "#":
            while i < n and text[i] not in "\r\n":
                i += 1
        elif ch.isalpha():
            start = i
            while i < n and (text[i].isalnum() or text[i] in _WORD_CHARS):
                i += 1
            tokens.append(Token(WORD, text[start:i], path, line))
        elif ch in _NUMBER_CHARS:
            start = i
            while i < n and text[i] in _NUMBER_CHARS:
                i += 1
            if i < n and text[i] in "eE" and i + 1 < n and text[i + 1] in _NUMBER_CHARS:
                raise InputError(f"number '{text[start:i + 2]}...' has an exponent, which Stage "
                                 "cannot read; write it in plain decimals", path, line)
            tokens.append(Token(NUMBER, text[start:i], path, line))
        elif ch == '"':
            end = i + 1
            while end < n and text[end] not in '"\r\n':
                end += 1
            if end >= n or text[end] != '"':
                raise InputError("unterminated string (missing closing \")", path, line)
            tokens.append(Token(STRING, text[i + 1:end], path, line))
            i = end + 1
        elif ch in _PUNCT:
            tokens.append(Token(_PUNCT[ch], ch, path, line))
            i += 1
        else:
            raise InputError(f"syntax error: unexpected character {ch!r}", path, line)
    return tokens


def _resolve_include(name_token: Token, top_dir: str) -> str:
    name = os.path.expanduser(name_token.text)
    if os.path.isabs(name):
        return name
    beside = os.path.join(os.path.dirname(name_token.path), name)
    if os.path.isfile(beside):
        return beside
    fallback = os.path.join(top_dir, name)
    return fallback if os.path.isfile(fallback) else beside


def tokenize(path: os.PathLike | str) -> list[Token]:
    """All tokens of the world file ``path`` with every ``include`` expanded in place."""
    path = os.path.abspath(os.fspath(path))
    return _tokenize(path, os.path.dirname(path), (), None)


def _tokenize(path: str, top_dir: str, stack: Sequence[str],
              included_from: Token | None) -> list[Token]:
    real = os.path.realpath(path)
    if real in stack:
        raise InputError(f"include cycle: '{included_from.text}' includes itself again",
                         included_from.path, included_from.line)
    raw = _scan(_read_text(path, included_from), path)
    out: list[Token] = []
    i = 0
    while i < len(raw):
        tok = raw[i]
        if tok.kind == WORD and tok.text == "include":
            if i + 1 >= len(raw) or raw[i + 1].kind != STRING or raw[i + 1].line != tok.line:
                raise InputError('syntax error in include statement: expected include "file"',
                                 tok.path, tok.line)
            target = _resolve_include(raw[i + 1], top_dir)
            out.extend(_tokenize(target, top_dir, (*stack, real), raw[i + 1]))
            i += 2
            continue
        out.append(tok)
        i += 1
    return out
