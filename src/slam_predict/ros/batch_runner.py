"""``batch_explore``: a batch of exploration runs through the ROS graph, one launch per run.

The batch logic is the in-process one (:class:`slam_predict.collect.batch.Batch`: worlds × runs,
``runs: auto`` estimation, per-run seeds, resume — finished runs are never redone, an
interrupted run's temporary folder is removed and the run redone); only the episode differs:
:func:`launch_episode` starts ``single_run.launch`` with the roslaunch Python API
(``ROSLaunchParent``), waits until its orchestrator has written the record and shut the run's
nodes down in order (simulator first: no process is killed) and returns run.json.
``DATA/summary.csv`` is regenerated at the end (:func:`slam_predict.collect.summary.write_summary`);
SIGINT/SIGTERM end the batch after the run in progress is shut down and discarded. With
``~end_launch`` the node then ends the roslaunch that started it, as Ctrl-C would, so
batch_explore.launch finishes without a "REQUIRED process has died".

Node choices (launch args ``sim``, ``slam``, ``nav``, ``explore``): ``slam_predict`` (our nodes,
the default), the real packages ``stage`` (stage_ros/stageros), ``gmapping``
(gmapping/slam_gmapping), ``move_base`` (move_base/move_base), ``explore_lite``
(explore_lite/explore), or ``none`` (started elsewhere, e.g. on a real robot). The SLAM
back-end is the settings' ``slam.type``; launch arg ``slam_type`` (``gmapping`` or ``karto``, also
``slam_toolbox``) picks the back-end's shipped settings when ``settings`` is empty and must agree
with it otherwise. Karto runs as our ``/slam_toolbox`` node (``sync_slam_toolbox_node``, or
``async_slam_toolbox_node`` for the settings' ``scan_gate`` async or none).

Seeds: run ``i`` of world ``w`` gets ``run_seed(base_seed, w, i)`` (as the in-process batch);
the simulator, explorer and SLAM nodes get the three children of ``SeedSequence(seed)`` in the
in-process loop's order, as 31-bit integers (XML-RPC ints are signed 32-bit; the run seed
itself is passed as a string).
"""
from __future__ import annotations

import logging
import time
from pathlib import Path

import numpy as np

from slam_predict.errors import InputError, did_you_mean

LOG = logging.getLogger(__name__)
PACKAGE, LAUNCH = "slam_predict", "single_run.launch"
CHOICES = {
    "sim": ("slam_predict", "stage", "none"),
    "slam": ("slam_predict", "gmapping", "none"),
    "nav": ("slam_predict", "move_base", "none"),
    "explore": ("slam_predict", "explore_lite", "none"),
}
# options passed through to single_run.launch as name:=value when set
PASS_THROUGH = ("max_sim_time", "max_wall_time", "snapshot_interval",
                "ground_truth_source", "ground_truth_topic", "ground_truth_frame",
                "ground_truth_fixed_frame", "speedup",
                "odom_model", "orchestrator_config")
ROS_HINT = " (use a new out:= folder, or force:=true to continue with the new ones)"
RUN_TIMEOUT_MARGIN_S = 300.0
NODE_EXIT_TIMEOUT_S = 40.0   # wall s a node gets to exit when the batch ends a run itself
END_GRACE_S = 4 * NODE_EXIT_TIMEOUT_S + 30.0  # wall s after the record for the ordered shutdown
PROCESS_EXIT_WAIT_S = 10.0  # wall s for processes that left the graph to exit before a kill


def node_seeds(seed: int) -> dict[str, int]:
    """Seeds of the simulator, explorer and SLAM nodes of a run (in-process loop's order)."""
    children = np.random.SeedSequence(int(seed)).spawn(3)
    return {name: int(child.generate_state(1)[0] >> 1)  # 31 bits: an XML-RPC int param
            for name, child in zip(("sim_seed", "explore_seed", "slam_seed"), children,
                                   strict=False)}


def check_choices(options: dict) -> None:
    """InputError for an unknown node choice (one line, with a did-you-mean hint)."""
    for key, allowed in CHOICES.items():
        value = str(options.get(key, "slam_predict"))
        if value not in allowed:
            raise InputError(f"{key}:={value} is not one of {', '.join(allowed)}"
                             + did_you_mean(value, allowed))


def find_worlds(path: str) -> dict[str, str]:
    """World name → file: every ``*.world`` in a folder (sorted), or one world file."""
    p = Path(path).expanduser()
    if p.is_dir():
        files = sorted(p.glob("*.world"))
        if not files:
            raise InputError("no *.world files in this folder", str(p))
    elif p.is_file():
        files = [p]
    else:
        raise InputError("no such world file or folder", str(p))
    return {f.stem: str(f.resolve()) for f in files}


def component_configs(settings_path=None) -> dict[str, str]:
    """The node config files a collect.yaml names (absolute), as single_run.launch args, so
    the nodes run with the configs whose hashes the record states. ``sim_overrides`` are
    merged into a robot file written beside the settings' cache (the node reads one file),
    ``nav_overrides`` into a copy of the navigation folder, ``explore_overrides`` into a copy of
    the explore file."""
    from slam_predict.collect.settings import DEFAULT_SETTINGS, CollectFiles, read_settings_tree
    from slam_predict.collect.settings_files import (
        merged_explore_file,
        merged_nav_folder,
        merged_robot_file,
        slam_params_file,
    )
    from slam_predict.config import from_dict

    path = Path(settings_path or DEFAULT_SETTINGS).resolve()
    tree = read_settings_tree(path)
    from_dict(CollectFiles, tree, str(path))   # unknown keys: InputError with a did-you-mean
    robot = tree["robot"]
    if tree.get("sim_overrides"):
        robot = str(merged_robot_file(path, tree))
    navigation = tree["navigation"]
    if tree.get("nav_overrides"):
        navigation = str(merged_nav_folder(tree))
    explore = tree["explore"]
    if tree.get("explore_overrides"):
        explore = str(merged_explore_file(path, tree))
    slam_type = tree["slam"]["type"]
    karto = {"karto_mode": karto_mode(path)} if slam_type == "karto" else {}
    return {"settings": str(path), "robot_config": robot,
            "gmapping_config": str(slam_params_file(path, tree)),
            "slam_type": slam_type, **karto,
            "nav_config_dir": str(Path(navigation).resolve()),
            "explore_config": explore}


def karto_mode(settings_path) -> str:
    """``async`` (async_slam_toolbox_node) when the settings' Karto ``scan_gate`` is async or
    none, else ``sync`` (sync_slam_toolbox_node)."""
    from slam_predict.collect.settings import load_settings

    gate = load_settings(settings_path).slam.params.scan_gate
    return "async" if gate in ("async", "none") else "sync"


def slam_node(options: dict) -> str:
    """The SLAM node's name for these choices: /slam_toolbox for our Karto, else
    /slam_gmapping."""
    if options.get("slam", "slam_predict") != "slam_predict":
        return "/slam_gmapping"
    configs = component_configs(options.get("settings") or None)
    return "/slam_toolbox" if configs["slam_type"] == "karto" else "/slam_gmapping"


def resolve_slam_type(options: dict) -> None:
    """Apply launch arg ``slam_type`` to ``options``: the back-end's shipped settings when
    none are given (InputError when given settings name another back-end)."""
    from slam_predict.collect.settings import settings_for_slam

    name = options.pop("slam_type", "") or None
    settings = settings_for_slam(name, options.get("settings") or None, "slam_type:=")
    if settings:
        options["settings"] = str(settings)


def launch_arguments(spec) -> list[str]:
    """``name:=value`` arguments of single_run.launch for a :class:`RunSpec`."""
    options = spec.options
    args = {"world": spec.world_path, "world_name": spec.world, "run_index": spec.index,
            "seed": spec.seed, "out": spec.out_dir, **node_seeds(spec.seed),
            **component_configs(options.get("settings") or None)}
    for key in CHOICES:
        args[key] = options.get(key, "slam_predict")
    for key in PASS_THROUGH:
        if options.get(key) not in (None, ""):
            args[key] = options[key]
    return [f"{k}:={v}" for k, v in args.items()]


def run_nodes(options: dict) -> list[str]:
    """The nodes single_run.launch starts for these choices, in shutdown order (simulator
    first, then explorer, navigation, SLAM; the orchestrator ends itself)."""
    names = {"sim": {"slam_predict": "/stage_sim", "stage": "/stageros"},
             "explore": {"slam_predict": "/explore", "explore_lite": "/explore"},
             "nav": {"slam_predict": "/move_base", "move_base": "/move_base"},
             "slam": {"slam_predict": slam_node(options), "gmapping": "/slam_gmapping"}}
    return [names[key][options.get(key, "slam_predict")] for key in names
            if options.get(key, "slam_predict") in names[key]]


def launch_episode(spec) -> dict:
    """One run through the ROS graph (the batch's episode function); returns run.json.

    The run ends when the orchestrator has written the record and shut the run's nodes down in
    order (every process of the run's launch has exited). A stop request (SIGINT/SIGTERM of the
    batch) or the run timeout shuts the nodes down in the same order and ends the launch.

    Raises RuntimeError when the run ended without a record (a node died, the run timed out),
    :class:`~slam_predict.collect.interrupt.Interrupted` when the batch was asked to stop.
    """
    import json

    import roslaunch
    import roslib

    from slam_predict.collect import interrupt

    check_choices(spec.options)
    # keep this process's SIGINT/SIGTERM handlers (the batch's stop flag): a non-interactive
    # roslaunch would take them over and kill the run's nodes itself (SIGINT, then SIGKILL)
    roslib.set_interactive(True)
    path = spec.options.get("launch_file") or roslaunch.rlutil.resolve_launch_arguments(
        [PACKAGE, LAUNCH])[0]
    uuid = roslaunch.rlutil.get_or_generate_uuid(None, False)
    arguments = launch_arguments(spec) + ["orchestrator_required:=false"]
    parent = roslaunch.parent.ROSLaunchParent(uuid, [(path, arguments)],
                                              is_core=False, show_summary=False)
    timeout = float(spec.options.get("run_timeout") or 0) or _default_timeout(spec.options)
    started = time.monotonic()
    run_json = Path(spec.out_dir) / "run.json"
    parent.start()
    ended = "error"
    try:
        ended = _wait_for_run_end(parent, run_json, started, timeout, spec)
    finally:
        if not parent.runner.pm.is_shutdown:
            from slam_predict.ros.node_shutdown import end_run_graph
            end_run_graph(["/orchestrator", *run_nodes(spec.options)], NODE_EXIT_TIMEOUT_S,
                          caller="/batch_explore", reason=f"batch_explore: run {ended}")
            _wait_until(lambda: parent.runner.pm.is_shutdown, PROCESS_EXIT_WAIT_S)
        parent.shutdown()
    wall = time.monotonic() - started
    if ended == "stop":
        raise interrupt.Interrupted("the batch was asked to stop")
    if not run_json.is_file():
        raise RuntimeError(f"run ended after {wall:.0f} s wall without a record in {spec.out_dir}"
                           " (see the nodes' logs in ~/.ros/log)")
    LOG.info("%s run %d: %.1f s wall including launch and shutdown", spec.world, spec.index, wall)
    return json.loads(run_json.read_text())


def _wait_for_run_end(parent, run_json: Path, started: float, timeout: float, spec) -> str:
    """Spin the run's launch until every process exited ('ended'), a stop request ('stop'),
    the run timeout, or nodes left running long after the record was written ('timeout')."""
    from slam_predict.collect import interrupt

    recorded_at = None
    while not parent.runner.pm.is_shutdown:
        if interrupt.stop_signal() is not None or _interrupted():
            return "stop"
        now = time.monotonic()
        if now - started > timeout:
            LOG.error("%s run %d: no record after %.0f s wall: stopping it", spec.world,
                      spec.index, timeout)
            return "timeout"
        if recorded_at is None and run_json.is_file():
            recorded_at = now
        if recorded_at is not None and now - recorded_at > END_GRACE_S:
            LOG.warning("%s run %d: nodes still running %.0f s after the record: stopping them",
                        spec.world, spec.index, END_GRACE_S)
            return "timeout"
        time.sleep(0.1)   # no parent.spin_once(): it would re-take the signal handlers
    return "ended"


def _wait_until(condition, timeout_s: float, poll_s: float = 0.1) -> bool:
    """Poll ``condition`` for up to ``timeout_s`` wall seconds; returns its last value."""
    deadline = time.monotonic() + timeout_s
    while not condition() and time.monotonic() < deadline:
        time.sleep(poll_s)
    return bool(condition())


def _interrupted() -> bool:
    try:
        import rospy
        return rospy.core.is_initialized() and rospy.is_shutdown()
    except ImportError:
        return False


def _default_timeout(options: dict) -> float:
    """Per-run wall limit: the stop rule's wall-clock limit plus a margin for launch/shutdown."""
    wall = float(options.get("max_wall_time") or 0)
    if wall <= 0:
        from slam_predict.collect.settings import load_settings
        wall = load_settings(options.get("settings") or None).stop.max_wall_time_s
    return wall + RUN_TIMEOUT_MARGIN_S


def ros_identity(options: dict) -> dict:
    """What a batch's runs depend on beyond the settings and the seed: the node choices and the
    launch options passed through to every run."""
    chosen = {key: str(options.get(key, "slam_predict")) for key in CHOICES}
    passed = {key: _text(options[key]) for key in PASS_THROUGH
              if options.get(key) not in (None, "")}
    return {**chosen, **passed}


def _text(value) -> str:
    """A launch option as text; numbers as floats, so 45 (rosrun) and 45.0 (a launch file's
    double) are the same option."""
    if isinstance(value, (int, float)) and not isinstance(value, bool):
        return repr(float(value))
    return str(value)


def open_ros_campaign(out: Path, options: dict, base_seed: int) -> dict:
    """Write or check ``out``/campaign.json as ``collect`` does (base seed, resolved settings)
    plus the batch's ``ros`` identity; a resume with another seed, other settings or other
    nodes is refused (:class:`~slam_predict.collect.campaign.CampaignMismatch`, exit 2)
    unless ``options['force']``."""
    from slam_predict.collect.campaign import check_out_folder, identity, open_campaign
    from slam_predict.collect.record import code_version
    from slam_predict.collect.settings import load_settings

    check_out_folder(out)
    current = identity(load_settings(options.get("settings") or None), base_seed,
                       code_version())
    current["ros"] = ros_identity(options)
    out.mkdir(parents=True, exist_ok=True)
    return open_campaign(out, current, force=_true(options.get("force")), hint=ROS_HINT)


def _true(value) -> bool:
    """A launch-file boolean (a bool, or the text true/1/yes)."""
    return value is True or str(value).strip().lower() in ("true", "1", "yes")


def run_batch(worlds: str, runs, out: str, options: dict, base_seed: int = 0,
              max_runs: int = 50) -> int:
    """Run (or resume) the batch; returns the exit code: 0, 1 when runs failed, or 128 + the
    signal number when SIGINT/SIGTERM stopped it."""
    from slam_predict.collect.batch import Batch, BatchConfig
    from slam_predict.collect.summary import write_summary
    from slam_predict.words import plural

    check_choices(options)
    resolve_slam_type(options)
    open_ros_campaign(Path(out), options, base_seed)
    runs = runs if runs == "auto" else int(runs)
    config = BatchConfig(runs=runs, max_runs=max_runs, jobs=1, base_seed=base_seed,
                         progress=False, episode="slam_predict.ros.batch_runner:launch_episode",
                         options=dict(options))
    batch = Batch(find_worlds(worlds), out, config)
    done = batch.run()
    path = write_summary(Path(out))
    LOG.info("%s done, %d failed; summary %s", plural(done, "run"), len(batch.failures), path)
    for failure in batch.failures:
        LOG.error("failed: %s", failure)
    if batch.stopped_by is not None:
        LOG.warning("stopped by signal %d: the run in progress was discarded", batch.stopped_by)
        return 128 + batch.stopped_by
    return 1 if batch.failures else 0


def end_parent_launch() -> bool:
    """SIGINT to the roslaunch that started this node (as Ctrl-C: it stops its nodes and
    exits); nothing when the parent is not roslaunch (rosrun, rostest). True when sent."""
    import os
    import signal

    parent = os.getppid()
    try:
        command = Path(f"/proc/{parent}/cmdline").read_bytes().split(b"\0")
    except OSError:
        return False
    if not any(Path(part.decode(errors="replace")).name == "roslaunch" for part in command[:2]):
        return False
    os.kill(parent, signal.SIGINT)
    return True


def main(argv=None) -> int:
    """Node entry point: ~worlds, ~runs, ~out, ~base_seed, ~max_runs, ~end_launch and the run
    options."""
    import rospy

    from slam_predict.ros.rosout import forward_logging

    rospy.init_node("batch_explore", argv=argv)
    forward_logging(rospy)
    get = rospy.get_param
    options = {key: get(f"~{key}", "slam_predict") for key in CHOICES}
    for key in PASS_THROUGH + ("settings", "slam_type", "run_timeout", "launch_file", "force"):
        value = get(f"~{key}", "")
        if value not in ("", None):
            options[key] = value
    try:
        code = run_batch(str(get("~worlds")), get("~runs", 1), str(get("~out")), options,
                         int(get("~base_seed", 0)), int(get("~max_runs", 50)))
    except InputError as exc:
        rospy.logfatal("batch_explore: %s", exc.one_line())
        code = 2
    except KeyError as exc:
        rospy.logfatal("batch_explore: parameter %s is not set", exc)
        code = 2
    if get("~end_launch", False) and end_parent_launch():
        rospy.loginfo("batch_explore: done; ending the launch")
    return code
