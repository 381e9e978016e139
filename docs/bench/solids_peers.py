#!/usr/bin/env python3
"""Per-tetrahedron projection cost on the peers' cantilever, in one sitting: our five models
(`eapbd simulate --scene beam --resolution 24 --young 1e6 --threads 1`) beside pypbd's
FEM-based XPBD and FEM-based PBD (`peer_beam.py`, the same mesh, masses and settings), at the
issue's split (1 substep x 15 iterations of a 1/60 s frame) and at 60 x 1, where pypbd's XPBD
beam stays stable. With `--old BIN` a second build of eapbd runs in the same turns (to compare
builds). ns per projection = median ms per frame / (tets x substeps x iterations); the frame's
other passes (prediction, finish, the frame's statistics) are included.

    python3 docs/bench/solids_peers.py [--bin target/release/eapbd] [--old OLD_BIN] [--frames 120]
                                       [--csv docs/bench/solids.csv]
"""
import argparse
import csv
import os
import re
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import peer_beam  # noqa: E402  (sets OMP_NUM_THREADS=1 before pypbd loads)

MODELS = ["linear", "stvk", "neo-hookean", "mooney-rivlin", "arruda-boyce"]
SPLITS = [(1, 15), (60, 1)]


def eapbd(binary, model, substeps, iterations, frames):
    """Median ms per frame and the final max stretch of one `simulate` run."""
    out = subprocess.run(
        [binary, "simulate", "--scene", "beam", "--resolution", "24", "--material", model,
         "--young", "1e6", "--substeps", str(substeps), "--iterations", str(iterations),
         "--threads", "1", "--frames", str(frames)],
        check=True, capture_output=True, text=True).stdout
    m = re.search(r"\(median ([0-9.]+)\), final stretch mean \S+ max ([^,]+),", out)
    if not m:
        sys.exit(f"unexpected output of {binary}:\n{out[-500:]}")
    return float(m.group(1)), m.group(2) + (", finite" if "all finite" in out else ", NOT FINITE")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--bin", default="target/release/eapbd")
    ap.add_argument("--old", help="an earlier build of eapbd, run in the same turns")
    ap.add_argument("--frames", type=int, default=120)
    ap.add_argument("--csv", metavar="PATH")
    a = ap.parse_args()
    points, tets = peer_beam.beam(24)
    rows, keep = [], []
    for substeps, iterations in SPLITS:
        per = len(tets) * substeps * iterations
        for name, method in peer_beam.METHODS:
            ms, sag, model = peer_beam.run(method, points, tets, a.frames, substeps, iterations)
            keep.append(model)
            rows.append((f"{substeps} x {iterations}", f"pypbd {name}", ms, ms * 1e6 / per, f"tip moved {sag:.2f} m"))
        builds = [("eapbd", a.bin)] + ([("eapbd (old build)", a.old)] if a.old else [])
        for model in MODELS:
            for label, binary in builds:
                ms, sanity = eapbd(binary, model, substeps, iterations, a.frames)
                rows.append((f"{substeps} x {iterations}", f"{label} {model}", ms, ms * 1e6 / per, f"max stretch {sanity}"))
    print(f"{len(tets)} tetrahedra, {a.frames} frames, one thread\n")
    print("| split | solver | ms/frame | ns per tet projection | sanity |\n|---|---|---|---|---|")
    for split, solver, ms, ns, note in rows:
        print(f"| {split} | {solver} | {ms:.3f} | {ns:.1f} | {note} |")
    if a.csv:
        with open(a.csv, "w", newline="") as fh:
            w = csv.writer(fh)
            w.writerow(["split", "solver", "ms_per_frame", "ns_per_projection", "sanity"])
            w.writerows([(s, n, f"{ms:.4f}", f"{ns:.2f}", note) for s, n, ms, ns, note in rows])


if __name__ == "__main__":
    main()
