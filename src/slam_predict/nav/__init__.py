"""Navigation: a move_base equivalent (costmap_2d layers, navfn/global_planner-like planner,
base_local_planner trajectory rollout, move_base's state machine), in sim time.

Entry point: :class:`slam_predict.nav.navigator.Navigator` with a
:class:`slam_predict.nav.config.MoveBaseConfig` (``load_nav_config("config")``).
"""
