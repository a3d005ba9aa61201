//! The windowed preview under Xvfb (package xvfb, installed by `make test`): what it presents equals the
//! offscreen render, simulated keys change the image as they should, resizing and hot reloading work, and
//! the validation layer stays quiet (every run uses --validate and must exit 0).
#![cfg(feature = "preview")]

mod common;

use std::path::Path;
use std::process::{Command, Output};
use std::time::Duration;

use common::*;
use vk_render::Scene;

/// `vk-render --validate preview ARGS` in a virtual X server, with a private runtime folder (kept alive by
/// the returned guard), as the loader wants under Xvfb.
fn preview_command(args: &[&str]) -> (Command, tempfile::TempDir) {
    let runtime = temp_dir();
    let mut command = Command::new("xvfb-run");
    command
        .args(["-a", "-s", "-screen 0 1280x1024x24", env!("CARGO_BIN_EXE_vk-render"), "--validate", "preview"])
        .args(args)
        .env("XDG_RUNTIME_DIR", runtime.path());
    (command, runtime)
}

/// Runs the preview to its end.
fn preview(args: &[&str]) -> Output {
    let (mut command, _runtime) = preview_command(args);
    command.output().expect("xvfb-run (package xvfb: run `make setup-test`)")
}

/// Exit status 0, and no validation message at any time, teardown included (they are logged).
fn succeeded(output: &Output) {
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "preview failed: {}\n{stderr}", String::from_utf8_lossy(&output.stdout));
    assert!(!stderr.contains("validation:") && !stderr.contains("VUID"), "{stderr}");
}

fn offscreen(scene: &str, overrides: &[&str]) -> image::RgbImage {
    let scene = asset_scene(scene, overrides);
    render(&scene).to_rgb8(&scene.image)
}

fn assert_same(shot: &image::RgbImage, expected: &image::RgbImage, what: &str) {
    assert_eq!(shot.dimensions(), expected.dimensions(), "{what}");
    let everything = vec![false; (shot.width() * shot.height()) as usize];
    let c = vk_render::pictures::compare::compare(shot, expected, &everything);
    assert!(c.max <= 1 && c.fraction_over_3 == 0.0, "{what}: {c}");
}

/// Figure 1 previewed at `size` for `frames` frames with the `keys` script: the last frame presented.
fn screenshot(size: (u32, u32), frames: u32, keys: &str) -> image::RgbImage {
    let folder = temp_dir();
    let shot = folder.path().join("shot.png");
    let scene = root().join("assets/scenes/fig1-lambert.toml");
    let (width, height, frames) = (size.0.to_string(), size.1.to_string(), frames.to_string());
    let output = preview(&[
        scene.to_str().unwrap(),
        "--frames",
        &frames,
        "--screenshot",
        shot.to_str().unwrap(),
        "--width",
        &width,
        "--height",
        &height,
        "--keys",
        keys,
    ]);
    succeeded(&output);
    image::open(&shot).unwrap().into_rgb8()
}

#[test]
fn the_presented_frame_is_the_offscreen_render() {
    let shot = screenshot((320, 240), 3, "");
    assert_same(&shot, &offscreen("fig1-lambert.toml", &["image.width=320", "image.height=240"]), "figure 1");
}

#[test]
fn simulated_keys_switch_the_brdf_and_the_image_follows() {
    // 2: Oren-Nayar with sigma 0.3 on the selected (first) object; Up: sigma 0.4.
    let shot = screenshot((320, 240), 4, "2,Up");
    let size = ["image.width=320", "image.height=240"];
    let expected =
        offscreen("fig1-lambert.toml", &[size[0], size[1], "material.grey.brdf=oren-nayar", "material.grey.sigma=0.4"]);
    assert_same(&shot, &expected, "after keys 2, Up");
    assert_ne!(shot, offscreen("fig1-lambert.toml", &size), "the keys changed nothing");
}

#[test]
fn resizing_mid_run_renders_at_the_new_size() {
    let shot = screenshot((320, 240), 6, "resize:200x150");
    assert_same(&shot, &offscreen("fig1-lambert.toml", &["image.width=200", "image.height=150"]), "after resizing");
}

#[test]
fn edited_files_are_reloaded_and_broken_ones_keep_the_last_good_image() {
    let folder = temp_dir();
    let scene_path = folder.path().join("scene.toml");
    let shaders = folder.path().join("shaders");
    copy_tree(&root().join("shaders"), &shaders);
    let original = std::fs::read_to_string(root().join("assets/scenes/fig1-lambert.toml")).unwrap();
    std::fs::write(&scene_path, &original).unwrap();
    let shot = folder.path().join("shot.png");
    // Each step waits for the preview's own line saying it saw the last (-v), never for a fixed time; the run's
    // 20 s bound only its whole, which ends on a frame drawn after both reloads.
    let (mut command, _runtime) = preview_command(&[
        scene_path.to_str().unwrap(),
        "--shaders",
        shaders.to_str().unwrap(),
        "--seconds",
        "20",
        "--screenshot",
        shot.to_str().unwrap(),
        "--width",
        "160",
        "--height",
        "120",
    ]);
    command.arg("-v");
    let mut child = command.stderr(std::process::Stdio::piped()).stdout(std::process::Stdio::null()).spawn().unwrap();
    let (log, reader) = common::server::kept_on_a_thread(child.stderr.take().unwrap());
    let wait_for = |lines: &[&str], after: usize| -> usize {
        let started = std::time::Instant::now();
        loop {
            let text = log.lock().unwrap().clone();
            if lines.iter().all(|line| text[after..].contains(line)) {
                return text.len();
            }
            assert!(started.elapsed() < Duration::from_secs(60), "no {lines:?} within 60 s: {text}");
            std::thread::sleep(Duration::from_millis(20));
        }
    };
    let shown = wait_for(&["edits to it and the shaders of"], 0);
    // A broken shader and a broken scene: each logged, the last good ones kept.
    let lambert = shaders.join("brdf/lambert.glsl");
    let good_shader = std::fs::read_to_string(&lambert).unwrap();
    std::fs::write(&lambert, good_shader.replace("return kd * INV_PI;", "return kd * ;")).unwrap();
    std::fs::write(&scene_path, original.replace("radius = 1.0", "radius = -1.0")).unwrap();
    let kept = wait_for(&["keeping the last good shaders", "keeping the last good scene"], shown);
    // Mended, each differently from the start: a Lambert shader at half its reflectance, and a brighter
    // sphere. The last frame must show both, so both reloads are seen in its pixels, not only in the log.
    let halved = good_shader.replace("return kd * INV_PI;", "return 0.5 * kd * INV_PI;");
    assert_ne!(halved, good_shader);
    std::fs::write(&lambert, halved).unwrap();
    std::fs::write(&scene_path, original.replace("kd = [0.5, 0.5, 0.5]", "kd = [0.9, 0.9, 0.9]")).unwrap();
    wait_for(&["reloaded the shaders of", &format!("reloaded {}", scene_path.display())], kept);
    let status = child.wait().unwrap();
    reader.join().unwrap();
    let stderr = log.lock().unwrap().clone();
    assert!(status.success(), "preview failed: {stderr}");
    assert!(!stderr.contains("validation:") && !stderr.contains("VUID"), "{stderr}");
    assert!(stderr.contains("brdf/lambert.glsl") && stderr.contains("keeping the last good shaders"), "{stderr}");
    assert!(stderr.contains("object.0.radius = -1") && stderr.contains("keeping the last good scene"), "{stderr}");
    let shot = image::open(&shot).unwrap().into_rgb8();
    // The embedded (unhalved) Lambert with every kd halved: the sphere's 0.9 and the plane's red.
    let size = ["image.width=160", "image.height=120"];
    let expected =
        offscreen("fig1-lambert.toml", &[size[0], size[1], "material.grey.kd=0.45", "material.red.kd=[0.5, 0.0, 0.0]"]);
    assert_same(&shot, &expected, "after the reloads");
    assert_ne!(shot, offscreen("fig1-lambert.toml", &[size[0], size[1], "material.grey.kd=0.9"]), "shader kept");
}

fn copy_tree(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for entry in std::fs::read_dir(from).unwrap().flatten() {
        let target = to.join(entry.file_name());
        if entry.path().is_dir() {
            copy_tree(&entry.path(), &target);
        } else {
            std::fs::copy(entry.path(), target).unwrap();
        }
    }
}

#[test]
fn b_shows_the_selected_objects_lobe() {
    // B: the first object's (the sphere's) lobe for the first light, standing on its highlight.
    let shot = screenshot((320, 240), 3, "b");
    let size = ["image.width=320", "image.height=240"];
    let mut scene = asset_scene("fig1-lambert.toml", &size);
    let lobe =
        vk_render::analysis::lobe3d::lobe_on_object(&mut renderer(), &scene, 0).unwrap().expect("a sphere's lobe");
    scene.objects.extend(lobe);
    assert_same(&shot, &render(&scene).to_rgb8(&scene.image), "with the lobe");
    assert_ne!(shot, offscreen("fig1-lambert.toml", &size), "B changed nothing");
}

/// The sky's spheres previewed at 48 x 24 for `frames` still frames: the last frame presented.
fn environment_screenshot(frames: u32) -> image::RgbImage {
    let folder = temp_dir();
    let shot = folder.path().join("shot.png");
    let scene = root().join("assets/environment/spheres-sky.toml");
    let frames = frames.to_string();
    let args = [scene.to_str().unwrap(), "--frames", &frames, "--screenshot", shot.to_str().unwrap()];
    let output = preview(&[&args[..], &["--width", "48", "--height", "24"]].concat());
    succeeded(&output);
    image::open(&shot).unwrap().into_rgb8()
}

#[test]
fn with_an_environment_a_moving_frame_is_fast_and_a_still_one_refines_to_the_exact_render() {
    let overrides = ["image.width=48", "image.height=24"];
    let exact = {
        let scene = Scene::load(&root().join("assets/environment/spheres-sky.toml"), &parsed(&overrides)).unwrap();
        render(&scene).to_rgb8(&scene.image)
    };
    let fast = {
        let mut overrides = parsed(&overrides);
        overrides.push("environment.mode=\"fast\"".parse().unwrap());
        let scene = Scene::load(&root().join("assets/environment/spheres-sky.toml"), &overrides).unwrap();
        render(&scene).to_rgb8(&scene.image)
    };
    // The two modes differ at this size too, so each equality below says which mode the frame is.
    assert_ne!(fast, exact, "the fast and the exact render are the same image: the test cannot tell them apart");
    assert_eq!(environment_screenshot(1), fast, "the first frame is the fast mode's render");
    // One fast frame, then at most 256 exact passes, one a frame: the still image is the exact render.
    assert_eq!(environment_screenshot(300), exact, "the refined frame is the exact render");
}

fn parsed(overrides: &[&str]) -> Vec<vk_render::Override> {
    overrides.iter().map(|o| o.parse().unwrap()).collect()
}

/// Figure 1 at 320 x 240 with its camera orbited `steps` times, as the preview's Orbit step turns it.
fn orbited(steps: u32) -> Scene {
    use vk_render::preview::{Controls, ORBIT_STEP_PIXELS};
    let mut scene = asset_scene("fig1-lambert.toml", &["image.width=320", "image.height=240"]);
    let mut controls = Controls::new(&scene);
    for _ in 0..steps {
        controls.orbit.drag(ORBIT_STEP_PIXELS, 0.0);
    }
    scene.camera.position = controls.orbit.position(scene.camera.look_at);
    scene
}

/// A motion frame of `scene`, as the preview draws it: the motion scene rendered offscreen, scaled up.
fn motion_frame(scene: &Scene) -> image::RgbImage {
    let small_scene = vk_render::preview::motion_scene(scene);
    let small = render(&small_scene).to_rgb8(&small_scene.image);
    let (width, height) = (scene.image.width, scene.image.height);
    let mut texels = vec![0; (width * height * 3) as usize];
    vk_render::preview::scale_up(small.as_raw(), small.dimensions(), &mut texels, (width, height), 3);
    image::RgbImage::from_raw(width, height, texels).unwrap()
}

#[test]
fn while_the_camera_moves_motion_frames_and_once_still_the_offscreen_render() {
    use vk_render::preview::{MOTION_SAMPLES, MOTION_SCALE, SETTLE_FRAMES};
    const { assert!(MOTION_SCALE >= 2 && MOTION_SAMPLES == 1 && SETTLE_FRAMES >= 2) };
    // Orbit, Orbit, then S (a screenshot of that frame, into the working folder) while it still moves; the
    // run then settles: its last frame, past the count, is the exact render at the orbited camera.
    let folder = temp_dir();
    let shot = folder.path().join("shot.png");
    let scene = root().join("assets/scenes/fig1-lambert.toml");
    let (mut command, _runtime) = preview_command(&[
        scene.to_str().unwrap(),
        "--frames",
        "4",
        "--screenshot",
        shot.to_str().unwrap(),
        "--width",
        "320",
        "--height",
        "240",
        "--keys",
        "Orbit,Orbit,s,Orbit",
    ]);
    let output = command.current_dir(folder.path()).output().expect("xvfb-run");
    succeeded(&output);
    let stderr = String::from_utf8_lossy(&output.stderr);
    // The first frame is still (nothing moved yet); frames 2 to 4 move, then SETTLE_FRAMES - 1 more motion
    // frames before the still one: every motion frame counted, the run longer than asked.
    let moving = 3 + SETTLE_FRAMES - 1;
    assert!(stderr.contains(&format!("presented {} frames", 1 + moving + 1)), "{stderr}");
    assert!(stderr.contains(&format!("; {moving} moving frames, ")), "{stderr}");
    let settled = image::open(&shot).unwrap().into_rgb8();
    assert_same(&settled, &render(&orbited(3)).to_rgb8(&orbited(3).image), "the settled frame");
    // The frame S saved (the third: two orbits, then nothing moved for one frame) is the motion frame.
    let moving_shot = image::open(folder.path().join("vk-render-screenshot-1.png")).unwrap().into_rgb8();
    assert_same(&moving_shot, &motion_frame(&orbited(2)), "the motion frame");
    assert_ne!(moving_shot, render(&orbited(2)).to_rgb8(&orbited(2).image), "a motion frame is cheaper");
}
