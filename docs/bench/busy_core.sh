#!/bin/bash
# Two builds of eapbd in turns on the bunny and the cloth of the bench (64 x 64, k = 1e6, 1 x 30),
# one and two threads, alone and beside a busy loop that keeps one core working (another program
# on the machine): three runs of 300 frames each, each run's median solve time per frame (ms).
# Usage: docs/bench/busy_core.sh OLD_BINARY NEW_BINARY
set -uo pipefail
median() { "$@" --frames 300 2>&1 | grep -o 'median [0-9.]*' | cut -d' ' -f2; }
for rep in 1 2 3; do
  for scene in "--scene bunny" "--scene cloth --resolution 64 --stiffness 1e6 --substeps 1 --iterations 30"; do
    for busy in no yes; do
      if [ "$busy" = yes ]; then (while :; do :; done) & loop=$!; sleep 0.5; fi
      line="run $rep | $scene | busy core: $busy"
      for bin in "$1" "$2"; do
        # shellcheck disable=SC2086
        line="$line | $bin: one thread $(median "$bin" simulate $scene --threads 1), two $(median "$bin" simulate $scene --threads 2)"
      done
      if [ "$busy" = yes ]; then kill "$loop"; wait "$loop" 2>/dev/null; fi
      echo "$line"
    done
  done
done
