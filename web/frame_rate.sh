#!/usr/bin/env bash
# The web page's frame rate in headless Chromium (WebGPU on SwiftShader where there is no GPU):
# serves DIR (default target/web, built by web/build.sh) on localhost, opens the page once per
# QUERY and prints what the page posts after its last frame: the solver that ran, the mean frame
# rate over the run (start-up included) and the viewer's split of a frame (ms).
#
# Usage: web/frame_rate.sh [--dir DIR] [QUERY ...]
#   default QUERY: the viewer's start at 1280 x 800 for 300 frames, with the CPU and the GPU solver
set -euo pipefail
dir=target/web
if [ "${1:-}" = --dir ]; then dir=$2; shift 2; fi
[ $# -gt 0 ] || set -- "backend=cpu&frames=300&width=1280&height=800&panels=1" \
    "backend=gpu&frames=300&width=1280&height=800&panels=1"
browser=${EAPBD_CHROMIUM:-chromium}
log=$(mktemp)
port=$((20000 + RANDOM % 20000))
python3 - "$dir" "$port" >"$log" 2>/dev/null <<'PY' &
import http.server, sys
class Handler(http.server.SimpleHTTPRequestHandler):
    def __init__(self, *a, **k):
        super().__init__(*a, directory=sys.argv[1], **k)
    def do_POST(self):
        self.rfile.read(int(self.headers["Content-Length"]))
        self.send_response(200)
        self.end_headers()
        print(self.path.split("?", 1)[1], flush=True)
    def log_message(self, *a):
        pass
http.server.HTTPServer(("127.0.0.1", int(sys.argv[2])), Handler).serve_forever()
PY
server=$!
trap 'kill $server 2>/dev/null; rm -f "$log"' EXIT
sleep 1
for query in "$@"; do
    before=$(wc -l <"$log")
    profile=$(mktemp -d)
    "$browser" --headless --no-sandbox --no-first-run --enable-unsafe-webgpu --enable-features=Vulkan \
        --use-vulkan=swiftshader --use-angle=swiftshader --enable-unsafe-swiftshader \
        --remote-debugging-port=0 --user-data-dir="$profile" \
        "http://127.0.0.1:$port/index.html?$query&post=/frame" >/dev/null 2>&1 &
    pid=$!
    for _ in $(seq 600); do
        [ "$(wc -l <"$log")" -gt "$before" ] && break
        sleep 1
    done
    kill $pid 2>/dev/null; wait $pid 2>/dev/null || true
    rm -rf "$profile" 2>/dev/null || true
    echo "$query: $(tail -n +$((before + 1)) "$log" | head -1)"
done
