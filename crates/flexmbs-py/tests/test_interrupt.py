"""Ctrl-C during a run: KeyboardInterrupt, and a readable results file with status interrupted."""

from __future__ import annotations

import os
import signal
import threading
import time
from pathlib import Path

import pytest

import flexmbs


def long_run(spring: flexmbs.Model) -> flexmbs.Model:
    spring["solver.t_end"] = "100000 s"  # about 10 min: only an interrupt ends it in the test
    spring["output.csv"] = None
    spring["output.plots"] = None
    spring["output.animation"] = False
    spring["output.dt"] = "0.1 s"
    return spring


def test_ctrl_c_raises_keyboard_interrupt_and_leaves_results(spring: flexmbs.Model, tmp_path: Path) -> None:
    timer = threading.Timer(0.5, os.kill, (os.getpid(), signal.SIGINT))
    start = time.monotonic()
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            flexmbs.run(long_run(spring), out_dir=tmp_path)
    finally:
        timer.cancel()
    assert time.monotonic() - start < 30.0
    r = flexmbs.read_results(tmp_path / "results.h5")
    assert r.status == "interrupted"
    assert r.rows > 1 and 0.0 < r.status_time < 100000.0
    assert r.time[-1] == pytest.approx(r.status_time)
    assert r.series("mass.position").shape == (r.rows, 3)


def test_exception_in_progress_callback_stops_the_run(spring: flexmbs.Model, tmp_path: Path) -> None:
    def progress(p: flexmbs.Progress) -> None:
        if p.t > 1.0:
            raise ValueError("enough")

    with pytest.raises(ValueError, match="enough"):
        flexmbs.run(long_run(spring), out_dir=tmp_path, progress=progress, progress_interval=0.0)
    r = flexmbs.read_results(tmp_path / "results.h5")
    assert r.status == "interrupted" and 1.0 < r.status_time < 1.1


class _Enough(Exception):
    pass


def test_run_releases_the_gil(spring: flexmbs.Model, tmp_path: Path) -> None:
    """A Python thread counting in a loop keeps its pace while the integration is inside Rust
    (measured between the first and the last progress callback, i.e. only while `run` is in its
    time loop), compared with its pace while the main thread sleeps. A C loop that holds the GIL
    (`sum(range(n))`) stops it: the control shows the measurement tells the two apart (with the
    GIL held between the callbacks, the thread could only count during the callbacks)."""
    count = [0]
    done = threading.Event()

    def spin() -> None:
        while not done.is_set():
            count[0] += 1

    def pace(block) -> float:
        """Counts per second of wall time while `block()` runs in the main thread."""
        c0, t0 = count[0], time.perf_counter()
        block()
        return (count[0] - c0) / (time.perf_counter() - t0)

    marks: list[tuple[float, int]] = []

    def progress(p: flexmbs.Progress) -> None:
        marks.append((time.perf_counter(), count[0]))
        if marks[-1][0] - marks[0][0] > 1.5:
            raise _Enough

    worker = threading.Thread(target=spin, daemon=True)
    worker.start()
    try:
        free = pace(lambda: time.sleep(0.5))
        held = pace(lambda: sum(range(15_000_000)))
        with pytest.raises(_Enough):
            flexmbs.run(long_run(spring), out_dir=tmp_path, progress=progress, progress_interval=0.25)
    finally:
        done.set()
        worker.join()
    (t0, c0), (t1, c1) = marks[0], marks[-1]
    during_run = (c1 - c0) / (t1 - t0)
    assert len(marks) >= 6 and free > 0.0
    assert held < 0.1 * free, (held, free)
    print(f"pace: free {free:.3g}/s, GIL held {held:.3g}/s, during the run {during_run:.3g}/s")
    assert during_run > 0.2 * free, (during_run, free, held)
    assert flexmbs.read_results(tmp_path / "results.h5").status == "interrupted"


def test_ctrl_c_stops_a_sweep(spring: flexmbs.Model, tmp_path: Path) -> None:
    long = long_run(spring)
    timer = threading.Timer(0.5, os.kill, (os.getpid(), signal.SIGINT))
    start = time.monotonic()
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            flexmbs.sweep(long, {"load[spring].stiffness": [100.0, 200.0, 300.0, 400.0]}, ["mass.position.x"], workers=2, out_dir=tmp_path)
    finally:
        timer.cancel()
    assert time.monotonic() - start < 30.0
    # the variants that had started were stopped after their step, their files finished
    started = sorted(tmp_path.glob("variant_*/results.h5"))
    assert 1 <= len(started) <= 2
    for f in started:
        assert flexmbs.read_results(f).status == "interrupted"
