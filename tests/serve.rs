//! `vk-render serve` against a real server on a loopback port: every route answers as the command line does
//! (the same PNG bytes, the same CSV, the same verdict), every hostile input gets its status and one line and
//! the next request is served, the token guards a server that listens beyond loopback, and the faults (a
//! client gone mid-upload, SIGTERM in a burst, a device error) leave every accepted request answered; and
//! `vk-render site` writes the server's pages and the API's answers as files.

mod common;

use std::io::Write;
use std::net::TcpStream;
use std::path::Path;
use std::time::{Duration, Instant};

use serde_json::json;

use common::server::{read_answer, Answer, Server};
use vk_render::check::catalogue::CATALOGUE;
use vk_render::check::render_candidates;
use vk_render::scene::figures::practical_image;

/// A small render request that any server answers with 200.
fn small_render() -> serde_json::Value {
    json!({"scene": "fig1-lambert", "width": 96, "height": 64})
}

/// Asserts a refusal: its status, one line naming `needle`, and that the next request is served.
fn refused(server: &Server, answer: &Answer, status: u16, needle: &str) {
    let text = answer.text();
    assert_eq!(answer.status, status, "{text}");
    assert!(text.trim_end().lines().count() == 1 && text.contains(needle), "expected one line with `{needle}`: {text}");
    let next = server.post_json("/api/render", &small_render());
    assert_eq!(next.status, 200, "the request after a refusal: {}", next.text());
}

/// `vk-render render SCENE ARGS -o OUT.png`'s bytes.
fn cli_render(folder: &Path, scene: &Path, args: &[&str]) -> Vec<u8> {
    let out = folder.join("cli.png");
    let mut all = vec!["render", scene.to_str().unwrap(), "-o", out.to_str().unwrap()];
    all.extend_from_slice(args);
    let output = common::vk_render(&all);
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    std::fs::read(out).unwrap()
}

fn figure_path(id: &str) -> std::path::PathBuf {
    common::root().join("assets/scenes").join(format!("{id}.toml"))
}

#[test]
fn every_route_answers_as_the_command_line_does() {
    let folder = common::temp_dir();
    let server = Server::local();
    // The catalogue: every figure by id, with its materials' parameters and ranges.
    let scenes = server.get("/api/scenes");
    assert_eq!(scenes.status, 200);
    let scenes = scenes.json();
    let ids: Vec<&str> = scenes.as_array().unwrap().iter().map(|s| s["id"].as_str().unwrap()).collect();
    assert!(ids.contains(&"fig1-lambert") && ids.contains(&"fig5-golden-bunny"), "{ids:?}");
    let fig3 = scenes.as_array().unwrap().iter().find(|s| s["id"] == "fig3-plastic-s-16").unwrap();
    let shininess = fig3["materials"]
        .as_object()
        .unwrap()
        .values()
        .flat_map(|m| m["parameters"].as_array().unwrap())
        .find(|p| p["name"] == "shininess")
        .unwrap();
    assert_eq!((shininess["kind"].as_str(), shininess["log"].as_bool()), (Some("number"), Some(true)), "{shininess}");

    // A render: the PNG `vk-render render` writes for the same overrides, byte for byte.
    let set = json!({"light.0.power": 30, "material.grey.kd": [0.2, 0.6, 0.3], "camera.position": [0.5, 0.2, -0.3]});
    let answer =
        server.post_json("/api/render", &json!({"scene": "fig1-lambert", "set": set, "width": 240, "height": 160}));
    assert_eq!((answer.status, answer.header("content-type")), (200, Some("image/png")), "{}", answer.text());
    let cli = cli_render(
        folder.path(),
        &figure_path("fig1-lambert"),
        &[
            "--width",
            "240",
            "--height",
            "160",
            "--set",
            "light.0.power=30",
            "--set",
            "material.grey.kd=[0.2, 0.6, 0.3]",
            "--set",
            "camera.position=[0.5, 0.2, -0.3]",
        ],
    );
    assert!(answer.body == cli, "the API's PNG differs from vk-render render's");

    // The scene file to download reproduces that render through the command line.
    let file =
        server.post_json("/api/scene-file", &json!({"scene": "fig1-lambert", "set": set, "width": 240, "height": 160}));
    assert_eq!(file.status, 200, "{}", file.text());
    assert!(file.header("content-disposition").unwrap().contains("fig1-lambert.toml"));
    let downloaded = folder.path().join("downloaded.toml");
    std::fs::write(&downloaded, &file.body).unwrap();
    assert!(cli_render(folder.path(), &downloaded, &[]) == cli, "the downloaded scene renders otherwise");

    // Lobe and albedo: the command line's CSV, to the byte; SVG and JSON beside it.
    let lobe =
        server.post_json("/api/lobe", &json!({"scene": "fig3-plastic-s-16", "material": "plastic", "theta_i": [45]}));
    assert_eq!(lobe.status, 200, "{}", lobe.text());
    let csv = folder.path().join("lobe.csv");
    let output = common::vk_render(&[
        "plot",
        "lobe",
        figure_path("fig3-plastic-s-16").to_str().unwrap(),
        "--material",
        "plastic",
        "--theta-i",
        "45",
        "-o",
        csv.to_str().unwrap(),
    ]);
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    assert_eq!(lobe.text(), std::fs::read_to_string(&csv).unwrap());
    let svg = server.post_json(
        "/api/lobe?format=svg",
        &json!({"material": {"brdf": "phong", "kd": 0.3, "ks": 0.5, "shininess": 20}}),
    );
    assert!(svg.status == 200 && svg.text().starts_with("<svg"), "{}", svg.text());
    let albedo = server.post_json(
        "/api/albedo?format=json",
        &json!({"material": {"brdf": "lambert", "kd": [0.5, 0.25, 1.0]}, "theta_o": [0, 45, 80]}),
    );
    assert_eq!(albedo.status, 200, "{}", albedo.text());
    let albedo = albedo.json();
    for rho in albedo["albedo"].as_array().unwrap() {
        // Lambert's directional albedo is kd at every angle.
        let rho: Vec<f64> = rho.as_array().unwrap().iter().map(|v| v.as_f64().unwrap()).collect();
        assert!((rho[0] - 0.5).abs() < 1e-3 && (rho[1] - 0.25).abs() < 1e-3 && (rho[2] - 1.0).abs() < 1e-3, "{rho:?}");
    }
    let albedo_csv = server.post_json("/api/albedo", &json!({"scene": "fig1-lambert", "material": "grey"}));
    let csv = folder.path().join("albedo.csv");
    let output = common::vk_render(&[
        "plot",
        "albedo",
        figure_path("fig1-lambert").to_str().unwrap(),
        "--material",
        "grey",
        "-o",
        csv.to_str().unwrap(),
    ]);
    assert!(output.status.success());
    assert_eq!(albedo_csv.text(), std::fs::read_to_string(&csv).unwrap());

    // Checks of the students' images: the verdict and the mistakes `vk-render check` gives, and a report.
    let students = student_images(folder.path());
    for (file, scene) in &students {
        let bytes = std::fs::read(folder.path().join(file)).unwrap();
        let answer =
            server.post_form("/api/check", &[("image", Some(file), &bytes), ("scene", None, scene.as_bytes())]);
        assert_eq!(answer.status, 200, "{file}: {}", answer.text());
        let checked = answer.json();
        let (matches, mistakes) = cli_check(&folder.path().join(file), scene);
        let named: Vec<String> =
            checked["mistakes"].as_array().unwrap().iter().map(|m| m["name"].as_str().unwrap().to_string()).collect();
        assert_eq!((checked["matches"].as_bool().unwrap(), named), (matches, mistakes), "{file} against {scene}");
        assert_eq!(checked["scene"], json!(scene));
        // The report, at its unguessable address, never cached.
        let address = checked["report"].as_str().unwrap();
        let id = checked["report_id"].as_str().unwrap();
        assert!(id.len() == 32 && id.chars().all(|c| c.is_ascii_hexdigit()) && address.ends_with(id), "{address}");
        let page = server.get(address);
        assert_eq!((page.status, page.header("cache-control")), (200, Some("no-store")));
        let kept = server.get(&format!("/api/reports/{id}"));
        assert_eq!((kept.status, kept.header("cache-control")), (200, Some("no-store")));
        assert_eq!(kept.json(), checked);
        for picture in checked["pictures"].as_array().unwrap() {
            let png = server.get(&format!("/api/reports/{id}/{}.png", picture.as_str().unwrap()));
            assert_eq!((png.status, png.header("content-type")), (200, Some("image/png")), "{picture}");
        }
        let exact =
            image::load_from_memory(&server.get(&format!("/api/reports/{id}/exact.png")).body).unwrap().to_rgb8();
        assert_eq!(exact.dimensions(), image::open(folder.path().join(file)).unwrap().to_rgb8().dimensions());
    }
    // Without a scene, the server names the closest figure, among figures as alike as Figure 2's four.
    let sized = ["image.width=160".parse().unwrap(), "image.height=120".parse().unwrap()];
    let fig2 = practical_image("fig2-oren-nayar-sigma-0.4").unwrap().scene(&sized).unwrap();
    let mut jpeg = Vec::new();
    let exact = common::renderer().render_rgb8(&fig2).unwrap();
    image::codecs::jpeg::JpegEncoder::new_with_quality(&mut jpeg, 90).encode_image(&exact).unwrap();
    let answer = server.post_form("/api/check", &[("image", Some("mine.jpg"), &jpeg)]);
    assert_eq!(answer.status, 200, "{}", answer.text());
    let answer = answer.json();
    assert_eq!(
        (answer["scene"].as_str(), answer["scene_chosen_by_server"].as_bool()),
        (Some("fig2-oren-nayar-sigma-0.4"), Some(true))
    );
    assert_eq!(answer["verdict"], json!("matches"));
    assert_eq!(server.get("/api/reports/0123456789abcdef0123456789abcdef").status, 404);

    // The pages and their headers: a policy without inline script, nosniff, no framing.
    for page in ["/", "/explore", "/check", "/static/explore.js", "/static/style.css"] {
        let answer = server.get(page);
        assert_eq!(answer.status, 200, "{page}");
        let policy = answer.header("content-security-policy").unwrap_or_default();
        assert!(
            policy.contains("script-src 'self' 'wasm-unsafe-eval'")
                && !policy.contains("unsafe-inline")
                && policy.contains("frame-ancestors 'none'"),
            "{page}: {policy}"
        );
        assert_eq!(answer.header("x-content-type-options"), Some("nosniff"), "{page}");
        assert!(!answer.text().contains("<script>"), "{page} has an inline script");
    }
    // The browser's files: every translated shader, and each object's mesh as the renderer draws it (Figure
    // 1's plane: the fan of four triangles from its point to four vertices at infinity), by id and index only.
    let shaders = server.get("/static/shaders.json").json();
    for entry in
        ["forward.vert", "forward.frag", "forward_sphere.frag", "shadow.vert", "shadow.frag", "web/resolve.frag"]
    {
        assert!(shaders[entry].as_str().is_some_and(|t| t.starts_with("#version 300 es\n")), "{entry}");
    }
    let plane = server.get("/api/mesh?scene=fig1-lambert&object=1");
    assert_eq!((plane.status, plane.header("content-type")), (200, Some("application/octet-stream")));
    let count = |k: usize| u32::from_le_bytes(plane.body[4 * k..4 * k + 4].try_into().unwrap());
    assert_eq!((count(0), count(1), plane.body.len()), (5, 12, 8 + 5 * 40 + 12 * 4));
    let described = server.get("/api/scenes").json();
    let fig1 = described.as_array().unwrap().iter().find(|s| s["id"] == "fig1-lambert").unwrap();
    assert!(
        fig1["browser"]["unsupported"].is_null() && fig1["browser"]["objects"][1]["sphere"] == json!(false),
        "{fig1}"
    );
    // The bunny's lighter mesh for motion frames (at most 16,384 triangles), and none for the plane.
    let bunny = described.as_array().unwrap().iter().find(|s| s["id"] == "fig5-golden-bunny").unwrap();
    assert_eq!(bunny["browser"]["objects"][0]["motion_mesh"], json!(true), "{bunny}");
    let light = server.get("/api/mesh?scene=fig5-golden-bunny&object=0&motion=true");
    let triangles = u32::from_le_bytes(light.body[4..8].try_into().unwrap()) / 3;
    assert!(light.status == 200 && (4096..=16_384).contains(&triangles), "{} triangles", triangles);
    for (query, status) in [
        ("scene=fig1-lambert&object=1&motion=true", 404),
        ("scene=../assets/scenes/fig1-lambert&object=0", 404),
        ("scene=fig1-lambert&object=2", 404),
        ("scene=fig1-lambert", 400),
        ("scene=fig1-lambert&object=-1", 400),
    ] {
        assert_eq!(server.get(&format!("/api/mesh?{query}")).status, status, "{query}");
    }
    let status = server.get("/api/status").json();
    assert_eq!(status["pending"], json!(0), "{status}");
    let (code, stderr, _) = server.terminate(Duration::from_secs(30));
    assert_eq!(code, Some(0), "{stderr}");
    assert!(!stderr.contains("Validation"), "validation messages: {stderr}");
}

/// Students' images as the check tests make them: three known mistakes and the exact image, as JPEGs at
/// 160 x 120, and an image twice too bright (no known mistake).
fn student_images(folder: &Path) -> Vec<(String, String)> {
    let mut made = Vec::new();
    let sized = ["image.width=160".parse().unwrap(), "image.height=120".parse().unwrap()];
    for (mistake, scene) in [
        ("gamma-applied", "fig1-lambert"),
        ("sigma-in-degrees", "fig2-oren-nayar-sigma-0.6"),
        ("phong-wrong-reflection", "fig3-plastic-s-16"),
        ("", "fig1-lambert"),
    ] {
        let figure = practical_image(scene).unwrap().scene(&sized).unwrap();
        let mistakes: Vec<_> = CATALOGUE.iter().filter(|m| m.name == mistake).collect();
        let candidates = render_candidates(&mut common::renderer(), &figure, &mistakes, |_, _| {}).unwrap();
        let image = &candidates.last().unwrap().image;
        let file = format!("{}.jpg", if mistake.is_empty() { "exact" } else { mistake });
        let mut jpeg = Vec::new();
        image::codecs::jpeg::JpegEncoder::new_with_quality(&mut jpeg, 90).encode_image(image).unwrap();
        std::fs::write(folder.join(&file), jpeg).unwrap();
        made.push((file, scene.to_string()));
        if mistake.is_empty() {
            let bright = image::RgbImage::from_fn(160, 120, |x, y| {
                image::Rgb(image.get_pixel(x, y).0.map(|c| c.saturating_mul(2)))
            });
            bright.save(folder.join("bright.png")).unwrap();
            made.push(("bright.png".into(), scene.to_string()));
        }
    }
    made
}

/// `vk-render check`'s word: whether it matches, and the mistakes its diagnosis names.
fn cli_check(image: &Path, scene: &str) -> (bool, Vec<String>) {
    let output = common::vk_render(&["check", image.to_str().unwrap(), "--scene", scene]);
    let stdout = String::from_utf8_lossy(&output.stdout).into_owned();
    assert!(matches!(output.status.code(), Some(0 | 1)), "{stdout}{}", String::from_utf8_lossy(&output.stderr));
    let named = stdout
        .lines()
        .filter_map(|l| l.strip_prefix("diagnosis: ").or_else(|| l.strip_prefix("  ")))
        .filter_map(|l| l.split_once(": ").map(|(name, _)| name.to_string()))
        .filter(|name| CATALOGUE.iter().any(|m| m.name == name))
        .collect();
    (output.status.code() == Some(0), named)
}

/// A PNG of 30 kB whose header claims 60000 x 60000 pixels (10.8 GB of RGB): refused from its header.
fn pixel_bomb() -> Vec<u8> {
    let mut png = b"\x89PNG\r\n\x1a\n".to_vec();
    let chunk = |png: &mut Vec<u8>, kind: &[u8], data: &[u8]| {
        png.extend_from_slice(&(data.len() as u32).to_be_bytes());
        let mut crc_input = kind.to_vec();
        crc_input.extend_from_slice(data);
        png.extend_from_slice(&crc_input);
        png.extend_from_slice(&crc32(&crc_input).to_be_bytes());
    };
    let mut header = Vec::new();
    header.extend_from_slice(&60000u32.to_be_bytes());
    header.extend_from_slice(&60000u32.to_be_bytes());
    header.extend_from_slice(&[8, 2, 0, 0, 0]);
    chunk(&mut png, b"IHDR", &header);
    chunk(&mut png, b"IDAT", &vec![0u8; 30_000]);
    chunk(&mut png, b"IEND", &[]);
    png
}

fn crc32(bytes: &[u8]) -> u32 {
    let mut crc = 0xFFFF_FFFFu32;
    for &byte in bytes {
        crc ^= u32::from(byte);
        for _ in 0..8 {
            crc = if crc & 1 != 0 { (crc >> 1) ^ 0xEDB8_8320 } else { crc >> 1 };
        }
    }
    !crc
}

/// A real JPEG of 16 x 16 pixels whose frame header is made to claim 60000 x 60000.
fn jpeg_claiming_huge_dimensions() -> Vec<u8> {
    let mut jpeg = Vec::new();
    image::codecs::jpeg::JpegEncoder::new(&mut jpeg).encode_image(&image::RgbImage::new(16, 16)).unwrap();
    let frame = jpeg.windows(2).position(|w| w == [0xFF, 0xC0]).expect("a baseline frame header");
    // FF C0, length (2), precision (1), then height and width (2 each).
    jpeg[frame + 5..frame + 7].copy_from_slice(&60000u16.to_be_bytes());
    jpeg[frame + 7..frame + 9].copy_from_slice(&60000u16.to_be_bytes());
    jpeg
}

#[test]
fn hostile_inputs_get_their_status_and_one_line_and_the_next_request_is_served() {
    // Timeouts of a few seconds (the defaults are 10 and 30 s): each is shown to be the option's, not the
    // default's, by when it fires.
    let server = Server::start("127.0.0.1:0", &["--workers", "1", "--header-timeout", "5", "--body-timeout", "8"], &[]);
    // A slow body: the request is answered 408 once its body has paused for the body timeout, on a thread
    // while the rest goes on.
    let address = server.loopback();
    let slow_body = std::thread::spawn(move || {
        let mut stream = TcpStream::connect(address).unwrap();
        let (kind, _) = common::server::multipart(&[]);
        let head = format!("POST /api/check HTTP/1.1\r\nHost: x\r\nConnection: close\r\nContent-Type: {kind}\r\nContent-Length: 100000\r\n\r\n");
        stream.write_all(head.as_bytes()).unwrap();
        stream.write_all(b"--vk-render-test-boundary-7f3a\r\n").unwrap();
        let started = Instant::now();
        stream.set_read_timeout(Some(Duration::from_secs(60))).unwrap();
        (read_answer(&mut stream), started.elapsed())
    });
    // Slow headers: the connection is dropped after the header timeout, every request below served meanwhile.
    let slow_headers = std::thread::spawn(move || {
        let mut slow = TcpStream::connect(address).unwrap();
        slow.write_all(b"GET /api/scenes HTTP/1.1\r\nHost: x\r\n").unwrap();
        let started = Instant::now();
        slow.set_read_timeout(Some(Duration::from_secs(30))).unwrap();
        let mut rest = Vec::new();
        let _ = std::io::Read::read_to_end(&mut slow, &mut rest);
        started.elapsed()
    });
    use image::ImageEncoder;
    let against = |image: &[u8], name: &str, scene: &[u8]| {
        server.post_form("/api/check", &[("image", Some(name), image), ("scene", None, scene)])
    };
    let check = |image: &[u8], name: &str| against(image, name, b"fig1-lambert");
    let mut png = Vec::new();
    image::codecs::png::PngEncoder::new(&mut png)
        .write_image(&[128u8; 64 * 48 * 3], 64, 48, image::ExtendedColorType::Rgb8)
        .unwrap();
    // Uploads: recognised by content, their size read from the header before any pixel is decoded.
    refused(&server, &check(b"", "empty.png"), 400, "image: the file is empty");
    refused(&server, &check(&png[..png.len() / 2], "truncated.png"), 400, "not a PNG or JPEG image vk-render can read");
    let before = server.peak_mb();
    let bomb = pixel_bomb();
    assert!(bomb.len() < 31_000);
    refused(&server, &check(&bomb, "bomb.png"), 413, "60000 x 60000 pixels");
    refused(&server, &check(&jpeg_claiming_huge_dimensions(), "huge.jpg"), 413, "60000 x 60000 pixels");
    assert!(server.peak_mb() < before + 64, "the bombs grew the server from {before} to {} MB", server.peak_mb());
    refused(&server, &check(b"GIF89a\x10\x00\x10\x00\x80\x00\x00", "cat.png"), 415, "not a PNG or JPEG file");
    refused(
        &server,
        &check(b"<svg xmlns=\"http://www.w3.org/2000/svg\"><script>alert(1)</script></svg>", "a.png"),
        415,
        "not a PNG or JPEG file",
    );
    refused(&server, &check(b"<!DOCTYPE html><html><body>hi</body></html>", "page.png"), 415, "not a PNG or JPEG file");
    // A body past the limit (16 MiB by default).
    let big = vec![0x89u8; 17 << 20];
    let (kind, body) = common::server::multipart(&[("image", Some("big.png"), &big)]);
    let answer = send_racing(&server, "/api/check", &kind, &body);
    refused(&server, &answer, 413, "larger than this server takes");
    // A form of thousands of parts.
    let parts: Vec<(&str, Option<&str>, &[u8])> = (0..5000).map(|_| ("scene", None, &b"fig1-lambert"[..])).collect();
    refused(&server, &server.post_form("/api/check", &parts), 400, "more than 4 parts");
    // Ids are ids: paths and unknown scenes are no scene at all.
    for id in ["../../etc/passwd", "..", "fig1-lambert/../fig1-lambert", "/etc/passwd", "fig9-unknown"] {
        refused(&server, &server.post_json("/api/render", &json!({"scene": id})), 404, "no such scene");
        refused(&server, &against(&png, "x.png", id.as_bytes()), 404, "no such scene");
    }
    // Overrides that would name a file, or switch to a model that reads one, are refused by key.
    for (key, value) in [
        ("material.grey.file", json!("/etc/passwd")),
        ("object.0.path", json!("../../x.obj")),
        ("material.grey.brdf", json!("measured")),
        ("environment.map", json!("/etc/shadow")),
    ] {
        let answer = server.post_json("/api/render", &json!({"scene": "fig1-lambert", "set": {key: value}}));
        refused(&server, &answer, 400, key);
    }
    refused(
        &server,
        &server.post_json("/api/render", &json!({"scene": "fig1-lambert", "width": 5000})),
        400,
        "at most 2048 pixels a side",
    );
    refused(
        &server,
        &server.post_json("/api/lobe", &json!({"material": {"brdf": "analytic", "file": "/etc/passwd"}})),
        400,
        "material.given.brdf",
    );
    // Invalid UTF-8, in a JSON body and in a form's field.
    refused(
        &server,
        &server.send("POST", "/api/render", &[("Content-Type", "application/json")], b"{\"scene\": \"\xff\xfe\"}"),
        400,
        "not JSON",
    );
    refused(
        &server,
        &server.post_form("/api/check", &[("image", Some("a.png"), &png), ("scene", None, b"\xff\xfe")]),
        400,
        "scene: not UTF-8",
    );
    refused(
        &server,
        &server.post_json("/api/render", &json!({"scene": "fig1-lambert", "bogus": 1})),
        400,
        "`bogus`: no such field",
    );
    // Slow headers and a slow body went on while the other inputs were sent.
    let served = server.post_json("/api/render", &small_render());
    assert_eq!(served.status, 200);
    let waited = slow_headers.join().unwrap();
    assert!(waited >= Duration::from_millis(4500) && waited < Duration::from_millis(9500), "dropped after {waited:?}");
    assert!(server.get("/api/status").status == 200);
    let (answer, waited) = slow_body.join().unwrap();
    assert_eq!(answer.status, 408, "{}", answer.text());
    assert!(answer.text().contains("paused for 8 s"), "{}", answer.text());
    assert!(waited >= Duration::from_millis(7500) && waited < Duration::from_secs(20), "answered after {waited:?}");
    // A WebSocket flood: closed as a policy violation.
    let (mut socket, _) = tungstenite::client::client(
        format!("ws://{}/api/explore", server.loopback()),
        TcpStream::connect(server.loopback()).unwrap(),
    )
    .unwrap();
    let mut closed = None;
    for _ in 0..2000 {
        if socket.send(tungstenite::Message::Text(small_render().to_string().into())).is_err() {
            break;
        }
    }
    socket.get_mut().set_read_timeout(Some(Duration::from_secs(30))).unwrap();
    while let Ok(message) = socket.read() {
        if let tungstenite::Message::Close(frame) = message {
            closed = frame.map(|f| u16::from(f.code));
            break;
        }
    }
    assert_eq!(closed, Some(1008), "the flood was not closed as a policy violation");
    // A page of another site may not open the socket.
    let mut request =
        tungstenite::client::IntoClientRequest::into_client_request(format!("ws://{}/api/explore", server.loopback()))
            .unwrap();
    request.headers_mut().insert("Origin", "http://evil.example".parse().unwrap());
    let refused_origin = tungstenite::client::client(request, TcpStream::connect(server.loopback()).unwrap());
    assert!(
        matches!(refused_origin, Err(tungstenite::HandshakeError::Failure(tungstenite::Error::Http(ref r))) if r.status() == 403)
    );
    let next = server.post_json("/api/render", &small_render());
    assert_eq!(next.status, 200);
    let (code, stderr, _) = server.terminate(Duration::from_secs(30));
    assert_eq!(code, Some(0), "{stderr}");
}

/// A form posted while its answer is read: a server may answer 413 before the body is all sent.
fn send_racing(server: &Server, path: &str, kind: &str, body: &[u8]) -> Answer {
    let mut stream = TcpStream::connect(server.loopback()).unwrap();
    let head = format!(
        "POST {path} HTTP/1.1\r\nHost: x\r\nConnection: close\r\nContent-Type: {kind}\r\nContent-Length: {}\r\n\r\n",
        body.len()
    );
    let mut writer = stream.try_clone().unwrap();
    let body = body.to_vec();
    let sending = std::thread::spawn(move || {
        let _ = writer.write_all(head.as_bytes());
        let _ = writer.write_all(&body);
    });
    stream.set_read_timeout(Some(Duration::from_secs(60))).unwrap();
    let answer = read_answer(&mut stream);
    let _ = sending.join();
    answer
}

/// Reads the next frame of the explore socket: its header and its PNG (error messages fail the test).
fn next_frame(socket: &mut tungstenite::WebSocket<TcpStream>) -> (serde_json::Value, Vec<u8>) {
    let header = loop {
        match socket.read().expect("a frame") {
            tungstenite::Message::Text(text) => {
                let header: serde_json::Value = serde_json::from_str(&text).unwrap();
                assert!(header.get("error").is_none(), "{header}");
                break header;
            }
            tungstenite::Message::Ping(_) | tungstenite::Message::Pong(_) => continue,
            other => panic!("expected a frame's header, got {other:?}"),
        }
    };
    match socket.read().expect("the frame's PNG") {
        tungstenite::Message::Binary(png) => (header, png.to_vec()),
        other => panic!("expected the frame's PNG, got {other:?}"),
    }
}

#[test]
fn the_explore_socket_sends_motion_frames_then_the_exact_still_frame() {
    let folder = common::temp_dir();
    let server = Server::local();
    let (mut socket, _) = tungstenite::client::client(
        format!("ws://{}/api/explore", server.loopback()),
        TcpStream::connect(server.loopback()).unwrap(),
    )
    .unwrap();
    socket.get_mut().set_read_timeout(Some(Duration::from_secs(60))).unwrap();
    let state = |power: f64| json!({"scene": "fig3-plastic-s-16", "width": 300, "height": 200, "set": {"light.0.power": power}});
    let send = |socket: &mut tungstenite::WebSocket<TcpStream>, power: f64| {
        socket.send(tungstenite::Message::Text(state(power).to_string().into())).unwrap();
    };
    // The first frame of a scene is its still frame: the render itself.
    send(&mut socket, 40.0);
    let (header, png) = next_frame(&mut socket);
    assert_eq!((header["kind"].as_str(), header["width"].as_u64()), (Some("still"), Some(300)), "{header}");
    let cli = cli_render(
        folder.path(),
        &figure_path("fig3-plastic-s-16"),
        &["--width", "300", "--height", "200", "--set", "light.0.power=40"],
    );
    assert!(png == cli, "the first still frame differs from vk-render render");
    // A control moving: motion frames (half size) while it moves, then one still frame of its last value.
    let moved = Instant::now();
    for k in 0..30 {
        send(&mut socket, 41.0 + f64::from(k));
        std::thread::sleep(Duration::from_millis(15));
    }
    let mut motion = 0;
    let still = loop {
        let (header, png) = next_frame(&mut socket);
        match header["kind"].as_str() {
            Some("motion") => {
                assert_eq!((header["width"].as_u64(), header["height"].as_u64()), (Some(150), Some(100)), "{header}");
                motion += 1;
            }
            Some("still") => break (header, png),
            other => panic!("{other:?}"),
        }
    };
    assert!((1..30).contains(&motion), "{motion} motion frames for 30 changes: latest wins, no queue");
    assert_eq!(still.0["state"], json!(31), "the still frame is of the last state sent: {}", still.0);
    let cli = cli_render(
        folder.path(),
        &figure_path("fig3-plastic-s-16"),
        &["--width", "300", "--height", "200", "--set", "light.0.power=70"],
    );
    assert!(still.1 == cli, "the still frame after the motion differs from vk-render render");
    eprintln!("{motion} motion frames, the still frame {:?} after the first change", moved.elapsed());
    // A state the server refuses is answered on the socket, which stays open.
    socket.send(tungstenite::Message::Text(json!({"scene": "../x"}).to_string().into())).unwrap();
    let error = loop {
        if let tungstenite::Message::Text(text) = socket.read().unwrap() {
            break serde_json::from_str::<serde_json::Value>(&text).unwrap();
        }
    };
    assert!(error["error"].as_str().unwrap().contains("no such scene"), "{error}");
    send(&mut socket, 40.0);
    let (header, png) = next_frame(&mut socket);
    assert_eq!(header["kind"], json!("still"));
    assert!(
        png == cli_render(
            folder.path(),
            &figure_path("fig3-plastic-s-16"),
            &["--width", "300", "--height", "200", "--set", "light.0.power=40"]
        )
    );
    let (code, stderr, _) = server.terminate(Duration::from_secs(30));
    assert_eq!(code, Some(0), "{stderr}");
}

#[test]
fn a_server_beyond_loopback_needs_its_token() {
    // Without a token it does not start.
    let output = common::vk_render(&["serve", "--listen", "0.0.0.0:0"]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        !output.status.success() && stderr.lines().count() == 1 && stderr.contains("give the server a token"),
        "{stderr}"
    );
    let folder = common::temp_dir();
    let short = folder.path().join("short");
    std::fs::write(&short, "secret\n").unwrap();
    let output = common::vk_render(&["serve", "--listen", "0.0.0.0:0", "--token-file", short.to_str().unwrap()]);
    assert!(String::from_utf8_lossy(&output.stderr).contains("at least 22 printable characters"));
    let token = "3f1d0c9a7be2458e9d6b1a2c4e8f7a90";
    let server = Server::start("0.0.0.0:0", &["--workers", "1"], &[("VK_RENDER_TOKEN", token)]);
    let link = server.next_printed_line(Duration::from_secs(30));
    assert!(link.starts_with("sign in: "), "the sign-in link is printed after the address: {link}");
    assert!(link.ends_with(&format!("/signin?token={token}")), "{link}");
    // Missing or wrong: 401, for the API and the pages alike (a page gets the sign-in page).
    for headers in [
        vec![],
        vec![("Authorization", "Bearer wrong-token-wrong-token-00")],
        vec![("Authorization", &*format!("Bearer {token}x"))],
        vec![("Cookie", "vk_render_session=00")],
    ] {
        let answer = server.send("GET", "/api/scenes", &headers, b"");
        assert_eq!(answer.status, 401, "{headers:?}: {}", answer.text());
        assert_eq!(answer.text().lines().count(), 1);
        let render = server.send("POST", "/api/render", &headers, small_render().to_string().as_bytes());
        assert_eq!(render.status, 401);
        let page = server.send("GET", "/explore", &headers, b"");
        assert!(page.status == 401 && page.text().contains("Sign in"), "{}", page.status);
    }
    assert_eq!(server.get("/signin?token=not-the-token").status, 401);
    assert_eq!(server.get("/static/style.css").status, 200);
    // A script's Bearer token; a browser's link exchanged for a cookie.
    let bearer = format!("Bearer {token}");
    let answer = server.send(
        "POST",
        "/api/render",
        &[("Authorization", &bearer), ("Content-Type", "application/json")],
        small_render().to_string().as_bytes(),
    );
    assert_eq!(answer.status, 200, "{}", answer.text());
    let signed = server.get(&format!("/signin?token={token}"));
    assert_eq!((signed.status, signed.header("location")), (303, Some("/")));
    let cookie = signed.header("set-cookie").unwrap().to_string();
    assert!(cookie.contains("HttpOnly") && cookie.contains("SameSite=Strict") && !cookie.contains(token), "{cookie}");
    let session = cookie.split(';').next().unwrap();
    let answer = server.send("GET", "/api/scenes", &[("Cookie", session)], b"");
    assert_eq!(answer.status, 200);
    let form = server.send(
        "POST",
        "/signin",
        &[("Content-Type", "application/x-www-form-urlencoded")],
        format!("token={token}").as_bytes(),
    );
    assert_eq!(form.status, 303);
    let (code, stderr, _) = server.terminate(Duration::from_secs(30));
    assert_eq!(code, Some(0), "{stderr}");
}

#[test]
fn faults_leave_every_accepted_request_answered() {
    // A device error in one request: that request 500 with its line, and the server goes on.
    let server = Server::start("127.0.0.1:0", &["--workers", "1"], &[("VK_RENDER_SERVE_FAULT", "2")]);
    assert_eq!(server.post_json("/api/render", &small_render()).status, 200);
    let failed = server.post_json("/api/render", &small_render());
    assert_eq!(failed.status, 500, "{}", failed.text());
    assert!(failed.text().contains("device has been lost") && failed.text().lines().count() == 1, "{}", failed.text());
    assert_eq!(server.post_json("/api/render", &small_render()).status, 200);
    // A client killed mid-upload frees its place.
    for _ in 0..8 {
        let mut stream = TcpStream::connect(server.loopback()).unwrap();
        let (kind, _) = common::server::multipart(&[]);
        let head =
            format!("POST /api/check HTTP/1.1\r\nHost: x\r\nContent-Type: {kind}\r\nContent-Length: 8000000\r\n\r\n");
        stream.write_all(head.as_bytes()).unwrap();
        stream.write_all(&vec![b'x'; 1 << 20]).unwrap();
        drop(stream);
    }
    server.wait_for("no request pending once the killed uploads are dropped", Duration::from_secs(30), |server| {
        server.get("/api/status").json()["pending"] == json!(0)
    });
    assert_eq!(server.post_json("/api/render", &small_render()).status, 200);
    drop(server);

    // SIGTERM in a burst: no new connection after it, every request accepted before it answered, exit 0.
    // Each job held 150 ms on the worker, so that most are still queued at SIGTERM on any device (an H200
    // rendered twelve 1024 x 768 images, as this test asked before, in under 300 ms).
    let server =
        Server::start("127.0.0.1:0", &["--workers", "1", "--queue", "64"], &[("VK_RENDER_SERVE_HOLD_MS", "150")]);
    let address = server.loopback();
    let burst: Vec<_> = (0..12)
        .map(|k| {
            std::thread::spawn(move || {
                let body = json!({"scene": "fig3-plastic-s-16", "width": 160, "height": 120, "set": {"light.0.power": 30 + k}}).to_string();
                let mut stream = TcpStream::connect(address).unwrap();
                let request = format!("POST /api/render HTTP/1.1\r\nHost: x\r\nConnection: close\r\nContent-Type: application/json\r\nContent-Length: {}\r\n\r\n{body}", body.len());
                stream.write_all(request.as_bytes()).unwrap();
                stream.set_read_timeout(Some(Duration::from_secs(60))).unwrap();
                read_answer(&mut stream)
            })
        })
        .collect();
    // SIGTERM once at least 4 requests are in flight (polled: on 2 cores with other tests beside it, the
    // burst's threads may take a while to connect; a fixed wait once found only 2 there).
    server.wait_for("4 requests in flight", Duration::from_secs(30), |server| {
        server.get("/api/status").json()["pending"].as_u64().unwrap() >= 4
    });
    server.signal_stop();
    // The listener closes at once, while the requests in flight are still answered (each holds 150 ms).
    let closed = Instant::now();
    while TcpStream::connect(address).is_ok() {
        assert!(closed.elapsed() < Duration::from_secs(10), "connections still accepted 10 s after SIGTERM");
        std::thread::sleep(Duration::from_millis(10));
    }
    for (k, request) in burst.into_iter().enumerate() {
        let answer = request.join().unwrap();
        assert_eq!(
            (answer.status, answer.header("content-type")),
            (200, Some("image/png")),
            "request {k}: {}",
            answer.text()
        );
    }
    let (code, stderr, took) = server.exit_status(Duration::from_secs(60));
    assert_eq!(code, Some(0), "{stderr}");
    assert!(took < Duration::from_secs(30), "stopping took {took:?}");
}

#[test]
fn the_guides_api_examples_run_as_written() {
    // The curl example of docs/serve.md, "The HTTP API" (tests/docs.rs leaves it to this test).
    let page = std::fs::read_to_string(common::root().join("docs/serve.md")).unwrap();
    let start = page.find("\n## The HTTP API").expect("the guide's API section");
    let block = &page[start..];
    let block = &block[block.find("```sh\n").expect("its example") + 6..];
    let script = &block[..block.find("```").unwrap()];
    assert!(script.starts_with("VK=http://127.0.0.1:8080\n"), "{script}");
    let server = Server::local();
    let folder = common::temp_dir();
    let script = script.replace("http://127.0.0.1:8080", &format!("http://{}", server.loopback()));
    let output = std::process::Command::new("sh")
        .args(["-eu", "-c", &script])
        .current_dir(folder.path())
        .output()
        .expect("sh runs the guide's example (curl comes with make setup-test)");
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(output.status.success(), "{stdout}{}", String::from_utf8_lossy(&output.stderr));
    assert!(
        stdout.contains("\"id\":\"fig1-lambert\"")
            && stdout.contains("\"matches\":true")
            && stdout.contains("theta_o,plastic_r"),
        "{stdout}"
    );
    assert!(stdout.contains("\"error_bound\""), "{stdout}");
    let rendered = image::open(folder.path().join("fig1.png")).unwrap();
    assert_eq!((rendered.width(), rendered.height()), (300, 200));
    let scene = std::fs::read_to_string(folder.path().join("fig1-brighter.toml")).unwrap();
    assert!(scene.contains("power = 30"), "{scene}");
    let (code, stderr, _) = server.terminate(Duration::from_secs(30));
    assert_eq!(code, Some(0), "{stderr}");
}

#[test]
fn the_site_is_the_servers_pages_and_its_data_as_files() {
    let folder = common::temp_dir();
    let site = folder.path().join("site");
    let written = common::vk_render(&["site", "-o", site.to_str().unwrap()]);
    assert!(written.status.success(), "{}", String::from_utf8_lossy(&written.stderr));
    // The server's own pages and scripts, byte for byte, site.js aside.
    let server = Server::local();
    for (file, path) in [
        ("explore.html", "/explore"),
        ("check.html", "/check"),
        ("static/renderer/blocks.js", "/static/renderer/blocks.js"),
        ("static/explore/frames.js", "/static/explore/frames.js"),
        ("static/explore/editor.js", "/static/explore/editor.js"),
        ("static/brdf-templates.json", "/static/brdf-templates.json"),
        ("static/vk-render.wasm", "/static/vk-render.wasm"),
    ] {
        let served = server.get(path);
        assert_eq!(std::fs::read(site.join(file)).unwrap(), served.body, "{file}");
    }
    // The editor's WebAssembly is one (its magic number), the templates one per analytic entry.
    assert!(std::fs::read(site.join("static/vk-render.wasm")).unwrap().starts_with(b"\0asm"));
    let templates: serde_json::Value =
        serde_json::from_slice(&std::fs::read(site.join("static/brdf-templates.json")).unwrap()).unwrap();
    let entries: Vec<&String> = templates.as_object().unwrap().keys().collect();
    assert_eq!(
        entries,
        [
            "forward.frag",
            "forward.frag+TERM_VIEWS",
            "forward_sphere.frag",
            "forward_sphere.frag+TERM_VIEWS",
            "web/albedo.frag",
            "web/probe.frag"
        ]
    );
    // The scene list as the API answers it, each scene numbering its materials for their files.
    let scenes: serde_json::Value =
        serde_json::from_slice(&std::fs::read(site.join("data/scenes.json")).unwrap()).unwrap();
    let api: serde_json::Value = serde_json::from_slice(&server.get("/api/scenes").body).unwrap();
    assert_eq!(scenes.as_array().unwrap().len(), api.as_array().unwrap().len());
    assert_eq!(scenes[0]["site"]["materials"], json!({"grey": 0, "red": 1}), "{}", scenes[0]["id"]);
    // Each mesh as /api/mesh hands it out.
    let mesh = server.get("/api/mesh?scene=fig5-golden-bunny&object=0");
    assert_eq!(std::fs::read(site.join("data/fig5-golden-bunny/mesh-0.bin")).unwrap(), mesh.body);
    let (code, stderr, _) = server.terminate(std::time::Duration::from_secs(30));
    assert_eq!(code, Some(0), "{stderr}");
    // Written again over itself; an existing path it did not write is refused, one line, and left as it was.
    assert!(common::vk_render(&["site", "-o", site.to_str().unwrap()]).status.success());
    let other = folder.path().join("notes");
    std::fs::create_dir(&other).unwrap();
    std::fs::write(other.join("mine.txt"), "mine").unwrap();
    let refused = common::vk_render(&["site", "-o", other.to_str().unwrap()]);
    let stderr = String::from_utf8_lossy(&refused.stderr);
    assert!(!refused.status.success() && stderr.contains("it exists and is not an empty folder"), "{stderr}");
    assert_eq!(std::fs::read_dir(&other).unwrap().count(), 1);
    let missing = common::vk_render(&["site", "-o", site.to_str().unwrap(), "--scenes", "no-such-folder"]);
    let stderr = String::from_utf8_lossy(&missing.stderr);
    assert!(!missing.status.success() && stderr.contains("--scenes no-such-folder"), "{stderr}");
}
