"""Small test worlds built from numpy arrays, and random poses in them (seeded)."""
from __future__ import annotations

import numpy as np

from slam_predict.world.model import World


def box_world(width_m: float = 20.0, height_m: float = 20.0, res: float = 0.05,
              start=(0.0, 0.0, 0.0), wall_px: int = 2, **kwargs) -> World:
    """An empty rectangular room (walls ``wall_px`` thick) centred on the origin."""
    rows, cols = int(round(height_m / res)), int(round(width_m / res))
    occ = np.zeros((rows, cols), dtype=bool)
    occ[:wall_px, :] = occ[-wall_px:, :] = True
    occ[:, :wall_px] = occ[:, -wall_px:] = True
    return World("box", occ, res, start_pose=np.asarray(start, float), **kwargs)


def _line(occ: np.ndarray, r0: int, c0: int, r1: int, c1: int, thick: int = 1) -> None:
    """Rasterise a (possibly diagonal) line of cells, ``thick`` cells wide."""
    n = max(abs(r1 - r0), abs(c1 - c0)) + 1
    rr = np.rint(np.linspace(r0, r1, n)).astype(int)
    cc = np.rint(np.linspace(c0, c1, n)).astype(int)
    for dr in range(thick):
        for dc in range(thick):
            occ[np.clip(rr + dr, 0, occ.shape[0] - 1), np.clip(cc + dc, 0, occ.shape[1] - 1)] = True


def office_world(seed: int = 0, res: float = 0.05, size_px=(240, 320), thin: bool = False,
                 **kwargs) -> World:
    """Rooms with doors, pillars and diagonal walls; ``thin`` walls are one cell wide
    (including 1-cell diagonal walls whose cells touch only at corners)."""
    rng = np.random.default_rng(seed)
    rows, cols = size_px
    occ = np.zeros((rows, cols), dtype=bool)
    t = 1 if thin else 3
    occ[:t, :] = occ[-t:, :] = True
    occ[:, :t] = occ[:, -t:] = True
    door_w = max(rows // 12, 4)
    for c in (cols // 3, 2 * cols // 3):  # vertical walls with a door
        occ[:, c:c + t] = True
        door = rng.integers(t + 2, rows - t - door_w - 2)
        occ[door:door + door_w, c:c + t] = False
    r = rows // 2
    occ[r:r + t, : cols // 3] = True
    occ[r:r + t, cols // 12:cols // 12 + door_w] = False
    margin = max(rows // 24, 3)
    for _ in range(6):  # pillars
        pr, pc = rng.integers(margin, rows - margin - 5), rng.integers(margin, cols - margin - 5)
        occ[pr:pr + rng.integers(1, 6), pc:pc + rng.integers(1, 6)] = True
    for _ in range(3):  # diagonal walls
        r0, c0 = rng.integers(margin, rows - margin), rng.integers(margin, cols - margin)
        length = rng.integers(rows // 16 + 1, rows // 5 + 2)
        sign = rng.choice([-1, 1])
        _line(occ, r0, c0, np.clip(r0 + sign * length, 0, rows - 1),
              np.clip(c0 + length // 2 * rng.choice([1, 2]), 0, cols - 1), thick=1 if thin else 2)
    return World(f"office{seed}{'_thin' if thin else ''}", occ, res,
                 origin=(rng.uniform(-3, 3), rng.uniform(-3, 3)), **kwargs)


def random_free_poses(world: World, n: int, rng: np.random.Generator) -> np.ndarray:
    """(n, 3) poses uniformly on free cells (random point inside the cell, random yaw)."""
    rows, cols = np.nonzero(~world.occupied)
    pick = rng.integers(0, rows.size, n)
    centres = world.cell_to_world(np.stack([rows[pick], cols[pick]], axis=1))
    jitter = rng.uniform(-0.5, 0.5, (n, 2)) * world.resolution * 0.999
    yaw = rng.uniform(-np.pi, np.pi, n)
    return np.column_stack([centres + jitter, yaw])


__all__ = ["box_world", "office_world", "random_free_poses"]
