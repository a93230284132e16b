"""The layer table of docs/architecture.md against the imports of src/slam_predict.

The table's first column names a layer, its second column the modules and folders (in backticks)
that belong to it, its third the layers it may import. A layer may also import whatever the
layers it names may import (the relation is transitive). The imports come from the source's
syntax tree (tests/core/test_module_structure.import_graph), deferred ones included.
"""
from __future__ import annotations

import re
from pathlib import Path

import pytest
from test_module_structure import import_graph

DOC = Path(__file__).resolve().parents[2] / "docs" / "architecture.md"
TICKED = re.compile(r"`([^`]+)`")
PACKAGE_ITSELF = "the package itself"


def layer_table(text: str) -> tuple[dict, dict]:
    """(module or folder → layer, layer → layers it may import directly), from the first
    Markdown table under the doc's "## Layers" heading."""
    section = text.split("## Layers", 1)[1].split("\n## ", 1)[0]
    rows = [line for line in section.splitlines() if line.startswith("| `")]
    members, allowed, all_but = {}, {}, {}
    for row in rows:
        layer_cell, where, imports = (cell.strip() for cell in row.strip("|").split("|")[:3])
        layer = TICKED.findall(layer_cell)[0]
        for name in TICKED.findall(where):
            members[name.rstrip("/").replace("/", ".")] = layer
        if PACKAGE_ITSELF in where:
            members[""] = layer
        allowed[layer] = set(TICKED.findall(imports))
        if "every layer" in imports:      # "every layer but `x`": all the others
            all_but[layer] = set(TICKED.findall(imports.split("every layer", 1)[1]))
    for layer, excluded in all_but.items():
        allowed[layer] = set(allowed) - excluded - {layer}
    return members, allowed


def closure(allowed: dict) -> dict:
    """Each layer's directly allowed layers plus everything those may import, itself included."""
    reach = {}
    for start in allowed:
        seen, todo = {start}, [start]
        while todo:
            for nxt in allowed.get(todo.pop(), ()):
                if nxt in allowed and nxt not in seen:
                    seen.add(nxt)
                    todo.append(nxt)
        reach[start] = seen
    return reach


def layer_of(module: str, members: dict) -> str | None:
    """The layer of a dotted module of slam_predict: its longest listed prefix."""
    relative = module.split(".", 1)[1] if "." in module else ""
    parts = relative.split(".") if relative else []
    for size in range(len(parts), -1, -1):
        key = ".".join(parts[:size])
        if key in members and (size or not parts):
            return members[key]
    return None


def test_every_module_has_a_layer():
    members, _ = layer_table(DOC.read_text(encoding="utf-8"))
    missing = sorted(m for m in import_graph().nodes if layer_of(m, members) is None)
    assert not missing, f"modules in no layer of docs/architecture.md: {missing}"


def forbidden(edges, members: dict, allowed: dict) -> list:
    """The import edges (module, module) that the table does not allow, as readable lines."""
    reach = closure(allowed)
    return sorted(f"{a} -> {b} ({layer_of(a, members)} -> {layer_of(b, members)})"
                  for a, b in edges
                  if layer_of(b, members) not in reach.get(layer_of(a, members), ()))


def test_imports_follow_the_layer_table():
    members, allowed = layer_table(DOC.read_text(encoding="utf-8"))
    wrong = forbidden(import_graph().edges, members, allowed)
    assert not wrong, "imports the layer table does not allow:\n" + "\n".join(wrong)


def test_a_forbidden_arrow_is_found():
    """The check itself: upward arrows are reported, downward and transitive ones are not."""
    members, allowed = layer_table(DOC.read_text(encoding="utf-8"))
    edges = [("slam_predict.slam.runner", "slam_predict.explore.loop"),     # slam -> explore
             ("slam_predict.errors", "slam_predict.cli.main"),              # core -> cli
             ("slam_predict.nav.planner", "slam_predict.sim.raycast"),      # nav -> sim
             ("slam_predict.explore.loop", "slam_predict.world.model"),     # via sim
             ("slam_predict.cli.main", "slam_predict.learn.store")]
    wrong = forbidden(edges, members, allowed)
    assert [line.split(" (")[0] for line in wrong] == [
        "slam_predict.errors -> slam_predict.cli.main",
        "slam_predict.nav.planner -> slam_predict.sim.raycast",
        "slam_predict.slam.runner -> slam_predict.explore.loop"]


@pytest.mark.parametrize("module,layer", [("slam_predict.slam.gmapping.filter", "slam"),
                                          ("slam_predict", "core"),
                                          ("slam_predict.world.stagefile.writer", "world")])
def test_layer_of(module, layer):
    members, _ = layer_table(DOC.read_text(encoding="utf-8"))
    assert layer_of(module, members) == layer
