//! The viewer's web page in a real browser: `web/build.sh` builds it, a server on localhost
//! serves it, headless Chromium runs `cloth-paper` for 60 frames on its WebGPU adapter
//! (SwiftShader where there is no GPU) with either solver, and the page posts its last frame's
//! scene back. Each must show the cloth and match the same viewer session drawn natively (the
//! CPU solver, lavapipe in CI) within `MEAN_TOLERANCE`. A second test drags the cloth with the
//! mouse through Chromium's DevTools protocol.
//!
//! Needs Chromium: Debian's `chromium` package (`.ci/run` installs it), or the binary that
//! `EAPBD_CHROMIUM` names. It fails, rather than skips, when the browser, its WebGPU adapter or
//! the page's build is missing.
#![cfg(feature = "viewer")]

mod common;

use std::io::{BufRead, BufReader, Read, Write};
use std::net::{TcpListener, TcpStream};
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::mpsc::{Receiver, Sender, channel};
use std::time::Duration;

use common::mean_abs_diff;
use eapbd::gpu::GpuContext;
use eapbd::render::{OFFSCREEN_FORMAT, OffscreenTarget};
use eapbd::scene::{SceneOptions, default_iterations};
use eapbd::simulation::Backend;
use eapbd::solver::Settings;
use eapbd::viewer::{SceneChoice, Session, ViewerState};

const W: u32 = 320;
const H: u32 = 240;
const FRAMES: u32 = 60;
/// Mean absolute difference per channel (0–255) allowed between the page's picture and the
/// native one: different rasterisers (SwiftShader, lavapipe) and the solver in WebAssembly or
/// WGSL against native code; the screenshot tests allow the same.
const MEAN_TOLERANCE: f64 = 1.5;
/// How long the page may take to post its frame.
const PAGE_TIMEOUT: Duration = Duration::from_secs(240);

/// Builds the page with `web/build.sh` (incremental: seconds when nothing changed), once for
/// the tests that run at the same time.
fn build_page() -> PathBuf {
    static PAGE: std::sync::OnceLock<PathBuf> = std::sync::OnceLock::new();
    PAGE.get_or_init(build).clone()
}

fn build() -> PathBuf {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let out = root.join("target").join("web");
    let status = Command::new("bash")
        .arg(root.join("web").join("build.sh"))
        .arg("--out")
        .arg(&out)
        .current_dir(root)
        .status()
        .expect("bash runs web/build.sh");
    assert!(status.success(), "web/build.sh failed");
    for file in ["index.html", "eapbd.js", "eapbd_bg.wasm"] {
        assert!(out.join(file).is_file(), "web/build.sh did not write {file}");
    }
    out
}

/// The Chromium binary: `EAPBD_CHROMIUM`, else the first of the usual names on the path.
fn chromium() -> PathBuf {
    if let Some(p) = std::env::var_os("EAPBD_CHROMIUM") {
        return PathBuf::from(p);
    }
    let path = std::env::var_os("PATH").unwrap_or_default();
    ["chromium", "chromium-browser", "google-chrome"]
        .iter()
        .flat_map(|name| std::env::split_paths(&path).map(move |dir| dir.join(name)))
        .find(|p| p.is_file())
        .expect("the web test needs Chromium: install Debian's `chromium` package or set EAPBD_CHROMIUM")
}

/// Reads an HTTP message's start line and headers: the start line and its `Content-Length`
/// (0 without one).
fn read_head(reader: &mut impl BufRead) -> std::io::Result<(String, usize)> {
    let mut line = String::new();
    reader.read_line(&mut line)?;
    let mut length = 0;
    loop {
        let mut header = String::new();
        if reader.read_line(&mut header)? == 0 || header.trim().is_empty() {
            return Ok((line, length));
        }
        if let Some((name, value)) = header.split_once(':')
            && name.eq_ignore_ascii_case("content-length")
        {
            length = value.trim().parse().unwrap_or(0);
        }
    }
}

/// What the page posts: its URL's query and its body.
type Posted = (String, Vec<u8>);

/// Answers one request: a file of `dir` for a GET, and a POST's query and body sent to `posted`.
fn answer(stream: TcpStream, dir: &Path, posted: &Sender<Posted>) -> std::io::Result<()> {
    let mut reader = BufReader::new(stream.try_clone()?);
    let (line, length) = read_head(&mut reader)?;
    let mut parts = line.split_whitespace();
    let (method, target) = (parts.next().unwrap_or(""), parts.next().unwrap_or("/"));
    let (path, query) = target.split_once('?').unwrap_or((target, ""));
    let path = path.trim_start_matches('/');
    let (status, kind, body) = if method == "POST" {
        let mut body = vec![0; length];
        reader.read_exact(&mut body)?;
        let _ = posted.send((query.to_string(), body));
        ("200 OK", "text/plain", b"ok".to_vec())
    } else {
        let name = if path.is_empty() { "index.html" } else { path };
        let kind = match Path::new(name).extension().and_then(|e| e.to_str()) {
            Some("html") => "text/html",
            Some("js") => "text/javascript",
            Some("wasm") => "application/wasm",
            _ => "application/octet-stream",
        };
        match (name.contains(".."), std::fs::read(dir.join(name))) {
            (false, Ok(bytes)) => ("200 OK", kind, bytes),
            _ => ("404 Not Found", "text/plain", b"not found".to_vec()),
        }
    };
    let mut stream = stream;
    write!(
        stream,
        "HTTP/1.1 {status}\r\nContent-Type: {kind}\r\nContent-Length: {}\r\nConnection: close\r\n\r\n",
        body.len()
    )?;
    stream.write_all(&body)
}

/// Serves `dir` on a free port of localhost (a secure context, as WebGPU needs); what the page
/// posts arrives on the receiver.
fn serve(dir: PathBuf) -> (u16, Receiver<Posted>) {
    let listener = TcpListener::bind("127.0.0.1:0").expect("a port on localhost");
    let port = listener.local_addr().unwrap().port();
    let (tx, rx) = channel();
    std::thread::spawn(move || {
        for stream in listener.incoming().flatten() {
            let (dir, tx) = (dir.clone(), tx.clone());
            std::thread::spawn(move || answer(stream, &dir, &tx));
        }
    });
    (port, rx)
}

/// Headless Chromium on one page, closed (and its profile removed) when dropped.
struct Browser {
    child: std::process::Child,
    profile: PathBuf,
    /// The port of its DevTools protocol.
    devtools: u16,
}

impl Browser {
    /// Opens `url` in headless Chromium.
    fn open(url: &str, (w, h): (u32, u32)) -> Browser {
        static OPENED: std::sync::atomic::AtomicU32 = std::sync::atomic::AtomicU32::new(0);
        let k = OPENED.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        let profile = std::env::temp_dir().join(format!("eapbd-chromium-{}-{k}", std::process::id()));
        let mut child = Command::new(chromium())
            .args(["--headless", "--no-sandbox", "--disable-gpu-sandbox", "--no-first-run"])
            // WebGPU on Chromium's software Vulkan (SwiftShader), which draws a canvas headless.
            .args(["--enable-unsafe-webgpu", "--enable-features=Vulkan", "--use-vulkan=swiftshader"])
            .args(["--use-angle=swiftshader", "--enable-unsafe-swiftshader"])
            // The DevTools protocol on a free port (it drives the mouse), which also keeps the
            // headless browser open until the test closes it.
            .arg("--remote-debugging-port=0")
            .arg(format!("--user-data-dir={}", profile.display()))
            .arg(format!("--window-size={w},{h}"))
            .arg(url)
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::piped())
            .spawn()
            .expect("Chromium starts");
        // "DevTools listening on ws://127.0.0.1:PORT/devtools/browser/…" on its standard error,
        // which is then read to its end so that the browser never blocks on it.
        let (tx, rx) = channel();
        let stderr = child.stderr.take().unwrap();
        std::thread::spawn(move || {
            for line in BufReader::new(stderr).lines().map_while(|l| l.ok()) {
                if let Some(rest) = line.split("ws://127.0.0.1:").nth(1) {
                    let _ = tx.send(rest.split('/').next().unwrap_or("").parse::<u16>().unwrap_or(0));
                }
            }
        });
        let devtools = rx.recv_timeout(Duration::from_secs(60)).unwrap_or(0);
        Browser { child, profile, devtools }
    }

    /// The DevTools protocol of its page.
    fn page(&self) -> DevTools {
        assert!(self.devtools != 0, "Chromium gave no DevTools port");
        let mut s = TcpStream::connect(("127.0.0.1", self.devtools)).unwrap();
        // The page's address names the host this request names.
        write!(s, "GET /json/list HTTP/1.1\r\nHost: 127.0.0.1:{}\r\n\r\n", self.devtools).unwrap();
        // The answer's body by its length (the connection stays open).
        let mut reader = BufReader::new(s);
        let (_, length) = read_head(&mut reader).unwrap();
        let mut body = vec![0; length];
        reader.read_exact(&mut body).unwrap();
        let list = String::from_utf8_lossy(&body);
        let start = list.find("ws://").expect("the page's DevTools address");
        let url = &list[start..start + list[start..].find('"').unwrap()];
        DevTools::connect(url)
    }
}

impl Drop for Browser {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
        let _ = std::fs::remove_dir_all(&self.profile);
    }
}

/// A minimal client of Chromium's DevTools protocol: JSON commands over a WebSocket.
struct DevTools {
    stream: TcpStream,
    next_id: u32,
}

impl DevTools {
    /// Opens the WebSocket at `url` (`ws://127.0.0.1:PORT/PATH`).
    fn connect(url: &str) -> DevTools {
        let rest = url.trim_start_matches("ws://");
        let (host, path) = rest.split_at(rest.find('/').unwrap());
        let mut stream = TcpStream::connect(host).unwrap_or_else(|e| panic!("DevTools at {url}: {e}"));
        stream.set_read_timeout(Some(Duration::from_secs(30))).unwrap();
        write!(
            stream,
            "GET {path} HTTP/1.1\r\nHost: {host}\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n\
             Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\nSec-WebSocket-Version: 13\r\n\r\n"
        )
        .unwrap();
        let mut head = Vec::new();
        let mut byte = [0u8; 1];
        while !head.ends_with(b"\r\n\r\n") {
            stream.read_exact(&mut byte).unwrap();
            head.push(byte[0]);
        }
        assert!(
            head.starts_with(b"HTTP/1.1 101"),
            "DevTools refused the WebSocket: {}",
            String::from_utf8_lossy(&head)
        );
        DevTools { stream, next_id: 1 }
    }

    /// Sends one text frame (masked, as a client must).
    fn send(&mut self, text: &str) {
        let payload = text.as_bytes();
        let mut frame = vec![0x81u8];
        match payload.len() {
            n if n < 126 => frame.push(0x80 | n as u8),
            n if n < 65536 => {
                frame.push(0x80 | 126);
                frame.extend_from_slice(&(n as u16).to_be_bytes());
            }
            n => {
                frame.push(0x80 | 127);
                frame.extend_from_slice(&(n as u64).to_be_bytes());
            }
        }
        let mask = [0x12u8, 0x34, 0x56, 0x78];
        frame.extend_from_slice(&mask);
        frame.extend(payload.iter().enumerate().map(|(k, b)| b ^ mask[k % 4]));
        self.stream.write_all(&frame).unwrap();
    }

    /// Receives one message (its frames joined).
    fn recv(&mut self) -> String {
        let mut message = Vec::new();
        loop {
            let mut head = [0u8; 2];
            self.stream.read_exact(&mut head).unwrap();
            let len = match head[1] & 0x7f {
                126 => {
                    let mut l = [0u8; 2];
                    self.stream.read_exact(&mut l).unwrap();
                    u16::from_be_bytes(l) as usize
                }
                127 => {
                    let mut l = [0u8; 8];
                    self.stream.read_exact(&mut l).unwrap();
                    u64::from_be_bytes(l) as usize
                }
                n => n as usize,
            };
            let mut payload = vec![0; len];
            self.stream.read_exact(&mut payload).unwrap();
            message.extend(payload);
            if head[0] & 0x80 != 0 {
                return String::from_utf8_lossy(&message).into_owned();
            }
        }
    }

    /// Runs `method` with the JSON object `params` and returns its answer.
    fn call(&mut self, method: &str, params: &str) -> String {
        let id = self.next_id;
        self.next_id += 1;
        self.send(&format!(r#"{{"id":{id},"method":"{method}","params":{params}}}"#));
        loop {
            let m = self.recv();
            if m.starts_with(&format!(r#"{{"id":{id},"#)) {
                return m;
            }
        }
    }

    /// Sends a mouse event of `kind` at `(x, y)` (CSS pixels) with the left button.
    fn mouse(&mut self, kind: &str, (x, y): (f64, f64)) {
        let buttons = if kind == "mouseReleased" { 0 } else { 1 };
        let params =
            format!(r#"{{"type":"{kind}","x":{x},"y":{y},"button":"left","buttons":{buttons},"clickCount":1}}"#);
        self.call("Input.dispatchMouseEvent", &params);
    }
}

/// Opens the page with `query` in headless Chromium and returns the picture it posts and the
/// query it posts it with (the solver that ran, the frame rate, the particles grabbed); `drive`
/// gets the page's DevTools protocol once it is open.
fn run_page(
    port: u16,
    posted: &Receiver<Posted>,
    query: &str,
    size: (u32, u32),
    drive: impl FnOnce(&Browser),
) -> (image::RgbaImage, String) {
    let url = format!("http://127.0.0.1:{port}/index.html?{query}");
    let browser = Browser::open(&url, size);
    drive(&browser);
    let got = posted.recv_timeout(PAGE_TIMEOUT);
    drop(browser);
    let (said, png) = got.unwrap_or_else(|_| panic!("{url}: the page posted no frame within {PAGE_TIMEOUT:?}"));
    (image::load_from_memory(&png).expect("the page posts a PNG").to_rgba8(), said)
}

/// The state the page starts in for `cloth-paper` (see `src/viewer/web.rs`).
fn state(backend: Backend) -> ViewerState {
    let choice = SceneChoice::new("cloth-paper", &SceneOptions::default()).unwrap();
    ViewerState::new(choice, Settings { iterations: default_iterations("cloth-paper"), ..Settings::default() }, backend)
}

/// The same viewer session natively: `FRAMES` frames of the CPU solver, drawn over the whole
/// target with one sample per pixel, as the page on a software adapter draws.
fn native() -> image::RgbaImage {
    let ctx = GpuContext::new().unwrap_or_else(|e| panic!("the web test needs a native GPU adapter too: {e}"));
    let target = OffscreenTarget::new(&ctx.device, W, H, 1).unwrap();
    let mut session = Session::new(&ctx, OFFSCREEN_FORMAT, 1, state(Backend::Cpu)).unwrap();
    for _ in 0..FRAMES {
        session.apply_changes(&ctx);
        let mut enc = ctx.device.create_command_encoder(&Default::default());
        session.encode_frame(&mut enc, target.views(), [0.0, 0.0, W as f32, H as f32]).unwrap();
        ctx.queue.submit([enc.finish()]);
        session.after_submit();
        session.poll();
    }
    target.read_rgba(&ctx.device, &ctx.queue).unwrap()
}

/// Fraction of the pixels that are the cloth's red, which neither the sky nor the floor is.
fn cloth_fraction(img: &image::RgbaImage) -> f64 {
    let red = img.pixels().filter(|p| p.0[0] as i32 - p.0[2] as i32 > 60).count();
    red as f64 / (img.width() * img.height()) as f64
}

#[test]
fn the_page_runs_cloth_paper_like_the_native_viewer_with_either_solver() {
    let (port, posted) = serve(build_page());
    let reference = native();
    // Where to write the pictures compared, to look at them.
    let keep = std::env::var_os("EAPBD_WEB_FRAME_DIR").map(PathBuf::from);
    if let Some(dir) = &keep {
        reference.save(dir.join("native.png")).unwrap();
    }
    let covered = cloth_fraction(&reference);
    assert!(covered > 0.02, "the native frame shows the cloth over {:.1}% of it", 100.0 * covered);
    for backend in ["cpu", "gpu"] {
        let query = format!("scene=cloth-paper&backend={backend}&frames={FRAMES}&width={W}&height={H}&post=/frame");
        let (page, said) = run_page(port, &posted, &query, (W, H), |_| {});
        assert!(
            said.starts_with(&format!("solver={backend}&")),
            "asked for the {backend} solver, the page says {said}"
        );
        if let Some(dir) = &keep {
            page.save(dir.join(format!("web_{backend}.png"))).unwrap();
        }
        assert_eq!(page.dimensions(), (W, H), "{backend}: the page's frame");
        let cloth = cloth_fraction(&page);
        let diff = mean_abs_diff(&page, &reference);
        println!(
            "{backend} solver in the page ({said}): the cloth covers {:.1}%, {diff:.3} from the native frame",
            100.0 * cloth
        );
        assert!(cloth > 0.5 * covered, "{backend}: the page shows the cloth over {:.1}% of its frame", 100.0 * cloth);
        assert!(diff <= MEAN_TOLERANCE, "{backend}: the page's frame is {diff:.3} from the native one");
    }
}

#[test]
fn dragging_the_cloth_in_the_page_pulls_it_with_either_solver() {
    // The page at 800 × 500 with its panels. Once the cloth hangs (frame 100), the mouse presses
    // on it in the middle of the scene, drags it 100 px to the right over half a second and lets
    // go. The page must say it grabbed a particle, and its last frame must differ from the same
    // run left alone.
    const SIZE: (u32, u32) = (800, 500);
    const FRAMES: u32 = 130;
    let (port, posted) = serve(build_page());
    for backend in ["cpu", "gpu"] {
        let query = format!(
            "scene=cloth-paper&backend={backend}&frames={FRAMES}&width={}&height={}&post=/frame",
            SIZE.0, SIZE.1
        );
        let (alone, said_alone) = run_page(port, &posted, &query, SIZE, |_| {});
        assert!(said_alone.contains("&grabs=0"), "{backend}: left alone, the page says {said_alone}");
        let (dragged, said) = run_page(port, &posted, &query, SIZE, |browser| {
            let mut page = browser.page();
            let frames =
                r#"{"expression":"Number(document.getElementById('eapbd').dataset.frames || 0)","returnByValue":true}"#;
            let start = std::time::Instant::now();
            loop {
                let answer = page.call("Runtime.evaluate", frames);
                let drawn: u32 = answer
                    .split(r#""value":"#)
                    .nth(1)
                    .and_then(|v| v.split(['}', ',']).next()?.parse().ok())
                    .unwrap_or(0);
                if drawn >= 100 {
                    break;
                }
                assert!(start.elapsed() < PAGE_TIMEOUT, "the page drew {drawn} frames in {PAGE_TIMEOUT:?}");
                std::thread::sleep(Duration::from_millis(50));
            }
            // Three drags: in one run of five the GPU backend's press grabbed nothing (it picks
            // against its latest read-back snapshot, at about 6 frames a second in this software
            // browser). A later press may miss a cloth the first drag moved away, so the page's
            // count of grabs must reach one, not three.
            let from = (SIZE.0 as f64 / 2.0, SIZE.1 as f64 / 2.0);
            for _ in 0..3 {
                page.mouse("mousePressed", from);
                for k in 1..=10 {
                    std::thread::sleep(Duration::from_millis(50));
                    page.mouse("mouseMoved", (from.0 + 10.0 * k as f64, from.1));
                }
                page.mouse("mouseReleased", (from.0 + 100.0, from.1));
                std::thread::sleep(Duration::from_millis(200));
            }
        });
        let grabs: u32 = said.split("grabs=").nth(1).and_then(|v| v.parse().ok()).unwrap_or(0);
        let diff = mean_abs_diff(&dragged, &alone);
        println!("{backend}: dragged ({said}), {diff:.3} from the run left alone");
        assert!(grabs >= 1, "{backend}: the mouse grabbed nothing ({said})");
        assert!(diff > 1.0, "{backend}: the dragged cloth looks like the one left alone ({diff:.3})");
    }
}
