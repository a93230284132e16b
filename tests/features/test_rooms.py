"""Room segmentation and ground-truth rooms on plans with known answers."""
from __future__ import annotations

import numpy as np
import pytest

from slam_predict.features.rooms import (RoomsConfig, ground_truth_rooms, merge_small,
                                         rooms_of, segment)
from slam_predict.world.model import World

from .plans import corridor_with_rooms, four_rooms_cycle, ring_corridor, single_room


def _best_iou(labels: np.ndarray, mask: np.ndarray) -> float:
    best = 0.0
    for k in np.unique(labels[mask]):
        if k == 0:
            continue
        other = labels == k
        best = max(best, (mask & other).sum() / (mask | other).sum())
    return best


def _truth_masks(world: World):
    truth = ground_truth_rooms(world)
    return [mask_full(truth.labels, k) for k in range(1, truth.count + 1)]


def mask_full(labels, k):
    return labels == k


@pytest.mark.parametrize("k", [1, 3, 6])
def test_corridor_with_k_rooms(k):
    world = corridor_with_rooms(k).world()
    rooms = segment(world.occupied, world.resolution)
    assert rooms.count == k + 1
    areas = rooms.areas_m2()
    for room, mask in zip(world.rooms, _truth_masks(world)):
        assert _best_iou(rooms.labels, mask) > 0.9
        if room.id != "corridor":  # 4 m × 4 m rooms
            label = np.bincount(rooms.labels[mask]).argmax()
            assert areas[label - 1] == pytest.approx(16.0, rel=0.05)


def test_four_rooms_and_single_room_and_ring():
    assert segment(four_rooms_cycle().world().occupied, 0.05).count == 4
    single = segment(single_room(10, 6).world().occupied, 0.05)
    assert single.count == 1 and single.areas_m2()[0] == pytest.approx(60.0, rel=0.01)
    assert segment(ring_corridor().world().occupied, 0.05).count == 1


def test_resolution_does_not_change_room_count():
    counts = [segment(corridor_with_rooms(4, res=r).world().occupied, r).count
              for r in (0.05, 0.1)]
    assert counts == [5, 5]


def test_wide_opening_is_not_a_door_when_door_width_is_small():
    world = corridor_with_rooms(3, door=1.6).world()
    assert segment(world.occupied, world.resolution, RoomsConfig(max_door_width_m=1.2)).count == 1
    assert segment(world.occupied, world.resolution).count == 4


def test_ground_truth_source():
    world = four_rooms_cycle().world()
    rooms = rooms_of(world, RoomsConfig(source="ground_truth"))
    assert rooms.count == 4
    free = ~world.occupied
    assert ((rooms.labels > 0) == free).all()  # door pixels join a neighbouring room
    np.testing.assert_allclose(np.sort(rooms.areas_m2()), 25.0, rtol=0.03)


def test_ground_truth_falls_back_to_segmentation(caplog):
    world = corridor_with_rooms(2).world().replace(rooms=[])
    assert rooms_of(world, RoomsConfig(source="ground_truth")).count == 3
    assert "no ground-truth rooms" in caplog.text


def test_merge_small_regions():
    labels = np.zeros((10, 10), np.int32)
    labels[:, :6] = 1
    labels[:, 6:9] = 2
    labels[0, 9] = 3  # touches 2 only
    labels[9, 9] = 0
    out = merge_small(labels, min_px=25)
    assert set(np.unique(out)) == {0, 1, 2} and out[0, 9] == 2  # 3 joins its only neighbour
    assert set(np.unique(merge_small(labels, min_px=40))) == {0, 1}  # 2 (31 px) joins 1
    lonely = np.zeros((5, 5), np.int32)
    lonely[2, 2] = 1
    assert merge_small(lonely, 4).max() == 0


def test_config_validation():
    with pytest.raises(ValueError, match="source"):
        RoomsConfig(source="magic")
