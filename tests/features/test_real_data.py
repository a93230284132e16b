"""Checks against real data in ../shared/data (skipped when absent); slow ones marked slow.

Figures are recorded in docs/benchmarks.md (``bench/bench_features.py --real`` prints them).
"""
from __future__ import annotations

import glob
import os

import numpy as np
import pytest

from slam_predict.features.validation import (downsampled, ipa_room_scores, single_feature_r2,
                                              thesis_rows)
from slam_predict.features.vector import FeaturesConfig, compute_features
from slam_predict.world.generator import generate

TRAVERSAL = FeaturesConfig(families=("voronoi_traversal",))
# Guards of the measured resolution (in)dependence on the 44 thesis buildings, 0.05 vs 0.10 m/px
# (docs/benchmarks.md, 2026-12-01: 33 equal room counts, 40 within ±1, traversal within 5 % on
# 38, worst 15 %). The target (all 44 equal, all within 5 %) is NOT met; these guard the
# measured level against regressions.
ROOM_COUNT_EQUAL, ROOM_COUNT_WITHIN_1, TRAVERSAL_WITHIN_5PCT = 32, 39, 36


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
    """Issue #6 target: traversal within 5 % and the same room count on every building — NOT
    met (docs/benchmarks.md). Guarded here at the measured level: the room count is equal on
    most buildings and off by more than one on few (layouts are rasterised separately at each
    resolution, so walls and doors differ by a pixel and borderline doorway tests at corridor
    junctions flip), and the traversal (mean over 4 grid phases) is within 5 % on most
    buildings, within 20 % on all."""
    fine = {r["env"]: r["ours"] for r in thesis_rows(str(shared_data), resolution=0.05)}
    coarse = {r["env"]: r["ours"] for r in thesis_rows(str(shared_data), resolution=0.1)}
    ratios = np.array([coarse[k]["voronoi_traversal_distance"] /
                       fine[k]["voronoi_traversal_distance"] for k in fine])
    assert len(ratios) == 44
    assert np.median(np.abs(ratios - 1)) <= 0.05
    assert np.sum(np.abs(ratios - 1) <= 0.05) >= TRAVERSAL_WITHIN_5PCT
    assert np.all(np.abs(ratios - 1) <= 0.2)
    rooms = np.array([abs(coarse[k]["num_spaces"] - fine[k]["num_spaces"]) for k in fine])
    assert np.sum(rooms == 0) >= ROOM_COUNT_EQUAL and np.sum(rooms <= 1) >= ROOM_COUNT_WITHIN_1


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
