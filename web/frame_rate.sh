#!/usr/bin/env bash
# The web page's frame rate in headless Chromium (WebGPU on SwiftShader where there is no GPU):
# serves DIR (default target/web, built by web/build.sh) on localhost, opens the page once per
# QUERY and prints what the page posts after its last frame: the solver that ran, the mean frame
# rate from its first frame to its last and the viewer's split of a frame (ms).
#
# Usage: web/frame_rate.sh [--dir DIR] [QUERY ...]
#   default QUERY: cloth-paper at 1280 x 800 for 300 frames, panels drawn, with the CPU and the GPU
#   solver
set -euo pipefail
dir=target/web
if [ "${1:-}" = --dir ]; then dir=$2; shift 2; fi
[ $# -gt 0 ] || set -- "scene=cloth-paper&backend=cpu&frames=300&width=1280&height=800&panels=1" \
    "scene=cloth-paper&backend=gpu&frames=300&width=1280&height=800&panels=1"
browser=${EAPBD_CHROMIUM:-chromium}
command -v "$browser" >/dev/null || { echo "web/frame_rate.sh: no $browser (set EAPBD_CHROMIUM)" >&2; exit 1; }
[ -f "$dir/eapbd_bg.wasm" ] || { echo "web/frame_rate.sh: no page in $dir (run web/build.sh)" >&2; exit 1; }
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
http.server.ThreadingHTTPServer(("127.0.0.1", int(sys.argv[2])), Handler).serve_forever()
PY
server=$!
pid=
trap 'kill $server $pid 2>/dev/null; rm -f "$log"' EXIT
sleep 1
kill -0 $server 2>/dev/null || { echo "web/frame_rate.sh: the server did not start on port $port" >&2; exit 1; }
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
        kill -0 $pid 2>/dev/null || break
        sleep 1
    done
    kill $pid 2>/dev/null || true
    wait $pid 2>/dev/null || true
    rm -rf "$profile" 2>/dev/null || true
    echo "$query: $(tail -n +$((before + 1)) "$log" | head -1)"
    pid=
done
