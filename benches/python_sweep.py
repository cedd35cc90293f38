"""Sweep speed-up: 16 variants of examples/mbs/slider_crank.toml (slider mass 20..50 g) run by
flexmbs.sweep on 1 worker and on 2 workers; prints the wall times and checks that both give the
same table.    python benches/python_sweep.py"""

import time
from pathlib import Path

import numpy as np

import flexmbs

MODEL = Path(__file__).resolve().parent.parent / "examples" / "mbs" / "slider_crank.toml"
OUTPUTS = ["max(rod_mid.deformation.y)", "absmax(drive.torque.z)", "slider.position.x"]


def main() -> None:
    model = flexmbs.load(MODEL)
    params = {"body[slider].mass": list(np.linspace(0.02, 0.05, 16))}
    times = {}
    tables = {}
    for workers in (1, 2):
        start = time.perf_counter()
        tables[workers] = flexmbs.sweep(model, params, OUTPUTS, workers=workers)
        times[workers] = time.perf_counter() - start
        assert list(tables[workers]["status"]) == ["completed"] * 16
        print(f"workers={workers}: {times[workers]:.2f} s")
    for name in OUTPUTS:
        assert np.array_equal(tables[1][name], tables[2][name]), name
    print(f"speed-up {times[1] / times[2]:.2f}")


if __name__ == "__main__":
    main()
