"""Checks of the features against real data (ipa room ground truth, the seed thesis' table).

* :func:`ipa_room_scores` — room segmentation against an ipa ``*_gt_segmentation.png`` (the
  map with doorways closed by drawn lines; each 4-connected white region of at least
  ``min_room_m2`` not touching the image border is one room): per ground-truth room the best
  IoU over our rooms (0 when unmatched), averaged; and the room-count error.
* :func:`thesis_rows` — our features for every thesis building with a plan, built by
  :func:`slam_predict.world.thesis.thesis_world` (the scale and start pose of the thesis'
  Stage worlds, as ``worlds import-thesis`` builds them), next to the thesis' values.
* :func:`single_feature_r2` — R² on the test part of seeded 80/20 splits of a one-feature
  linear regression.
"""
from __future__ import annotations

import csv
import os
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from scipy import ndimage

from slam_predict.features.vector import Context, FeaturesConfig, compute_with_context
from slam_predict.world.bitmap import load_occupancy, read_grey, resample_square
from slam_predict.world.model import World

IPA_RESOLUTION = 0.05
FOUR = ndimage.generate_binary_structure(2, 1)


@dataclass
class RoomScore:
    """Segmentation quality on one map: mean best-match IoU, room counts (truth, ours)."""

    name: str
    mean_iou: float
    truth_rooms: int
    our_rooms: int

    @property
    def count_error(self) -> int:
        """Our room count minus the ground truth's."""
        return self.our_rooms - self.truth_rooms


def ipa_truth_labels(gt_path: str, min_room_m2: float = 1.0):
    """(labels, room label list) of an ipa ground-truth segmentation image at 0.05 m/px."""
    free = read_grey(gt_path) >= 250
    labels, count = ndimage.label(free, structure=FOUR)
    border = set(np.unique(np.concatenate([labels[0], labels[-1], labels[:, 0],
                                           labels[:, -1]])).tolist())
    sizes = np.bincount(labels.ravel())
    min_px = min_room_m2 / IPA_RESOLUTION ** 2
    rooms = [k for k in range(1, count + 1) if k not in border and sizes[k] >= min_px]
    return labels, rooms


def best_match_iou(ours: np.ndarray, truth: np.ndarray, rooms: Sequence[int]) -> float:
    """Mean over the truth ``rooms`` of the best IoU with any of our labels (0 = none)."""
    scores = []
    for k in rooms:
        mask = truth == k
        candidates, overlaps = np.unique(ours[mask], return_counts=True)
        best = 0.0
        for label, overlap in zip(candidates, overlaps, strict=False):
            if label > 0:
                best = max(best, overlap / float((mask | (ours == label)).sum()))
        scores.append(best)
    return float(np.mean(scores)) if scores else 0.0


def ipa_room_scores(map_path: str, config: FeaturesConfig | None = None) -> RoomScore:
    """Segment an ipa map (0.05 m/px) as the feature vector does, and score it."""
    config = config or FeaturesConfig()
    occupied = load_occupancy(map_path)
    world = World(name=os.path.basename(map_path), occupied=occupied,
                  resolution=IPA_RESOLUTION)
    rooms = Context(world, config).rooms
    ours = _to_shape(rooms.labels, occupied.shape)
    ours[occupied] = 0
    gt_path = map_path[:-4] + "_gt_segmentation.png"
    truth, truth_rooms = ipa_truth_labels(gt_path)
    return RoomScore(os.path.basename(map_path), best_match_iou(ours, truth, truth_rooms),
                     len(truth_rooms), rooms.count)


def _to_shape(labels: np.ndarray, shape) -> np.ndarray:
    """Nearest-neighbour resize of a label image to ``shape`` (rows, cols)."""
    if labels.shape == tuple(shape):
        return labels.copy()
    rows = np.minimum(((np.arange(shape[0]) + 0.5) * labels.shape[0] / shape[0]).astype(int),
                      labels.shape[0] - 1)
    cols = np.minimum(((np.arange(shape[1]) + 0.5) * labels.shape[1] / shape[1]).astype(int),
                      labels.shape[1] - 1)
    return labels[np.ix_(rows, cols)]


def read_thesis_stats(path: str) -> dict[str, dict[str, float]]:
    """stats_realistic.csv as {building: {column: value}} (column names stripped)."""
    with open(path, newline="", encoding="utf-8") as handle:
        rows = list(csv.DictReader(handle))
    return {r["dataset"]: {k.strip(): float(v) for k, v in r.items() if k != "dataset"}
            for r in rows}


def thesis_rows(data_dir: str, config: FeaturesConfig | None = None,
                resolution: float = 0.05, only: Sequence[str] | None = None) -> list[dict]:
    """Our features next to the thesis' for every thesis building with a plan in ``data_dir``."""
    from slam_predict.world.thesis import read_environments, thesis_world

    config = config or FeaturesConfig()
    stats = read_thesis_stats(os.path.join(data_dir, "thesis", "stats_realistic.csv"))
    rows = []
    for env in read_environments(os.path.join(data_dir, "thesis", "environments.csv")):
        if only is not None and env.env not in only:
            continue
        world, info = thesis_world(env, resolution)
        values, _ = compute_with_context(world, config)
        rows.append({"env": env.env, "source": env.source, "faithful": info["faithful"] == "yes",
                     "ours": values, "theirs": stats[env.env]})
    return rows


def single_feature_r2(x: np.ndarray, y: np.ndarray, seeds: Sequence[int] = range(20),
                      test_size: float = 0.2) -> np.ndarray:
    """Test-set R² of ``y ~ a·x + b`` over seeded random 80/20 splits (one value per seed)."""
    from sklearn.linear_model import LinearRegression
    from sklearn.metrics import r2_score
    from sklearn.model_selection import train_test_split

    x = np.asarray(x, float).reshape(-1, 1)
    scores = []
    for seed in seeds:
        x_tr, x_te, y_tr, y_te = train_test_split(x, y, test_size=test_size, random_state=seed)
        model = LinearRegression().fit(x_tr, y_tr)
        scores.append(r2_score(y_te, model.predict(x_te)))
    return np.array(scores)


def downsampled(world: World, resolution: float) -> World:
    """The same plan on a coarser grid (obstacle where any source pixel is)."""
    return world.replace(occupied=resample_square(world.occupied, world.size_m, resolution),
                         resolution=resolution)
