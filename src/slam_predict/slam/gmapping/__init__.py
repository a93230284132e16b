"""A port of openslam_gmapping as driven by ROS slam_gmapping (ros_interfaces.md §2).

Modules: :mod:`.params` (parameters), :mod:`.motion` (odometry motion model), :mod:`.kernels`
(scan matcher and hit registration, numba), :mod:`.raytrace` (published-map ray tracing, numba),
:mod:`.maps` (copy-on-write patch maps), :mod:`.tree` (trajectory tree), :mod:`.filter` (the
Rao-Blackwellized particle filter), :mod:`.gridmap` (published occupancy grid), :mod:`.runner`
(offline runs over CARMEN logs).
"""
