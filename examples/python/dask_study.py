"""The same parameter study on a Dask distributed cluster (here a local one with 2 workers), for
studies that outgrow one machine: every task runs one variant with flexmbs.sweep(..., workers=1)
on the worker that got it. Checks that the cluster gives the numbers of the local sweep.

    python examples/python/dask_study.py [OUT_DIR]

On a real cluster replace LocalCluster by the scheduler's address: Client("tcp://host:8786"); the
workers need flexmbs installed and the model's files (FE sources) at the same paths.
"""

import sys
from pathlib import Path

import numpy as np
from distributed import Client, LocalCluster

import flexmbs

HERE = Path(__file__).resolve().parent
MODEL = HERE.parent / "mbs" / "spring_damper.toml"
OUTPUTS = ["max(mass.position.x)", "min(mass.position.x)", "absmax(u/mass.v_x)"]


def run_variant(model_data: dict, base_dir: str, key: str, value: object) -> dict:
    """One variant on a Dask worker: the model travels as plain data."""
    model = flexmbs.Model.from_dict(model_data, base_dir=base_dir)
    row = flexmbs.sweep(model, {key: [value]}, OUTPUTS, workers=1)
    return {k: v[0] for k, v in row.items()}


def main() -> None:
    model = flexmbs.load(MODEL)
    stiffness = [f"{k} N/m" for k in (25, 50, 100, 200, 400, 800)]
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster, Client(cluster) as client:
        futures = client.map(run_variant, [model.to_dict()] * len(stiffness), [str(model.base_dir)] * len(stiffness),
                             ["load[spring].stiffness"] * len(stiffness), stiffness)
        rows = client.gather(futures)
    local = flexmbs.sweep(model, {"load[spring].stiffness": stiffness}, OUTPUTS, workers=2)
    for k, row in enumerate(rows):
        assert row["status"] == "completed", row
        for name in OUTPUTS:
            assert row[name] == local[name][k], (name, k)
    print(f"{'stiffness':>10} " + " ".join(f"{o:>22}" for o in OUTPUTS))
    for s, row in zip(stiffness, rows):
        print(f"{s:>10} " + " ".join(f"{row[o]:22.6g}" for o in OUTPUTS))
    # a stiffer spring swings faster: the largest speed grows like sqrt(k)
    vmax = np.array([row["absmax(u/mass.v_x)"] for row in rows])
    assert np.all(np.diff(vmax) > 0)
    print("Dask cluster results equal the local sweep")


if __name__ == "__main__":
    main()
