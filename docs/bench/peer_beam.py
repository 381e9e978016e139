#!/usr/bin/env python3
"""Per-tetrahedron projection cost of PositionBasedDynamics (pypbd 2.2.2) on the cantilever beam.

The `beam` scene of our simulator, rebuilt in pypbd: a 1 m x 0.2 m x 0.2 m box from
(-0.5, 0.9, -0.1) to (0.5, 1.1, 0.1), nx x ny x nz cells (nx = --resolution, ny = nz =
max(nx // 5, 1)), each cell split into 6 tetrahedra around its main diagonal (the same
vertex numbering, tetrahedra and orientation as `TetMesh::box_grid`; 2304 tets at nx = 24).
Density 1000 kg/m^3 as lumped vertex masses (each tet gives a quarter of its mass to each
corner; pypbd's own default is 1 kg per particle), E = 1e6 Pa, nu = 0.3, gravity -9.81 in y
(pypbd's default), the x = -0.5 end fixed (mass 0), frames of 1/60 s, one substep
of 15 position iterations unless --substeps and --iterations say otherwise, no velocity iterations, no collision detection, no damping.

Run once for each of pypbd's FEM solid methods (`SimulationModel.addSolidConstraints`):
  2 = "FEM-based PBD"  (Bender et al. 2014: C = rest volume x StVK energy density)
  3 = "FEM-based XPBD" (C = sqrt(2 U / E), compliance 1 / (E dt^2))
Both compute the deformation gradient and the StVK stress of every tet in every
iteration (an SVD only for a tet below 20 % of its rest volume). The iteration count is
exact: `TimeStepController` runs all `maxIterations` with no convergence test, in
graph-coloured groups of independent constraints (Gauss-Seidel). In the PBD method
Young's modulus cancels out of the correction (C and grad C both scale with E), so the
result does not depend on E: it is as stiff as 15 iterations make it.

pypbd is built with OpenMP (it links libgomp; groups of more than 64 constraints run in
parallel); OMP_NUM_THREADS=1 is set before the import so it runs on one thread.

Timing: a few warm-up frames, then `--frames` frames each timed with time.perf_counter
around `TimeStep.step`; reported are the median ms per frame and the median divided by
tets x iterations x substeps (ns per tet projection; the frame's integration and
bookkeeping are included in it). "tip sag" is the largest displacement of a vertex of the
free end (x = +0.5) after the run: a sanity check that the beam sags and does not explode.
(The static Euler-Bernoulli sag at E = 1e6 Pa is 0.37 m, and nothing damps the swing.)
With one 1/60 s substep the XPBD beam goes unstable within a few frames; its inverted tets
then take the SVD path, so its timing is of that path for many tets.

    python3 docs/bench/peer_beam.py [--resolution 24] [--frames 120] [--substeps 1] [--iterations 15]
                                    [--csv out.csv]

`docs/bench/solids_peers.py` runs it beside our models in one sitting.
"""
import os

os.environ["OMP_NUM_THREADS"] = "1"

import argparse
import csv
import itertools
import statistics
import time

import numpy as np
import pypbd as pbd

DENSITY, YOUNG, POISSON = 1000.0, 1e6, 0.3
DT, WARMUP = 1.0 / 60.0, 5
METHODS = [("FEM-based XPBD", 3), ("FEM-based PBD", 2)]
LO, HI = np.array([-0.5, 0.9, -0.1]), np.array([0.5, 1.1, 0.1])


def beam(nx):
    """Vertices and tets of the box grid: each cell cut into 6 positively oriented tets."""
    n = np.array([nx, max(nx // 5, 1), max(nx // 5, 1)])
    idx = lambda i, j, k: i + (n[0] + 1) * (j + (n[1] + 1) * k)
    step = (HI - LO) / n
    points = [LO + step * np.array([i, j, k], dtype=float)
              for k in range(n[2] + 1) for j in range(n[1] + 1) for i in range(n[0] + 1)]
    tets = []
    for k, j, i in itertools.product(range(n[2]), range(n[1]), range(n[0])):
        for p in itertools.permutations(range(3)):
            c, t = [i, j, k], [idx(i, j, k)]
            for axis in p:
                c[axis] += 1
                t.append(idx(*c))
            if p in ((0, 2, 1), (1, 0, 2), (2, 1, 0)):  # odd permutations: mirror back
                t[2], t[3] = t[3], t[2]
            tets.append(t)
    return np.array(points), np.array(tets)


def run(method, points, tets, frames, substeps=1, iterations=15):
    sim = pbd.Simulation.getCurrent()
    model = pbd.SimulationModel()  # no collision detection is attached (unlike initDefault)
    model.init()
    sim.setModel(model)
    sim.reset()
    ts = sim.getTimeStep()
    ts.setValueUInt(pbd.TimeStepController.NUM_SUB_STEPS, substeps)
    ts.setValueUInt(pbd.TimeStepController.MAX_ITERATIONS, iterations)
    ts.setValueUInt(pbd.TimeStepController.MAX_ITERATIONS_V, 0)
    pbd.TimeManager.getCurrent().setTimeStepSize(DT)

    tm = model.addTetModel([p.reshape(3, 1) for p in points], tets.ravel().tolist())
    e = points[tets]
    vol = np.einsum("ij,ij->i", e[:, 1] - e[:, 0], np.cross(e[:, 2] - e[:, 0], e[:, 3] - e[:, 0])) / 6
    assert (vol > 0).all()
    mass = np.zeros(len(points))
    np.add.at(mass, tets.ravel(), np.repeat(DENSITY * vol / 4, 4))
    mass[points[:, 0] <= LO[0] + 1e-9] = 0.0
    pd = model.getParticles()
    off = tm.getIndexOffset()
    for i, m in enumerate(mass):
        pd.setMass(off + i, float(m))
    model.addSolidConstraints(tm, method, YOUNG, POISSON, YOUNG, False, False)

    times = []
    for f in range(WARMUP + frames):
        t0 = time.perf_counter()
        ts.step(model)
        t1 = time.perf_counter()
        if f >= WARMUP:
            times.append(t1 - t0)
    tip = [off + i for i in np.flatnonzero(points[:, 0] >= HI[0] - 1e-9)]
    sag = max(np.linalg.norm(pd.getPosition(i).ravel() - pd.getPosition0(i).ravel()) for i in tip)
    return statistics.median(times) * 1e3, sag, model


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--resolution", type=int, default=24)
    ap.add_argument("--frames", type=int, default=120)
    ap.add_argument("--substeps", type=int, default=1)
    ap.add_argument("--iterations", type=int, default=15)
    ap.add_argument("--csv", metavar="PATH")
    a = ap.parse_args()
    points, tets = beam(a.resolution)
    rows, keep = [], []
    for name, method in METHODS:
        ms, sag, model = run(method, points, tets, a.frames, a.substeps, a.iterations)
        keep.append(model)  # the Simulation holds a raw pointer to it
        ns = ms * 1e6 / (len(tets) * a.iterations * a.substeps)
        print(f"pypbd {name}: {len(tets)} tets, {a.substeps} x {a.iterations}, median {ms:.3f} ms/frame, "
              f"{ns:.1f} ns per tet projection, tip sag {sag:.4f} m")
        rows.append([f"pypbd {name}", len(tets), a.substeps, a.iterations, f"{ms:.4f}", f"{ns:.2f}", f"{sag:.6f}"])
    if a.csv:
        with open(a.csv, "w", newline="") as fh:
            w = csv.writer(fh)
            w.writerow(["solver", "tets", "substeps", "iterations", "ms_per_frame", "ns_per_projection", "tip_sag_m"])
            w.writerows(rows)


if __name__ == "__main__":
    main()
