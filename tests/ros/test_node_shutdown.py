"""Ending a run's graph in order (simulator first), waiting for each node's process to exit."""
from __future__ import annotations

import time

from slam_predict.ros import batch_runner as br
from slam_predict.ros.node_shutdown import node_alive, shutdown_nodes


class FakeGraph:
    """Nodes whose process exits ``delay_s`` after their shutdown request (None: never); like
    real ones they stay registered with the master after exiting."""

    def __init__(self, delays):
        self.delays = dict(delays)
        self.asked = {}

    def lookup(self, name):
        return f"http://host{name}" if name in self.delays else None

    def alive(self, uri):
        name = uri[len("http://host"):]
        asked, delay = self.asked.get(name), self.delays[name]
        return asked is None or delay is None or time.monotonic() - asked < delay

    def request(self, name, uri):
        assert uri == self.lookup(name)
        # the order matters: no node is asked before the previous one has exited
        assert not any(self.alive(self.lookup(other)) for other in self.asked)
        self.asked[name] = time.monotonic()

    def shutdown(self, names, timeout_s=2.0, request=None):
        return shutdown_nodes(names, self.lookup, request or self.request, self.alive,
                              timeout_s=timeout_s, poll_s=0.01)


def test_nodes_are_shut_down_one_after_the_other_in_order():
    graph = FakeGraph({"/stage_sim": 0.05, "/explore": 0.0, "/slam_gmapping": 0.02})
    assert graph.shutdown(["/stage_sim", "/explore", "/move_base", "/slam_gmapping"]) == []
    assert list(graph.asked) == ["/stage_sim", "/explore", "/slam_gmapping"]  # move_base absent


def test_a_node_that_does_not_exit_is_reported_and_the_others_still_stop():
    graph = FakeGraph({"/stage_sim": None, "/explore": 0.0})
    started = time.monotonic()
    stuck = graph.shutdown(["/stage_sim", "/explore"], timeout_s=0.2,
                           request=lambda name, uri: graph.asked.setdefault(name, time.monotonic()))
    assert stuck == ["/stage_sim"] and "/explore" in graph.asked
    assert time.monotonic() - started < 2.0


def test_a_failed_request_is_not_an_error_and_the_node_is_reported():
    graph = FakeGraph({"/explore": 0.0, "/slam_gmapping": 0.0})

    def request(name, uri):
        if name == "/explore":
            raise OSError("connection refused")
        graph.request(name, uri)
    assert graph.shutdown(["/explore", "/slam_gmapping"], timeout_s=0.1,
                          request=request) == ["/explore"]
    assert list(graph.asked) == ["/slam_gmapping"]


def test_a_node_that_no_longer_answers_is_not_alive():
    assert not node_alive("http://127.0.0.1:9/")   # discard port: connection refused


def test_end_parent_launch_only_signals_a_roslaunch_parent():
    assert br.end_parent_launch() is False   # pytest's parent is not roslaunch: no signal sent
