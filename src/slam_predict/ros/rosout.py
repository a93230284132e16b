"""Forward the library's ``logging`` records to rosout (so they show with ``output="screen"``).

rospy configures the root logger to write the node's log file only; a node that wants the
library's INFO messages on screen and on /rosout calls :func:`forward_logging` after init_node.
"""
from __future__ import annotations

import logging


class RosoutHandler(logging.Handler):
    """A logging handler calling rospy.logerr / logwarn / loginfo / logdebug."""

    def __init__(self, rospy_module):
        super().__init__()
        self.rospy = rospy_module

    def emit(self, record: logging.LogRecord) -> None:
        try:
            message = self.format(record)
            if record.levelno >= logging.ERROR:
                self.rospy.logerr(message)
            elif record.levelno >= logging.WARNING:
                self.rospy.logwarn(message)
            elif record.levelno >= logging.INFO:
                self.rospy.loginfo(message)
            else:
                self.rospy.logdebug(message)
        except Exception:  # noqa: BLE001 - logging must never raise
            self.handleError(record)


def forward_logging(rospy_module, logger: str = "slam_predict", level: int = logging.INFO) -> None:
    """Send ``logger``'s records at ``level`` and above to rosout (once per process)."""
    log = logging.getLogger(logger)
    log.setLevel(level)
    if not any(isinstance(h, RosoutHandler) for h in log.handlers):
        log.addHandler(RosoutHandler(rospy_module))
