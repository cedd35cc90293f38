"""Rebuilds examples/mbs/double_pendulum.toml in Python, runs it, checks it against the model file
(bit for bit) and plots the tip path and the energy with matplotlib.

    python examples/python/double_pendulum.py [OUT_DIR]
"""

import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import flexmbs  # noqa: E402

HERE = Path(__file__).resolve().parent
out = Path(sys.argv[1]) if len(sys.argv) > 1 else Path("out/python_double_pendulum")

# two 1 m slender links of 1 kg on revolute joints about z, released from the horizontal
model = flexmbs.Model.from_dict(
    {
        "model": {"name": "double_pendulum", "gravity": [0, "-9.81 m/s^2", 0]},
        "solver": {"type": "generalized-alpha", "rho_inf": 1.0, "h": "1 ms", "t_end": "2 s"},
        "output": {"every": 10, "signals": ["link2_tip.position", "shoulder.force", "shoulder.reaction"]},
    }
)
for i, x in enumerate(["0.5 m", "1.5 m"], start=1):
    model[f"body[{i - 1}]"] = {
        "name": f"link{i}",
        "type": "rigid",
        "mass": "1 kg",
        "inertia": [1e-4, 0.0834, 0.0834],  # m L^2 / 12 (+ a small axial moment)
        "position": [x, 0, 0],
    }
frames = [("hinge", "ground", None), ("link1_top", "link1", "-0.5 m"), ("link1_tip", "link1", "0.5 m"),
          ("link2_top", "link2", "-0.5 m"), ("link2_tip", "link2", "0.5 m")]
for k, (name, body, x) in enumerate(frames):
    model[f"frame[{k}]"] = {"name": name, "body": body, **({"position": [x, 0, 0]} if x else {})}
model["joint[0]"] = {"name": "shoulder", "type": "revolute", "a": "hinge", "b": "link1_top"}
model["joint[1]"] = {"name": "elbow", "type": "revolute", "a": "link1_tip", "b": "link2_top"}

print(flexmbs.check(model))
res = flexmbs.run(model, out_dir=out / "python")
ref = flexmbs.run(HERE.parent / "mbs" / "double_pendulum.toml", out_dir=out / "toml")
for group in ("q", "u", "lambda", "energy", "signals"):
    assert np.array_equal(res.series(group), ref.series(group)), group
print(f"{res.rows} rows, identical to the model file; energy balance error {res.summary['energy_drift']:.2e} J")

tip = res.series("link2_tip.position")  # (n, 3) in m
fig, (a, b) = plt.subplots(1, 2, figsize=(10, 4))
a.plot(tip[:, 0], tip[:, 1])
a.set(xlabel="x [m]", ylabel="y [m]", title="tip of link 2", aspect="equal")
for name in ("energy/kinetic", "energy/gravity", "energy/total"):
    b.plot(res.time, res.series(name), label=name)
b.set(xlabel="t [s]", ylabel="energy [J]")
b.legend()
fig.tight_layout()
fig.savefig(out / "double_pendulum.png", dpi=100)
print("wrote", out / "double_pendulum.png")
