"""A SLAM back-end beside collected routes (``slam-predict slam beside``).

Every run of a collected campaign that kept its sensor log (``sensors.bag``) is a route: the
scans, odometry and ground truth of a robot that explored a building on its own SLAM map. The
back-end of ``S`` (``slam:``, with its real-time scan gate or ``slam_compute``) processes the
route's scans as its ROS node would, and the pose it publishes at every scan (map → odom as it
stood, composed with the odometry: what the closed loop records each step) is measured with the
run's metric settings and seed. The back-end never steers the robot: a false loop closure raises
its error but does not end the exploration. This is how the later study of the seed study's
group compared GMapping and slam_toolbox (the robot drove without the SLAM map in the loop;
docs/karto.md "Karto beside GMapping's routes"), and it puts two algorithms on the same routes.

Each route's record goes to ``DIR/<world>/<run>/run.json`` (with ``slam.tum`` and the back-end's
final map), written atomically: the route's fields (world, seed, robot, coverage, path, stop)
with the back-end's ``slam``, ``config_hashes``, ``metric`` and its own map's coverage
(``map_coverage``), and ``route`` naming the run it replayed. ``S`` must describe the same chain
as the routes' runs (simulator, navigation, explorer, stop rule and metric hashes equal), so the
beside back-end is measured on the chain it is named with. Finished runs are not redone; the
folder's summary.csv is regenerated at the end.
"""
from __future__ import annotations

import json
import logging
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from slam_predict.atomic import atomic_dir
from slam_predict.collect import record as rec
from slam_predict.collect.sensorlog import SENSOR_BAG
from slam_predict.collect.store import RUN_JSON, RunStore
from slam_predict.collect.summary import write_summary
from slam_predict.errors import InputError
from slam_predict.formats.tum import write_tum
from slam_predict.paths import PROJECT_ROOT, portable_path

LOG = logging.getLogger(__name__)
# the parts of the chain a route and its beside back-end must share (config_hashes keys)
CHAIN_KEYS = ("sim", "nav", "explore", "stop", "metric")
# route fields copied into the beside record as they are
ROUTE_FIELDS = ("world", "world_file", "run_index", "seed", "odometry_model", "ranger_model",
                "odometry_error", "sensor", "stop_reason", "explorer_end", "sim_duration_s",
                "distance_m", "rotation_rad", "coverage", "coverage_swept", "stalls",
                "free_area_m2", "stuck", "snapshots", "design")


@dataclass
class Route:
    """One collected run to replay: its folder (``<world>/<run>``) and its run.json."""

    folder: Path
    record: dict

    @property
    def key(self) -> tuple[str, str]:
        """(world, run folder name): where its beside record goes."""
        return self.folder.parent.name, self.folder.name


def find_routes(routes_dir: Path) -> list[Route]:
    """The complete runs below ``routes_dir`` that kept a sensor bag, by world and index."""
    store = RunStore(Path(routes_dir))
    if not Path(routes_dir).is_dir():
        raise InputError("no such campaign folder", routes_dir)
    routes = []
    for world in store.worlds():
        for index in store.completed(world):
            folder = store.run_dir(world, index)
            if (folder / SENSOR_BAG).is_file():
                routes.append(Route(folder, json.loads((folder / RUN_JSON).read_text())))
    if not routes:
        raise InputError("no collected run with a sensor log (sensors.bag) below it; collect "
                         "with sensor_logs: true", routes_dir)
    return routes


def check_same_chain(route: Route, settings) -> None:
    """InputError unless ``settings`` has the route's simulator, navigation, explorer, stop rule
    and metric (their config hashes)."""
    mine, theirs = settings.hashes(), route.record.get("config_hashes") or {}
    differ = [k for k in CHAIN_KEYS if mine.get(k) != theirs.get(k)]
    if differ:
        raise InputError(f"{settings.source}: its {', '.join(differ)} differ from the chain "
                         f"that collected this run (config_hashes); a beside back-end must run "
                         f"on the routes' own chain", route.folder / RUN_JSON)


def replay(route: Route, settings):
    """The settings' back-end over the route's sensor bag (its SLAM generator from the route's
    seed, as a collected run draws it): a :class:`~slam_predict.slam.runner.RunResult` and the
    input."""
    from slam_predict.slam import runner

    data = runner.read_input(route.folder / SENSOR_BAG)
    if data.reference is None:
        raise InputError("sensor bag has no ground truth", route.folder / SENSOR_BAG)
    seed = int(route.record["seed"])
    result = runner.run(data, settings.slam.type, settings.slam.params, seed,
                        rng=runner.in_loop_slam_rng(seed),
                        compute=settings.compute)
    return result, data


def map_coverage(route: Route, settings, grid) -> float | None:
    """Coverage of the reachable floor by the back-end's final map (None without the world)."""
    from slam_predict.explore.coverage import coverage, reachable_free
    from slam_predict.nav.costmap import inscribed_radius
    from slam_predict.world.load import load_plan

    world_file = route.record.get("world_file") or ""
    path = PROJECT_ROOT / world_file   # a portable path: relative to the project, or absolute
    if not world_file or not path.is_file():
        LOG.warning("%s: world file %s not found; map_coverage left out", route.folder,
                    world_file)
        return None
    world = load_plan(str(path))
    reach = reachable_free(world, inscribed_radius(settings.nav.global_costmap))
    return float(coverage(world, grid, reach, np.array(world.start_pose, dtype=float)))


def beside_record(route: Route, settings, result, data, cpu_s: float,
                  coverage_of_map: float | None) -> dict:
    """run.json of one beside run: the route's fields, the back-end's measurement."""
    traj = rec.Trajectories(np.asarray(data.times), np.asarray(data.reference),
                            result.online, np.asarray(data.odometry))
    metric = rec.measure(traj, settings, int(route.record["seed"]))
    out = {k: route.record[k] for k in ROUTE_FIELDS if k in route.record}
    stats = result.stats
    out.update({
        "code_version": rec.code_version(), "config_hashes": settings.hashes(),
        "slam": settings.slam.record(), "settings_file": portable_path(settings.source),
        "route": {"run": "/".join(route.key), "slam": (route.record.get("slam") or {}).get("type"),
                  "config_hashes": route.record.get("config_hashes"),
                  "settings_file": route.record.get("settings_file"),
                  "code_version": route.record.get("code_version")},
        "map_coverage": coverage_of_map, "scans_processed": int(stats["scans_processed"]),
        "metric": metric, "wall_time_s": float(stats["wall_s"]), "timing": {"cpu_s": cpu_s},
    })
    if metric is None:
        out["metric_note"] = rec.NO_METRIC_NOTE
    if "loop_closures" in stats:
        out["loop_closures"] = len(stats["loop_closures"])
    if "async" in stats:
        out["slam_async"] = stats["async"]
    if "slam_compute" in stats:
        out["slam_compute"] = stats["slam_compute"]
    return out


def run_beside(route: Route, settings, out_dir: Path) -> dict:
    """Replay one route and write its beside run folder (atomically); returns its record."""
    cpu0 = time.process_time()
    result, data = replay(route, settings)
    cov = map_coverage(route, settings, result.grid)
    record = beside_record(route, settings, result, data, round(time.process_time() - cpu0, 3),
                           cov)
    with atomic_dir(out_dir) as folder:
        rec.write_map(folder, result.grid.data, result.grid.resolution, result.grid.origin)
        write_tum(folder / "slam.tum", data.times, result.online,
                  header=[f"{settings.slam.type} beside {'/'.join(route.key)}"])
        rec.write_run_json(folder, record)
    return record


def _job(args: tuple) -> tuple[Route, float | None]:
    route, settings, out_dir = args
    done = run_beside(route, settings, Path(out_dir))
    return route, (done["metric"] or {}).get("trans_mean")


def _progress_line(route: Route, trans: float | None, slam_type: str) -> str:
    """'<world>/<run>: karto ε_t 0.112 m, the route's gmapping 0.112 m'."""
    theirs = (route.record.get("metric") or {}).get("trans_mean")
    route_slam = (route.record.get("slam") or {}).get("type", "route")
    mine = "no metric" if trans is None else f"ε_t {trans:.3f} m"
    line = f"{'/'.join(route.key)}: {slam_type} {mine}"
    return line if theirs is None else f"{line}, the route's {route_slam} {theirs:.3f} m"


def beside_campaign(routes_dir: Path, settings, out_dir: Path, jobs: int = 1,
                    progress: Callable[[str], None] | None = None) -> int:
    """Replay every route of ``routes_dir`` not yet in ``out_dir``; returns how many ran."""
    routes = find_routes(routes_dir)
    for route in routes:
        check_same_chain(route, settings)
    store = RunStore(Path(out_dir))
    with store.lock():
        store.remove_leftovers()
        _check_resume(store, settings)
        dest = {r.key: Path(out_dir).joinpath(*r.key) for r in routes}
        todo = [r for r in routes if not (dest[r.key] / RUN_JSON).is_file()]
        for route, trans in _map([(r, settings, dest[r.key]) for r in todo], jobs):
            if progress is not None:
                progress(_progress_line(route, trans, settings.slam.type))
        if todo or not (Path(out_dir) / "summary.csv").is_file():
            write_summary(Path(out_dir))
    return len(todo)


def _map(args: list, jobs: int):
    if jobs <= 1 or len(args) <= 1:
        yield from map(_job, args)
        return
    from concurrent.futures import ProcessPoolExecutor, as_completed

    with ProcessPoolExecutor(max_workers=jobs) as pool:
        for future in as_completed([pool.submit(_job, a) for a in args]):
            yield future.result()


def _check_resume(store: RunStore, settings) -> None:
    """InputError when ``store`` already holds beside runs of other settings."""
    mine = settings.hashes()
    for world in store.worlds():
        for record in store.records(world):
            if record.get("config_hashes") != mine:
                raise InputError("--out holds runs of other settings (config_hashes differ); "
                                 "use a new folder", store.root / world)
