"""The analyses release the GIL; a sweep reports progress from the calling thread between
points and stops on Ctrl-C or on an exception from its progress callback.

As in test_threads.py, the always-on checks are about progress, not speed: while an analysis
runs in another thread, the main thread keeps executing Python bytecode (a held GIL would
stall it for the whole analysis). The speed-up of ``threads=2`` is a timing measurement and
runs only with ``LINKDYN_TIMING_TESTS=1`` on a machine with at least 2 CPUs.
"""

import _thread
import io
import os
import signal
import sys
import threading
import time

import numpy as np
import pytest

import linkdyn

MODEL = "models/farahan2016.toml"
FAST = {"drivers.motor.speed_rpm": 3500}
SWEEP = dict(param="joints.B.clearance", observe="coupler.phi", revs=8, transient=4,
             formulation="reduced")


def longest_pause_while(work):
    """Runs `work` in a thread; returns (its duration, the main thread's longest pause)."""
    done = threading.Event()
    started = threading.Event()
    box = {}

    def run():
        started.set()
        t0 = time.perf_counter()
        box["result"] = work()
        box["duration"] = time.perf_counter() - t0
        done.set()

    worker = threading.Thread(target=run)
    worker.start()
    started.wait()
    last = time.perf_counter()
    longest = 0.0
    while not done.is_set():
        now = time.perf_counter()
        longest = max(longest, now - last)
        last = now
    worker.join()
    return box["duration"], longest


@pytest.mark.parametrize(
    "name, work",
    [
        ("poincare", lambda m: m.poincare(revs=12, observe="B.ex")),
        ("spectrum", lambda m: m.spectrum("B.fn", revs=3)),
        ("lyapunov", lambda m: m.lyapunov(revs=4)),
        ("bifurcation", lambda m: m.bifurcation(
            **SWEEP, from_=2e-4, to=5e-4, steps=5, threads=1, progress=False)),
    ],
)
def test_main_thread_progresses_while_an_analysis_runs(name, work):
    model = linkdyn.load(MODEL)
    duration, pause = longest_pause_while(lambda: work(model))
    # Each takes ≥ 0.1 s of integration; below 0.05 s the check would say nothing.
    assert duration > 0.05, (name, duration)
    assert pause < 0.5 * duration, (
        f"{name}: main thread paused {pause:.3f} s during a {duration:.3f} s analysis: "
        "the GIL looks held")


def test_progress_is_reported_from_the_calling_thread_after_each_point():
    calls = []

    def progress(done, total):
        calls.append((done, total, threading.current_thread() is threading.main_thread()))

    linkdyn.load(MODEL, set=FAST).bifurcation(
        **SWEEP, from_=2e-4, to=5e-4, steps=3, threads=2, progress=progress)
    # Every count reported once, in order, ending at the total (two points may finish in the
    # same wait, so a count may be skipped, but never the last), always on the main thread.
    done = [c[0] for c in calls]
    assert done == sorted(set(done)) and done[-1] == 4, calls
    assert all(total == 4 and main for _, total, main in calls), calls


def test_progress_line_without_tqdm(monkeypatch):
    # tqdm missing (an import of it fails): a plain line on stderr.
    monkeypatch.setitem(sys.modules, "tqdm", None)
    monkeypatch.setitem(sys.modules, "tqdm.auto", None)
    err = io.StringIO()
    monkeypatch.setattr(sys, "stderr", err)
    linkdyn.load(MODEL, set=FAST).bifurcation(
        **SWEEP, values=[2e-4, 3e-4], threads=1, progress=True)
    lines = err.getvalue().splitlines()
    assert lines and lines[-1].startswith("bifurcation joints.B.clearance: 2/2 points, "), lines


def test_an_exception_from_the_progress_callback_stops_the_sweep():
    calls = []

    def progress(done, total):
        calls.append(done)
        raise RuntimeError("stop here")

    with pytest.raises(RuntimeError, match="stop here"):
        linkdyn.load(MODEL, set=FAST).bifurcation(
            **SWEEP, from_=2e-4, to=5e-4, steps=5, threads=1, progress=progress)
    # Called once, never again after raising.
    assert len(calls) == 1, calls


def test_ctrl_c_stops_the_sweep():
    calls = []

    def progress(done, total):
        calls.append(done)
        if len(calls) == 1:
            # SIGINT as a terminal would send it, during the sweep. Raised here, on the main
            # thread, rather than from another thread: a helper thread can lose the race against
            # a fast sweep on an idle machine (the sweep ends before the signal arrives, and the
            # KeyboardInterrupt lands in the next test).
            _thread.interrupt_main()

    # A process started in the background by a non-interactive shell inherits SIGINT ignored, and
    # Python then installs no handler, so interrupt_main() would do nothing: install Python's own.
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        with pytest.raises(KeyboardInterrupt):
            linkdyn.load(MODEL, set=FAST).bifurcation(
                **SWEEP, from_=2e-4, to=5e-4, steps=11, threads=1, progress=progress)
    finally:
        signal.signal(signal.SIGINT, previous)
    # 12 points; the interrupt came with the first report, so the sweep stopped long before 12.
    assert calls and calls[-1] < 12, calls


@pytest.mark.skipif(
    os.environ.get("LINKDYN_TIMING_TESTS") != "1" or (os.cpu_count() or 1) < 2,
    reason="timing check: set LINKDYN_TIMING_TESTS=1 on an otherwise idle machine with 2+ CPUs",
)
def test_two_sweep_threads_take_clearly_less_than_one():
    model = linkdyn.load(MODEL, set=FAST)

    def best(threads, reps=3):
        times = []
        for _ in range(reps):
            t0 = time.perf_counter()
            r = model.bifurcation(**SWEEP, from_=2e-4, to=5e-4, steps=7, threads=threads,
                                  progress=False)
            times.append(time.perf_counter() - t0)
        return min(times), r

    one, a = best(1)
    two, b = best(2)
    assert np.array_equal(a.value, b.value)
    # Perfectly parallel: 0.5×; serialised: 1.0×. 0.8 leaves room for uneven points.
    assert two < 0.8 * one, f"threads=2 {two:.3f} s vs threads=1 {one:.3f} s"
