#!/usr/bin/env python3
"""Exudyn counterpart of `crates/flexmbs-validate/benches/ffr_steps.rs` (rotating tube, one FFR body).

Reads the reduced data exported by the flexmbs bench (`FFR_BENCH_EXPORT=dir cargo bench -p
flexmbs-validate --bench ffr_steps`): node positions, lumped node masses, the 100 translational
modes (mass-normalized, clamped at x = 0) and the reduced stiffness. For each mode count n it builds
Exudyn's C++ ObjectFFRFreducedOrder from the first n modes with the same data (a duck-typed
FEMinterface: diagonal lumped mass matrix; the reduced stiffness is set to the exported k_ff), with
the rigid-body node of type RotationRxyz (Cardan x-y-z, as the flexmbs body), and the same
simulation: reference frame origin fixed and the rotation about z driven at 100 rad/s (coordinate
constraints; rotation rate prescribed at velocity level), rigid spin as initial state, initial
modal velocity 0.05 on the first two modes, generalized-alpha rho_inf = 0.9, fixed step h = 1e-4 s,
2000 steps. Times `mbs.SolveDynamic` with time.perf_counter (set-up excluded), and compares the
tip deflection (body-frame y of the node at (L, R, 0): Phi_tip,y q_f) with flexmbs'
`tip_flexmbs_<n>_full.csv` and `tip_flexmbs_<n>_modified.csv` (full / modified Newton).

Usage: python3 ffr_exudyn.py DIR [n ...]   (needs `pip install exudyn numpy scipy`)
"""
import sys
import time

import numpy as np
import scipy.sparse as sp

import exudyn as exu
from exudyn.FEM import ObjectFFRFreducedOrderInterface
import exudyn.itemInterface as eii

H, STEPS, OMEGA, QF_DOT0 = 1e-4, 2000, 100.0, 0.05


class ReducedData:
    """Duck-typed FEMinterface with exactly the members ObjectFFRFreducedOrderInterface uses."""

    def __init__(self, nodes, masses, modes):
        self.nodes = nodes
        self.modeBasis = {'matrix': modes}
        self.postProcessingModes = {}
        self.mass = sp.diags(np.repeat(masses, 3)).tocsr()

    def GetNodePositionsAsArray(self):
        return self.nodes

    def GetSurfaceTriangles6(self):
        return []

    def GetSurfaceTriangles(self):
        return []

    def GetMassMatrix(self, sparse=True):
        return self.mass

    def GetStiffnessMatrix(self, sparse=True):
        # the reduced stiffness is overwritten with the exported k_ff below
        return sp.csr_matrix(self.mass.shape)


def tip_node(nodes):
    return int(np.argmin(((nodes - np.array([1.0, 0.01, 0.0])) ** 2).sum(axis=1)))


def run(d, n):
    nodes = np.load(f'{d}/nodes.npy')
    masses = np.load(f'{d}/masses.npy')
    modes = np.load(f'{d}/modes.npy')[:, :n].copy()
    kff = np.load(f'{d}/kff.npy')[:n, :n].copy()
    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    cms = ObjectFFRFreducedOrderInterface(ReducedData(nodes, masses, modes),
                                          rigidBodyNodeType='NodeType.RotationRxyz')
    cms.stiffnessMatrixReduced = kff
    cms.AddObjectFFRFreducedOrder(mbs, positionRef=[0, 0, 0], initialVelocity=[0, 0, 0],
                                  initialAngularVelocity=[0, 0, OMEGA])
    nR, nG = cms.nRigidBody, cms.nGenericODE2
    v0 = [0.0] * n
    for i in range(min(2, n)):
        v0[i] = QF_DOT0
    mbs.SetNodeParameter(nG, 'initialCoordinates_t', v0)
    ground = mbs.AddNode(eii.NodePointGround())
    mg = mbs.AddMarker(eii.MarkerNodeCoordinate(nodeNumber=ground, coordinate=0))
    for c in range(6):
        mc = mbs.AddMarker(eii.MarkerNodeCoordinate(nodeNumber=nR, coordinate=c))
        if c < 5:
            mbs.AddObject(eii.CoordinateConstraint(markerNumbers=[mg, mc]))
        else:  # theta_z_dot = OMEGA
            mbs.AddObject(eii.CoordinateConstraint(markerNumbers=[mg, mc], offset=OMEGA,
                                                   velocityLevel=True))
    mbs.AddSensor(eii.SensorNode(nodeNumber=nG, storeInternal=True,
                                 outputVariableType=exu.OutputVariableType.Coordinates))
    mbs.Assemble()
    ss = exu.SimulationSettings()
    ss.timeIntegration.numberOfSteps = STEPS
    ss.timeIntegration.endTime = STEPS * H
    ss.timeIntegration.adaptiveStep = False
    ss.timeIntegration.generalizedAlpha.spectralRadius = 0.9
    ss.timeIntegration.verboseMode = 0
    ss.solutionSettings.writeSolutionToFile = False  # noqa (name kept for older Exudyn)
    ss.solutionSettings.sensorsWritePeriod = 10 * H
    ss.displayComputationTime = False
    t0 = time.perf_counter()
    mbs.SolveDynamic(ss, solverType=exu.DynamicSolverType.GeneralizedAlpha)
    wall = time.perf_counter() - t0
    data = mbs.GetSensorStoredData(0)
    tip = tip_node(nodes)
    phi = modes[3 * tip + 1, :]
    tip_y = data[:, 1:1 + n] @ phi
    return wall, data[:, 0], tip_y


def main():
    d = sys.argv[1]
    counts = [int(x) for x in sys.argv[2:]] or [6, 12, 24, 50, 100]
    print('| modes | Exudyn wall [s] | Exudyn us/step | tip y [mm] at t = 0.05 / 0.1 / 0.2 s (Exudyn) '
          '| same (flexmbs, full Newton) | max abs difference over the run, full / modified Newton [mm] |')
    print('|---|---|---|---|---|---|')
    pick = lambda tt, yy: ' / '.join(f'{1e3 * np.interp(x, tt, yy):.4f}' for x in (0.05, 0.1, 0.2))
    for n in counts:
        wall, t, y = run(d, n)
        diffs = []
        for kind in ('full', 'modified'):
            ref = np.loadtxt(f'{d}/tip_flexmbs_{n}_{kind}.csv', delimiter=',', skiprows=1)
            yr = np.interp(t, ref[:, 0], ref[:, 1], left=np.nan)
            ok = ~np.isnan(yr)
            diffs.append(np.max(np.abs(y[ok] - yr[ok])) * 1e3)
            if kind == 'full':
                flex = pick(ref[:, 0], ref[:, 1])
        print(f'| {n} | {wall:.3f} | {1e6 * wall / STEPS:.1f} | {pick(t, y)} | {flex} | '
              f'{diffs[0]:.2e} / {diffs[1]:.2e} |', flush=True)


if __name__ == '__main__':
    main()
