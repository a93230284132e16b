"""Parse a Stage 4 world file into a tree of entities with macros expanded.

Grammar (Stage's worldfile.cc): at the top level, ``define NEW BASE ( body )`` statements,
properties ``name value`` and entities ``type ( body )``; a body holds properties and nested
entities; a value is a number, a ``"string"`` or a tuple ``[v v ...]`` of numbers and strings.

Macros as in Stage: instantiating ``NEW`` first builds ``BASE`` (itself possibly a macro, to any
depth), then applies the macro body, then the instance body; later properties override earlier
ones and nested entities accumulate. The first definition of a name wins (Stage keeps the first
and ignores redefinitions; we warn). Macros are looked up when used, so a macro body may name a
macro defined later in the file. A property set twice in one body keeps the last value.
"""
from __future__ import annotations

import logging
import os
import re
from dataclasses import dataclass, field

from slam_predict.errors import InputError, did_you_mean
from slam_predict.world.stagefile import schema
from slam_predict.world.stagefile.lexer import (
    CLOSE,
    NUMBER,
    OPEN,
    STRING,
    TUPLE_CLOSE,
    TUPLE_OPEN,
    WORD,
    Token,
    tokenize,
)

LOG = logging.getLogger(__name__)
MAX_MACRO_DEPTH = 64
_INDEXED_NAME = re.compile(r"^[A-Za-z][\w.-]*\[\d+\]$")  # e.g. point[3] in a block


@dataclass
class Prop:
    """A property: its name token and value tokens (NUMBER or STRING); ``is_tuple`` for [..]."""

    token: Token
    values: tuple[Token, ...]
    is_tuple: bool

    @property
    def name(self) -> str:
        return self.token.text


@dataclass
class Entity:
    """An entity after macro expansion.

    ``type`` is the built-in Stage type at the root of the macro chain ("world" for the file
    itself); ``macros`` the macro names used, outermost first (e.g. ("floorplan",)).
    """

    type: str
    token: Token | None
    macros: tuple[str, ...] = ()
    props: dict[str, Prop] = field(default_factory=dict)
    children: list[Entity] = field(default_factory=list)

    def walk(self):
        """This entity and all its descendants, depth first, with their parents."""
        stack = [(self, None)]
        while stack:
            node, parent = stack.pop()
            yield node, parent
            stack.extend((child, node) for child in reversed(node.children))

    @property
    def label(self) -> str:
        """The name a user wrote for this entity (macro name, else type)."""
        return self.macros[0] if self.macros else self.type


@dataclass
class _Macro:
    name: str
    base: Token
    body: tuple[Token, ...]


def _same_line(a: Token, b: Token) -> bool:
    return a.path == b.path and a.line == b.line


class _Parser:
    """Recursive-descent parser over one token list (includes already expanded)."""

    def __init__(self, tokens: list[Token], path: str):
        self.tokens = tokens
        self.path = path
        self.macros: dict[str, _Macro] = {}

    def _error(self, problem: str, token: Token | None) -> InputError:
        if token is None:
            return InputError(problem, self.path)
        return InputError(problem, token.path, token.line)

    def parse(self) -> Entity:
        root = Entity("world", None)
        toks = self.tokens
        i = 0
        while i < len(toks):
            tok = toks[i]
            if tok.kind == WORD and tok.text == "define":
                i = self._define(toks, i)
            elif tok.kind == WORD:
                i = self._statement(root, toks, i, 0)
            else:
                raise self._error(f"syntax error: unexpected '{tok.text}' (expected a property "
                                  "name, an entity or define)", tok)
        return root

    # -- statements -------------------------------------------------------------------------
    def _define(self, toks: list[Token], i: int) -> int:
        head = toks[i]
        if i + 3 >= len(toks) or toks[i + 1].kind != WORD or toks[i + 2].kind != WORD \
                or toks[i + 3].kind != OPEN:
            raise self._error("syntax error in define: expected 'define NEW BASE ( ... )'", head)
        name, base = toks[i + 1], toks[i + 2]
        end = self._matching_close(toks, i + 3)
        if name.text in schema.MODEL_TYPES:
            raise self._error(f"define cannot redefine the Stage model type '{name.text}'", name)
        if name.text in self.macros:
            first = self.macros[name.text].base
            LOG.warning("%s:%d: macro '%s' redefined; Stage keeps the first definition (%s:%d)",
                        name.path, name.line, name.text, first.path, first.line)
        else:
            self.macros[name.text] = _Macro(name.text, base, tuple(toks[i + 4:end]))
        return end + 1

    def _matching_close(self, toks: list[Token], open_index: int) -> int:
        depth = 0
        for j in range(open_index, len(toks)):
            if toks[j].kind == OPEN:
                depth += 1
            elif toks[j].kind == CLOSE:
                depth -= 1
                if depth == 0:
                    return j
        raise self._error("missing ')' for the '(' opened here", toks[open_index])

    def _statement(self, parent: Entity, toks, i: int, depth: int) -> int:
        """Parse ``name value`` or ``type ( body )`` starting at toks[i] into ``parent``."""
        name = toks[i]
        if name.text in ("define", "include"):
            raise self._error(f"'{name.text}' is only allowed at the top level of a file", name)
        if "[" in name.text and not _INDEXED_NAME.match(name.text):
            raise self._error(f"syntax error in '{name.text}': put a space before '[' (Stage "
                              "reads brackets inside a word as part of the name)", name)
        if i + 1 >= len(toks):
            raise self._error(f"syntax error: '{name.text}' has no value", name)
        nxt = toks[i + 1]
        if nxt.kind == OPEN:
            end = self._matching_close(toks, i + 1)
            child = self._instantiate(name, depth)
            if not schema.allowed_children(parent.type, child.type):
                where = "the top level" if parent.type == "world" else f"a {parent.label}"
                raise self._error(f"a {child.type} cannot be placed in {where}", name)
            self._body(child, toks[i + 2:end], depth)
            parent.children.append(child)
            return end + 1
        if nxt.kind in (NUMBER, STRING, TUPLE_OPEN) and not _same_line(name, nxt):
            raise self._error(f"syntax error: the value of '{name.text}' must be on the same "
                              "line as its name", nxt)
        if nxt.kind in (NUMBER, STRING):
            parent.props[name.text] = Prop(name, (nxt,), False)
            return i + 2
        if nxt.kind == TUPLE_OPEN:
            values = []
            j = i + 2
            while j < len(toks) and toks[j].kind in (NUMBER, STRING) and _same_line(nxt, toks[j]):
                values.append(toks[j])
                j += 1
            if j < len(toks) and not _same_line(nxt, toks[j]):
                raise self._error(f"syntax error in tuple '{name.text}': a tuple must end with "
                                  "']' on the line where it starts", nxt)
            if j >= len(toks) or toks[j].kind != TUPLE_CLOSE:
                bad = toks[j] if j < len(toks) else nxt
                raise self._error(f"syntax error in tuple '{name.text}': expected numbers, "
                                  "strings or ']'", bad)
            parent.props[name.text] = Prop(name, tuple(values), True)
            return j + 1
        hint = ""
        if nxt.kind == WORD:
            hint = f" (quote string values: {name.text} \"{nxt.text}\")"
        raise self._error(f"syntax error: '{name.text}' must be followed by a value or "
                          f"'(' but got '{nxt.text}'{hint}", nxt)

    def _body(self, entity: Entity, toks, depth: int) -> None:
        i = 0
        while i < len(toks):
            if toks[i].kind != WORD:
                raise self._error(f"syntax error: unexpected '{toks[i].text}' in "
                                  f"{entity.label}( ... )", toks[i])
            i = self._statement(entity, toks, i, depth)

    # -- macros -----------------------------------------------------------------------------
    def _instantiate(self, type_token: Token, depth: int) -> Entity:
        name = type_token.text
        if depth > MAX_MACRO_DEPTH:
            raise self._error(f"macro '{name}' expands into itself (recursive define)",
                              type_token)
        macro = self.macros.get(name)
        if macro is not None:
            entity = self._instantiate(macro.base, depth + 1)
            entity.macros = (name,) + entity.macros
            entity.token = type_token
            self._body(entity, macro.body, depth + 1)
            return entity
        if name in schema.BUILTIN_TYPES:
            return Entity(name, type_token)
        known = sorted(schema.BUILTIN_TYPES | set(self.macros))
        hint = f" ({schema.HINTS[name]})" if name in schema.HINTS else did_you_mean(name, known)
        raise self._error(f"unknown model type '{name}'{hint}", type_token)


def parse_file(path: os.PathLike | str) -> Entity:
    """Parse the world file ``path`` (with its includes) into its root entity (type "world")."""
    path = os.fspath(path)
    tokens = tokenize(path)
    return _Parser(tokens, os.path.abspath(path)).parse()
