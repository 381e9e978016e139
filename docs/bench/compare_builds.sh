#!/bin/bash
# Two builds of eapbd in turns on the peer scene (30 x 1 and 1 x 30) and cloth-paper, one and two
# threads, five runs of 120 frames each: prints each run's median solve time per frame (ms), then
# the median over the runs and the ratio NEW/OLD.
# Usage: docs/bench/compare_builds.sh OLD_BINARY NEW_BINARY
set -euo pipefail
old=$1 new=$2
peer="--scene cloth --resolution 64 --stiffness 1e6 --bending-stiffness 1e-3 --diagonals alternating"
out=$(mktemp)
for case in "peer 30x1" "peer 1x30" "cloth-paper"; do
  case $case in
    "peer 30x1") args="$peer --iterations 30 --substeps 1" ;;
    "peer 1x30") args="$peer --iterations 1 --substeps 30" ;;
    *) args="--scene cloth-paper" ;;
  esac
  for threads in 1 2; do
    for _ in 1 2 3 4 5; do
      for b in old new; do
        bin=$old; [ "$b" = new ] && bin=$new
        m=$("$bin" simulate $args --frames 120 --threads "$threads" --print-every 100000 2>&1 | grep -o "median [0-9.]*" | awk '{print $2}')
        echo "$case|$threads|$b|$m" | tee -a "$out"
      done
    done
  done
done
python3 - "$out" <<'PY'
import collections, statistics, sys
d = collections.defaultdict(list)
for line in open(sys.argv[1]):
    case, threads, b, m = line.strip().split("|")
    d[(case, threads, b)].append(float(m))
for case, threads in sorted({(k[0], k[1]) for k in d}):
    o, n = (statistics.median(d[(case, threads, b)]) for b in ("old", "new"))
    print(f"{case}, {threads} thread(s): old {o:.3f} ms, new {n:.3f} ms, new/old {n / o:.3f}")
PY
