"""single_run.launch / batch_explore.launch resolve for our nodes and for the real packages.

The real packages (stage_ros, gmapping, move_base, explore_lite) are not installed here, so their
branch is checked on the parsed launch configuration (roslaunch.config.load_config_default):
node package/type, arguments, remaps and loaded parameters — nothing is executed. Our branch is
also checked with the ``roslaunch --files`` / ``--nodes`` / ``--args`` command line.
"""
from __future__ import annotations

import os
import shutil
import subprocess
from pathlib import Path

import pytest

roslaunch = pytest.importorskip("roslaunch", reason="roslaunch not installed")

ROOT = Path(__file__).resolve().parents[2]
WORLD = str(ROOT / "worlds" / "tiny.world")
REAL = ["sim:=stage", "slam:=gmapping", "nav:=move_base", "explore:=explore_lite"]


def _package_found() -> bool:
    if shutil.which("roslaunch") is None or shutil.which("rospack") is None:
        return False
    found = subprocess.run(["rospack", "find", "slam_predict"], capture_output=True, text=True)
    return found.returncode == 0 and Path(found.stdout.strip()).resolve() == ROOT


pytestmark = pytest.mark.skipif(not _package_found(),
                                reason="slam_predict not on ROS_PACKAGE_PATH (source setup.bash)")


def cli(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run(["roslaunch", *args], capture_output=True, text=True, timeout=60,
                          env={**os.environ, "ROS_HOME": os.environ.get("ROS_HOME", "/tmp/.ros")})


def config(launch: str, *args: str):
    path = str(ROOT / "launch" / launch)
    return roslaunch.config.load_config_default([(path, list(args))], None)


def _ack_list(value):
    from slam_predict.ros.stage_sim_params import ack_list as parse
    return parse(value)


def nodes_of(cfg) -> dict:
    return {n.name: n for n in cfg.nodes}


def test_files_list_the_included_launch_files_for_our_nodes():
    out = cli("--files", "slam_predict", "single_run.launch", f"world:={WORLD}", "out:=/tmp/x")
    assert out.returncode == 0, out.stderr
    names = {Path(line).name for line in out.stdout.split()}
    assert names == {"single_run.launch", "stage_sim.launch", "slam_gmapping.launch"}
    out = cli("--files", "slam_predict", "single_run.launch", f"world:={WORLD}", "out:=/tmp/x",
              *REAL)
    assert out.returncode == 0, out.stderr
    assert {Path(line).name for line in out.stdout.split()} == {"single_run.launch"}


def test_nodes_of_both_choices():
    ours = cli("--nodes", "slam_predict", "single_run.launch", f"world:={WORLD}", "out:=/x")
    real = cli("--nodes", "slam_predict", "single_run.launch", f"world:={WORLD}", "out:=/x",
               *REAL)
    assert ours.returncode == 0 and real.returncode == 0, ours.stderr + real.stderr
    assert set(ours.stdout.split()) == {"/stage_sim", "/slam_gmapping", "/move_base",
                                        "/explore", "/orchestrator"}
    assert set(real.stdout.split()) == {"/stageros", "/slam_gmapping", "/move_base",
                                        "/explore", "/orchestrator"}


@pytest.mark.parametrize("node,script", [("/stage_sim", "stage_sim"),
                                         ("/slam_gmapping", "slam_gmapping"),
                                         ("/move_base", "move_base"), ("/explore", "explore"),
                                         ("/orchestrator", "orchestrator")])
def test_args_resolve_our_executables(node, script):
    out = cli("--args", node, "slam_predict", "single_run.launch", f"world:={WORLD}",
              "out:=/tmp/x")
    assert out.returncode == 0, out.stderr
    assert f"/slam_predict/{script}" in out.stdout and f"__name:={node[1:]}" in out.stdout
    if node == "/stage_sim":
        assert WORLD in out.stdout


def test_our_branch_configuration():
    cfg = config("single_run.launch", f"world:={WORLD}", "out:=/tmp/run_007", "seed:=4000000000",
                 "sim_seed:=11", "slam_seed:=12", "explore_seed:=13", "max_sim_time:=30")
    nodes = nodes_of(cfg)
    assert {(n.package, n.type) for n in nodes.values()} == {
        ("slam_predict", "stage_sim"), ("slam_predict", "slam_gmapping"),
        ("slam_predict", "move_base"), ("slam_predict", "explore"),
        ("slam_predict", "orchestrator")}
    p = {k: v.value for k, v in cfg.params.items()}
    assert p["/use_sim_time"] is True and p["/stage_sim/speedup"] == 0
    assert p["/stage_sim/seed"] == 11 and p["/slam_gmapping/seed"] == 12
    assert p["/explore/seed"] == 13
    assert p["/orchestrator/seed"] == "4000000000"      # beyond XML-RPC ints: a string
    assert p["/orchestrator/out"] == "/tmp/run_007" and p["/orchestrator/max_sim_time"] == 30.0
    assert p["/stage_sim/wait_for_service"] == "/orchestrator/ready"
    assert p["/orchestrator/wait_for_nodes"].split() == ["/slam_gmapping", "/move_base",
                                                         "/explore"]
    assert p["/slam_gmapping/particles"] == 40           # config/gmapping.yaml
    assert nodes["orchestrator"].required
    assert ["scan", "base_scan"] in nodes["slam_gmapping"].remap_args
    # the whole graph in lockstep: stage_sim waits for each of our nodes' ~sim_ack (and for
    # move_base's ~scan_ack: its costmaps hold every scan)
    assert _ack_list(p["/stage_sim/lockstep_acks"]) == (
        ("/slam_gmapping/sim_ack", None), ("/move_base/sim_ack", 0.0),
        ("/move_base/scan_ack", None), ("/explore/sim_ack", 0.0))


def test_lockstep_acks_follow_the_component_choices():
    for choices, expected in (
            (["nav:=none", "explore:=none"], (("/slam_gmapping/sim_ack", None),)),
            (["nav:=move_base", "explore:=explore_lite"], (("/slam_gmapping/sim_ack", None),)),
            (["slam:=gmapping"], (("/move_base/sim_ack", 0.0), ("/move_base/scan_ack", None),
                                  ("/explore/sim_ack", 0.0))),
            (["slam:=none", "nav:=none", "explore:=none"], ())):
        cfg = config("single_run.launch", f"world:={WORLD}", "out:=/tmp/x", *choices)
        p = {k: v.value for k, v in cfg.params.items()}
        assert _ack_list(p["/stage_sim/lockstep_acks"]) == expected, choices


def test_real_package_branch_configuration():
    cfg = config("single_run.launch", f"world:={WORLD}", "out:=/tmp/x", *REAL)
    nodes = nodes_of(cfg)
    kinds = {name: (n.package, n.type) for name, n in nodes.items()}
    assert kinds == {"stageros": ("stage_ros", "stageros"),
                     "slam_gmapping": ("gmapping", "slam_gmapping"),
                     "move_base": ("move_base", "move_base"),
                     "explore": ("explore_lite", "explore"),
                     "orchestrator": ("slam_predict", "orchestrator")}
    assert nodes["stageros"].args == f"-g {WORLD}"
    for name in ("slam_gmapping", "move_base"):
        assert ["scan", "base_scan"] in nodes[name].remap_args
    p = {k: v.value for k, v in cfg.params.items()}
    assert p["/slam_gmapping/maxUrange"] == 30.0 and p["/slam_gmapping/particles"] == 40
    assert p["/move_base/controller_frequency"] == 10.0
    assert p["/move_base/global_costmap/global_frame"] == "map"
    assert p["/move_base/local_costmap/inflation_radius"] == 2.25
    assert p["/move_base/TrajectoryPlannerROS/max_vel_x"] == 0.85
    assert p["/explore/costmap_topic"] == "map"
    assert "/stage_sim/wait_for_service" not in p        # stageros cannot wait: no such param
    assert p["/orchestrator/sim"] == "stage" and p["/orchestrator/explore"] == "explore_lite"


def test_none_choices_for_a_real_robot():
    cfg = config("single_run.launch", "out:=/tmp/x", "sim:=none", "nav:=none", "explore:=none",
                 "ground_truth_source:=pose", "ground_truth_topic:=/robot/pose")
    assert set(nodes_of(cfg)) == {"slam_gmapping", "orchestrator"}
    p = {k: v.value for k, v in cfg.params.items()}
    assert p["/use_sim_time"] is False
    assert p["/orchestrator/ground_truth_source"] == "pose"
    assert p["/orchestrator/wait_for_nodes"].split() == ["/slam_gmapping"]


def test_an_unknown_choice_is_refused():
    out = cli("--nodes", "slam_predict", "single_run.launch", "out:=/x", "slam:=gmaping")
    assert out.returncode != 0 and "invalid_slam_choice" in out.stderr


def test_the_slam_back_end_reaches_our_node_and_the_real_package_runs_only_gmapping():
    p = {k: v.value for k, v in config("single_run.launch", f"world:={WORLD}", "out:=/tmp/x",
                                       "slam_type:=dummy").params.items()}
    assert p["/slam_gmapping/type"] == "dummy"
    p = {k: v.value for k, v in config("single_run.launch", f"world:={WORLD}",
                                       "out:=/tmp/x").params.items()}
    assert p["/slam_gmapping/type"] == "gmapping"
    out = cli("--nodes", "slam_predict", "single_run.launch", "out:=/x", "slam:=gmapping",
              "slam_type:=dummy")
    assert out.returncode != 0 and "invalid_slam_type" in out.stderr


def test_batch_launch_resolves_and_passes_its_args():
    out = cli("--args", "/batch_explore", "slam_predict", "batch_explore.launch",
              "worlds:=/w", "out:=/d")
    assert out.returncode == 0, out.stderr
    assert "/slam_predict/batch_explore" in out.stdout
    cfg = config("batch_explore.launch", "worlds:=/w", "out:=/d", "runs:=auto", *REAL)
    p = {k: v.value for k, v in cfg.params.items()}
    assert p["/batch_explore/runs"] == "auto" and p["/batch_explore/nav"] == "move_base"
    assert p["/batch_explore/sim"] == "stage" and p["/batch_explore/worlds"] == "/w"


def test_batch_launch_ends_itself_without_a_required_node():
    cfg = config("batch_explore.launch", "worlds:=/w", "out:=/d")
    assert not nodes_of(cfg)["batch_explore"].required
    assert cfg.params["/batch_explore/end_launch"].value is True


@pytest.mark.parametrize("choices, expected", [
    ([], ["/stage_sim", "/explore", "/move_base", "/slam_gmapping"]),
    (REAL, ["/stageros", "/explore", "/move_base", "/slam_gmapping"]),
    (["sim:=none", "nav:=none", "explore:=none"], ["/slam_gmapping"]),
])
def test_the_orchestrator_shuts_the_run_down_simulator_first(choices, expected):
    from slam_predict.ros.batch_runner import run_nodes

    cfg = config("single_run.launch", f"world:={WORLD}", "out:=/tmp/x", *choices)
    assert cfg.params["/orchestrator/shutdown_nodes"].value.split() == expected
    options = dict(choice.split(":=") for choice in choices)
    assert run_nodes(options) == expected   # what the batch uses when it ends a run itself


def test_every_launch_argument_is_documented():
    import xml.etree.ElementTree as ET

    for path in sorted((ROOT / "launch").glob("*.launch")):
        for arg in ET.parse(path).getroot().findall("arg"):
            assert arg.get("doc"), f"{path.name}: arg {arg.get('name')} has no doc="


@pytest.mark.parametrize("mode", ["sync", "async"])
def test_karto_runs_as_our_slam_toolbox_node(mode):
    cfg = config("single_run.launch", f"world:={WORLD}", "out:=/tmp/x", "slam_type:=karto",
                 f"karto_mode:={mode}", f"gmapping_config:={ROOT / 'config' / 'karto.yaml'}")
    node = nodes_of(cfg)["slam_toolbox"]
    assert (node.package, node.type) == ("slam_predict", f"{mode}_slam_toolbox_node")
    assert "slam_gmapping" not in nodes_of(cfg)
    p = {k: v.value for k, v in cfg.params.items()}
    assert p["/slam_toolbox/minimum_travel_distance"] == 0.5   # slam_toolbox's names
    assert p["/orchestrator/shutdown_nodes"].split()[-1] == "/slam_toolbox"
    assert "/slam_toolbox" in p["/orchestrator/wait_for_nodes"].split()
    acks = _ack_list(p["/stage_sim/lockstep_acks"])
    assert acks[0][0] == "/slam_toolbox/sim_ack"
    out = cli("--nodes", "slam_predict", "single_run.launch", "out:=/x", "slam_type:=karto",
              "karto_mode:=lifelong")
    assert out.returncode != 0 and "invalid_karto_mode" in out.stderr


def test_the_slam_toolbox_launch_file_runs_the_chosen_executable():
    for mode in ("sync", "async"):
        node = nodes_of(config("slam_toolbox.launch", f"mode:={mode}"))["slam_toolbox"]
        assert node.type == f"{mode}_slam_toolbox_node"
    p = {k: v.value for k, v in config("slam_toolbox.launch").params.items()}
    assert p["/slam_toolbox/type"] == "karto" and p["/slam_toolbox/scan_gate"] == "sync"


def test_batch_launch_passes_the_slam_type():
    cfg = config("batch_explore.launch", "worlds:=/w", "out:=/d", "slam_type:=karto")
    assert cfg.params["/batch_explore/slam_type"].value == "karto"
