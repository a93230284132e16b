"""The ROS layer: node classes wrapping the library, and message conversions.

Only here is rospy imported.
"""
