"""Ending a run's ROS graph in order, so nothing has to be killed.

The simulator goes first: with its clock stopped the other nodes have nothing left to do, while
they are still alive to answer its last lockstep wait (stopped after them, stage_sim would wait
for acks that never come until roslaunch escalates to SIGKILL). Then the explorer, the
navigation, the SLAM node. Each is asked through the ROS node API's ``shutdown`` (what
``rosnode kill`` does) and waited for, in wall time, until its process no longer answers on
its XML-RPC URI (``rosnode ping``: a node that exited can stay registered with the master).
"""
from __future__ import annotations

import logging
import time
import xmlrpc.client
from collections.abc import Callable, Sequence

LOG = logging.getLogger(__name__)
CALLER = "/orchestrator"
CALL_TIMEOUT_S = 5.0  # wall s for one XML-RPC call to a node


def shutdown_nodes(names: Sequence[str], lookup: Callable[[str], str | None],
                   request: Callable[[str, str], None], alive: Callable[[str], bool],
                   timeout_s: float, poll_s: float = 0.1) -> list[str]:
    """Shut ``names`` down one after the other; returns those still alive after ``timeout_s``
    wall seconds each (not waited for again).

    Args:
        names: node names in shutdown order; ones the master does not know are skipped.
        lookup: node name → its XML-RPC URI from the master, or None.
        request: (name, uri) → ask that node to shut down.
        alive: uri → True while the node's process still answers there.
    """
    stuck = []
    for name in names:
        uri = lookup(name)
        if uri is None or not alive(uri):
            continue
        try:
            request(name, uri)
        except (OSError, ValueError) as exc:  # the node went away meanwhile
            LOG.debug("shutdown of %s: %s", name, exc)
        deadline = time.monotonic() + timeout_s
        while alive(uri) and time.monotonic() < deadline:
            time.sleep(poll_s)
        if alive(uri):
            LOG.warning("%s still running %.0f s after its shutdown request", name, timeout_s)
            stuck.append(name)
        else:
            LOG.info("%s shut down", name)
    return stuck


def master_lookup(caller: str = CALLER) -> Callable[[str], str | None]:
    """``lookup`` for :func:`shutdown_nodes` through the ROS master."""
    import rosgraph

    master = rosgraph.Master(caller)

    def lookup(name: str) -> str | None:
        try:
            return master.lookupNode(name)
        except (rosgraph.MasterError, OSError):
            return None
    return lookup


class _TimedTransport(xmlrpc.client.Transport):
    """An XML-RPC transport whose connections time out after ``timeout_s`` (wall s)."""

    def __init__(self, timeout_s: float):
        super().__init__()
        self.timeout_s = timeout_s

    def make_connection(self, host):
        connection = super().make_connection(host)
        connection.timeout = self.timeout_s
        return connection


def _proxy(uri: str) -> xmlrpc.client.ServerProxy:
    return xmlrpc.client.ServerProxy(uri, transport=_TimedTransport(CALL_TIMEOUT_S))


def node_alive(uri: str, caller: str = CALLER) -> bool:
    """True while a node answers ``getPid`` on its XML-RPC URI (``rosnode ping``)."""
    try:
        _proxy(uri).getPid(caller)
    except (OSError, xmlrpc.client.Error):
        return False
    return True


def node_api_request(caller: str = CALLER, reason: str = "run finished"):
    """``request`` for :func:`shutdown_nodes`: the node API's ``shutdown`` call."""
    def request(_name: str, uri: str) -> None:
        try:
            _proxy(uri).shutdown(caller, reason)
        except xmlrpc.client.Error as exc:
            raise ValueError(str(exc)) from None
    return request


def end_run_graph(names: Sequence[str], timeout_s: float, caller: str = CALLER,
                  reason: str = "run finished") -> list[str]:
    """:func:`shutdown_nodes` through the master and the node API."""
    return shutdown_nodes(names, master_lookup(caller), node_api_request(caller, reason),
                          lambda uri: node_alive(uri, caller), timeout_s)
