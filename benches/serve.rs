//! `vk-render serve` under load, in one run (`cargo bench --bench serve`, `make bench-serve`), on the
//! server as a class would start it (two workers, no validation layer):
//! 1. the explore page's frames at 600 x 400 to one client while a control moves (a state every 16 ms, as a
//!    dragged slider sends them): motion frames a second, and the time from a control's last change to its
//!    still frame (the median of several);
//! 2. a check through the API against `vk-render check` on the same file, each the whole of it (the request;
//!    the process), taking turns, medians and their ratio (mark: at most 1.3);
//! 3. 50 clients for a minute, 40 asking for frames and 10 for checks: requests answered, 503s, p50 and p99
//!    latency of the answered ones, the server's peak memory, and every accepted check's report fetched;
//! 4. the explore page drawing in the browser (headless Chromium, SwiftShader's WebGL2 on the CPU) at
//!    600 x 400: the time from opening the page to its first frame, the shaders' compilation included, and
//!    frames a second while a control moves, for Figure 1, Figure 3 and the bunny (mark: 20);
//! 5. 500 simulated explorers for a minute, each loading the page and its files once, then moving a control
//!    as a person does (a change every 50 ms for 2 s, then a second's rest), asking the server for what the
//!    page asks it (the lobe and the albedo once a material's control rests; nothing for the frames, which
//!    the browser draws): requests refused, p50 and p99, the server's peak memory and CPU time (mark: none
//!    refused).

#[allow(dead_code)] // the tests' client, of which the benchmark uses a part
#[path = "../tests/common/server.rs"]
mod server;

#[allow(dead_code)] // the browser tests' WebDriver client
#[path = "../tests/common/webdriver.rs"]
mod webdriver;

use std::net::TcpStream;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use serde_json::json;

use server::{Answer, Server};
use vk_render::scene::figures::practical_image;
use vk_render::{Renderer, RendererOptions};

fn median(mut samples: Vec<Duration>) -> Duration {
    samples.sort();
    samples[samples.len() / 2]
}

fn percentile(sorted: &[Duration], p: f64) -> Duration {
    sorted[((sorted.len() - 1) as f64 * p).round() as usize]
}

type Socket = tungstenite::WebSocket<TcpStream>;

/// The next frame's header within `wait`, its PNG read and dropped.
fn frame_within(socket: &mut Socket, wait: Duration) -> Option<serde_json::Value> {
    socket.get_mut().set_read_timeout(Some(wait)).ok()?;
    loop {
        match socket.read() {
            Ok(tungstenite::Message::Text(text)) => {
                let header: serde_json::Value = serde_json::from_str(&text).ok()?;
                if let Some(error) = header.get("error") {
                    panic!("the server refused a state: {error}");
                }
                socket.get_mut().set_read_timeout(Some(Duration::from_secs(30))).ok()?;
                let _png = socket.read().ok()?;
                return Some(header);
            }
            Ok(_) => continue,
            Err(_) => return None,
        }
    }
}

fn explore(server: &Server) {
    let (mut socket, _) = tungstenite::client::client(
        format!("ws://{}/api/explore", server.loopback()),
        TcpStream::connect(server.loopback()).expect("connect"),
    )
    .expect("the explore socket");
    let state =
        |power: f64| json!({"scene": "fig1-lambert", "width": 600, "height": 400, "set": {"light.0.power": power}});
    let send = |socket: &mut Socket, power: f64| {
        socket.send(tungstenite::Message::Text(state(power).to_string().into())).expect("send a state");
    };
    send(&mut socket, 60.0);
    frame_within(&mut socket, Duration::from_secs(60)).expect("the first frame");
    // A control dragged for 5 s: a state every 16 ms, frames read in between.
    let (mut motion, mut still) = (0u32, 0u32);
    let started = Instant::now();
    let mut next = started;
    let mut power = 60.0;
    while started.elapsed() < Duration::from_secs(5) {
        if Instant::now() >= next {
            power = if power > 110.0 { 20.0 } else { power + 0.5 };
            send(&mut socket, power);
            next += Duration::from_millis(16);
        }
        let wait = next.saturating_duration_since(Instant::now()).max(Duration::from_millis(1));
        if let Some(header) = frame_within(&mut socket, wait) {
            match header["kind"].as_str() {
                Some("motion") => motion += 1,
                _ => still += 1,
            }
        }
    }
    let moving = started.elapsed();
    // Drain what the drag left, then time single changes to their still frame.
    while let Some(header) = frame_within(&mut socket, Duration::from_millis(1500)) {
        if header["kind"] == "still" {
            break;
        }
    }
    let mut to_still = Vec::new();
    for k in 0..7 {
        let changed = Instant::now();
        send(&mut socket, 30.0 + f64::from(k) * 7.0);
        loop {
            let header = frame_within(&mut socket, Duration::from_secs(30)).expect("a frame");
            if header["kind"] == "still" {
                to_still.push(changed.elapsed());
                break;
            }
        }
    }
    println!(
        "explore, one client, 600 x 400: {:.1} motion frames a second while a control moves ({motion} in {:.1} s, {still} still \
         frames among them; mark: at least 20); from a control's change to its still frame: median {:.0} ms of {} \
         (a motion frame, 150 ms of rest, then the exact frame)",
        f64::from(motion) / moving.as_secs_f64(),
        moving.as_secs_f64(),
        median(to_still.clone()).as_secs_f64() * 1000.0,
        to_still.len(),
    );
}

/// A student's JPEG of Figure 2 (600 x 400, the practical's size).
fn student_jpeg(folder: &std::path::Path) -> std::path::PathBuf {
    let mut renderer = Renderer::new(RendererOptions::default()).expect("a renderer");
    let scene = practical_image("fig2-oren-nayar-sigma-0.6").expect("the figure").scene(&[]).expect("its scene");
    let image = renderer.render_rgb8(&scene).expect("a render");
    let path = folder.join("student.jpg");
    let mut jpeg = Vec::new();
    image::codecs::jpeg::JpegEncoder::new_with_quality(&mut jpeg, 90).encode_image(&image).expect("a JPEG");
    std::fs::write(&path, jpeg).expect("write the JPEG");
    path
}

fn check_against_the_command_line(server: &Server, student: &std::path::Path) {
    let bytes = std::fs::read(student).expect("the JPEG");
    let (mut api, mut cli) = (Vec::new(), Vec::new());
    for _ in 0..5 {
        let started = Instant::now();
        let answer = server.post_form(
            "/api/check",
            &[("image", Some("student.jpg"), &bytes), ("scene", None, b"fig2-oren-nayar-sigma-0.6")],
        );
        api.push(started.elapsed());
        assert_eq!(answer.status, 200, "{}", answer.text());
        let started = Instant::now();
        let output = std::process::Command::new(env!("CARGO_BIN_EXE_vk-render"))
            .args(["check", student.to_str().expect("a path"), "--scene", "fig2-oren-nayar-sigma-0.6"])
            .output()
            .expect("vk-render check");
        cli.push(started.elapsed());
        assert!(output.status.code() == Some(0), "{}", String::from_utf8_lossy(&output.stdout));
    }
    let (api, cli) = (median(api), median(cli));
    println!(
        "check of a 600 x 400 JPEG: the API {:.2} s (the whole request), vk-render check {:.2} s (the whole process), \
         ratio {:.2} (mark: at most 1.3), medians of 5 taking turns",
        api.as_secs_f64(),
        cli.as_secs_f64(),
        api.as_secs_f64() / cli.as_secs_f64()
    );
}

/// What the load's clients saw.
#[derive(Default)]
struct Seen {
    answered: Vec<Duration>,
    busy: u32,
    other: Vec<u16>,
    reports: Vec<String>,
}

fn load(server: &Server, student: &std::path::Path) {
    let mut small = Vec::new();
    let image = image::open(student).expect("the JPEG").to_rgb8();
    let image = image::imageops::resize(&image, 240, 160, image::imageops::FilterType::Triangle);
    image::codecs::jpeg::JpegEncoder::new_with_quality(&mut small, 90).encode_image(&image).expect("a JPEG");
    let small = Arc::new(small);
    let seen = Arc::new(Mutex::new(Seen::default()));
    let stop = Arc::new(AtomicBool::new(false));
    let address = server.loopback();
    let started = Instant::now();
    let clients: Vec<_> = (0..50)
        .map(|k| {
            let (seen, stop, small) = (seen.clone(), stop.clone(), small.clone());
            std::thread::spawn(move || {
                let mut n = 0u32;
                while !stop.load(Ordering::Relaxed) {
                    n += 1;
                    let began = Instant::now();
                    let answer: Answer = if k < 40 {
                        // A motion frame's request: the explore page's motion path, through the API.
                        let body = json!({"scene": "fig1-lambert", "width": 300, "height": 200, "samples": 1, "set": {"light.0.power": 20 + (n % 80)}});
                        server::request(address, "POST", "/api/render", &[("Content-Type", "application/json")], body.to_string().as_bytes())
                    } else {
                        let (kind, body) = server::multipart(&[("image", Some("s.jpg"), &small), ("scene", None, b"fig2-oren-nayar-sigma-0.6")]);
                        server::request(address, "POST", "/api/check", &[("Content-Type", &kind)], &body)
                    };
                    let took = began.elapsed();
                    let mut seen = seen.lock().unwrap_or_else(|p| p.into_inner());
                    match answer.status {
                        200 => {
                            seen.answered.push(took);
                            if k >= 40 {
                                seen.reports.push(answer.json()["report"].as_str().unwrap_or_default().to_string());
                            }
                        }
                        503 => seen.busy += 1,
                        status => seen.other.push(status),
                    }
                    drop(seen);
                    std::thread::sleep(Duration::from_millis(if k < 40 { 50 } else { 200 }));
                }
            })
        })
        .collect();
    std::thread::sleep(Duration::from_secs(60));
    stop.store(true, Ordering::Relaxed);
    for client in clients {
        client.join().expect("a client");
    }
    let elapsed = started.elapsed();
    let seen = seen.lock().unwrap_or_else(|p| p.into_inner());
    let mut answered = seen.answered.clone();
    answered.sort();
    let missing = seen.reports.iter().filter(|address| server.get(&format!("/api{}", address)).status != 200).count();
    println!(
        "50 clients for {:.0} s (40 asking for 300 x 200 frames, 10 for checks of 240 x 160 JPEGs): {} answered ({} checks), \
         {} answered 503 (busy), {} other ({:?}); latency of the answered: p50 {:.0} ms, p99 {:.0} ms; the server's peak \
         memory {} MB; checks accepted without their report: {missing}",
        elapsed.as_secs_f64(),
        answered.len(),
        seen.reports.len(),
        seen.busy,
        seen.other.len(),
        seen.other.iter().take(5).collect::<Vec<_>>(),
        percentile(&answered, 0.5).as_secs_f64() * 1000.0,
        percentile(&answered, 0.99).as_secs_f64() * 1000.0,
        server.peak_mb(),
    );
}

/// The explore page drawing in the browser: for each scene, the time from opening the page to its first
/// frame, and frames a second while a material's control moves, one frame an animation frame as the page
/// draws them, each finished before the next (a pixel read back: WebGL's finish() does not wait in Chromium).
fn browser_frames(server: &Server) {
    // The load before it may leave checks queued on the workers, which would share the 2 cores.
    let idle = Instant::now();
    while server.get("/api/status").json()["pending"] != json!(0) {
        assert!(idle.elapsed() < Duration::from_secs(120), "the server is still busy after 120 s");
        std::thread::sleep(Duration::from_millis(100));
    }
    let browser = webdriver::Browser::start(1500, 1000);
    for (id, key, low, high) in [
        ("fig1-lambert", "material.grey.kd", 0.2, 0.9),
        ("fig3-plastic-s-16", "material.plastic.shininess", 4.0, 64.0),
        ("fig5-golden-bunny", "material.gold.roughness", 0.1, 0.8),
    ] {
        browser.open(&format!("http://{}/explore?scene={id}", server.loopback()));
        browser.wait_for(
            "the first frame",
            "return page.mode === 'browser' && page.firstFrame !== undefined;",
            Duration::from_secs(120),
        );
        let first = browser.run("return page.firstFrame;", &[]).as_f64().expect("a time");
        // The page's lobe and albedo, asked of the server when it opens, drawn before the frames are timed: a
        // control that moves asks for none until it rests, and the server's work would share the 2 cores.
        browser.wait_for(
            "the lobe and the albedo",
            "return ['lobe', 'albedo'].every((id) => document.getElementById(id).complete && document.getElementById(id).naturalWidth > 0);",
            Duration::from_secs(120),
        );
        let rate = |motion: bool| {
            let moving = browser.run_async(
                "const [key, low, high, motion, done] = arguments;
             const gl = page.browser.gl;
             const pixel = new Uint8Array(4);
             let frames = 0;
             const start = performance.now();
             function step() {
               const now = performance.now();
               if (now - start >= 3000) { done({frames, seconds: (now - start) / 1000, size: pictureSize()}); return; }
               const v = low + (high - low) * (0.5 + 0.5 * Math.sin(frames / 10));
               page.set[key] = key.endsWith('.kd') ? [v, v, v] : v;
               drawInBrowser(motion);
               gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, pixel);
               frames += 1;
               requestAnimationFrame(step);
             }
             requestAnimationFrame(step);",
                &[json!(key), json!(low), json!(high), json!(motion)],
            );
            let frames = moving["frames"].as_f64().expect("frames") / moving["seconds"].as_f64().expect("seconds");
            (frames, moving["size"].clone())
        };
        let (motion, size) = rate(true);
        let (still, _) = rate(false);
        println!(
            "in the browser, {id} at {} x {}: first frame {first:.0} ms after opening the page (shaders compiled, meshes \
             loaded, shadows drawn); while {key} moves, {motion:.1} motion frames a second (half size, scaled up, as \
             the server's; mark: 20), {still:.1} frames a second at the picture's size",
            size[0], size[1]
        );
    }
}

/// The server's CPU time so far (user and system), from /proc.
fn cpu_seconds(server: &Server) -> f64 {
    let stat = std::fs::read_to_string(format!("/proc/{}/stat", server.child.id())).unwrap_or_default();
    // The fields after the command's closing parenthesis: utime and stime are the 12th and 13th.
    let fields: Vec<&str> = stat.rsplit(')').next().unwrap_or_default().split_whitespace().collect();
    let ticks: f64 = [11, 12].iter().filter_map(|&k| fields.get(k)?.parse::<f64>().ok()).sum();
    // SAFETY: sysconf reads a constant of the system.
    ticks / unsafe { libc::sysconf(libc::_SC_CLK_TCK) } as f64
}

/// What the explorers saw, by kind of request.
#[derive(Default)]
struct Explorers {
    /// (kind, latency) of every answered request.
    answered: Vec<(&'static str, Duration)>,
    /// (kind, status or 0 for a connection refused or broken) of every refused one.
    refused: Vec<(&'static str, u16)>,
}

/// 500 simulated explorers for a minute (see the module's documentation).
fn explorers(server: &Server) {
    const COUNT: usize = 500;
    let address = server.loopback();
    let seen = Arc::new(Mutex::new(Explorers::default()));
    let stop = Arc::new(AtomicBool::new(false));
    let cpu_before = cpu_seconds(server);
    let started = Instant::now();
    // A refused connection is counted, not a failure of the benchmark: the client's panic is caught.
    std::panic::set_hook(Box::new(|_| {}));
    let explorers: Vec<_> = (0..COUNT)
        .map(|k| {
            let (seen, stop) = (seen.clone(), stop.clone());
            std::thread::spawn(move || {
                let ask = |kind: &'static str, method: &str, path: &str, body: &[u8]| {
                    let began = Instant::now();
                    let answer = std::panic::catch_unwind(|| {
                        server::request(address, method, path, &[("Content-Type", "application/json")], body)
                    });
                    let mut seen = seen.lock().unwrap_or_else(|p| p.into_inner());
                    match answer {
                        Ok(answer) if answer.status == 200 => seen.answered.push((kind, began.elapsed())),
                        Ok(answer) => seen.refused.push((kind, answer.status)),
                        Err(_) => seen.refused.push((kind, 0)),
                    }
                };
                // Arrivals spread over the first 10 s, as a class opening a link.
                std::thread::sleep(Duration::from_millis((k * 10_000 / COUNT) as u64));
                let (scene, objects, material, parameter) = [
                    ("fig1-lambert", 2, "grey", "kd"),
                    ("fig3-plastic-s-16", 2, "plastic", "shininess"),
                    ("fig5-golden-bunny", 2, "gold", "roughness"),
                ][k % 3];
                for file in ["/explore", "/static/style.css", "/static/common.js", "/static/renderer/renderer.js", "/static/explore.js", "/static/shaders.json", "/api/scenes"] {
                    ask("page", "GET", &format!("{file}{}", if file == "/explore" { format!("?scene={scene}") } else { String::new() }), b"");
                }
                for object in 0..objects {
                    ask("mesh", "GET", &format!("/api/mesh?scene={scene}&object={object}"), b"");
                }
                // The bunny's lighter mesh, for its motion frames.
                if scene == "fig5-golden-bunny" {
                    ask("mesh", "GET", &format!("/api/mesh?scene={scene}&object=0&motion=true"), b"");
                }
                // The page's requests at a rest: the lobe, and the albedo at its chart's angles (explore.js).
                let angles: Vec<u32> = (0..90).step_by(5).chain([89]).collect();
                let studies = |value: f64| {
                    let mut body = json!({"scene": scene, "material": material, "set": {format!("material.{material}.{parameter}"): value}});
                    ask("lobe", "POST", "/api/lobe?format=svg", body.to_string().as_bytes());
                    body["theta_o"] = json!(angles);
                    ask("albedo", "POST", "/api/albedo?format=svg", body.to_string().as_bytes());
                };
                studies(if parameter == "shininess" { 16.0 } else { 0.5 });
                let mut cycle = k;
                while !stop.load(Ordering::Relaxed) {
                    // 2 s of a control moving (the browser draws; the server is asked nothing), then a rest.
                    std::thread::sleep(Duration::from_secs(2));
                    cycle += 1;
                    // One control in three is the material's: its rest asks for the lobe and the albedo.
                    if cycle % 3 == 0 {
                        let value = if parameter == "shininess" { 4.0 + (cycle % 60) as f64 } else { 0.1 + (cycle % 70) as f64 / 100.0 };
                        studies(value);
                    }
                    std::thread::sleep(Duration::from_secs(1));
                }
            })
        })
        .collect();
    std::thread::sleep(Duration::from_secs(60));
    stop.store(true, Ordering::Relaxed);
    for explorer in explorers {
        let _ = explorer.join();
    }
    let _ = std::panic::take_hook();
    let elapsed = started.elapsed();
    let cpu = cpu_seconds(server) - cpu_before;
    let seen = seen.lock().unwrap_or_else(|p| p.into_inner());
    let mut lines = Vec::new();
    for kind in ["page", "mesh", "lobe", "albedo"] {
        let mut times: Vec<Duration> = seen.answered.iter().filter(|(k, _)| *k == kind).map(|(_, t)| *t).collect();
        times.sort();
        let refused: Vec<u16> = seen.refused.iter().filter(|(k, _)| *k == kind).map(|(_, s)| *s).collect();
        if times.is_empty() {
            lines.push(format!("{kind}: none answered, {} refused", refused.len()));
            continue;
        }
        lines.push(format!(
            "{kind}: {} answered, p50 {:.1} ms, p99 {:.1} ms, {} refused{}",
            times.len(),
            percentile(&times, 0.5).as_secs_f64() * 1000.0,
            percentile(&times, 0.99).as_secs_f64() * 1000.0,
            refused.len(),
            if refused.is_empty() { String::new() } else { format!(" ({:?})", &refused[..refused.len().min(5)]) }
        ));
    }
    println!(
        "{COUNT} explorers for {:.0} s (frames drawn by their browsers; a control moved 2 s, a rest of 1 s; the lobe \
         and albedo asked at a material's rest): {}; refused in all: {} (mark: 0); the server's peak memory {} MB, its \
         CPU time {:.1} s ({:.0}% of one core)",
        elapsed.as_secs_f64(),
        lines.join("; "),
        seen.refused.len(),
        server.peak_mb(),
        cpu,
        100.0 * cpu / elapsed.as_secs_f64(),
    );
}

fn main() {
    let folder = tempfile::tempdir().expect("a temporary folder");
    let student = student_jpeg(folder.path());
    let server = Server::spawn(&[], "127.0.0.1:0", &["--workers", "2"], &[]);
    println!("vk-render serve --workers 2 (pid {}), started: {} MB", server.child.id(), server.peak_mb());
    explore(&server);
    check_against_the_command_line(&server, &student);
    load(&server, &student);
    browser_frames(&server);
    explorers(&server);
    let (code, _, took) = server.terminate(Duration::from_secs(60));
    println!("stopped by SIGTERM in {:.2} s, exit status {code:?}", took.as_secs_f64());
}
