#!/usr/bin/env python3
"""Compares the FFR runs of `sliding_balls` with the nonlinear reference from their CSV series.

The series are written by `SLIDING_BALLS_SERIES=1 flexmbs validate sliding_balls --dir DIR`
(`series_modes<n>.csv`: t, x, y, tip_y, energy_dev; `series_reference.csv`: t, x, y, tip_y,
energy). Usage: `compare_series.py REFERENCE_CSV FFR_CSV... [--plot OUT.png]`. Prints, per FFR
run, the same measures as the validation case: RMS difference of the ball's height and of the tip
deflection relative to the reference's RMS, the largest difference of the ball's x, the smallest
tip deflection and the largest energy deviation. Used for the 5 s runs, which CI does not run.
"""
import re
import sys

import numpy as np


def load(path):
    return np.genfromtxt(path, delimiter=",", names=True)


def main(argv):
    plot = None
    if "--plot" in argv:
        i = argv.index("--plot")
        plot = argv[i + 1]
        argv = argv[:i] + argv[i + 2:]
    ref = load(argv[0])
    rms_y = np.sqrt(np.mean(ref["y"] ** 2))
    rms_tip = np.sqrt(np.mean(ref["tip_y"] ** 2))
    e0 = ref["energy"][0]
    print(f"reference: t_end {ref['t'][-1]:.3f} s, tip y min {ref['tip_y'].min():.4e} m, "
          f"energy dev {np.abs(ref['energy'] / e0 - 1).max():.2e}")
    print("| modes | ball y RMS diff | tip y RMS diff | ball x max diff (m) | tip y min (mm) | energy dev |")
    print("|---|---|---|---|---|---|")
    runs = []
    for path in argv[1:]:
        r = load(path)
        n = re.search(r"modes(\d+)", path)
        t = r["t"]
        y_ref = np.interp(t, ref["t"], ref["y"])
        tip_ref = np.interp(t, ref["t"], ref["tip_y"])
        x_ref = np.interp(t, ref["t"], ref["x"])
        dy = np.sqrt(np.mean((r["y"] - 0.025 - y_ref) ** 2)) / rms_y
        dtip = np.sqrt(np.mean((r["tip_y"] - tip_ref) ** 2)) / rms_tip
        dx = np.abs(r["x"] - x_ref).max()
        print(f"| {n.group(1) if n else path} | {dy:.2e} | {dtip:.2e} | {dx:.1e} | "
              f"{1e3 * r['tip_y'].min():.4f} | {np.abs(r['energy_dev']).max():.1e} |")
        runs.append((n.group(1) if n else path, r))
    print(f"| reference | - | - | - | {1e3 * ref['tip_y'].min():.4f} | "
          f"{np.abs(ref['energy'] / e0 - 1).max():.1e} |")
    if plot:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        fig, ax = plt.subplots(2, 1, figsize=(9, 7), sharex=True)
        for name, r in runs:
            ax[0].plot(r["t"], 1e3 * (r["y"] - 0.025), label=f"FFR {name} modes", lw=1)
            ax[1].plot(r["t"], 1e3 * r["tip_y"], label=f"FFR {name} modes", lw=1)
        ax[0].plot(ref["t"], 1e3 * ref["y"], "k--", label="nonlinear reference", lw=1)
        ax[1].plot(ref["t"], 1e3 * ref["tip_y"], "k--", label="nonlinear reference", lw=1)
        ax[0].set_ylabel("ball y - 25 mm [mm]")
        ax[1].set_ylabel("tip u_y [mm]")
        ax[1].set_xlabel("t [s]")
        ax[0].legend(fontsize=8)
        ax[0].set_title("sliding_balls, 5 s: FFR vs corotational-beam reference")
        fig.tight_layout()
        fig.savefig(plot, dpi=110)


if __name__ == "__main__":
    main(sys.argv[1:])
