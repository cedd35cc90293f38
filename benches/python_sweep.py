"""Sweep speed-up: 16 variants of examples/mbs/slider_crank.toml (slider mass 20..50 g) run by
flexmbs.sweep on 1 worker and on 2 workers; prints the wall times and checks that both give the
same table. The two are alternated REPEAT times (default 3) so that a changing machine load
affects both alike.    python benches/python_sweep.py [REPEAT]"""

import resource
import sys
import time
from pathlib import Path

import numpy as np

import flexmbs

MODEL = Path(__file__).resolve().parent.parent / "examples" / "mbs" / "slider_crank.toml"
OUTPUTS = ["max(rod_mid.deformation.y)", "absmax(drive.torque.z)", "slider.position.x"]


def cpu_seconds() -> float:
    r = resource.getrusage(resource.RUSAGE_SELF)
    return r.ru_utime + r.ru_stime


def main() -> None:
    repeat = int(sys.argv[1]) if len(sys.argv) > 1 else 3
    model = flexmbs.load(MODEL)
    params = {"body[slider].mass": list(np.linspace(0.02, 0.05, 16))}
    tables = {}
    walls: dict[int, list[float]] = {1: [], 2: []}
    for _ in range(repeat):
        for workers in (1, 2):
            start, cpu = time.perf_counter(), cpu_seconds()
            tables[workers] = flexmbs.sweep(model, params, OUTPUTS, workers=workers)
            wall, cpu = time.perf_counter() - start, cpu_seconds() - cpu
            walls[workers].append(wall)
            assert list(tables[workers]["status"]) == ["completed"] * 16
            print(f"workers={workers}: wall {wall:.2f} s, CPU {cpu:.2f} s ({cpu / wall:.2f} cores)", flush=True)
        for name in OUTPUTS:
            assert np.array_equal(tables[1][name], tables[2][name]), name
    best1, best2 = min(walls[1]), min(walls[2])
    print(f"best of {repeat}: 1 worker {best1:.2f} s, 2 workers {best2:.2f} s, speed-up {best1 / best2:.2f}")


if __name__ == "__main__":
    main()
