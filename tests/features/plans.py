"""Synthetic floor plans with known answers, built from numpy arrays.

Geometry is given in plan metres with (0, 0) at the top-left corner, x to the right and y
down; :class:`Plan` turns it into a World (bitmap centred on the origin, y up) whose
ground-truth rooms are the carved rectangles.
"""
from __future__ import annotations

import numpy as np

from slam_predict.world.model import Door, Room, World

Rect = tuple[float, float, float, float]  # x0, y0, x1, y1 in plan metres


class Plan:
    """A canvas of obstacle with free rectangles (rooms) and openings (doors) carved in."""

    def __init__(self, width_m: float, height_m: float, res: float = 0.05):
        self.res = res
        self.width, self.height = width_m, height_m
        self.occ = np.ones((int(round(height_m / res)), int(round(width_m / res))), bool)
        self.rooms: list[tuple[str, Rect]] = []
        self.doors: list[tuple[Rect, tuple[str, str]]] = []

    def _carve(self, rect: Rect) -> None:
        x0, y0, x1, y1 = (int(round(v / self.res)) for v in rect)
        self.occ[y0:y1, x0:x1] = False

    def room(self, name: str, rect: Rect) -> Plan:
        """Carve a free rectangle and record it as a ground-truth room."""
        self._carve(rect)
        self.rooms.append((name, rect))
        return self

    def door(self, rect: Rect, rooms: tuple[str, str]) -> Plan:
        """Carve an opening through a wall between two rooms."""
        self._carve(rect)
        self.doors.append((rect, rooms))
        return self

    def world_xy(self, x: float, y: float) -> tuple[float, float]:
        """World coordinates (m) of plan point (x, y)."""
        return x - self.width / 2.0, self.height / 2.0 - y

    def world(self, start_xy=None, yaw: float = 0.0, name: str = "plan") -> World:
        """The World; ``start_xy`` in plan metres (default: centre of the first room)."""
        if start_xy is None:
            x0, y0, x1, y1 = self.rooms[0][1]
            start_xy = ((x0 + x1) / 2, (y0 + y1) / 2)
        rooms = [Room(id=n, polygon=np.array([self.world_xy(x, y) for x, y in
                                              ((r[0], r[1]), (r[2], r[1]), (r[2], r[3]),
                                               (r[0], r[3]))]), label=n)
                 for n, r in self.rooms]
        doors = [Door(segment=np.array([self.world_xy(r[0], r[1]), self.world_xy(r[2], r[3])]),
                      rooms=pair) for r, pair in self.doors]
        sx, sy = self.world_xy(*start_xy)
        return World(name=name, occupied=self.occ.copy(), resolution=self.res,
                     start_pose=np.array([sx, sy, yaw]), rooms=rooms, doors=doors,
                     provenance={"start_given": True})


def corridor_with_rooms(k: int, res: float = 0.05, room: float = 4.0, wall: float = 0.2,
                        door: float = 0.9, corridor: float = 2.0) -> Plan:
    """A straight corridor with ``k`` rooms (room × room m) along its top side, one door each."""
    width = k * (room + wall) + wall + 2.0
    plan = Plan(width + 1.0, room + corridor + 3 * wall + 1.0, res)
    top = 0.5 + wall
    cy0 = top + room + wall
    plan.room("corridor", (0.5 + wall, cy0, 0.5 + width - wall, cy0 + corridor))
    for i in range(k):
        x0 = 0.5 + wall + i * (room + wall)
        plan.room(f"room{i}", (x0, top, x0 + room, top + room))
        mid = x0 + room / 2
        plan.door((mid - door / 2, top + room, mid + door / 2, cy0), (f"room{i}", "corridor"))
    return plan


def ring_corridor(res: float = 0.05, outer: float = 16.0, corridor: float = 2.0,
                  wall: float = 0.2) -> Plan:
    """A square ring corridor (outer × outer m, ``corridor`` m wide) around a solid block."""
    plan = Plan(outer + 2 * wall + 1.0, outer + 2 * wall + 1.0, res)
    o = 0.5 + wall
    plan.room("ring", (o, o, o + outer, o + outer))
    inner = (o + corridor, o + corridor, o + outer - corridor, o + outer - corridor)
    x0, y0, x1, y1 = (int(round(v / res)) for v in inner)
    plan.occ[y0:y1, x0:x1] = True
    return plan


def four_rooms_cycle(res: float = 0.05, room: float = 5.0, wall: float = 0.2,
                     door: float = 0.9) -> Plan:
    """Four rooms in a 2 × 2 block, each with a door to its two neighbours: a 4-cycle."""
    size = 2 * room + 3 * wall
    plan = Plan(size + 1.0, size + 1.0, res)
    o = 0.5 + wall
    a, b = o, o + room + wall
    names = {(0, 0): "nw", (1, 0): "ne", (0, 1): "sw", (1, 1): "se"}
    for (i, j), name in names.items():
        x0, y0 = (a, b)[i], (a, b)[j]
        plan.room(name, (x0, y0, x0 + room, y0 + room))
    mid = room / 2
    plan.door((a + room, a + mid - door / 2, b, a + mid + door / 2), ("nw", "ne"))
    plan.door((a + room, b + mid - door / 2, b, b + mid + door / 2), ("sw", "se"))
    plan.door((a + mid - door / 2, a + room, a + mid + door / 2, b), ("nw", "sw"))
    plan.door((b + mid - door / 2, a + room, b + mid + door / 2, b), ("ne", "se"))
    return plan


def single_room(width: float = 10.0, height: float = 6.0, res: float = 0.05,
                wall: float = 0.2) -> Plan:
    """One rectangular room."""
    plan = Plan(width + 2 * wall + 1.0, height + 2 * wall + 1.0, res)
    o = 0.5 + wall
    return plan.room("room", (o, o, o + width, o + height))
