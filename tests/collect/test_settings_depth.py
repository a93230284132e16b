"""Every settings file of config/ reaches its root in at most three `extends` steps (the
robot-aware and Karto campaigns extend the fidelity chain of record as it is, so that its
navigation and fitted settings have one copy)."""
from __future__ import annotations

from pathlib import Path

import yaml

ROOT = Path(__file__).resolve().parents[2]


def extends_depth(path: Path) -> int:
    """How many `extends` steps lead from ``path`` to a file without one."""
    depth = 0
    while True:
        parent = (yaml.safe_load(path.read_text(encoding="utf-8")) or {}).get("extends")
        if not isinstance(parent, str):
            return depth
        path = (path.parent / parent).resolve()
        depth += 1
        assert depth < 10, f"{path}: extends loop"


def test_settings_chains_are_at_most_three_deep():
    files = [p for p in sorted((ROOT / "config").rglob("*.yaml"))
             if "extends:" in p.read_text(encoding="utf-8")]
    assert files
    deep = {str(p.relative_to(ROOT)): extends_depth(p) for p in files}
    assert max(deep.values()) >= 2
    assert all(d <= 3 for d in deep.values()), deep
