"""Checks against real data in ../shared/data (skipped when absent); slow ones marked slow.

Figures are recorded in docs/benchmarks.md (``bench/bench_features.py --real`` prints them).
"""
from __future__ import annotations

import glob
import os

import numpy as np
import pytest

from slam_predict.features.validation import (
    downsampled,
    ipa_room_scores,
    single_feature_r2,
    thesis_rows,
)
from slam_predict.features.vector import FeaturesConfig, compute_features
from slam_predict.world.generator import generate

TRAVERSAL = FeaturesConfig(families=("voronoi_traversal",))


def ipa_maps(shared_data):
    maps = sorted(p for p in glob.glob(os.path.join(shared_data, "floorplans", "ipa", "*.png"))
                  if not p.endswith("_gt_segmentation.png"))
    assert len(maps) == 13
    return maps


def test_rooms_against_ipa_ground_truth(shared_data):
    scores = [ipa_room_scores(path) for path in ipa_maps(shared_data)]
    mean = np.mean([s.mean_iou for s in scores])
    assert mean >= 0.7, [(s.name, round(s.mean_iou, 3)) for s in scores]
    assert mean >= 0.8  # measured 0.821 (docs/benchmarks.md)
    assert all(s.mean_iou > 0.5 for s in scores)
    assert np.median([abs(s.count_error) for s in scores]) <= 3  # measured 2


@pytest.mark.slow
def test_ipa_maps_give_the_same_rooms_at_010(shared_data):
    """Every ipa map segmented at 0.05 m/px and downsampled to 0.10 m/px: same room count."""
    from slam_predict.features.vector import Context
    from slam_predict.world.bitmap import load_occupancy
    from slam_predict.world.model import World

    for path in ipa_maps(shared_data):
        world = World(os.path.basename(path), load_occupancy(path), 0.05)
        fine = Context(world, FeaturesConfig()).rooms.count
        assert Context(downsampled(world, 0.1), FeaturesConfig()).rooms.count == fine, path


def _ratio_stats(rows):
    ours = np.array([r["ours"]["voronoi_traversal_distance"] for r in rows])
    theirs = np.array([r["theirs"]["Voronoi distance"] for r in rows])
    return np.corrcoef(ours, theirs)[0, 1], np.median(ours / theirs), ours, theirs


def test_traversal_against_thesis_fast(shared_data):
    rows = thesis_rows(str(shared_data), TRAVERSAL,
                       only=("Borchen4_updated", "lab_intel", "Sabadell1_updated", "office_h",
                             "scuola_secondaria_i_grado_mera__updated", "office_c"))
    assert len(rows) == 6
    _, median, ours, theirs = _ratio_stats(rows)
    assert 0.8 <= median <= 1.4
    assert np.all((ours / theirs > 0.6) & (ours / theirs < 1.8))


@pytest.mark.slow
@pytest.mark.parametrize("mode", ["documented", "thesis_compatible"])
def test_traversal_against_thesis(shared_data, mode):
    rows = thesis_rows(str(shared_data), FeaturesConfig(families=("voronoi_traversal",),
                                                        mode=mode))
    assert len(rows) == 44
    r, median, _, _ = _ratio_stats(rows)
    assert 0.8 <= median <= 1.25
    assert r >= 0.95
    faithful = [row for row in rows if row["faithful"]]
    assert len(faithful) == 41
    r_faithful, _, _, _ = _ratio_stats(faithful)
    assert r_faithful >= 0.95


@pytest.mark.slow
def test_learning_sanity_check(shared_data):
    """One-feature linear model on our traversal distance predicting the thesis' measured
    transError.mean.mean (seeded 80/20 splits) vs the same model on the thesis' own column."""
    rows = thesis_rows(str(shared_data), TRAVERSAL)
    y = np.array([r["theirs"]["transError.mean.mean"] for r in rows])
    ours = np.array([r["ours"]["voronoi_traversal_distance"] for r in rows])
    theirs = np.array([r["theirs"]["Voronoi distance"] for r in rows])
    assert np.median(single_feature_r2(ours, y)) >= 0.7  # measured 0.754, thesis column 0.834
    faithful = np.array([r["faithful"] for r in rows])
    ours_f = single_feature_r2(ours[faithful], y[faithful])
    theirs_f = single_feature_r2(theirs[faithful], y[faithful])
    assert np.median(ours_f) >= np.median(theirs_f) - 0.1


def test_generated_buildings_at_two_resolutions():
    """Each building rasterised at 0.05 and at 0.10 m/px: the same room count on at least three
    of four and ±1 on all (since rooms are segmented on the 0.2 m grid, office seed 0 splits its
    L-shaped corridor at the corner at 0.05 m/px only: 41 vs 40 rooms, the generator's truth is
    41), and the traversal within 5 % for at least three of four (the greedy tour can flip one
    decision)."""
    close = same_rooms = 0
    for seed in range(4):
        a, b = (compute_features(generate("office", 800, seed, res)) for res in (0.05, 0.1))
        assert abs(a["num_spaces"] - b["num_spaces"]) <= 1
        same_rooms += a["num_spaces"] == b["num_spaces"]
        ratio = b["voronoi_traversal_distance"] / a["voronoi_traversal_distance"]
        assert 0.85 <= ratio <= 1.15
        close += abs(ratio - 1) <= 0.05
    assert close >= 3 and same_rooms >= 3


def test_downsampled_ipa_map_gives_the_same_features(shared_data):
    from slam_predict.world.bitmap import load_occupancy
    from slam_predict.world.model import World
    from slam_predict.world.start import default_start

    path = os.path.join(shared_data, "floorplans", "ipa", "office_h.png")
    world = World("office_h", load_occupancy(path), 0.05)
    world = world.replace(start_pose=default_start(world))
    a, b = compute_features(world), compute_features(downsampled(world, 0.1))
    assert a["num_spaces"] == b["num_spaces"]
    assert b["voronoi_traversal_distance"] == pytest.approx(a["voronoi_traversal_distance"],
                                                            rel=0.05)


@pytest.mark.slow
def test_thesis_buildings_at_two_resolutions(shared_data):
    """Issue #6: every thesis building at 0.05 and 0.10 m/px gives the same room count and a
    traversal within 5 % (docs/benchmarks.md). Measured: identical vectors on all 44 — the ipa
    maps are resampled from one image, the layouts rasterised conservatively on 0.05 m samples
    with extents in whole 0.1 m cells, so both share the features' 0.1 m working grid."""
    fine = {r["env"]: r["ours"] for r in thesis_rows(str(shared_data), resolution=0.05)}
    coarse = {r["env"]: r["ours"] for r in thesis_rows(str(shared_data), resolution=0.1)}
    ratios = np.array([coarse[k]["voronoi_traversal_distance"] /
                       fine[k]["voronoi_traversal_distance"] for k in fine])
    assert len(ratios) == 44
    assert np.all(np.abs(ratios - 1) <= 0.05)
    assert all(coarse[k]["num_spaces"] == fine[k]["num_spaces"] for k in fine)


def test_layout_at_two_resolutions_gives_the_same_features(shared_data):
    """A thesis layout and a real layout XML loaded at 0.05 and 0.10 m/px: the same vector
    (the 0.10 m/px raster is the 0.1 m working grid of the 0.05 m/px one; the snapped start
    pose may differ by a few cm, hence the traversal tolerance)."""
    from slam_predict.world.layout import load_layout
    from slam_predict.world.thesis import read_environments, thesis_world

    envs = {e.env: e for e in read_environments(
        os.path.join(shared_data, "thesis", "environments.csv"))}
    env = envs["Borchen4_updated"]
    a, b = (compute_features(thesis_world(env, res)[0]) for res in (0.05, 0.1))
    assert b == pytest.approx(a, rel=1e-9)  # eigenvector features: solver round-off only
    a, b = (compute_features(load_layout(env.plan, res, start=(0.0, 0.0), snap_start=True))
            for res in (0.05, 0.1))
    assert a["num_spaces"] == b["num_spaces"]
    assert b["voronoi_traversal_distance"] == pytest.approx(a["voronoi_traversal_distance"],
                                                            rel=0.05)


def test_layout_xml_with_ground_truth_rooms(shared_data, capsys):
    import json

    from slam_predict.cli.main import main
    from slam_predict.world.load import load_plan

    path = os.path.join(shared_data, "floorplans", "layouts", "Sabadell1_updated.xml")
    assert main(["features", path, "--rooms-source", "ground_truth", "--json"]) == 0
    values = json.loads(capsys.readouterr().out)
    world = load_plan(path)
    assert values["num_spaces"] == len(world.rooms)
    assert values["topology_order"] >= len(world.rooms) - 2  # a few spaces may lack a portal
    assert main(["features", path, "--json"]) == 0
    segmented = json.loads(capsys.readouterr().out)
    assert abs(segmented["num_spaces"] - len(world.rooms)) <= 0.4 * len(world.rooms)
