"""Dataset assembly: error tables (thesis and summary formats), joins, CSV round trip."""
from __future__ import annotations

import csv
import math

import numpy as np
import pytest

from slam_predict.errors import InputError
from slam_predict.learn import dataset as ds
from slam_predict.learn import sources


def write_csv(path, header, rows):
    with open(path, "w", newline="") as handle:
        writer = csv.writer(handle)
        writer.writerow(header)
        writer.writerows(rows)
    return path


def test_thesis_table_is_read_with_stripped_header(shared_data):
    path = shared_data / "thesis" / "stats_realistic.csv"
    rows = sources.read_error_table(path, "realistic")
    assert len(rows) == 88
    with open(path, newline="") as handle:
        raw = list(csv.reader(handle))
    assert raw[0][1] == " Voronoi distance"  # the leading space the reader must strip
    first = raw[1]
    row = rows[0]
    assert row.world == first[0]
    assert row.targets == {"trans_mean": float(first[5]), "trans_std": float(first[6]),
                           "rot_mean": float(first[7]), "rot_std": float(first[8])}
    assert row.reference["ref_voronoi_distance"] == float(first[1])
    assert row.reference["ref_total_len"] == float(first[3])
    assert row.setting == "realistic" and row.slam_config_hash == sources.THESIS_SLAM
    assert math.isnan(row.runs)


def test_summary_table_with_runs_and_reference(tmp_path):
    path = write_csv(tmp_path / "summary.csv",
                     ["world", "runs", "trans_mean", "trans_std", "rot_mean", "rot_std",
                      "path_length_mean", "rotation_mean", "coverage_mean"],
                     [["a", 5, 0.1, 0.01, 0.02, 0.002, 100.0, 30.0, 0.9],
                      ["b", 7, 0.2, 0.02, 0.03, 0.003, 200.0, 60.0, 0.95]])
    rows = sources.read_error_table(path, "optimistic")
    assert [r.world for r in rows] == ["a", "b"]
    assert rows[1].runs == 7 and rows[1].targets["rot_std"] == 0.003
    assert rows[0].reference == {"ref_total_len": 100.0, "ref_total_rot": 30.0}
    assert rows[0].setting == "optimistic"


@pytest.mark.parametrize("header,row,message", [
    (["world", "trans_mean", "trans_std", "rot_mean", "rot_stdd"], ["a", 1, 1, 1, 1],
     "missing column 'rot_std' (did you mean 'rot_stdd'?)"),
    (["world", "trans_mean", "trans_std", "rot_mean", "rot_std"], ["a", "x", 1, 1, 1],
     ":2: column 'trans_mean' is not a number: 'x'"),
    (["world", "trans_mean", "trans_std", "rot_mean", "rot_std"], ["a", 1, 1, 1],
     ":2: 4 fields, header has 5"),
])
def test_bad_tables_name_file_and_problem(tmp_path, header, row, message):
    path = write_csv(tmp_path / "bad.csv", header, [row])
    with pytest.raises(InputError) as err:
        sources.read_error_table(path)
    assert str(path) in err.value.one_line() and message in err.value.one_line()


def test_duplicate_building_is_refused(tmp_path):
    path = write_csv(tmp_path / "dup.csv", ["world", *ds.COMPONENTS],
                     [["a", 1, 1, 1, 1], ["a", 2, 2, 2, 2]])
    with pytest.raises(InputError, match="appears twice"):
        sources.read_error_table(path)


def _rows(names):
    return [ds.ErrorRow(n, {c: float(i + 1) for c in ds.COMPONENTS}, runs=i + 3,
                        setting="realistic", slam_config_hash="h")
            for i, n in enumerate(names)]


def test_join_matches_exact_and_normalised_names_and_drops_the_rest():
    rows = _rows(["putnam_junior_high_updated", "lab_a", "no_plan"])
    features = {"putnamjuniorhigh": {"f1": 1.0, "f2": 2.0}, "lab_a": {"f1": 3.0, "f2": 4.0}}
    data = ds.join(rows, features, "v1")
    assert data.worlds == ["putnam_junior_high_updated", "lab_a"]
    np.testing.assert_array_equal(data.X, [[1, 2], [3, 4]])
    np.testing.assert_array_equal(data.target("trans_mean"), [1, 2])
    assert data.feature_version == ["v1", "v1"] and list(data.runs) == [3, 4]


def test_join_refuses_inconsistent_feature_sets():
    with pytest.raises(InputError, match="different feature set"):
        ds.join(_rows(["a", "b"]), {"a": {"f1": 1.0}, "b": {"f2": 1.0}}, "v1")


def test_csv_round_trip_keeps_everything(tmp_path):
    rows = _rows(["a", "b", "c"])
    rows[0].reference = {"ref_voronoi_distance": 12.5}
    rows[1].runs = math.nan
    data = ds.join(rows, {n: {"x": i * 0.1 + 1e-12, "y": -i} for i, n in
                          enumerate("abc")}, "v7")
    ds.write_dataset(data, tmp_path / "d.csv", {"feature_config": {"k": 1}})
    back = ds.read_dataset(tmp_path / "d.csv")
    assert back.worlds == data.worlds and back.feature_names == data.feature_names
    np.testing.assert_array_equal(back.X, data.X)
    np.testing.assert_array_equal(back.Y, data.Y)
    np.testing.assert_array_equal(back.runs, data.runs)
    assert back.setting == data.setting and back.feature_version == data.feature_version
    np.testing.assert_array_equal(back.reference["ref_voronoi_distance"],
                                  data.reference["ref_voronoi_distance"])
    assert ds.read_meta(tmp_path / "d.csv") == {"feature_config": {"k": 1}}


def test_reference_as_features_is_marked_unshippable(shared_data):
    rows = sources.read_error_table(shared_data / "thesis" / "stats_realistic.csv", "realistic")
    data = ds.join(rows, {r.world: {"dummy": 0.0} for r in rows}, "v")
    ref = ds.reference_as_features(data, ["ref_voronoi_distance"])
    assert ref.feature_names == ["voronoi_distance"]
    assert set(ref.feature_version) == {"reference-table"}
    np.testing.assert_array_equal(ref.X[:, 0], data.reference["ref_voronoi_distance"])
    with pytest.raises(InputError, match="no reference column"):
        ds.reference_as_features(data, ["ref_voronoi_distanse"])


def test_unknown_component_hint():
    with pytest.raises(InputError, match="did you mean 'rot_mean'"):
        ds.component_index("rot_maen")
