//! The viewer's web page in a real browser: `web/build.sh` builds it, a server on localhost
//! serves it, headless Chromium runs `cloth-paper` for 60 frames on its WebGPU adapter
//! (SwiftShader where there is no GPU) with either solver, and the page posts its last frame's
//! scene back. Each must show the cloth and match the same viewer session drawn natively (the
//! CPU solver, lavapipe in CI) within `MEAN_TOLERANCE`.
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

/// Builds the page with `web/build.sh` (incremental: seconds when nothing changed).
fn build_page() -> PathBuf {
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

/// What the page posts: its URL's query and its body.
type Posted = (String, Vec<u8>);

/// Answers one request: a file of `dir` for a GET, and a POST's query and body sent to `posted`.
fn answer(stream: TcpStream, dir: &Path, posted: &Sender<Posted>) -> std::io::Result<()> {
    let mut reader = BufReader::new(stream.try_clone()?);
    let mut line = String::new();
    reader.read_line(&mut line)?;
    let mut parts = line.split_whitespace();
    let (method, target) = (parts.next().unwrap_or(""), parts.next().unwrap_or("/"));
    let mut length = 0;
    loop {
        let mut header = String::new();
        if reader.read_line(&mut header)? == 0 || header.trim().is_empty() {
            break;
        }
        if let Some((name, value)) = header.split_once(':')
            && name.eq_ignore_ascii_case("content-length")
        {
            length = value.trim().parse().unwrap_or(0);
        }
    }
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

/// Opens the page with `query` in headless Chromium and returns the picture it posts and the
/// query it posts it with (the solver that ran, the frame rate).
fn run_page(port: u16, posted: &Receiver<Posted>, query: &str) -> (image::RgbaImage, String) {
    let profile = std::env::temp_dir().join(format!("eapbd-chromium-{}-{port}", std::process::id()));
    let url = format!("http://127.0.0.1:{port}/index.html?{query}");
    let mut browser = Command::new(chromium())
        .args(["--headless", "--no-sandbox", "--disable-gpu-sandbox", "--no-first-run"])
        // WebGPU on Chromium's software Vulkan (SwiftShader), which draws a canvas headless.
        .args(["--enable-unsafe-webgpu", "--enable-features=Vulkan", "--use-vulkan=swiftshader"])
        .args(["--use-angle=swiftshader", "--enable-unsafe-swiftshader"])
        // Keeps the headless browser open until the test closes it.
        .arg("--remote-debugging-port=0")
        .arg(format!("--user-data-dir={}", profile.display()))
        .arg(format!("--window-size={W},{H}"))
        .arg(&url)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .expect("Chromium starts");
    let got = posted.recv_timeout(PAGE_TIMEOUT);
    let _ = browser.kill();
    let _ = browser.wait();
    let _ = std::fs::remove_dir_all(&profile);
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
        let (page, said) = run_page(port, &posted, &query);
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
