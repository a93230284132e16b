"""Synthetic test buildings for the exploration tests (numpy bitmaps, seeded)."""
from __future__ import annotations

import numpy as np

from slam_predict.world.model import World


def rooms_world(rooms_x: int = 3, rooms_y: int = 2, room_m: float = 4.0, corridor_m: float = 2.0,
                door_m: float = 1.0, res: float = 0.05, wall_px: int = 3, seed: int = 0,
                name: str = "rooms") -> World:
    """Two rows of rooms on either side of a corridor along x, one door per room (at a seeded
    position), walls ``wall_px`` cells thick, outside marked occupied; start in the corridor."""
    rng = np.random.default_rng(seed)
    room = int(round(room_m / res))
    corr = int(round(corridor_m / res))
    door = int(round(door_m / res))
    w = wall_px
    cols = rooms_x * (room + w) + w
    rows = rooms_y * (room + w) + corr + w * 2 if rooms_y == 2 else room + corr + 3 * w
    occ = np.zeros((rows, cols), bool)
    occ[:w, :] = occ[-w:, :] = True
    occ[:, :w] = occ[:, -w:] = True
    top_wall = w + room                        # wall between the top rooms and the corridor
    bottom_wall = top_wall + w + corr          # wall between the corridor and the bottom rooms
    occ[top_wall:top_wall + w, :] = True
    if rooms_y == 2:
        occ[bottom_wall:bottom_wall + w, :] = True
    for i in range(1, rooms_x):
        c = i * (room + w)
        occ[:top_wall, c:c + w] = True
        if rooms_y == 2:
            occ[bottom_wall:, c:c + w] = True
    for i in range(rooms_x):
        c0 = i * (room + w) + w
        for wall in ([top_wall, bottom_wall] if rooms_y == 2 else [top_wall]):
            d = c0 + int(rng.integers(0, room - door))
            occ[wall:wall + w, d:d + door] = False
    start_row = top_wall + w + corr // 2
    world = World(name, occ, res)
    x, y = world.cell_to_world((start_row, w + room // 2))
    world.start_pose = np.array([x, y, 0.0])
    world.provenance["start_given"] = True
    return world
