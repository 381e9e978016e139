#!/usr/bin/env bash
# The GPU path on a machine with a real GPU, in one short run (about five minutes): the bench's
# GPU rows, the volumetric bunny and the cantilever beam on the GPU and on the CPU of the same
# machine, the energy-aware projection and self-collision off and on, the headless renderer's cost
# per image, the GPU test suites on that hardware and (unless STABILITY=0) the stability study.
#
# Usage: docs/bench/gpu_machine.sh BIN_DIR OUT_DIR
#   BIN_DIR holds a release `eapbd` (built for that machine's processor: the project compiles
#   for the builder's, so build with RUSTFLAGS="-C target-cpu=x86-64-v3" when they differ) and,
#   optionally, test binaries named after their suites
#   (gpu_parity, gpu_stages, ...; from `cargo test --release --no-run`, renamed). Run it from
#   the repository root: the tests read their stored images from the directory they were built
#   in, so the script links that directory to this checkout when it does not exist.
#   OUT_DIR receives bench-gpu/ (bench.md and the CSV files), gpu_machine.log, bunny.png and
#   stability/.
set -u
bin=$(cd "$1" && pwd)
out=$2
mkdir -p "$out"
exec > >(tee "$out/gpu_machine.log") 2>&1
export WGPU_BACKEND=${WGPU_BACKEND:-vulkan} WGPU_POWER_PREF=${WGPU_POWER_PREF:-high}

echo "== machine"
date -u
nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv 2>/dev/null || echo "no nvidia-smi"
grep -m1 'model name' /proc/cpuinfo
nproc

echo "== the GPU adapter answers"
"$bin/eapbd" simulate --scene cloth-paper --backend gpu --frames 10 --print-every 10 || exit 1

echo "== bench --gpu-only"
timeout 300 "$bin/eapbd" bench --gpu-only --out "$out/bench-gpu" >/dev/null
tail -n +1 "$out/bench-gpu/bench.md" | sed -n '/## Time per frame/,/## Memory/p'
sed -n '/## Scaling/,$p' "$out/bench-gpu/bench.md"

echo "== solids: the default bunny and the peers' cantilever, GPU and CPU"
beam=(--scene beam --resolution 24 --material neo-hookean --young 1e6 --iterations 15)
for backend in "--backend gpu" "--threads 1" "--threads 0"; do
    for scene in "--scene bunny" "${beam[*]}"; do
        echo "-- $scene $backend"
        # shellcheck disable=SC2086
        timeout 60 "$bin/eapbd" simulate $scene $backend --frames 120 --print-every 120 | grep -E '^(scene|summary)'
    done
done

echo "== off and on, in turns: the energy-aware projection (hanging cloth, 10 x 3 and 30 x 1) and"
echo "   self-collision (the 64 x 64 drape at k = 1e6, 30 x 1), GPU, one thread and every thread"
aware=(--scene cloth --frames 600 --print-every 600)
drape=(--scene cloth-drape --resolution 64 --stiffness 1e6 --substeps 30 --iterations 1 --frames 300 --print-every 300)
for backend in "--backend gpu" "--threads 1" "--threads 0"; do
    for split in "--substeps 10 --iterations 3" "--substeps 30 --iterations 1"; do
        for mode in off project; do
            echo "-- energy-aware $mode $split $backend"
            # shellcheck disable=SC2086
            timeout 60 "$bin/eapbd" simulate "${aware[@]}" $split --energy-aware $mode $backend | grep -E '^summary'
        done
    done
    for mode in off on; do
        echo "-- self-collision $mode $backend"
        # shellcheck disable=SC2086
        timeout 60 "$bin/eapbd" simulate "${drape[@]}" --self-collision $mode $backend | grep -E '^(summary|self-collision)'
    done
done

echo "== headless images of the bunny (1280 x 800): 120 frames with one image, then with 120"
for every in 120 1; do
    start=$(date +%s%N)
    timeout 120 "$bin/eapbd" render --scene bunny --frames 120 --every "$every" --width 1280 --height 800 \
        --out /tmp/eapbd-frames-$every >/dev/null
    end=$(date +%s%N)
    echo "every $every: $(( (end - start) / 1000000 )) ms"
done
cp /tmp/eapbd-frames-120/frame_00120.png "$out/bunny.png" 2>/dev/null

echo "== GPU test suites"
built=/work/main
if [ ! -e "$built" ] && [ "$(pwd)" != "$built" ]; then
    mkdir -p "$(dirname "$built")" && ln -s "$(pwd)" "$built"
fi
# The CLI tests run the binary they were built beside (CARGO_BIN_EXE_eapbd, an absolute path).
want=$(grep -ao '/[[:alnum:]/_.-]*/release/eapbd' "$bin/screenshot" 2>/dev/null | head -1)
if [ -n "$want" ] && [ ! -e "$want" ]; then
    mkdir -p "$(dirname "$want")" && ln -s "$bin/eapbd" "$want"
fi
for t in gpu_parity gpu_stages gpu_solids gpu_projection self_collision screenshot allocation viewer_state; do
    [ -x "$bin/$t" ] || continue
    echo "-- $t"
    timeout 60 "$bin/$t" --test-threads 8 2>&1 | grep -E '^(test |test result|---- |thread )' | grep -v ' ok$'
done
if [ "${STABILITY:-1}" = 1 ]; then
    echo "== the stability study on this GPU"
    timeout 200 "$bin/eapbd" report stability --out "$out/stability" | tail -3
fi
echo "== done"
