#!/bin/bash
# Two builds of eapbd in turns, one and two threads, five runs of each case, with the cores'
# one-way handoff latency before each turn (the `core_latency` example: on a virtual machine it
# changes with where the host puts the cores, and the two threads' speed with it). Cases: the
# peer scene at 30 x 1 and 1 x 30 and cloth-paper (120 frames), the default bunny (200 frames);
# name some to run only those. Prints each run's median solve time per frame (ms), then per case
# the median over the runs, NEW/OLD, and each build's two-thread speed-up.
# Usage: docs/bench/compare_builds.sh OLD_BINARY NEW_BINARY [peer-30x1|peer-1x30|cloth-paper|bunny ...]
# (from the repository root)
set -euo pipefail
old=$1 new=$2
shift 2
cases=("$@")
[ ${#cases[@]} -eq 0 ] && cases=(peer-30x1 peer-1x30 cloth-paper bunny)
cargo build --release --quiet --example core_latency
latency=target/release/examples/core_latency
peer="--scene cloth --resolution 64 --stiffness 1e6 --bending-stiffness 1e-3 --diagonals alternating"
out=$(mktemp)
for case in "${cases[@]}"; do
  case $case in
    peer-30x1) args="$peer --iterations 30 --substeps 1 --frames 120" ;;
    peer-1x30) args="$peer --iterations 1 --substeps 30 --frames 120" ;;
    cloth-paper) args="--scene cloth-paper --frames 120" ;;
    bunny) args="--scene bunny --frames 200" ;;
    *) echo "unknown case $case" >&2; exit 2 ;;
  esac
  for threads in 1 2; do
    for _ in 1 2 3 4 5; do
      $latency 100000 | sed 's/.*: \([0-9.]*\) ns one way.*/latency|\1/' >> "$out"
      for b in old new; do
        bin=$old; [ "$b" = new ] && bin=$new
        # shellcheck disable=SC2086
        m=$("$bin" simulate $args --threads "$threads" --print-every 100000 2>&1 | grep -o "median [0-9.]*" | awk '{print $2}')
        echo "$case|$threads|$b|$m" | tee -a "$out"
      done
    done
  done
done
python3 - "$out" <<'PY'
import collections, statistics, sys
d, lat = collections.defaultdict(list), []
for line in open(sys.argv[1]):
    f = line.strip().split("|")
    if f[0] == "latency":
        lat.append(float(f[1]))
        continue
    d[(f[0], f[1], f[2])].append(float(f[3]))
med = {k: statistics.median(v) for k, v in d.items()}
for case in dict.fromkeys(k[0] for k in d):
    for threads in ("1", "2"):
        o, n = med[(case, threads, "old")], med[(case, threads, "new")]
        print(f"{case}, {threads} thread(s): old {o:.3f} ms, new {n:.3f} ms, new/old {n / o:.3f}")
    print(f"{case}, two-thread speed-up: old {med[(case, '1', 'old')] / med[(case, '2', 'old')]:.2f}, "
          f"new {med[(case, '1', 'new')] / med[(case, '2', 'new')]:.2f}")
print(f"one-way latency before the turns: {min(lat):.0f} to {max(lat):.0f} ns")
PY
