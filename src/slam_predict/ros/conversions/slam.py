"""SLAM occupancy grids ↔ ``nav_msgs/OccupancyGrid`` / ``MapMetaData``, fast for big maps.

:class:`slam_predict.slam.OccupancyGrid` already uses the message's layout (row 0 = smallest y,
values −1/0/100), so conversion is a header plus the raw bytes. :func:`grid_to_ros` returns a
``rospy.numpy_msg`` message whose ``data`` is serialised straight from the numpy buffer (a
4000 x 4000 map publishes in milliseconds instead of building a 16-million-item list); publish it
with a publisher of type :data:`NumpyOccupancyGrid`. ``origin`` is the grid's ``origin`` (for
GMapping: its cell (0, 0) position, as slam_gmapping publishes it), with no rotation.
"""
from __future__ import annotations

import numpy as np
from nav_msgs.msg import MapMetaData
from nav_msgs.msg import OccupancyGrid as RosOccupancyGrid
from nav_msgs.srv import GetMapResponse
from rospy.numpy_msg import numpy_msg

from slam_predict.geometry import quaternion_to_yaw
from slam_predict.ros.conversions.geometry import time_to_ros
from slam_predict.slam import OccupancyGrid

NumpyOccupancyGrid = numpy_msg(RosOccupancyGrid)
NumpyGetMapResponse = numpy_msg(GetMapResponse)


class _Int8Buffer(np.ndarray):
    """int8 data that genpy's numpy serialiser can write (it calls the removed ``tostring``)."""

    def tostring(self) -> bytes:  # noqa: D401 - genpy API
        return self.tobytes()


def metadata_to_ros(grid: OccupancyGrid, stamp: float = 0.0) -> MapMetaData:
    """The grid's ``nav_msgs/MapMetaData`` (``map_load_time`` = ``stamp`` s)."""
    info = MapMetaData()
    info.map_load_time = time_to_ros(stamp)
    info.resolution = float(grid.resolution)
    info.width, info.height = grid.width, grid.height
    info.origin.position.x, info.origin.position.y = float(grid.origin[0]), float(grid.origin[1])
    info.origin.orientation.w = 1.0
    return info


def grid_to_ros(grid: OccupancyGrid, frame_id: str = "map", stamp: float = 0.0):
    """``OccupancyGrid`` (numpy_msg flavour) of ``grid``, header stamped ``stamp`` s."""
    msg = NumpyOccupancyGrid()
    msg.header.frame_id = frame_id
    msg.header.stamp = time_to_ros(stamp)
    msg.info = metadata_to_ros(grid, stamp)
    data = np.ascontiguousarray(grid.data, dtype=np.int8).reshape(-1)
    msg.data = data.view(_Int8Buffer)
    return msg


def grid_from_ros(msg) -> OccupancyGrid:
    """:class:`OccupancyGrid` of a ``nav_msgs/OccupancyGrid`` (any flavour; no rotation)."""
    info = msg.info
    o = info.origin.orientation
    if (o.x, o.y, o.z, o.w) != (0.0, 0.0, 0.0, 0.0) and abs(
            float(quaternion_to_yaw(o.x, o.y, o.z, o.w))) > 1e-9:
        raise ValueError("rotated OccupancyGrid origins are not supported")
    data = msg.data
    if isinstance(data, (bytes, bytearray)):
        values = np.frombuffer(data, dtype=np.int8)
    else:
        values = np.asarray(data, dtype=np.int8)
    if values.size != info.width * info.height:
        raise ValueError(f"OccupancyGrid has {values.size} cells, expected "
                         f"{info.height} x {info.width}")
    return OccupancyGrid(values.reshape(info.height, info.width).copy(), float(info.resolution),
                         (float(info.origin.position.x), float(info.origin.position.y)))


def get_map_response(msg) -> NumpyGetMapResponse:
    """A ``nav_msgs/GetMap`` response carrying ``msg`` (from :func:`grid_to_ros`)."""
    response = NumpyGetMapResponse()
    response.map = msg
    return response
