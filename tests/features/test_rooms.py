"""Room segmentation and ground-truth rooms on plans with known answers."""
from __future__ import annotations

import numpy as np
import pytest

from slam_predict.features.rooms import (
    RoomsConfig,
    ground_truth_rooms,
    merge_small,
    rooms_of,
    segment,
)
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
    for room, mask in zip(world.rooms, _truth_masks(world), strict=False):
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


def test_room_behind_a_door_narrower_than_the_segmentation_grid_is_kept():
    """A 0.3 m door closes on the 0.2 m segmentation grid; the room behind it stays a room."""
    world = corridor_with_rooms(3, door=0.3).world()
    rooms = segment(world.occupied, world.resolution)
    assert rooms.count == 4
    for room, mask in zip(world.rooms, _truth_masks(world), strict=False):
        assert _best_iou(rooms.labels, mask) > 0.9, room.id
    tiny = corridor_with_rooms(1, door=0.3, room=0.8).world()  # 0.64 m² closet: merged
    assert segment(tiny.occupied, tiny.resolution).count == 1


def test_segmentation_grid_gives_the_map_grid_answer_on_a_plain_plan():
    """Segmenting on the 0.2 m grid and on the map's own 0.05 m grid: same rooms."""
    world = corridor_with_rooms(4).world()
    coarse = segment(world.occupied, world.resolution)
    fine = segment(world.occupied, world.resolution, RoomsConfig(segmentation_resolution_m=0))
    assert coarse.count == fine.count == 5
    assert coarse.labels.shape == world.occupied.shape
    assert ((coarse.labels > 0) == (fine.labels > 0)).all()  # every interior pixel labelled
    for k in range(1, fine.count + 1):
        assert _best_iou(coarse.labels, fine.labels == k) > 0.95


def _upsample_reference(coarse, interior):
    """Slow reference of upsample_labels (no lost regions): the coarse cell under every pixel,
    then breadth-first 4-connected growth through unlabelled interior pixels."""
    from collections import deque

    rows, cols = interior.shape
    out = np.zeros(interior.shape, np.int32)
    for r in range(rows):
        for c in range(cols):
            if interior[r, c]:
                out[r, c] = coarse[r * coarse.shape[0] // rows, c * coarse.shape[1] // cols]
    frontier = deque((r, c) for r in range(rows) for c in range(cols) if out[r, c])
    while frontier:  # grow level by level; a pixel reached by several takes the largest label
        level = {}
        for _ in range(len(frontier)):
            r, c = frontier.popleft()
            for dr, dc in ((1, 0), (-1, 0), (0, 1), (0, -1)):
                q = (r + dr, c + dc)
                if 0 <= q[0] < rows and 0 <= q[1] < cols and interior[q] and not out[q]:
                    level[q] = max(level.get(q, 0), out[r, c])
        for q, k in level.items():
            out[q] = k
            frontier.append(q)
    return out


def test_upsample_labels_matches_reference():
    from slam_predict.features.rooms import upsample_labels

    rng = np.random.default_rng(3)
    for _ in range(20):
        coarse = rng.integers(0, 4, (6, 7)).astype(np.int32)
        interior = rng.random((12, 14)) < 0.8
        interior[np.kron(coarse, np.ones((2, 2), np.int32)) > 0] = True
        got = upsample_labels(coarse, interior, min_px=1e9)
        want = _upsample_reference(coarse, interior)
        reached = want > 0
        np.testing.assert_array_equal(got[reached], want[reached])
        assert (got[interior] > 0).all() and (got[~interior] == 0).all()


def test_segmentation_resolution_validation():
    with pytest.raises(ValueError, match="segmentation_resolution_m"):
        RoomsConfig(segmentation_resolution_m=-1)
