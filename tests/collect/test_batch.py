"""Batches: scheduling, resume after SIGKILL, auto run counts, Dask, summary table."""
import csv
import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from slam_predict.collect.batch import Batch, BatchConfig
from slam_predict.collect.store import RunStore, run_seed
from slam_predict.collect.summary import COLUMNS, write_summary

HERE = Path(__file__).resolve().parent
FAKE = "fake_episode:run_episode"
WORLDS = {"alpha": "alpha.world", "beta": "beta.world"}


@pytest.fixture(autouse=True)
def importable_fake(monkeypatch):
    monkeypatch.syspath_prepend(str(HERE))
    monkeypatch.setenv("PYTHONPATH", os.pathsep.join([str(HERE), os.environ.get("PYTHONPATH", "")]))


def snapshot(root: Path):
    """Run records minus timing fields, for comparing two campaigns."""
    out = {}
    for path in sorted(root.glob("*/run_*/run.json")):
        record = json.loads(path.read_text())
        record.pop("wall_time_s")
        out[str(path.relative_to(root))] = record
    return out


def test_fixed_runs_and_summary(tmp_path):
    batch = Batch(WORLDS, tmp_path, BatchConfig(runs=3, episode=FAKE, progress=False))
    assert batch.run() == 6
    assert RunStore(tmp_path).completed("alpha") == [0, 1, 2]
    assert Batch(WORLDS, tmp_path, BatchConfig(runs=3, episode=FAKE)).pending() == []
    rows = list(csv.DictReader(open(write_summary(tmp_path))))
    assert [r["world"] for r in rows] == ["alpha", "beta"]
    assert tuple(rows[0]) == COLUMNS and rows[0]["runs"] == "3"
    trans = [json.loads(p.read_text())["metric"]["trans_mean"]
             for p in sorted((tmp_path / "alpha").glob("run_*/run.json"))]
    assert np.isclose(float(rows[0]["trans_mean"]), np.mean(trans))
    assert np.isclose(float(rows[0]["trans_std"]), np.std(trans))


def test_seeds_are_deterministic_and_distinct():
    assert run_seed(0, "alpha", 1) == run_seed(0, "alpha", 1)
    assert len({run_seed(0, w, i) for w in WORLDS for i in range(20)}) == 40


def test_local_processes_give_same_records(tmp_path):
    Batch(WORLDS, tmp_path / "a", BatchConfig(runs=2, episode=FAKE, progress=False)).run()
    Batch(WORLDS, tmp_path / "b", BatchConfig(runs=2, jobs=2, episode=FAKE, progress=False)).run()
    a, b = snapshot(tmp_path / "a"), snapshot(tmp_path / "b")
    assert a == b and len(a) == 4


def test_resume_after_sigkill(tmp_path):
    script = (f"from slam_predict.collect.batch import Batch, BatchConfig\n"
              f"Batch({WORLDS!r}, {str(tmp_path / 'killed')!r}, "
              f"BatchConfig(runs=4, episode={FAKE!r}, progress=False)).run()\n")
    env = dict(os.environ, FAKE_EPISODE_SLEEP="0.5")
    proc = subprocess.Popen([sys.executable, "-c", script], env=env, start_new_session=True)
    deadline = time.time() + 60
    while len(list((tmp_path / "killed").glob("*/run_*/run.json"))) < 3:
        assert time.time() < deadline and proc.poll() is None
        time.sleep(0.05)
    os.killpg(proc.pid, signal.SIGKILL)
    proc.wait()
    partial = snapshot(tmp_path / "killed")
    assert 3 <= len(partial) < 8
    Batch(WORLDS, tmp_path / "killed", BatchConfig(runs=4, episode=FAKE, progress=False)).run()
    Batch(WORLDS, tmp_path / "clean", BatchConfig(runs=4, episode=FAKE, progress=False)).run()
    resumed, clean = snapshot(tmp_path / "killed"), snapshot(tmp_path / "clean")
    assert resumed == clean and len(clean) == 8
    assert not list((tmp_path / "killed").glob("*/.run_*"))
    for name, record in partial.items():
        assert resumed[name] == record  # finished runs were kept, not redone


def test_auto_run_count_uses_estimate(tmp_path):
    calls = []

    def needed(records, done):
        calls.append(done)
        return 13

    batch = Batch({"alpha": "a.world"}, tmp_path,
                  BatchConfig(runs="auto", pilot_runs=10, max_runs=50, episode=FAKE,
                              progress=False), runs_needed=needed)
    assert batch.run() == 13
    assert RunStore(tmp_path).completed("alpha") == list(range(13))
    assert calls[0] == 10


def test_dask_local_cluster(tmp_path):
    distributed = pytest.importorskip("dask.distributed")
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster:
        config = BatchConfig(runs=1, episode=FAKE, progress=False,
                             scheduler=cluster.scheduler_address)
        assert Batch(WORLDS, tmp_path, config).run() == 2
    assert len(snapshot(tmp_path)) == 2


def test_second_batch_on_a_folder_in_use_is_refused_and_touches_nothing(tmp_path):
    from slam_predict.errors import InputError

    in_progress = tmp_path / "alpha" / ".run_001.abcd.tmp"
    in_progress.mkdir(parents=True)
    with RunStore(tmp_path).lock():  # a first batch holds the folder
        batch = Batch(WORLDS, tmp_path, BatchConfig(runs=2, episode=FAKE, progress=False))
        with pytest.raises(InputError) as caught:
            batch.run()
        assert str(tmp_path) in str(caught.value) and f"pid {os.getpid()}" in str(caught.value)
        assert "\n" not in str(caught.value)
        assert in_progress.is_dir()                      # its run in progress is left alone
        assert RunStore(tmp_path).completed("alpha") == []
    # once released, the folder is free again: the leftover goes and the runs are done
    assert batch.run() == 4 and not in_progress.exists()


def test_lock_of_a_killed_batch_does_not_block(tmp_path):
    code = ("import os, sys; from slam_predict.collect.store import RunStore\n"
            "with RunStore(sys.argv[1]).lock():\n    os.kill(os.getpid(), 9)\n")
    subprocess.run([sys.executable, "-c", code, str(tmp_path)], check=False)
    assert (tmp_path / ".collect.lock").exists()
    with RunStore(tmp_path).lock():
        pass
