"""ROS map_server maps: an 8-bit PGM image plus a YAML file (as map_saver writes, map_server reads).

Image orientation: row 0 of ``image`` is the TOP of the map (largest y), as in the PGM file; an
``nav_msgs/OccupancyGrid`` stores row 0 at the BOTTOM (at ``origin``), so the conversions below
flip rows. Pixel values follow map_saver: 0 occupied, 205 unknown, 254 free.

YAML keys: ``image`` (relative to the YAML file), ``resolution`` (m/px), ``origin`` ([x m, y m,
yaw rad] of the lower-left pixel), ``negate``, ``occupied_thresh``, ``free_thresh``; ``mode``
(trinary) is accepted on read.
"""
from __future__ import annotations

import os
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import yaml

from slam_predict.atomic import atomic_path, write_bytes
from slam_predict.errors import InputError, require_file

OCCUPIED, UNKNOWN, FREE = 0, 205, 254
OCCUPIED_THRESH, FREE_THRESH = 0.65, 0.196
# map_saver's (ROS Noetic) thresholds on OccupancyGrid values (0..100): <= free → 254, >= occ → 0.
SAVER_THRESHOLD_FREE, SAVER_THRESHOLD_OCCUPIED = 25, 65


@dataclass
class MapServerMap:
    """An 8-bit map image (row 0 = top) and its map_server metadata."""

    image: np.ndarray
    resolution: float
    origin: tuple[float, float, float] = (0.0, 0.0, 0.0)
    negate: int = 0
    occupied_thresh: float = OCCUPIED_THRESH
    free_thresh: float = FREE_THRESH
    extra: dict = field(default_factory=dict)

    def to_occupancy(self) -> np.ndarray:
        """OccupancyGrid values (int8: 100 occupied, 0 free, -1 unknown), row 0 = bottom.

        map_server's trinary rule: p = (255 − v)/255 (v/255 when negate); p > occupied_thresh →
        100, p < free_thresh → 0, otherwise −1.
        """
        value = self.image.astype(float)
        p = value / 255.0 if self.negate else (255.0 - value) / 255.0
        grid = np.full(self.image.shape, -1, dtype=np.int8)
        grid[p > self.occupied_thresh] = 100
        grid[p < self.free_thresh] = 0
        return grid[::-1].copy()


def occupancy_to_image(grid: np.ndarray, threshold_free: int = SAVER_THRESHOLD_FREE,
                       threshold_occupied: int = SAVER_THRESHOLD_OCCUPIED) -> np.ndarray:
    """map_saver's conversion of OccupancyGrid values (row 0 = bottom) to a PGM image (row 0 = top).

    0 ≤ value ≤ threshold_free → 254 (free); value ≥ threshold_occupied → 0; else 205 (unknown).
    """
    grid = np.asarray(grid)
    image = np.full(grid.shape, UNKNOWN, dtype=np.uint8)
    image[(grid >= 0) & (grid <= threshold_free)] = FREE
    image[grid >= threshold_occupied] = OCCUPIED
    return image[::-1].copy()


def encode_pgm(image: np.ndarray, comment: str = "") -> bytes:
    """Binary (P5) PGM bytes of an 8-bit image."""
    image = np.ascontiguousarray(image, dtype=np.uint8)
    if image.ndim != 2:
        raise ValueError(f"map image must be 2-D, got shape {image.shape}")
    head = "P5\n" + (f"# {comment}\n" if comment else "")
    head += f"{image.shape[1]} {image.shape[0]}\n255\n"
    return head.encode("ascii") + image.tobytes()


def decode_pgm(data: bytes, path: str = None) -> np.ndarray:
    """An 8-bit image from P5 (binary) or P2 (ASCII) PGM bytes; maxval ≤ 255 only."""
    tokens, pos = [], 0
    while len(tokens) < 4:
        while pos < len(data) and data[pos:pos + 1].isspace():
            pos += 1
        if data[pos:pos + 1] == b"#":
            pos = data.find(b"\n", pos) + 1 or len(data)
            continue
        start = pos
        while pos < len(data) and not data[pos:pos + 1].isspace():
            pos += 1
        if start == pos:
            raise InputError("truncated PGM header", path)
        tokens.append(data[start:pos])
    magic = tokens[0]
    try:
        width, height, maxval = (int(t) for t in tokens[1:])
    except ValueError as exc:
        raise InputError("malformed PGM header", path) from exc
    if magic not in (b"P5", b"P2") or maxval > 255 or maxval < 1:
        raise InputError(f"unsupported PGM ({magic.decode(errors='replace')}, maxval {maxval}); "
                         "need 8-bit P5 or P2", path)
    if magic == b"P5":
        body = data[pos + 1:pos + 1 + width * height]
        values = np.frombuffer(body, dtype=np.uint8)
    else:
        values = np.array(data[pos:].split(), dtype=np.int64)[:width * height]
    if values.size != width * height:
        raise InputError(f"PGM has {values.size} pixels, header says {width}x{height}", path)
    if maxval != 255:
        values = np.round(values.astype(float) * 255.0 / maxval)
    return values.astype(np.uint8).reshape(height, width)


def write_map(yaml_path: os.PathLike | str, image: np.ndarray, resolution: float,
              origin=(0.0, 0.0, 0.0), *, negate: int = 0, occupied_thresh: float = OCCUPIED_THRESH,
              free_thresh: float = FREE_THRESH) -> Path:
    """Write ``<stem>.pgm`` and ``yaml_path`` atomically (image first); returns the PGM path.

    ``image`` is 8-bit with row 0 at the top (see :func:`occupancy_to_image`).
    """
    yaml_path = Path(yaml_path)
    pgm_path = yaml_path.with_suffix(".pgm")
    write_bytes(pgm_path, encode_pgm(image, f"slam_predict {resolution:.3f} m/pix"))
    meta = {
        "image": pgm_path.name,
        "resolution": float(resolution),
        "origin": [float(v) for v in origin],
        "negate": int(negate),
        "occupied_thresh": float(occupied_thresh),
        "free_thresh": float(free_thresh),
    }
    with atomic_path(yaml_path) as tmp:
        tmp.write_text(yaml.safe_dump(meta, sort_keys=False, default_flow_style=None),
                       encoding="utf-8")
    return pgm_path


def write_occupancy(yaml_path: os.PathLike | str, grid: np.ndarray, resolution: float,
                    origin=(0.0, 0.0, 0.0)) -> Path:
    """Save OccupancyGrid values (row 0 = bottom) as map_saver does; returns the PGM path."""
    return write_map(yaml_path, occupancy_to_image(grid), resolution, origin)


def read_map(yaml_path: os.PathLike | str) -> MapServerMap:
    """Read a map_server YAML and its image (PGM; other formats through OpenCV)."""
    yaml_path = require_file(yaml_path, "map YAML")
    try:
        with open(yaml_path, encoding="utf-8") as fh:
            meta = yaml.safe_load(fh)
    except (OSError, yaml.YAMLError) as exc:
        raise InputError(f"cannot read map YAML: {exc}".splitlines()[0], yaml_path) from None
    if not isinstance(meta, dict):
        raise InputError("map YAML is not a mapping", yaml_path)
    for key in ("image", "resolution", "origin"):
        if key not in meta:
            raise InputError(f"map YAML lacks '{key}'", yaml_path)
    origin = meta["origin"]
    if not (isinstance(origin, list) and len(origin) == 3):
        raise InputError("origin must be a list [x, y, yaw]", yaml_path)
    image_path = Path(yaml_path).parent / str(meta["image"])
    image = _read_image(require_file(image_path, "map image"))
    known = {"image", "resolution", "origin", "negate", "occupied_thresh", "free_thresh"}
    try:
        return MapServerMap(
            image=image, resolution=float(meta["resolution"]),
            origin=tuple(float(v) for v in origin), negate=int(meta.get("negate", 0)),
            occupied_thresh=float(meta.get("occupied_thresh", OCCUPIED_THRESH)),
            free_thresh=float(meta.get("free_thresh", FREE_THRESH)),
            extra={k: v for k, v in meta.items() if k not in known})
    except (TypeError, ValueError) as exc:
        raise InputError(f"bad value in map YAML: {exc}", yaml_path) from None


def _read_image(path: str) -> np.ndarray:
    data = Path(path).read_bytes()
    if data[:2] in (b"P5", b"P2"):
        return decode_pgm(data, path)
    import cv2  # other image formats (PNG, ...) as map_server accepts them

    image = cv2.imdecode(np.frombuffer(data, np.uint8), cv2.IMREAD_GRAYSCALE)
    if image is None:
        raise InputError("cannot decode map image", path)
    return image
