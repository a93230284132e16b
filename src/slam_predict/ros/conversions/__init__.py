"""ROS message conversions: pure functions, `*_to_ros` / `*_from_ros` pairs, one module per area."""
