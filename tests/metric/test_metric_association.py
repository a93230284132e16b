"""Timestamp association, pause removal and truncated-line repair."""
from __future__ import annotations

import numpy as np
import pytest

from slam_predict.metric import (
    associate,
    dedupe_consecutive,
    drop_truncated_last_line,
    nearest_within,
)


def _brute_force(t_a, t_b, tol):
    """The documented rule, written the slow obvious way."""
    choice = {}
    for i, ta in enumerate(t_a):
        dists = [abs(ta - tb) for tb in t_b]
        j = int(np.argmin(dists))           # first minimum = earlier stamp on ties
        if dists[j] <= tol and (j not in choice or dists[j] < choice[j][1]):
            choice[j] = (i, dists[j])
    pairs = sorted((i, j) for j, (i, _) in choice.items())
    return [p[0] for p in pairs], [p[1] for p in pairs]


@pytest.mark.parametrize("seed", range(5))
def test_associate_matches_brute_force(seed):
    rng = np.random.default_rng(seed)
    t_a = np.sort(np.round(rng.uniform(0, 10, 60), 2))
    t_b = np.sort(np.round(rng.uniform(0, 10, 45), 2))
    ia, ib = associate(t_a, t_b, 0.1)
    ea, eb = _brute_force(t_a, t_b, 0.1)
    assert ia.tolist() == ea and ib.tolist() == eb
    assert np.all(np.diff(ia) > 0) and np.all(np.diff(ib) > 0)
    assert np.all(np.abs(t_a[ia] - t_b[ib]) <= 0.1)


def test_associate_identical_and_empty():
    t = np.arange(5) * 0.1
    ia, ib = associate(t, t, 0.001)
    assert ia.tolist() == ib.tolist() == list(range(5))
    assert len(associate([], t, 1)[0]) == 0
    with pytest.raises(ValueError):
        associate([2.0, 1.0], t, 0.1)


def test_nearest_within():
    idx = nearest_within([0.0, 0.26, 0.5, 9.0], [0.0, 0.2, 0.3], 0.05)
    assert idx.tolist() == [0, 2, -1, -1]


def test_dedupe_consecutive():
    poses = np.array([[0, 0, 0], [0, 0, 0], [1, 0, 0], [1, 0, 0], [1, 0, 0], [0, 0, 0]], float)
    t, p = dedupe_consecutive(np.arange(6.0), poses)
    assert t.tolist() == [0, 2, 5]
    np.testing.assert_array_equal(p, poses[[0, 2, 5]])
    t2, _ = dedupe_consecutive(np.arange(3.0), [[0, 0, 0], [1e-9, 0, 0], [1, 0, 0]], atol=1e-6)
    assert t2.tolist() == [0, 2]


@pytest.mark.parametrize("text, removed", [
    ("FLASER 0 1 2 3 1 2 3 10.0 h 10.0\nFLASER 0 1 2 3 1 2\n", True),
    ("FLASER 0 1 2 3 1 2 3 10.0 h 10.0\nFLASER 0 1 2 3 1 2 3 11.0 h 11.0\n", False),
    ("FLASER 0 1 2 3 1 2 3 10.0 h 10.0\nFLASER 0 1 2 3 1 2 3 11.0 h 11.", False),
    ("1 0 0 0 0 0 0 1\n2 0 0 0 0 0 0\n", True),
    ("1 0 0 0 0 0 0 1\n2 0 0 0 0 0 0 1\n", False),
])
def test_drop_truncated_last_line(tmp_path, text, removed):
    src = tmp_path / "log.txt"
    src.write_text(text)
    assert drop_truncated_last_line(src) == removed
    expected = text.splitlines(keepends=True)
    if removed:
        expected = expected[:-1]
    assert src.read_text() == "".join(expected)
