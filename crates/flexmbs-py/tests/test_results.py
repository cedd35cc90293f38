"""Results as numpy arrays: documented shapes and SI units, checked against the analytic solution
of the shipped spring-damper oscillator."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import flexmbs


def spring_damper_x(t: np.ndarray) -> np.ndarray:
    """x(t) of examples/mbs/spring_damper.toml: m = 1 kg, k = 100 N/m, d = 1 N s/m, free length
    1 m, released at rest 0.1 m stretched: 1 + 0.1 e^(-t/2) (cos wd t + sin(wd t) / (2 wd))."""
    wd = math.sqrt(100.0 - 0.25)
    return 1.0 + 0.1 * np.exp(-0.5 * t) * (np.cos(wd * t) + 0.5 / wd * np.sin(wd * t))


def test_shapes_units_and_analytic_solution(spring: flexmbs.Model, tmp_path: Path) -> None:
    info = flexmbs.check(spring)
    r = flexmbs.run(spring, out_dir=tmp_path)
    n = r.rows
    assert r.status == "completed" and r.summary["status"] == "completed"
    # the external work by part: only the damper works here, and it is what the energy lost
    work = r.summary["work"]
    assert work["loads"] == 0.0 and work["drives"] == 0.0 and work["stiffening"] is None
    assert work["dampers"] < 0.0
    assert sum(v for v in work.values() if v is not None) == pytest.approx(
        r.summary["external_work"], rel=1e-12
    )
    e_total = r.series("energy").sum(axis=1)
    assert e_total[-1] - e_total[0] == pytest.approx(work["dampers"], abs=1e-3 * e_total[0])
    assert n == 501  # 5 s every 10 ms, and t = 0
    assert r.time.shape == (n,) and r.time.dtype == np.float64
    assert r.time[0] == 0.0 and r.time[-1] == pytest.approx(5.0, abs=1e-12)  # "5 s" -> s
    # rows at the first accepted step at or past every 10 ms ("10 ms" -> 0.01 s)
    assert np.all(np.diff(r.time) > 0) and np.all(np.diff(r.time) < 0.021)
    assert r.series("q").shape == (n, info["coordinates"])
    assert r.series("u").shape == (n, len(r.columns("u")))
    assert r.series("lambda").shape == (n, 0)
    assert r.series("energy").shape == (n, 4)
    assert r.columns("energy") == ["kinetic", "gravity", "elastic", "springs"]
    assert r.series("drift").shape == (n, 2) and r.series("step").shape == (n, 3)
    pos = r.series("mass.position")
    assert pos.shape == (n, 3) and r.unit("mass.position") == "m"
    assert r.unit("mass.position.x") == "m" and r.unit("energy/total") == "J" and r.unit("step/h") == "s"
    assert np.array_equal(pos[:, 0], r.series("mass.position.x"))
    # the analytic solution, in metres (DOPRI5 at rtol 1e-8)
    assert np.max(np.abs(pos[:, 0] - spring_damper_x(r.time))) < 1e-6
    assert np.max(np.abs(pos[:, 1:])) < 1e-12
    # energy in J: spring energy at t = 0 is k x0^2 / 2 = 0.5 J
    assert r.series("energy/springs")[0] == pytest.approx(0.5, rel=1e-12)
    assert np.allclose(r.series("energy/total"), r.series("energy").sum(axis=1), rtol=1e-12, atol=1e-15)
    s = r.stats("mass.position.x")
    assert s["max"] == pytest.approx(1.1, abs=1e-12) and s["t_max"] == 0.0
    assert s["final"] == pos[-1, 0]
    # the same file read again
    again = flexmbs.read_results(tmp_path / "results.h5")
    assert np.array_equal(again.series("q"), r.series("q")) and again.summary is None
    assert again.attributes["solver"] == "dopri5"


def test_unknown_series_is_a_key_error_with_suggestions(spring: flexmbs.Model, tmp_path: Path) -> None:
    r = flexmbs.run(spring, out_dir=tmp_path)
    with pytest.raises(KeyError) as e:
        r.series("mass.position.w")
    assert isinstance(e.value, flexmbs.UnknownSeriesError)
    assert "did you mean mass.position.x" in str(e.value) and e.value.name == "mass.position.w"
    with pytest.raises(flexmbs.UnknownSeriesError, match=r"Results\.names\(\)"):
        r.series("zzzzzzzzzzzz")


def test_to_pandas(spring: flexmbs.Model, tmp_path: Path) -> None:
    pd = pytest.importorskip("pandas")
    r = flexmbs.run(spring, out_dir=tmp_path)
    df = r.to_pandas(["mass.position.x", "energy/total"])
    assert isinstance(df, pd.DataFrame) and df.shape == (r.rows, 2)
    assert np.array_equal(df.index.to_numpy(), r.time)
    assert len(r.to_pandas().columns) == len(r.names())


def test_progress_callback(spring: flexmbs.Model, tmp_path: Path) -> None:
    seen: list = []
    r = flexmbs.run(spring, out_dir=tmp_path, progress=seen.append, progress_interval=0.0)
    assert len(seen) == r.summary["steps"]  # interval 0: every accepted step
    assert all(isinstance(p, flexmbs.Progress) for p in seen)
    assert seen[-1].t == pytest.approx(5.0) and seen[-1].t_end == 5.0 and seen[-1].fraction == 1.0
    assert [p.steps for p in seen] == list(range(1, len(seen) + 1))
