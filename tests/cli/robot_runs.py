"""Shared by the CLI tests that run the tiny world with a robot description file."""
from __future__ import annotations

from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
TINY = ROOT / "worlds" / "tiny.world"
LDS = ROOT / "config" / "robots" / "lds_360_3p5.yaml"


def short_settings(folder: Path) -> Path:
    """Settings whose runs end after 25 s of sim time (the explorer is moving by then)."""
    path = folder / "short.yaml"
    path.write_text(f"extends: {ROOT / 'config' / 'collect.yaml'}\n"
                    "stop:\n  max_sim_time_s: 25.0\n")
    return path
