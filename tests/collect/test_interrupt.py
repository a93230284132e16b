"""Stop flag and signals: a batch stops at the next control step, runs are executed lazily."""
import os
import signal
import subprocess
import sys
from pathlib import Path

import pytest

from slam_predict.collect import interrupt
from slam_predict.collect.batch import Batch, BatchConfig, _Executor, plural

HERE = Path(__file__).resolve().parent
FAKE = "fake_episode:run_episode"


@pytest.fixture(autouse=True)
def importable_fake(monkeypatch):
    monkeypatch.syspath_prepend(str(HERE))
    yield
    interrupt.reset()
    interrupt._State.parent_pid = None


def test_check_raises_after_a_stop_request():
    interrupt.reset()
    interrupt.check()
    interrupt.request_stop(signal.SIGTERM)
    with pytest.raises(interrupt.Interrupted, match="SIGTERM"):
        interrupt.check()
    assert interrupt.stop_signal() == signal.SIGTERM


def test_parent_pid_check_is_the_portable_fallback():
    interrupt._State.parent_pid = os.getppid()
    interrupt.check()
    interrupt._State.parent_pid = os.getppid() + 1_000_000  # not our parent: it "died"
    assert interrupt.parent_died()
    with pytest.raises(interrupt.Interrupted, match="died"):
        interrupt.check()


def test_signal_handlers_set_the_flag_forward_and_are_restored():
    forwarded = []
    before = signal.getsignal(signal.SIGINT)
    interrupt.reset()
    with interrupt.signal_handlers(forward=forwarded.append):
        os.kill(os.getpid(), signal.SIGINT)   # no KeyboardInterrupt: only the flag is set
        assert interrupt.stop_signal() == signal.SIGINT
    assert forwarded == [signal.SIGINT]
    assert signal.getsignal(signal.SIGINT) is before


def test_in_process_runs_are_executed_one_at_a_time(tmp_path, monkeypatch):
    started = []
    monkeypatch.setattr("slam_predict.collect.batch.resolve_callable",
                        lambda _path: lambda spec: started.append(spec.index) or {"i": spec.index})
    specs = Batch({"alpha": "a.world"}, tmp_path, BatchConfig(runs=3)).pending()
    outcomes = _Executor(1, None).outcomes("unused:name", specs)
    spec, record, error = next(outcomes)
    assert started == [0] and record == {"i": 0} and error is None  # run 1 not started yet
    assert [s.index for s, _, _ in outcomes] == [1, 2]


def test_signal_during_a_run_stops_the_in_process_batch(tmp_path, monkeypatch):
    """The episode of run 1 gets SIGINT: run 0 is kept, run 1 discarded, runs 2-3 never start."""
    monkeypatch.setenv("FAKE_EPISODE_SLEEP", "0.2")
    monkeypatch.setenv("FAKE_EPISODE_SIGNAL_AT", "1")
    batch = Batch({"alpha": "a.world"}, tmp_path, BatchConfig(runs=4, episode=FAKE,
                                                              progress=False))
    assert batch.run() == 1
    assert batch.stopped_by == signal.SIGINT and batch.failures == []
    assert sorted(p.name for p in (tmp_path / "alpha").iterdir()) == ["run_000"]
    monkeypatch.delenv("FAKE_EPISODE_SIGNAL_AT")
    resumed = Batch({"alpha": "a.world"}, tmp_path, BatchConfig(runs=4, episode=FAKE,
                                                                progress=False))
    assert resumed.run() == 3 and resumed.stopped_by is None


def test_signal_stops_local_worker_processes(tmp_path, monkeypatch):
    """SIGTERM reaches the batch process only; it forwards it to its two workers."""
    monkeypatch.setenv("FAKE_EPISODE_SLEEP", "30")
    monkeypatch.setenv("FAKE_EPISODE_SIGNAL_PARENT_AT", "0")
    monkeypatch.setenv("PYTHONPATH", os.pathsep.join([str(HERE), os.environ.get("PYTHONPATH", "")]))
    batch = Batch({"alpha": "a.world"}, tmp_path, BatchConfig(runs=4, jobs=2, episode=FAKE,
                                                              progress=False))
    assert batch.run() == 0
    assert batch.stopped_by == signal.SIGTERM
    assert not (tmp_path / "alpha").exists()  # both runs in progress discarded


def test_plural():
    assert plural(1, "run") == "1 run" and plural(0, "run") == "0 runs"


def test_a_batch_outside_the_main_thread_runs_without_handlers(tmp_path):
    import threading

    results = []
    worker = threading.Thread(target=lambda: results.append(
        Batch({"alpha": "a.world"}, tmp_path, BatchConfig(runs=2, episode=FAKE,
                                                          progress=False)).run()))
    worker.start()
    worker.join(30)
    assert results == [2]


def test_a_worker_started_after_the_stop_signal_gets_it_too(monkeypatch):
    """The pool starts workers as runs are submitted: one that starts while the signal is being
    handled is passed the signal by the next wait of the batch loop, the others not twice."""
    killed, pids = [], [11]
    monkeypatch.setattr("slam_predict.collect.batch.os.kill",
                        lambda pid, signum: killed.append((pid, signum)))
    executor = _Executor(2, None)
    monkeypatch.setattr(executor, "_worker_pids", lambda: list(pids))
    try:
        executor.forward_signal(signal.SIGTERM)
        pids.append(12)
        executor.forward_to_late_workers(signal.SIGTERM)
        executor.forward_to_late_workers(signal.SIGTERM)
    finally:
        executor.close()
    assert killed == [(11, signal.SIGTERM), (12, signal.SIGTERM)]


def test_a_stop_received_before_the_worker_initializer_is_kept():
    """A forked worker handles a forwarded signal with the batch's handler until init_worker
    runs; init_worker must not forget it."""
    code = ("import os, signal\n"
            "from slam_predict.collect import interrupt\n"
            "interrupt.request_stop(signal.SIGTERM)\n"
            "interrupt.init_worker(os.getppid())\n"
            "print(interrupt.stop_signal())\n")
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          timeout=60)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.strip() == str(int(signal.SIGTERM))
