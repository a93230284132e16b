"""Thesis buildings as worlds: CSV reading, conservative resampling, scale, start pose, CLI."""
from __future__ import annotations

import csv

import numpy as np
import pytest

from slam_predict.cli.main import main
from slam_predict.errors import InputError
from slam_predict.world import raster
from slam_predict.world.thesis import read_environments, resample_conservative, thesis_world


@pytest.fixture(scope="module")
def envs(shared_data):
    return {e.env: e for e in read_environments(shared_data / "thesis" / "environments.csv")}


def reference_resample(occupied, size_m, resolution):
    """Slow reference: a target cell is occupied iff a source pixel it overlaps (> 1 %) is."""
    rows, cols = occupied.shape
    new_cols, new_rows = int(round(size_m[0] / resolution)), int(round(size_m[1] / resolution))
    out = np.zeros((new_rows, new_cols), bool)
    sx, sy = cols / new_cols, rows / new_rows
    for r in range(new_rows):
        for c in range(new_cols):
            for i in range(rows):
                for j in range(cols):
                    ov_y = min((r + 1) * sy, i + 1) - max(r * sy, i)
                    ov_x = min((c + 1) * sx, j + 1) - max(c * sx, j)
                    if ov_y > 0.01 and ov_x > 0.01 and occupied[i, j]:
                        out[r, c] = True
    return out


@pytest.mark.parametrize("seed", range(6))
def test_resample_conservative_matches_reference(seed):
    rng = np.random.default_rng(seed)
    occupied = rng.random((int(rng.integers(5, 12)), int(rng.integers(5, 12)))) < 0.15
    size = (float(rng.uniform(0.3, 1.2)), float(rng.uniform(0.3, 1.2)))
    got = resample_conservative(occupied, size, 0.1)
    assert np.array_equal(got, reference_resample(occupied, size, 0.1))


def test_resample_keeps_one_pixel_walls():
    occupied = np.zeros((100, 100), bool)
    occupied[50, :] = True  # a 1-px wall, shrunk to 0.7 of its size in y
    out = resample_conservative(occupied, (5.0, 3.5), 0.05)
    assert out.shape == (70, 100) and out.any(axis=0).all()


def test_read_environments(envs):
    assert len(envs) == 44
    assert sum(e.source == "ipa" for e in envs.values()) == 9
    lab = envs["lab_a"]
    assert lab.size_m == (82.4, 70.8) and lab.start == (-40.0, 29.0, 0.0)


@pytest.mark.parametrize("text, problem", [
    ("env,source\nx,ipa\n", "missing column"),
    ("env,source,file,world_size_x_m,world_size_y_m,robot_pose\nx,ipa,a.png,abc,3,0 0 0 0\n",
     "is not a number"),
    ("env,source,file,world_size_x_m,world_size_y_m,robot_pose\nx,ipa,a.png,-1,3,0 0 0 0\n",
     "must be > 0"),
    ("env,source,file,world_size_x_m,world_size_y_m,robot_pose\nx,ipa,a.png,2,3,0 0\n",
     "not 'x y z yaw'"),
])
def test_bad_environments_csv(tmp_path, text, problem):
    path = tmp_path / "env.csv"
    path.write_text(text)
    with pytest.raises(InputError, match=problem):
        read_environments(path)


def test_layout_building_at_thesis_scale(envs):
    env = envs["Borchen4_updated"]
    world, row = thesis_world(env)
    assert world.size_m == pytest.approx(env.size_m, abs=0.05)
    assert raster.label_free(~world.occupied)[1] == 1
    assert row["faithful"] == "yes" and row["start_snapped"] == "no"
    assert world.is_free_at(world.start_pose[:2])
    assert world.rooms and world.doors and world.provenance["mirrored"]


def test_mirrored_frame_puts_thesis_start_inside(envs):
    """RomainRolland1's thesis start (-3, -17) is inside the building only in the mirrored
    frame (the evidence for the mirror rule)."""
    world, row = thesis_world(envs["RomainRolland1_updated"])
    assert row["start_snapped"] == "no" and world.is_free_at([-3.0, -17.0])


def test_freiburg79_fitted_crop_not_faithful(envs):
    world, row = thesis_world(envs["freiburg79"])
    assert row["faithful"] == "no" and "crop" in row["reason"]
    assert world.size_m == pytest.approx((63.0, 25.0), abs=0.05)
    assert row["start_snapped"] == "no"  # (-28, 1) lands in the corridor's end
    assert 900 < row["free_area_m2"] < 1500


def test_anisotropic_office_b(envs):
    world, row = thesis_world(envs["office_b"])
    assert row["faithful"] == "no" and "anisotropic" in row["reason"]
    assert world.size_m == pytest.approx((60.0, 24.5), abs=0.05)
    labels, _ = raster.label_free(~world.occupied)
    rc = world.world_to_cell(world.start_pose[:2])
    assert labels[rc[0], rc[1]] > 0


def test_office_c_at_the_scale_the_thesis_ran(envs, shared_data):
    """office_c: the table's 102.85 x 32.5 m world cannot be the one the thesis explored (its
    path length per m² of free space would be 3.2, the other 43 buildings 0.20-0.77); the
    image at 0.1 m/px can (module docstring)."""
    world, row = thesis_world(envs["office_c"], resolution=0.1)
    assert world.size_m == pytest.approx((168.3, 96.5), abs=0.05)
    assert (row["world_size_x_m"], row["world_size_y_m"]) == pytest.approx((168.3, 96.5))
    assert row["faithful"] == "yes" and "0.1 m/px" in row["reason"]
    assert row["start_snapped"] == "no" and world.is_free_at([45.0, 0.0])
    stats = {r["dataset"]: float(r[" totalLen"]) for r in
             csv.DictReader(open(shared_data / "thesis" / "stats_realistic.csv", newline=""))}
    assert 0.2 <= stats["office_c"] / row["free_area_m2"] <= 0.8


def test_cli_import_thesis_subset(shared_data, tmp_path, capsys):
    out = tmp_path / "thesis"
    csv_path = shared_data / "thesis" / "environments.csv"
    assert main(["worlds", "import-thesis", str(csv_path), "--out", str(out), "--only",
                 "Borchen4_updated", "Lamuniere1_updated"]) == 0
    names = {p.name for p in out.iterdir()}
    assert {"Borchen4_updated.world", "Borchen4_updated.png", "Borchen4_updated.json",
            "Lamuniere1_updated.world", "thesis_worlds.csv"} <= names
    with open(out / "thesis_worlds.csv", newline="") as handle:
        rows = list(csv.DictReader(handle))
    assert [r["env"] for r in rows] == ["Borchen4_updated", "Lamuniere1_updated"]
    assert float(rows[0]["free_area_m2"]) > 250
    from slam_predict.world.load import load_plan
    world = load_plan(out / "Borchen4_updated.world")
    assert world.size_m == pytest.approx((20.61, 17.62), abs=0.05)


def test_cli_import_thesis_bad_input(shared_data, tmp_path, capsys):
    csv_path = shared_data / "thesis" / "environments.csv"
    assert main(["worlds", "import-thesis", str(csv_path), "--out", str(tmp_path / "o"),
                 "--only", "Borchen4"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "did you mean 'Borchen4_updated'" in err
    assert main(["worlds", "import-thesis", str(tmp_path / "missing.csv"), "--out",
                 str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err.strip()
    assert "not found" in err and "missing.csv" in err
    assert main(["worlds", "import-thesis", str(csv_path), "--out", str(tmp_path / "o"),
                 "--plans", str(tmp_path)]) == 2
    assert "plan file(s) not found" in capsys.readouterr().err
    assert not (tmp_path / "o").exists()


@pytest.mark.slow
def test_all_thesis_buildings(shared_data, tmp_path, capsys):
    out = tmp_path / "thesis"
    assert main(["worlds", "import-thesis", str(shared_data / "thesis" / "environments.csv"),
                 "--out", str(out)]) == 0
    with open(out / "thesis_worlds.csv", newline="") as handle:
        rows = list(csv.DictReader(handle))
    assert len(rows) == 44
    unfaithful = {r["env"] for r in rows if r["faithful"] == "no"}
    assert unfaithful == {"freiburg79", "office_b", "office_d"}
    assert all(float(r["free_area_m2"]) > 100 for r in rows)
