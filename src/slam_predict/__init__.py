"""slam_predict: predict GMapping's localization error in a building from its floor plan.

The library never imports rospy; the ROS layer lives in :mod:`slam_predict.ros`.
"""
import logging

__version__ = "0.1.0"

logging.getLogger(__name__).addHandler(logging.NullHandler())
