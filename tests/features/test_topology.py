"""Topological graph: star for a corridor with rooms, cycle for four rooms in a ring."""
from __future__ import annotations

import networkx as nx
import pytest

from slam_predict.features.rooms import RoomsConfig, rooms_of, segment
from slam_predict.features.topology import (
    TopologyConfig,
    room_pairs,
    topology_graph,
    topology_metrics,
)

from .plans import corridor_with_rooms, four_rooms_cycle, single_room


@pytest.mark.parametrize("k", [2, 5])
def test_corridor_with_rooms_is_a_star(k):
    world = corridor_with_rooms(k).world()
    graph = topology_graph(segment(world.occupied, world.resolution)).to_networkx()
    degrees = sorted(d for _, d in graph.degree())
    assert degrees == [1] * k + [k]
    assert nx.is_tree(graph)


@pytest.mark.parametrize("source", ["segment", "ground_truth"])
def test_four_rooms_form_a_cycle(source):
    world = four_rooms_cycle().world()
    graph = topology_graph(rooms_of(world, RoomsConfig(source=source)))
    g = graph.to_networkx()
    assert g.number_of_nodes() == 4 and nx.cycle_basis(g) and all(d == 2 for _, d in g.degree())
    values = topology_metrics(graph)
    assert (values["order"], values["size"], values["diameter"]) == (4.0, 4.0, 2.0)


def test_walls_do_not_connect_rooms():
    world = corridor_with_rooms(3).world()
    pairs = room_pairs(topology_graph(segment(world.occupied, world.resolution)))
    assert len(pairs) == 3  # rooms side by side share walls but no passage


def test_narrow_contact_is_not_a_passage():
    world = corridor_with_rooms(1, door=0.4).world()
    rooms = segment(world.occupied, world.resolution)
    assert room_pairs(topology_graph(rooms)) == [(1, 2)]
    assert room_pairs(topology_graph(rooms, TopologyConfig(min_passage_m=0.6))) == []


def test_single_room_metrics():
    world = single_room().world()
    values = topology_metrics(topology_graph(segment(world.occupied, world.resolution)))
    assert values["order"] == 1.0 and values["size"] == 0.0 and values["katz_mean"] == 1.0
