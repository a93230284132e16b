"""`slam-predict collect` as a process: a signal stops it within seconds keeping the finished
runs, and a `kill -9` of a parallel collect leaves no worker behind."""
import csv
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
TINY = ROOT / "worlds" / "tiny.world"
STOP_WITHIN_S = 20.0   # generous: the machine running the tests may be loaded


def short_settings(folder: Path, max_sim_time_s: float = 25.0) -> Path:
    """A collect.yaml that ends every run after ``max_sim_time_s`` of sim time (the thesis
    explorer starts moving after 17 s: its 15 s start delay and 2 s selection pause)."""
    path = folder / "short.yaml"
    path.write_text(f"extends: {ROOT / 'config' / 'collect.yaml'}\n"
                    f"stop:\n  max_sim_time_s: {max_sim_time_s}\n")
    return path


def start_collect(tmp_path: Path, runs: int, jobs: int) -> subprocess.Popen:
    env = dict(os.environ, PYTHONPATH=str(ROOT / "src"))
    env.setdefault("NUMBA_CACHE_DIR", str(ROOT / ".numba_cache"))
    command = [sys.executable, "-m", "slam_predict.cli.main", "collect", str(TINY),
               "--runs", str(runs), "--jobs", str(jobs), "--out", str(tmp_path / "data"),
               "--settings", str(short_settings(tmp_path))]
    return subprocess.Popen(command, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True, start_new_session=True)


def wait_for(condition, proc: subprocess.Popen, timeout_s: float = 300.0) -> None:
    deadline = time.monotonic() + timeout_s
    while not condition():
        assert proc.poll() is None, proc.communicate()
        assert time.monotonic() < deadline, "timed out"
        time.sleep(0.05)


def group_members(pgid: int):
    """Pids of live (non-zombie) processes in process group ``pgid``."""
    members = []
    for entry in Path("/proc").iterdir():
        if not entry.name.isdigit():
            continue
        try:
            stat = (entry / "stat").read_text()
        except OSError:
            continue
        fields = stat[stat.rindex(")") + 2:].split()
        if int(fields[2]) == pgid and fields[0] != "Z":
            members.append(int(entry.name))
    return members


@pytest.mark.parametrize("signum, jobs", [(signal.SIGINT, 1), (signal.SIGTERM, 2)])
def test_signal_stops_collect_keeping_finished_runs(tmp_path, signum, jobs):
    data = tmp_path / "data"
    proc = start_collect(tmp_path, runs=3, jobs=jobs)
    try:
        wait_for(lambda: list(data.glob("tiny/run_*/run.json")), proc)
        wait_for(lambda: list(data.glob("tiny/.run_*.tmp")), proc)  # a run in progress
        proc.send_signal(signum)
        sent = time.monotonic()
        out, err = proc.communicate(timeout=STOP_WITHIN_S)
        assert time.monotonic() - sent < STOP_WITHIN_S
    finally:
        if group_members(proc.pid):
            os.killpg(proc.pid, signal.SIGKILL)
    assert proc.returncode == 128 + signum, err
    assert "Traceback" not in err
    finished = sorted(p.parent.name for p in data.glob("tiny/run_*/run.json"))
    assert 1 <= len(finished) < 3
    assert sorted(p.name for p in (data / "tiny").iterdir()) == finished  # no partial folder
    rows = list(csv.DictReader(open(data / "summary.csv")))
    assert [(r["world"], int(r["runs"])) for r in rows] == [("tiny", len(finished))]
    assert f"{len(finished)} run{'' if len(finished) == 1 else 's'} done" in out
    if jobs == 1:
        assert "1/3" in err  # the progress bar advanced per finished run


def test_kill_9_of_parallel_collect_leaves_no_worker(tmp_path):
    proc = start_collect(tmp_path, runs=4, jobs=2)
    try:
        wait_for(lambda: len(group_members(proc.pid)) >= 3, proc)  # the parent + 2 workers
        wait_for(lambda: list((tmp_path / "data").glob("tiny/.run_*.tmp")), proc)
        proc.kill()
        proc.wait()
        deadline = time.monotonic() + 10.0
        while group_members(proc.pid) and time.monotonic() < deadline:
            time.sleep(0.1)
        survivors = group_members(proc.pid)
    finally:
        if group_members(proc.pid):
            os.killpg(proc.pid, signal.SIGKILL)
    assert survivors == []
