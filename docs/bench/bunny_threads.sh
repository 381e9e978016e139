#!/bin/bash
# Two builds of eapbd in turns on the default bunny (4,998 tetrahedra, 30 × 1), one thread and
# two, five runs of 200 frames each, with the cores' one-way latency before each run (the
# `core_latency` example: on a virtual machine it changes with where the host puts the cores, and
# the two threads' speed with it). Prints each run's median solve time per frame (ms), then the
# medians over the runs, each build's two-thread speed-up and NEW/OLD.
# Usage: docs/bench/bunny_threads.sh OLD_BINARY NEW_BINARY  (from the repository root)
set -euo pipefail
old=$1 new=$2
cargo build --release --quiet --example core_latency
latency=target/release/examples/core_latency
out=$(mktemp)
for run in 1 2 3 4 5; do
  $latency 200000 | tee -a "$out.latency"
  for threads in 1 2; do
    for b in old new; do
      bin=$old; [ "$b" = new ] && bin=$new
      m=$("$bin" simulate --scene bunny --frames 200 --threads "$threads" --print-every 100000 2>&1 | grep -o "median [0-9.]*" | awk '{print $2}')
      echo "run $run|$threads|$b|$m" | tee -a "$out"
    done
  done
done
python3 - "$out" <<'PY'
import collections, statistics, sys
d = collections.defaultdict(list)
for line in open(sys.argv[1]):
    _, threads, b, m = line.strip().split("|")
    d[(threads, b)].append(float(m))
med = {k: statistics.median(v) for k, v in d.items()}
for b in ("old", "new"):
    print(f"{b}: one thread {med[('1', b)]:.3f} ms, two {med[('2', b)]:.3f} ms, speed-up {med[('1', b)] / med[('2', b)]:.2f}")
for t in ("1", "2"):
    print(f"{t} thread(s): new/old {med[(t, 'new')] / med[(t, 'old')]:.3f}")
PY
sed 's/.*: \([0-9.]*\) ns one way.*/\1/' "$out.latency" | sort -n | awk '{a[NR]=$1} END {print "one-way latency over the runs: " a[1] " to " a[NR] " ns"}'
