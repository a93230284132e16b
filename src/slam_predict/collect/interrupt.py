"""Stopping a batch cleanly: a stop flag set by SIGINT/SIGTERM, checked by the episode loop.

The batch process installs :func:`signal_handlers`: a signal sets the flag (and is forwarded to
the worker processes); the episode loop calls :func:`check` once per control step, which raises
:class:`Interrupted` so the run's temporary folder is discarded and nothing half-written is left.

Worker processes run :func:`init_worker`: the same handlers, plus a death signal from the parent
(Linux ``prctl(PR_SET_PDEATHSIG)``) and, portably, a parent-pid check in :func:`check`, so a
``kill -9`` of the batch never leaves workers running on their own.
"""
from __future__ import annotations

import contextlib
import ctypes
import logging
import os
import signal
import sys
import threading
from collections.abc import Callable, Iterator

LOG = logging.getLogger(__name__)
STOP_SIGNALS = (signal.SIGINT, signal.SIGTERM)
PR_SET_PDEATHSIG = 1  # <linux/prctl.h>


class Interrupted(Exception):
    """The run was stopped by a signal (or its parent died) before it finished."""


class _State:
    """Process-wide stop state (one per process: the batch, or one worker)."""

    signum: int | None = None
    parent_pid: int | None = None
    in_run: bool = False


def stop_signal() -> int | None:
    """The signal that asked this process to stop, or None."""
    return _State.signum


def request_stop(signum: int = signal.SIGINT) -> None:
    """Ask the current run (and batch) to stop at the next control step."""
    if _State.signum is None:
        _State.signum = int(signum)


def reset() -> None:
    """Forget a previous stop request (a new batch in the same process)."""
    _State.signum = None


def parent_died() -> bool:
    """True in a worker whose batch process is gone (it was re-parented)."""
    return _State.parent_pid is not None and os.getppid() != _State.parent_pid


def check() -> None:
    """Raise :class:`Interrupted` when a stop was requested or the batch process died."""
    if _State.signum is not None:
        raise Interrupted(f"stopped by {signal.Signals(_State.signum).name}")
    if parent_died():
        raise Interrupted("the batch process died")


@contextlib.contextmanager
def signal_handlers(forward: Callable[[int], None] | None = None) -> Iterator[None]:
    """SIGINT/SIGTERM set the stop flag (and call ``forward(signum)``) inside the block; the
    previous handlers are restored after it (outside the main thread: nothing installed)."""
    def handler(signum, _frame):
        if _State.signum is None:
            LOG.warning("%s: stopping; the runs in progress are discarded",
                        signal.Signals(signum).name)
        request_stop(signum)
        if forward is not None:
            forward(signum)

    if threading.current_thread() is not threading.main_thread():
        yield   # only the main thread receives signals; request_stop() still works
        return
    previous = {sig: signal.signal(sig, handler) for sig in STOP_SIGNALS}
    try:
        yield
    finally:
        for sig, old in previous.items():
            signal.signal(sig, old)


def init_worker(parent_pid: int) -> None:
    """Worker-process initializer: stop handlers, death with the parent, parent-pid check.

    A stop already requested is kept: a worker forked from the batch process runs the batch's
    handler until this function replaces it, so a signal forwarded in between has set the flag
    (clearing it here let that worker run a whole episode after the stop)."""
    _State.parent_pid = int(parent_pid)
    if sys.platform.startswith("linux"):
        try:
            libc = ctypes.CDLL(None, use_errno=True)
            if libc.prctl(PR_SET_PDEATHSIG, int(signal.SIGTERM), 0, 0, 0) != 0:
                LOG.debug("prctl(PR_SET_PDEATHSIG) failed: errno %d", ctypes.get_errno())
        except (OSError, AttributeError) as exc:
            LOG.debug("prctl unavailable: %s", exc)
    for sig in STOP_SIGNALS:
        signal.signal(sig, _worker_handler)
    if parent_died():  # the parent died before prctl took effect
        os._exit(128 + signal.SIGTERM)


def _worker_handler(signum, _frame) -> None:
    """In a worker: stop the run in progress; idle and orphaned, exit at once."""
    request_stop(signum)
    if not _State.in_run and parent_died():
        os._exit(128 + signum)


@contextlib.contextmanager
def running() -> Iterator[None]:
    """Marks a run in progress in this process (an idle orphaned worker exits at once)."""
    _State.in_run = True
    try:
        yield
    finally:
        _State.in_run = False
