//! `vk-render serve` under load, in one run (`cargo bench --bench serve`, `make bench-serve`), on the
//! server as a class would start it (two workers, no validation layer):
//! 1. the explore page's frames at 600 x 400 to one client while a control moves (a state every 16 ms, as a
//!    dragged slider sends them): motion frames a second, and the time from a control's last change to its
//!    still frame (the median of several);
//! 2. a check through the API against `vk-render check` on the same file, each the whole of it (the request;
//!    the process), taking turns, medians and their ratio (mark: at most 1.3);
//! 3. 50 clients for a minute, 40 asking for frames and 10 for checks: requests answered, 503s, p50 and p99
//!    latency of the answered ones, the server's peak memory, and every accepted check's report fetched.

#[allow(dead_code)] // the tests' client, of which the benchmark uses a part
#[path = "../tests/common/server.rs"]
mod server;

use std::net::TcpStream;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use serde_json::json;

use server::{Answer, Server};
use vk_render::figures::practical_image;
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

fn main() {
    let folder = tempfile::tempdir().expect("a temporary folder");
    let student = student_jpeg(folder.path());
    let server = Server::spawn(&[], "127.0.0.1:0", &["--workers", "2"], &[]);
    println!("vk-render serve --workers 2 (pid {}), started: {} MB", server.child.id(), server.peak_mb());
    explore(&server);
    check_against_the_command_line(&server, &student);
    load(&server, &student);
    let (code, _, took) = server.terminate(Duration::from_secs(60));
    println!("stopped by SIGTERM in {:.2} s, exit status {code:?}", took.as_secs_f64());
}
