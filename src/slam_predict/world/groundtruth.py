"""Ground-truth rooms and doors of a World as a JSON-ready record, and back.

Stage world files cannot hold rooms and doors, so writers store them in a JSON file beside the
world (``<name>.json``): ``rooms`` = [{id, label, polygon [[x, y], ...] m}], ``doors`` =
[{rooms [a, b], segment [[x, y], [x, y]] m, width m}], in the World frame (x right, y up, m).
"""
from __future__ import annotations

import json
import os

import numpy as np

from slam_predict.errors import InputError, require_file
from slam_predict.world.model import Door, Room

DIGITS = 4


def rooms_record(rooms: list[Room]) -> list[dict]:
    """Rooms as plain dicts (polygons rounded to 0.1 mm)."""
    return [{"id": r.id, "label": r.label,
             "polygon": np.round(np.asarray(r.polygon, float), DIGITS).tolist()} for r in rooms]


def doors_record(doors: list[Door]) -> list[dict]:
    """Doors as plain dicts: the two room ids, the segment (m) and its length (m)."""
    out = []
    for d in doors:
        seg = np.asarray(d.segment, float)
        out.append({"rooms": list(d.rooms), "segment": np.round(seg, DIGITS).tolist(),
                    "width": round(float(np.hypot(*(seg[1] - seg[0]))), DIGITS)})
    return out


def from_record(record: dict, source: str = "") -> tuple[list[Room], list[Door]]:
    """(rooms, doors) from a record written by :func:`rooms_record`/:func:`doors_record`."""
    try:
        rooms = [Room(id=str(r["id"]), label=str(r.get("label", "")),
                      polygon=np.asarray(r["polygon"], float).reshape(-1, 2))
                 for r in record.get("rooms", [])]
        doors = [Door(segment=np.asarray(d["segment"], float).reshape(2, 2),
                      rooms=tuple(str(x) for x in d["rooms"])) for d in record.get("doors", [])]
    except (KeyError, TypeError, ValueError) as exc:
        raise InputError(f"bad ground-truth record ({exc})", source or None) from None
    return rooms, doors


def read_ground_truth(path: os.PathLike | str) -> tuple[list[Room], list[Door]]:
    """(rooms, doors) from a ground-truth JSON file."""
    path = require_file(path, "ground-truth JSON")
    try:
        with open(path, encoding="utf-8") as handle:
            record = json.load(handle)
    except (OSError, json.JSONDecodeError) as exc:
        raise InputError(f"cannot read ground-truth JSON ({exc})", path) from None
    return from_record(record, path)
