"""sweep: variants on Rust threads give the same numbers as single runs; bad variants are
reported per row."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import flexmbs
from conftest import ROOT

OUTPUTS = ["max(mass.position.x)", "min(mass.position.x)", "mass.position.x", "absmax(u/mass.v_x)", "mean(energy/total)"]


def test_sweep_matches_single_runs(spring: flexmbs.Model, tmp_path: Path) -> None:
    stiffness = ["50 N/m", "100 N/m", "200 N/m", "400 N/m"]
    table = flexmbs.sweep(spring, {"load[spring].stiffness": stiffness}, OUTPUTS, workers=2)
    assert list(table["status"]) == ["completed"] * 4
    assert list(table["load[spring].stiffness"]) == stiffness
    for k, value in enumerate(stiffness):
        m = spring.copy()
        m["load[spring].stiffness"] = value
        r = flexmbs.run(m, out_dir=tmp_path / str(k))
        x = r.series("mass.position.x")
        assert table["max(mass.position.x)"][k] == np.max(x)
        assert table["min(mass.position.x)"][k] == np.min(x)
        assert table["mass.position.x"][k] == x[-1]
        assert table["absmax(u/mass.v_x)"][k] == np.max(np.abs(r.series("u/mass.v_x")))
        assert table["mean(energy/total)"][k] == pytest.approx(np.mean(r.series("energy/total")), rel=1e-12)
    # released at rest 0.1 m stretched: the largest x is the start, 1.1 m, for every stiffness
    assert np.all(table["max(mass.position.x)"] == 1.1)


def test_sweep_reports_invalid_variants_and_grid(spring: flexmbs.Model) -> None:
    design = flexmbs.grid({"body[mass].mass": ["1 kg", "-1 kg"], "load[spring].damping": [1.0, 2.0]})
    assert design == {"body[mass].mass": ["1 kg", "1 kg", "-1 kg", "-1 kg"], "load[spring].damping": [1.0, 2.0, 1.0, 2.0]}
    table = flexmbs.sweep(spring, design, ["mass.position.x"], workers=2, as_pandas=False)
    assert list(table["status"]) == ["completed", "completed", "invalid", "invalid"]
    assert "at `body[0].mass`: mass must be > 0" in table["message"][2]
    assert np.isnan(table["mass.position.x"][2]) and np.isfinite(table["mass.position.x"][0])
    assert table["load[spring].damping"].dtype == np.float64
    with pytest.raises(ValueError):
        flexmbs.sweep(spring, {"solver.h": [1, 2], "solver.t_end": [1]}, ["mass.position.x"])
    with pytest.raises(ValueError, match="unknown statistic"):
        flexmbs._native.sweep([], "", "", [("x", "median")], 1)


def test_sweep_unknown_output_is_reported(spring: flexmbs.Model) -> None:
    table = flexmbs.sweep(spring, {"solver.t_end": ["0.1 s"]}, ["max(mass.position.w)"], workers=1)
    assert table["status"][0] == "error" and "unknown series" in table["message"][0]


def _require(module: str) -> None:
    try:
        __import__(module)
    except ImportError:
        if os.environ.get("FLEXMBS_REQUIRE_TOOLS") == "1":
            raise
        pytest.skip(f"{module} is not installed")


@pytest.mark.parametrize("script", ["double_pendulum.py", "dask_study.py"])
def test_examples_run(script: str, tmp_path: Path) -> None:
    """The Python examples run to the end (each checks its own numbers)."""
    _require("matplotlib" if script == "double_pendulum.py" else "distributed")
    path = ROOT / "examples" / "python" / script
    done = subprocess.run([sys.executable, str(path), str(tmp_path)], capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stdout + done.stderr


def test_sweep_as_pandas(spring: flexmbs.Model) -> None:
    """`as_pandas=True`: a DataFrame with the columns and values of the dict form."""
    pd = pytest.importorskip("pandas")
    parameters = {"load[spring].stiffness": ["50 N/m", "100 N/m", "-1 N/m"]}
    outputs = ["max(mass.position.x)", "mass.position.x"]
    df = flexmbs.sweep(spring, parameters, outputs, workers=2, as_pandas=True)
    table = flexmbs.sweep(spring, parameters, outputs, workers=2)
    assert isinstance(df, pd.DataFrame) and len(df) == 3
    assert list(df.columns) == ["load[spring].stiffness", *outputs, "status", "message"]
    assert list(df["status"]) == list(table["status"])
    assert df["status"].iloc[2] == "invalid" and np.isnan(df["mass.position.x"].iloc[2])
    for spec in outputs:
        assert df[spec].dtype == np.float64
        assert np.array_equal(df[spec].to_numpy(), table[spec], equal_nan=True)
    assert list(df["load[spring].stiffness"]) == parameters["load[spring].stiffness"]
