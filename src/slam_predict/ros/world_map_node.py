"""``world_map_server``: publish a plan's occupancy as a latched map, like map_server.

Topics (latched): ``map`` (nav_msgs/OccupancyGrid) and ``map_metadata``
(nav_msgs/MapMetaData), in frame ``~frame_id`` (default ``map``). Params (read in main() only):
``~world`` (plan path: .world, image, map YAML or layout XML), ``~resolution`` (m/px, images
only), ``~frame_id``.
"""
from __future__ import annotations

import sys

from slam_predict.ros.conversions.map import occupancy_to_ros
from slam_predict.world.model import World


class WorldMapServer:
    """Holds one World and publishes it once on latched ``map`` / ``map_metadata`` topics."""

    def __init__(self, world: World, frame_id: str = "map"):
        self.world = world
        self.frame_id = frame_id
        self._publishers = None

    def map_message(self, stamp=None):
        """The OccupancyGrid of the World (stamped ``stamp`` when given)."""
        return occupancy_to_ros(self.world, frame_id=self.frame_id, stamp=stamp)

    def start(self, rospy_module) -> None:
        """Advertise the latched topics and publish the map (call after init_node)."""
        from nav_msgs.msg import MapMetaData, OccupancyGrid

        map_pub = rospy_module.Publisher("map", OccupancyGrid, queue_size=1, latch=True)
        meta_pub = rospy_module.Publisher("map_metadata", MapMetaData, queue_size=1, latch=True)
        msg = self.map_message(rospy_module.Time.now())
        meta_pub.publish(msg.info)
        map_pub.publish(msg)
        self._publishers = (map_pub, meta_pub)


def main(argv=None) -> int:
    """Node entry point: read ~params, load the plan, publish, spin."""
    import rospy

    from slam_predict.errors import InputError
    from slam_predict.world.load import load_plan

    rospy.init_node("world_map_server", argv=argv)
    path = rospy.get_param("~world", "")
    resolution = rospy.get_param("~resolution", None)
    frame_id = rospy.get_param("~frame_id", "map")
    if not path:
        rospy.logfatal("world_map_server: parameter ~world (plan file) is required")
        return 2
    try:
        world = load_plan(path, resolution=resolution)
    except InputError as exc:
        rospy.logfatal("world_map_server: %s", exc.one_line())
        return 2
    server = WorldMapServer(world, frame_id)
    server.start(rospy)
    rows, cols = world.shape
    rospy.loginfo("world_map_server: %s, %d x %d cells at %g m/px on 'map'", world.name, cols,
                  rows, world.resolution)
    rospy.spin()
    return 0


if __name__ == "__main__":
    sys.exit(main())
