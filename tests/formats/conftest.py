"""Helpers of the prepared-scans tests (GMapping and Karto variants)."""
from __future__ import annotations

import numpy as np
import pytest


def parse_prepared_text(text: str):
    """(first line, {key: [values]}, SCAN rows as an array) of a prepared-scans text."""
    lines = text.splitlines()
    header, scans = {}, []
    for line in lines[1:]:
        key, *values = line.split()
        if key == "SCAN":
            scans.append([float(v) for v in values])
        else:
            header[key] = values
    return lines[0], header, np.array(scans)


@pytest.fixture
def parse_prepared():
    """:func:`parse_prepared_text`."""
    return parse_prepared_text
