"""One row of a whitespace-separated text table of numbers (TUM trajectories, relations)."""
from __future__ import annotations

import os

import numpy as np

from slam_predict.errors import InputError


def parse_number_row(tokens: list[str], fields: str, what: str,
                     path: os.PathLike | str, number: int) -> list[float]:
    """The values of one line split into ``tokens``; ``fields`` names the columns it must have
    (space-separated), ``what`` the kind of line in the messages. Raises InputError naming the
    file and line when the count is wrong or a value is not a finite number."""
    count = len(fields.split())
    if len(tokens) != count:
        raise InputError(f"expected {count} values '{fields}', got {len(tokens)}", path, number)
    try:
        values = [float(v) for v in tokens]
    except ValueError as exc:
        raise InputError(f"non-numeric value in {what}", path, number) from exc
    if not np.all(np.isfinite(values)):
        raise InputError(f"non-finite value in {what}", path, number)
    return values
