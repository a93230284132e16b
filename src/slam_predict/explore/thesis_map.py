"""The aau ``explorer``'s own costmap and its per-cell tests (the thesis explorer).

The aau explorer searches frontiers on its own global costmap (costmap_2d cost values, 0.1 m
cells, inflation radius 2.25 m, cost_scaling_factor 7.5: the package's
pioneer3at_*costmap*.yaml; the thesis' 0.4 m footprint, which one stored version of the
package has, gives an inscribed radius of 0.2 m). :func:`explorer_costmap` builds that costmap
from the SLAM map: cells are coarsened to ``resolution`` (a coarse cell is lethal if any of its
cells is occupied, else free if any is free, else unknown), lethal cells are inflated as
costmap_2d's inflation layer does (cost 253 within the inscribed radius,
252·exp(−k·(d − r_inscribed)) truncated to an integer out to the inflation radius; unknown
cells stay 255 except within the inscribed radius).

Per-cell rules (``ExplorationPlanner``):

* :func:`frontier_cells` (``isFrontier``): a cell of cost exactly 0 (FREE_SPACE) with at least
  one unknown (255) and no lethal (254) cell among its 16 neighbours (the 8 adjacent cells and
  the 8 cells two steps away along the same 8 directions). With the thesis' inflation a cost-0
  cell is > 0.94 m from every obstacle (r_inscribed + ln(252)/7.5).
* :func:`seen_mask` (``clearSeenFrontiers``): a stored frontier point is "seen" when the cells
  1..6 steps from it along the 4 axes hold no unknown cell, or a lethal one, or no cost-0 one
  (cells beyond the costmap count as lethal).
* :func:`backoff_goal` (``smartGoalBackoff``): the first cell, in the order +x, −x, +y, −y at
  1, 2, ... 40 steps, of cost ≤ 50 or unknown whose own cells 1..5 steps along the axes are
  all ≤ 50 or unknown; its centre is the goal sent to move_base (None when there is none).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy import ndimage

from slam_predict.explore.frontiers import known_box

FREE_SPACE, INSCRIBED, LETHAL, NO_INFORMATION = 0, 253, 254, 255
MARGIN_M = 4.5   # m of unknown kept around the known area (the package's costmap is 150 m wide)
# isFrontier's 16 neighbours (row, col): 8 adjacent cells, then the same 8 directions x 2
NEIGHBOURS_16 = [(0, -1), (-1, 0), (0, 1), (1, 0), (-1, -1), (-1, 1), (1, 1), (1, -1)]
NEIGHBOURS_16 = NEIGHBOURS_16 + [(2 * r, 2 * c) for r, c in NEIGHBOURS_16]


@dataclass
class Costmap:
    """costmap_2d costs (uint8, rows = y) with origin (m) and resolution (m/cell)."""

    cost: np.ndarray
    origin: tuple[float, float]
    resolution: float

    def cell(self, x: float, y: float) -> tuple[int, int]:
        """(row, col) of the world point (m); may lie outside the array."""
        return (int(math.floor((y - self.origin[1]) / self.resolution)),
                int(math.floor((x - self.origin[0]) / self.resolution)))

    def centre(self, row, col):
        """World (x, y) of cell centres (m), scalars or arrays."""
        return (self.origin[0] + (np.asarray(col) + 0.5) * self.resolution,
                self.origin[1] + (np.asarray(row) + 0.5) * self.resolution)

    def cost_at(self, rows: np.ndarray, cols: np.ndarray) -> np.ndarray:
        """Costs of cells; cells outside the costmap are LETHAL (the package's getCost)."""
        rows, cols = np.asarray(rows), np.asarray(cols)
        inside = (rows >= 0) & (cols >= 0) & (rows < self.cost.shape[0]) & \
            (cols < self.cost.shape[1])
        out = np.full(rows.shape, LETHAL, dtype=np.uint8)
        out[inside] = self.cost[rows[inside], cols[inside]]
        return out


def coarsen(data: np.ndarray, factor: int) -> np.ndarray:
    """Occupancy data (−1 unknown, 0..100) on cells ``factor`` times larger: 100 if any cell
    is occupied (≥ 50), else 0 if any is free, else −1; the array is padded with unknown."""
    if factor <= 1:
        return data
    rows = -(-data.shape[0] // factor) * factor
    cols = -(-data.shape[1] // factor) * factor
    padded = np.full((rows, cols), -1, dtype=np.int16)
    padded[:data.shape[0], :data.shape[1]] = data
    blocks = padded.reshape(rows // factor, factor, cols // factor, factor)
    occupied = (blocks >= 50).any(axis=(1, 3))
    free = ((blocks >= 0) & (blocks < 50)).any(axis=(1, 3))
    out = np.full(occupied.shape, -1, dtype=np.int8)
    out[free] = 0
    out[occupied] = 100
    return out


def inflate(data: np.ndarray, resolution: float, inscribed_radius: float,
            inflation_radius: float, cost_scaling_factor: float) -> np.ndarray:
    """costmap_2d costs of occupancy ``data`` (−1 / 0 / 100) with its inflation layer."""
    lethal = data >= 50
    cost = np.where(data < 0, NO_INFORMATION, FREE_SPACE).astype(np.uint8)
    if lethal.any():
        dist = ndimage.distance_transform_edt(~lethal) * resolution
        factor = np.exp(-cost_scaling_factor * (dist - inscribed_radius))
        decayed = np.floor((INSCRIBED - 1) * factor).astype(np.int32)
        inflated = np.where(dist <= inscribed_radius, INSCRIBED,
                            np.where(dist <= inflation_radius, decayed, FREE_SPACE))
        known = data >= 0
        cost[known] = inflated[known].astype(np.uint8)
        cost[~known & (dist <= inscribed_radius)] = INSCRIBED
        cost[lethal] = LETHAL
    return cost


def explorer_costmap(grid, resolution: float, inscribed_radius: float, inflation_radius: float,
                     cost_scaling_factor: float) -> Costmap | None:
    """The explorer's costmap of the SLAM ``grid`` (data, origin, resolution), cropped to the
    known area plus the inflation radius and ``MARGIN_M``; None when nothing is known."""
    data = np.asarray(grid.data)
    res = float(grid.resolution)
    factor = max(1, int(round(resolution / res)))
    # unknown margin: inflation, and room for the back-off search (4.5 m) beyond known cells
    margin = int(math.ceil((inflation_radius + MARGIN_M) / res)) + 2 * factor
    box = known_box(data, margin)
    if box is None:
        return None
    r0, _, c0, _ = box
    r0, c0 = r0 - r0 % factor, c0 - c0 % factor     # coarse cells stay aligned to the grid
    coarse = coarsen(data[r0:box[1], c0:box[3]], factor)
    coarse_res = res * factor
    origin = (float(grid.origin[0]) + c0 * res, float(grid.origin[1]) + r0 * res)
    cost = inflate(coarse, coarse_res, inscribed_radius, inflation_radius, cost_scaling_factor)
    return Costmap(cost, origin, coarse_res)


def _shifted(cost: np.ndarray, dr: int, dc: int, fill: int) -> np.ndarray:
    """cost[r + dr, c + dc] for every cell (``fill`` beyond the array)."""
    out = np.full(cost.shape, fill, dtype=cost.dtype)
    rows, cols = cost.shape
    src_r = slice(max(0, dr), rows + min(0, dr))
    dst_r = slice(max(0, -dr), rows + min(0, -dr))
    src_c = slice(max(0, dc), cols + min(0, dc))
    dst_c = slice(max(0, -dc), cols + min(0, -dc))
    out[dst_r, dst_c] = cost[src_r, src_c]
    return out


def frontier_cells(costmap: Costmap) -> np.ndarray:
    """(n, 2) world points (m) of the frontier cells, in the costmap's index order (row-major,
    rows = y), as ``findFrontiers`` visits them. Neighbours beyond the costmap count as
    neither unknown nor lethal."""
    cost = costmap.cost
    unknown_near = np.zeros(cost.shape, bool)
    lethal_near = np.zeros(cost.shape, bool)
    for dr, dc in NEIGHBOURS_16:
        neighbour = _shifted(cost, dr, dc, FREE_SPACE)
        unknown_near |= neighbour == NO_INFORMATION
        lethal_near |= neighbour == LETHAL
    rows, cols = np.nonzero((cost == FREE_SPACE) & unknown_near & ~lethal_near)
    xs, ys = costmap.centre(rows, cols)
    return np.stack([xs, ys], axis=1) if len(rows) else np.zeros((0, 2))


def _axis_cells(row: int, col: int, steps: int):
    """(rows, cols) of the cells 1..steps from (row, col) along +x, −x, +y, −y, in the
    package's order (getMapNeighbours: for each step, +x, −x, +y, −y)."""
    k = np.repeat(np.arange(1, steps + 1), 4)
    d_col = np.tile([1, -1, 0, 0], steps) * k
    d_row = np.tile([0, 0, 1, -1], steps) * k
    return row + d_row, col + d_col


def seen_mask(costmap: Costmap, points: np.ndarray, steps: int) -> np.ndarray:
    """True for the stored frontier ``points`` (m) that ``clearSeenFrontiers`` removes."""
    out = np.zeros(len(points), bool)
    for k, (x, y) in enumerate(points):
        row, col = costmap.cell(x, y)
        costs = costmap.cost_at(*_axis_cells(row, col, steps))
        out[k] = (not (costs == NO_INFORMATION).any() or (costs == LETHAL).any()
                  or not (costs == FREE_SPACE).any())
    return out


def _acceptable(costs: np.ndarray, max_cost: int) -> np.ndarray:
    return (costs <= max_cost) | (costs == NO_INFORMATION)


def backoff_goal(costmap: Costmap, x: float, y: float, search_steps: int, inner_steps: int,
                 max_cost: int) -> np.ndarray | None:
    """``smartGoalBackoff``: the goal point (m) near the frontier point (x, y), or None."""
    row, col = costmap.cell(x, y)
    rows, cols = _axis_cells(row, col, search_steps)
    ok = _acceptable(costmap.cost_at(rows, cols), max_cost)
    for r, c in zip(rows[ok], cols[ok], strict=False):
        inner = costmap.cost_at(*_axis_cells(int(r), int(c), inner_steps))
        if _acceptable(inner, max_cost).all():
            return np.array(costmap.centre(r, c), dtype=float)
    return None
