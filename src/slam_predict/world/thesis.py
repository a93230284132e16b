"""The seed thesis' buildings as Worlds at the thesis' scale (``worlds import-thesis``).

Input: ``thesis/environments.csv`` (env, source, file, world_size_x_m, world_size_y_m,
floorplan_pose, robot_pose, world_bitmap); plan files are looked up relative to
``<csv folder>/../floorplans``. Rows with source ``none`` have no plan and are skipped.

Scale (the thesis' Stage ``floorplan size [W H]`` stretches the bitmap to W x H m):
- ``ipa`` images: the occupancy by the threshold rule of :mod:`slam_predict.world.bitmap`,
  stretched to W x H and resampled to square cells of ``resolution`` m with the *conservative*
  rule (a cell is an obstacle when any source pixel it overlaps is one), so 1-px walls survive
  down-sampling. office_b and office_d are stretched unevenly by the thesis' world files (Stage
  stretches the bitmap to W x H); they are reproduced as Stage simulated them and marked not
  faithful. (The seed's feature code measured its Voronoi distance on the *bitmap* and divided
  by the x scale only, ``scale = width / worldWidth``, i.e. on the isotropic image at the x
  scale: for these two its ``Voronoi distance`` is not that of the stretched world.)
  office_c: the table's 102.85 x 32.5 m world file is not the one the thesis ran: its explored
  path (``totalLen`` 3283 m) is 3.2 m per m² of that world's free space (1027 m²) where the other
  43 buildings lie between 0.20 and 0.77, and its ``Voronoi distance`` (1378 m) is 0.6 times what
  the traversal gives there; at 0.1 m/px, the scale of the other large ipa buildings (office_a,
  lab_a, lab_intel, NLB), the world is 168.3 x 96.5 m with 5100 m² free (0.64 m/m²) and the
  traversal's ratio to the table is that of the other buildings. The seed repository itself
  holds that world: ``nav2dfiles/office_c.world`` (AIRLab-POLIMI/predictivebenchmarking,
  commit a4e26239) has ``size [168.3 96.5 1.0]`` for the same ``office_c.png``, while the
  102.85 x 32.5 m file of the table is a later ``runs/datasets`` copy. It is imported at
  0.1 m/px (:data:`SCALE_OVERRIDES`) with the table's start pose in metres. freiburg79 used a
  crop of unknown offsets: the image's free-space bounding box is scaled isotropically to fit
  the W x H world (1 m margin) and centred — not faithful.
- ``layouts``: rasterised (:mod:`slam_predict.world.layout`) through the frame that maps the XML
  point extent exactly onto W x H (as the thesis bitmap spanned exactly that extent), with the
  drawing's y axis (down in the drawing) as world y (up): the thesis' bitmaps are vertical
  mirror images of the drawings. Evidence: the thesis start poses of RomainRolland1 (-3, -17)
  and Vipiteno2 (0, 4) lie 19 m and 7 m outside the building in the unmirrored frame and inside
  a room in the mirrored one; no other start pose tells the two frames apart. A mirror image
  has the same geometry for SLAM; ``load_layout`` (real buildings) does not mirror.
  Resolution: the grid spans W x H rounded to whole 0.1 m cells
  (:func:`layout_raster.nested_cells`) and the layout is rasterised on samples
  :data:`layout.DEFAULT_SAMPLE` (0.05 m) apart, a cell being an obstacle when any of its samples is
  (:func:`layout_raster.rasterise_sampled`): the 0.05 m/px world is the pixel-centre raster,
  the 0.10 m/px world its 2 x 2 "any" reduction — exactly the features' 0.1 m working grid of
  the 0.05 m/px world, so both give the same feature vector (issue #6).

Start pose: ``robot_pose`` x y (m) and yaw (deg), Stage frame; a pose in (or too close to) a
wall, or outside the largest free component (the building proper), is snapped to the nearest
cell of that component with room for the robot
(:func:`slam_predict.world.start.resolve_start`), and the move is recorded.
"""
from __future__ import annotations

import csv
import logging
import os
from dataclasses import dataclass

import numpy as np

from slam_predict.errors import InputError, require_file
from slam_predict.world import bitmap
from slam_predict.world.layout import DEFAULT_SAMPLE
from slam_predict.world.model import World

LOG = logging.getLogger(__name__)
COLUMNS = ("env", "source", "file", "world_size_x_m", "world_size_y_m", "robot_pose")
ANISOTROPIC = {"office_b", "office_d"}
# m/px of the image that the thesis really simulated when its world file says otherwise
# (module docstring): the world is image size x this, isotropic.
SCALE_OVERRIDES = {"office_c": 0.1}
CROPPED = {"freiburg79"}
FIT_MARGIN = 1.0  # m around a fitted crop


@dataclass
class ThesisEnv:
    """One thesis building: name, plan source/path, world size (m), start (m, m, deg)."""

    env: str
    source: str
    plan: str
    size_m: tuple[float, float]
    start: tuple[float, float, float]


def _number(text: str, what: str, path: str, line: int) -> float:
    try:
        value = float(text)
    except ValueError:
        raise InputError(f"{what} '{text}' is not a number", path, line) from None
    if not np.isfinite(value):
        raise InputError(f"{what} '{text}' is not finite", path, line)
    return value


def read_environments(path: os.PathLike | str, plans_dir: str | None = None
                      ) -> list[ThesisEnv]:
    """The rows of environments.csv that have a plan; InputError for a malformed file."""
    path = require_file(path, "environments CSV")
    plans_dir = plans_dir or os.path.join(os.path.dirname(os.path.abspath(path)), os.pardir,
                                          "floorplans")
    try:
        with open(path, newline="", encoding="utf-8") as handle:
            rows = list(csv.DictReader(handle))
    except (OSError, UnicodeDecodeError, csv.Error) as exc:
        raise InputError(f"cannot read CSV ({exc})", path) from None
    missing = [c for c in COLUMNS if not rows or c not in rows[0]]
    if missing:
        raise InputError(f"not a thesis environments table: missing column(s) "
                         f"{', '.join(missing)}", path)
    envs = []
    for line, row in enumerate(rows, start=2):
        if row["source"] not in ("ipa", "layouts"):
            continue
        width = _number(row["world_size_x_m"], "world_size_x_m", path, line)
        height = _number(row["world_size_y_m"], "world_size_y_m", path, line)
        if width <= 0 or height <= 0:
            raise InputError(f"world size must be > 0 (got {width:g} x {height:g})", path, line)
        pose = (row["robot_pose"] or "0 0 0 0").split()
        if len(pose) != 4:
            raise InputError(f"robot_pose '{row['robot_pose']}' is not 'x y z yaw'", path, line)
        x, y, _, yaw = (_number(v, "robot_pose", path, line) for v in pose)
        envs.append(ThesisEnv(row["env"], row["source"], os.path.join(plans_dir, row["file"]),
                              (width, height), (x, y, yaw)))
    return envs


def resample_conservative(occupied: np.ndarray, size_m: tuple[float, float],
                          resolution: float) -> np.ndarray:
    """Resample a bitmap stretched to ``size_m`` (W, H m) onto square ``resolution`` cells;
    a cell is occupied when any source pixel overlapping it (by > 1 % of a pixel) is."""
    rows, cols = occupied.shape
    new_cols = max(1, int(round(size_m[0] / resolution)))
    new_rows = max(1, int(round(size_m[1] / resolution)))
    integral = np.zeros((rows + 1, cols + 1), dtype=np.int64)
    integral[1:, 1:] = occupied.astype(np.int64).cumsum(0).cumsum(1)

    def spans(n_new: int, n_old: int):
        edges = np.arange(n_new + 1) * (n_old / n_new)
        lo = np.floor(edges[:-1] + 0.01).astype(int)
        hi = np.ceil(edges[1:] - 0.01).astype(int)
        return np.clip(lo, 0, n_old - 1), np.clip(np.maximum(hi, lo + 1), 1, n_old)

    r0, r1 = spans(new_rows, rows)
    c0, c1 = spans(new_cols, cols)
    total = (integral[np.ix_(r1, c1)] - integral[np.ix_(r0, c1)] - integral[np.ix_(r1, c0)]
             + integral[np.ix_(r0, c0)])
    return total > 0


def _largest_component(free: np.ndarray) -> np.ndarray:
    from slam_predict.world.raster import label_free

    labels, count = label_free(free)
    if count <= 1:
        return free
    sizes = np.bincount(labels.ravel())
    sizes[0] = 0
    return labels == int(np.argmax(sizes))


def _fit_crop(occupied: np.ndarray, size_m: tuple[float, float]) -> tuple[np.ndarray, float]:
    """The image cropped/padded around the bounding box of its largest free component (the
    building, without scan fragments outside it) to the aspect of ``size_m``, and the isotropic
    m/px that fits that box into the world with FIT_MARGIN m around it."""
    rr, cc = np.nonzero(_largest_component(~occupied))
    box_h, box_w = rr.max() - rr.min() + 1, cc.max() - cc.min() + 1
    scale = min((size_m[0] - 2 * FIT_MARGIN) / box_w, (size_m[1] - 2 * FIT_MARGIN) / box_h)
    out_w, out_h = int(round(size_m[0] / scale)), int(round(size_m[1] / scale))
    canvas = np.ones((out_h, out_w), dtype=bool)
    top = (out_h - box_h) // 2
    left = (out_w - box_w) // 2
    canvas[top:top + box_h, left:left + box_w] = occupied[rr.min():rr.max() + 1,
                                                          cc.min():cc.max() + 1]
    return canvas, float(scale)


def _ipa_world(env: ThesisEnv, resolution: float) -> tuple[World, str]:
    occupied = bitmap.load_occupancy(require_file(env.plan, "plan image"))
    note = ""
    size_m = env.size_m
    if env.env in CROPPED:
        occupied, scale = _fit_crop(occupied, env.size_m)
        note = (f"crop offsets unknown: free-space bounding box fitted into the world at "
                f"{scale:.4f} m/px (thesis: about 0.1 m/px)")
    elif env.env in SCALE_OVERRIDES:
        rows, cols = occupied.shape
        scale = SCALE_OVERRIDES[env.env]
        size_m = (cols * scale, rows * scale)
        note = (f"world {size_m[0]:.2f} x {size_m[1]:.2f} m ({scale:g} m/px) instead of the "
                f"table's {env.size_m[0]:g} x {env.size_m[1]:g} m: the thesis' path length and "
                f"Voronoi distance match this scale")
    elif env.env in ANISOTROPIC:
        rows, cols = occupied.shape
        note = (f"anisotropic stretch {env.size_m[0] / cols:.4f} x {env.size_m[1] / rows:.4f} "
                f"m/px (building distorted as in the thesis)")
    grid = resample_conservative(occupied, size_m, resolution)
    free = bitmap.remove_outside(~grid, env.plan)
    world = World(name=env.env, occupied=~free, resolution=resolution,
                  provenance={"source": os.path.abspath(env.plan), "format": "thesis-ipa"})
    return world, note


def _layout_world(env: ThesisEnv, resolution: float, wall: float, door: float,
                  sample_m: float | None) -> World:
    from slam_predict.world.layout import layout_world, parse_layout, stretched_frame
    from slam_predict.world.layout_raster import nested_cells
    from slam_predict.world.raster import Grid

    layout = parse_layout(env.plan)
    frame = stretched_frame(layout, env.size_m, mirror=True)
    grid = Grid(nested_cells(env.size_m[1], resolution), nested_cells(env.size_m[0], resolution),
                resolution)
    world = layout_world(layout, frame, grid, wall, door, env.env, sample_m)
    world.provenance.update(format="thesis-layout", mirrored=True)
    return world


def thesis_world(env: ThesisEnv, resolution: float = 0.05, wall_thickness: float = 0.15,
                 door_width: float = 0.9, layout_sample_m: float | None = DEFAULT_SAMPLE
                 ) -> tuple[World, dict]:
    """(World with its start pose, index row) of one thesis building; layouts are rasterised
    conservatively on ``layout_sample_m`` m samples (None: pixel-centre rule at ``resolution``)."""
    from slam_predict.world.start import resolve_start

    note = ""
    if env.source == "ipa":
        world, note = _ipa_world(env, resolution)
    else:
        world = _layout_world(env, resolution, wall_thickness, door_width, layout_sample_m)
    world.provenance.update(start_given=True, thesis_size_m=list(env.size_m), import_note=note,
                            thesis_robot_pose=list(env.start))
    # snap into the building proper (the largest free component), not a scan fragment
    probe = world.replace(occupied=~_largest_component(~world.occupied))
    world = world.replace(start_pose=resolve_start(probe, env.start, snap=True).start_pose)
    moved = float(np.hypot(world.start_pose[0] - env.start[0], world.start_pose[1] - env.start[1]))
    faithful = env.env not in ANISOTROPIC | CROPPED
    size = world.size_m if env.env in SCALE_OVERRIDES else env.size_m
    row = {"env": env.env, "source": env.source, "world_file": f"{env.env}.world",
           "faithful": "yes" if faithful else "no", "reason": note,
           "free_area_m2": round(world.free_area_m2, 2),
           "world_size_x_m": round(float(size[0]), 3),
           "world_size_y_m": round(float(size[1]), 3),
           "start_x": round(float(world.start_pose[0]), 3),
           "start_y": round(float(world.start_pose[1]), 3),
           "start_yaw_deg": env.start[2], "start_snapped": "yes" if moved > 1e-9 else "no",
           "snap_distance_m": round(moved, 3)}
    return world, row
