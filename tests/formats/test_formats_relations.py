"""Freiburg relations files."""
from __future__ import annotations

import logging

import numpy as np
import pytest

from slam_predict.errors import InputError
from slam_predict.formats.relations import Relations, read_relations, write_relations


def test_read_example_line(tmp_path):
    path = tmp_path / "a.relations"
    path.write_text("# a comment\n1232658478.161285 1232658644.149293 1.031273 -0.003531 0 0 -0 "
                    "-0.009755   # trailing\n\n")
    rel = read_relations(path)
    assert len(rel) == 1
    assert rel.t1[0] == 1232658478.161285 and rel.t2[0] == 1232658644.149293
    np.testing.assert_array_equal(rel.deltas, [[1.031273, -0.003531, -0.009755]])


def test_round_trip_exact(tmp_path):
    rng = np.random.default_rng(0)
    rel = Relations(1e9 + rng.uniform(0, 100, 50), 1e9 + rng.uniform(100, 200, 50),
                    rng.normal(size=(50, 3)))
    write_relations(tmp_path / "r.relations", rel, header=["test"])
    again = read_relations(tmp_path / "r.relations")
    for a, b in ((rel.t1, again.t1), (rel.t2, again.t2), (rel.deltas, again.deltas)):
        np.testing.assert_array_equal(a, b)


def test_non_planar_values_warned(tmp_path, caplog):
    path = tmp_path / "a.relations"
    path.write_text("1 2 0.5 0 0.1 0 0 0.2\n")
    with caplog.at_level(logging.WARNING):
        rel = read_relations(path)
    assert "z/roll/pitch" in caplog.text
    np.testing.assert_array_equal(rel.deltas, [[0.5, 0, 0.2]])


@pytest.mark.parametrize("line, words", [("1 2 3 4 5 6 7", "expected 8"),
                                         ("1 2 3 4 5 6 7 x", "non-numeric"),
                                         ("1 2 3 4 5 6 7 inf", "non-finite")])
def test_bad_lines(tmp_path, line, words):
    path = tmp_path / "a.relations"
    path.write_text("1 2 0 0 0 0 0 0\n" + line + "\n")
    with pytest.raises(InputError, match=words) as err:
        read_relations(path)
    assert err.value.line == 2
