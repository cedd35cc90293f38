#!/usr/bin/env python3
"""Writes the CalculiX reference deck of `cantilever_plate` (seed 001 §8.4).

Plate 10 m x 1 m x 0.1 m (x, y, z), E = 12 GPa, nu = 0.3, C3D20R elements nx x ny x nz,
clamped at x = 0 (every node of that face), geometrically nonlinear (NLGEOM). The tip face
x = 10 is tied rigidly in two halves (y <= 0.49 and y >= 0.51: the node line y = 0.5 is in
neither), with reference nodes at the half-face centres (10, 0.25, 0.05) and (10, 0.75, 0.05);
each carries a vertical force -P/2 (global z, fixed direction: *CLOAD is not a follower load).
P = 1e5 N (P L^2 / EI = 10 with EI = E b t^3 / 12 = 1e6 N m^2) is applied with automatic
increments (at most 0.05 P); the reference-node displacements are printed at P/20, 2P/20, ..., P.

usage: make_deck.py nx ny nz out.inp
"""
import sys

L, B, T = 10.0, 1.0, 0.1
E, NU = 12e9, 0.3
P = 1e5


def deck(nx, ny, nz):
    ids = {}
    lines = ["*HEADING", f"cantilever_plate C3D20R {nx}x{ny}x{nz} NLGEOM", "*NODE"]
    nid = 0
    for k in range(2 * nz + 1):
        for j in range(2 * ny + 1):
            for i in range(2 * nx + 1):
                if (i % 2) + (j % 2) + (k % 2) > 1:
                    continue
                nid += 1
                ids[(i, j, k)] = nid
                x, y, z = L * i / (2 * nx), B * j / (2 * ny), T * k / (2 * nz)
                lines.append(f"{nid}, {x:.12g}, {y:.12g}, {z:.12g}")
    ref_a, ref_b = nid + 1, nid + 2
    rot_a, rot_b = nid + 3, nid + 4
    lines.append(f"{ref_a}, {L}, {0.25 * B}, {0.5 * T}")
    lines.append(f"{ref_b}, {L}, {0.75 * B}, {0.5 * T}")
    lines.append(f"{rot_a}, {L}, {0.25 * B}, {0.5 * T}")
    lines.append(f"{rot_b}, {L}, {0.75 * B}, {0.5 * T}")
    lines.append("*ELEMENT, TYPE=C3D20R, ELSET=PLATE")
    eid = 0
    for k in range(nz):
        for j in range(ny):
            for i in range(nx):
                a, b, c = 2 * i, 2 * j, 2 * k
                corner = [(a, b, c), (a + 2, b, c), (a + 2, b + 2, c), (a, b + 2, c),
                          (a, b, c + 2), (a + 2, b, c + 2), (a + 2, b + 2, c + 2), (a, b + 2, c + 2)]
                mid = lambda p, q: tuple((u + v) // 2 for u, v in zip(p, q))
                edges = [(0, 1), (1, 2), (2, 3), (3, 0), (4, 5), (5, 6), (6, 7), (7, 4),
                         (0, 4), (1, 5), (2, 6), (3, 7)]
                nodes = [ids[p] for p in corner] + [ids[mid(corner[p], corner[q])] for p, q in edges]
                eid += 1
                row = [eid] + nodes
                lines.append(", ".join(str(v) for v in row[:16]) + ",")
                lines.append(", ".join(str(v) for v in row[16:]))
    root = [n for (i, j, k), n in ids.items() if i == 0]
    tip_a = [n for (i, j, k), n in ids.items() if i == 2 * nx and B * j / (2 * ny) <= 0.49]
    tip_b = [n for (i, j, k), n in ids.items() if i == 2 * nx and B * j / (2 * ny) >= 0.51]

    def nset(name, ns):
        lines.append(f"*NSET, NSET={name}")
        for s in range(0, len(ns), 12):
            lines.append(", ".join(str(n) for n in ns[s:s + 12]) + ",")

    nset("ROOT", sorted(root))
    nset("TIPA", sorted(tip_a))
    nset("TIPB", sorted(tip_b))
    nset("REFS", [ref_a, ref_b])
    lines += [
        "*MATERIAL, NAME=M", "*ELASTIC", f"{E:.6e}, {NU}", "*DENSITY", "1000.",
        "*SOLID SECTION, ELSET=PLATE, MATERIAL=M",
        f"*RIGID BODY, NSET=TIPA, REF NODE={ref_a}, ROT NODE={rot_a}",
        f"*RIGID BODY, NSET=TIPB, REF NODE={ref_b}, ROT NODE={rot_b}",
        "*BOUNDARY", "ROOT, 1, 3",
        "*TIME POINTS, NAME=T1, GENERATE", "0.05, 1.0, 0.05",
        "*STEP, NLGEOM, INC=1000", "*STATIC", "0.01, 1.0, 1e-6, 0.05",
        "*CLOAD", f"{ref_a}, 3, {-0.5 * P:.6e}", f"{ref_b}, 3, {-0.5 * P:.6e}",
        "*NODE PRINT, NSET=REFS, TIME POINTS=T1", "U", "*END STEP",
    ]
    return "\n".join(lines) + "\n"


if __name__ == "__main__":
    nx, ny, nz = (int(v) for v in sys.argv[1:4])
    open(sys.argv[4], "w").write(deck(nx, ny, nz))
