"""File formats: CARMEN logs, TUM trajectories, Freiburg relations, map_server maps, ROS bags."""
