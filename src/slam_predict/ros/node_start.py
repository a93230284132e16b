"""The start of a node's main(): init_node, the library's logging on screen, its parameters."""
from __future__ import annotations

import logging
from collections.abc import Callable
from typing import Any

from slam_predict.errors import InputError


def start_node(rospy_module, name: str, label: str, read: Callable[[Any], Any],
               argv=None) -> Any:
    """Initialise the node ``name``, log the library's INFO messages as ``[label] LEVEL text``
    and return ``read(rospy_module)`` (its parameters), or None when they are bad: the
    InputError is then logged as fatal in one line and the caller exits 2."""
    rospy_module.init_node(name, argv=argv)
    logging.basicConfig(level=logging.INFO, format=f"[{label}] %(levelname)s %(message)s")
    try:
        return read(rospy_module)
    except InputError as exc:
        rospy_module.logfatal(f"{label}: {exc.one_line()}")
        return None
