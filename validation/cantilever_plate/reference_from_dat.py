#!/usr/bin/env python3
"""Tip displacements of the two reference nodes from a CalculiX .dat of make_deck.py's deck:
one row per printed time point, `P_N, w_over_L, minus_u_over_L` (mean of the two nodes).

usage: reference_from_dat.py job.dat out.csv
"""
import re
import sys

L, P = 10.0, 1e5
rows = []
lines = open(sys.argv[1]).read().splitlines()
for i, line in enumerate(lines):
    m = re.search(r"displacements \(vx,vy,vz\) for set REFS and time\s+(\S+)", line)
    if not m:
        continue
    t = float(m.group(1))
    vals = [list(map(float, lines[i + k].split()[1:4])) for k in (2, 3)]
    ux = sum(v[0] for v in vals) / 2
    uz = sum(v[2] for v in vals) / 2
    rows.append((t * P, -uz / L, -ux / L))
with open(sys.argv[2], "w") as f:
    f.write("P_N,w_over_L,minus_u_over_L\n")
    for p, w, u in rows:
        f.write(f"{p:.6g},{w:.9g},{u:.9g}\n")
