//! The `vk-render` command as a user runs it: success, and every kind of bad input, each with a clear
//! message naming the file, the key and the value, a non-zero exit status and no output file.

mod common;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use common::{root, temp_dir, vk_render};

/// A scene file in `folder` made from Figure 1 with `edit` applied to its text.
fn scene_file(folder: &Path, edit: impl Fn(&str) -> String) -> PathBuf {
    let base = std::fs::read_to_string(root().join("assets/scenes/fig1-lambert.toml")).unwrap();
    let text = edit(&base);
    let path = folder.join("scene.toml");
    std::fs::write(&path, text).unwrap();
    path
}

/// `vk-render render SCENE -o OUT`, then `extra` arguments.
fn render_to(scene: &Path, out: &Path, extra: &[&str]) -> Output {
    let mut args = vec!["render", scene.to_str().unwrap(), "-o", out.to_str().unwrap()];
    args.extend_from_slice(extra);
    vk_render(&args)
}

/// `vk-render sweep` of Figure 1 over the grey material's kd, through `values`, its sheet at `sheet`, then
/// `extra` arguments.
fn sweep_grey_kd(values: &str, sheet: &Path, extra: &[&str]) -> Output {
    let fig1 = root().join("assets/scenes/fig1-lambert.toml");
    let mut args = vec!["sweep", fig1.to_str().unwrap(), "--param", "material.grey.kd", "--values", values];
    args.extend_from_slice(&["-o", sheet.to_str().unwrap()]);
    args.extend_from_slice(extra);
    vk_render(&args)
}

/// Runs a render that must fail, and checks the exit status, that stderr holds every `needle` and that no
/// output file (nor a partial one) was written.
fn fails_with(scene: &Path, extra: &[&str], needles: &[&str]) -> String {
    let folder = scene.parent().unwrap();
    let out = folder.join("out.png");
    let output = render_to(scene, &out, extra);
    let stderr = String::from_utf8_lossy(&output.stderr).to_string();
    assert!(!output.status.success(), "exit status 0 for bad input; stderr: {stderr}");
    assert_eq!(output.status.code(), Some(1), "a clean error exit, not a crash; stderr: {stderr}");
    for needle in needles {
        assert!(stderr.contains(needle), "stderr lacks {needle:?}:\n{stderr}");
    }
    assert!(!stderr.contains("panicked"), "{stderr}");
    let left: Vec<_> = std::fs::read_dir(folder).unwrap().flatten().map(|e| e.file_name()).collect();
    assert!(!out.exists(), "an output file was written: {left:?}");
    assert!(left.iter().all(|n| !n.to_string_lossy().contains("partial")), "a partial file was left: {left:?}");
    stderr
}

/// "line N" for the first line of the file that holds `needle`.
fn line_of(path: &Path, needle: &str) -> String {
    let text = std::fs::read_to_string(path).unwrap();
    let index = text.lines().position(|l| l.contains(needle)).expect("needle in the file");
    format!("line {}", index + 1)
}

/// Figure 1 with `from` replaced by `to` must fail with every needle in its message.
fn fails_after_edit(from: &'static str, to: &'static str, needles: &[&str]) {
    let folder = temp_dir();
    let scene = scene_file(folder.path(), edited(from, to));
    fails_with(&scene, &[], needles);
}

fn edited(from: &'static str, to: &'static str) -> impl Fn(&str) -> String {
    move |text: &str| {
        assert!(text.contains(from), "Figure 1 no longer holds {from:?}");
        text.replacen(from, to, 1)
    }
}

#[test]
fn renders_figure_1_to_png_and_exits_0() {
    let folder = temp_dir();
    let out = folder.path().join("fig1.png");
    let scene = root().join("assets/scenes/fig1-lambert.toml");
    let output = vk_render(&[
        "render",
        scene.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--width",
        "300",
        "--height",
        "200",
    ]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "{stderr}");
    // Not even at teardown may the validation layer speak (its messages are logged).
    assert!(!stderr.contains("validation:"), "{stderr}");
    let image = image::open(&out).unwrap().into_rgb8();
    assert_eq!(image.dimensions(), (300, 200));
    assert_eq!(image.get_pixel(150, 100).0, [152, 152, 152]);
}

#[test]
fn lists_devices() {
    let output = vk_render(&["devices"]);
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(stdout.contains("0: ") && stdout.contains('*'), "{stdout}");
}

#[test]
fn an_unknown_device_is_an_error_that_lists_the_devices() {
    let output = vk_render(&["--device", "no-such-gpu", "devices"]);
    // `devices` lists whatever is there; rendering with a device that does not exist fails.
    assert!(output.status.success());
    let folder = temp_dir();
    let scene = root().join("assets/scenes/fig1-lambert.toml");
    let out = folder.path().join("o.png");
    let output =
        vk_render(&["--device", "no-such-gpu", "render", scene.to_str().unwrap(), "-o", out.to_str().unwrap()]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("no-such-gpu") && stderr.contains("0: "), "{stderr}");
    assert!(!out.exists());
}

#[test]
fn missing_scene_file() {
    let folder = temp_dir();
    fails_with(
        &folder.path().join("nowhere.toml"),
        &[],
        &["nowhere.toml", "cannot read the scene file", "No such file"],
    );
}

#[test]
fn toml_syntax_error_names_the_line() {
    let folder = temp_dir();
    let scene = scene_file(folder.path(), edited("radius = 1.0", "radius = = 1.0"));
    let line = line_of(&scene, "radius = = 1.0");
    fails_with(&scene, &[], &["scene.toml", &line, "radius = = 1.0"]);
}

#[test]
fn unknown_key_names_the_key_and_line() {
    let folder = temp_dir();
    let scene = scene_file(folder.path(), edited("height = 400", "height = 400\nwidht = 3"));
    let line = line_of(&scene, "widht = 3");
    fails_with(&scene, &[], &["scene.toml", &line, "widht = 3", "unknown field `widht`"]);
}

#[test]
fn wrong_type_names_the_key_and_value() {
    fails_after_edit(
        "power = 60.0",
        "power = \"bright\"",
        &["scene.toml", "power = \"bright\"", "invalid type: string \"bright\""],
    );
}

#[test]
fn a_vector_of_another_length_is_refused_not_truncated() {
    for (from, to) in [
        ("center = [0.0, 0.0, 3.0]", "center = [0.0, 0.0, 3.0, 9.0]"),
        ("center = [0.0, 0.0, 3.0]", "center = [0.0, 0.0, 3.0, \"junk\"]"),
        ("normal = [0.0, 1.0, 0.0]", "normal = [0, 1, 0, 9, 9]"),
        ("position = [0.0, 0.0, 0.0]", "position = [0, 0, 0, 7]"),
        ("position = [0.0, 0.0, -2.0]", "position = [0.0, -2.0]"),
        ("background = [0.5, 0.5, 0.5]", "background = [0.5, 0.5, 0.5, 1.0]"),
    ] {
        fails_after_edit(from, to, &["scene.toml", to, "three numbers"]);
    }
}

#[test]
fn undefined_material() {
    fails_after_edit(
        "material = \"grey\"",
        "material = \"gray\"",
        &["scene.toml", "object.0.material = \"gray\"", "no [material.gray]", "grey, red"],
    );
}

#[test]
fn unknown_brdf() {
    fails_after_edit(
        "brdf = \"lambert\"",
        "brdf = \"lambertian\"",
        &["scene.toml", "material.grey.brdf = \"lambertian\"", "unknown brdf", "\"oren-nayar\""],
    );
}

#[test]
fn a_parameter_of_another_brdf() {
    fails_after_edit(
        "kd = [0.5, 0.5, 0.5]",
        "kd = [0.5, 0.5, 0.5]\nsigma = 0.3",
        &["scene.toml", "material.grey.sigma", "not a parameter of brdf \"lambert\""],
    );
}

#[test]
fn a_sampler_switch_on_a_model_without_a_table() {
    // `sampler` turns a measured table's own sampler off; the course's models have none to turn.
    fails_after_edit(
        "kd = [0.5, 0.5, 0.5]",
        "kd = [0.5, 0.5, 0.5]\nsampler = false",
        &["scene.toml", "material.grey.sampler", "not a parameter of brdf \"lambert\""],
    );
}

#[test]
fn out_of_range_reflectance() {
    fails_after_edit(
        "kd = [0.5, 0.5, 0.5]",
        "kd = [0.5, 1.5, 0.5]",
        &["scene.toml", "material.grey.kd = [0.5, 1.5, 0.5]", "[0, 1]"],
    );
}

#[test]
fn negative_radius() {
    fails_after_edit("radius = 1.0", "radius = -1.0", &["scene.toml", "object.0.radius = -1", "greater than 0"]);
}

#[test]
fn zero_length_normal() {
    fails_after_edit(
        "normal = [0.0, 1.0, 0.0]",
        "normal = [0.0, 0.0, 0.0]",
        &["scene.toml", "object.1.normal = [0.0, 0.0, 0.0]", "zero length"],
    );
}

#[test]
fn zero_length_up() {
    fails_after_edit(
        "up = [0.0, 1.0, 0.0]",
        "up = [0, 0, 0]",
        &["scene.toml", "camera.up = [0.0, 0.0, 0.0]", "zero length"],
    );
}

#[test]
fn look_at_equal_to_position() {
    fails_after_edit(
        "look_at = [0.0, 0.0, 1.0]",
        "look_at = [0.0, 0.0, 0.0]",
        &["scene.toml", "camera.look_at = [0.0, 0.0, 0.0]", "equal to camera.position"],
    );
}

#[test]
fn look_at_a_hair_from_position_blames_look_at() {
    fails_after_edit(
        "look_at = [0.0, 0.0, 1.0]",
        "look_at = [0.0, 0.0, 1e-9]",
        &["scene.toml", "camera.look_at = [0.0, 0.0, 1e-9]", "from camera.position"],
    );
}

#[test]
fn zero_width() {
    fails_after_edit("width = 600", "width = 0", &["scene.toml", "image.width = 0", "from 1 to 65536"]);
}

#[test]
fn a_huge_width_names_the_real_bound() {
    fails_after_edit(
        "width = 600",
        "width = 1099511627776",
        &["scene.toml", "image.width = 1099511627776", "from 1 to 65536", "device's own limit"],
    );
}

#[test]
fn a_scene_without_objects_renders_its_background_and_says_so() {
    let folder = temp_dir();
    let scene = folder.path().join("empty.toml");
    std::fs::write(&scene, "# nothing but a comment\n").unwrap();
    let out = folder.path().join("out.png");
    let output = render_to(&scene, &out, &[]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "{stderr}");
    assert!(
        stderr.contains("warning: ") && stderr.contains("empty.toml") && stderr.contains("no [[object]]"),
        "{stderr}"
    );
    let lightless = folder.path().join("lightless.toml");
    let text = "[material.m]\nbrdf = \"lambert\"\nkd = 0.5\n[[object]]\nshape = \"sphere\"\ncenter = [0.0, 0.0, 3.0]\nradius = 1.0\nmaterial = \"m\"\n";
    std::fs::write(&lightless, text).unwrap();
    let output = render_to(&lightless, &out, &[]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        output.status.success() && stderr.contains("lightless.toml") && stderr.contains("no [[light]]"),
        "{stderr}"
    );
}

#[test]
fn empty_sweep_values_are_named_as_typed() {
    let folder = temp_dir();
    let sheet = folder.path().join("sheet.png");
    for values in ["", ",,,", "0.1,,0.2", "0.1,0.2,"] {
        let output = sweep_grey_kd(values, &sheet, &[]);
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert!(!output.status.success(), "{values:?}: {stderr}");
        assert!(stderr.contains("--values") && !stderr.contains("--set"), "{values:?}: {stderr}");
        assert_eq!(std::fs::read_dir(folder.path()).unwrap().count(), 0, "{values:?}: a file was written");
    }
}

#[test]
fn height_above_the_device_limit() {
    let folder = temp_dir();
    let scene = scene_file(folder.path(), |t| t.to_string());
    fails_with(&scene, &["--height", "40000"], &["scene.toml", "image.height = 40000", "above the limit"]);
}

#[test]
fn samples_the_device_does_not_support() {
    fails_after_edit(
        "samples = 4",
        "samples = 64",
        &["scene.toml", "image.samples = 64", "not supported by device", "it supports 1"],
    );
}

/// Figure 1 with its sphere replaced by the mesh `name`, written beside the scene with `contents` (or not
/// at all), must fail naming the object's path key, the file and `why`.
fn mesh_fails(name: &'static str, contents: Option<&str>, why: &str) {
    let folder = temp_dir();
    if let Some(text) = contents {
        std::fs::write(folder.path().join(name), text).unwrap();
    }
    let mesh = format!("shape = \"mesh\"\npath = \"{name}\"");
    let scene = scene_file(folder.path(), |t| {
        t.replacen("shape = \"sphere\"\ncenter = [0.0, 0.0, 3.0]\nradius = 1.0", &mesh, 1)
    });
    fails_with(&scene, &[], &["scene.toml", "object.0.path", name, why]);
}

#[test]
fn a_fifo_or_a_device_as_the_scene_is_refused_without_waiting() {
    let folder = temp_dir();
    let fifo = folder.path().join("scene.toml");
    assert!(Command::new("mkfifo").arg(&fifo).status().expect("mkfifo").success());
    fails_with(&fifo, &[], &["scene.toml", "is a FIFO (named pipe), not a regular file"]);
    let output = render_to(Path::new("/dev/zero"), &folder.path().join("out.png"), &[]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("/dev/zero is a device, not a regular file"), "{stderr}");
}

#[test]
fn a_device_or_a_folder_as_the_obj_is_refused_by_name() {
    mesh_fails("/dev/zero", None, "is a device, not a regular file");
    let folder = temp_dir();
    std::fs::create_dir(folder.path().join("meshes.obj")).unwrap();
    let scene = scene_file(folder.path(), |t| {
        t.replacen(
            "shape = \"sphere\"\ncenter = [0.0, 0.0, 3.0]\nradius = 1.0",
            "shape = \"mesh\"\npath = \"meshes.obj\"",
            1,
        )
    });
    fails_with(&scene, &[], &["object.0.path", "meshes.obj", "is a folder, not a regular file"]);
}

#[test]
fn a_scene_file_over_16_mib_is_refused_by_size() {
    let folder = temp_dir();
    let scene = scene_file(folder.path(), |t| format!("{t}\n{}", "# padding\n".repeat(1_700_000)));
    fails_with(&scene, &[], &["scene.toml", "over the 16 MiB a scene file may hold"]);
}

#[test]
fn zero_columns_and_an_id_map_over_the_image_are_refused() {
    let folder = temp_dir();
    let sheet = folder.path().join("sheet.png");
    let fig1 = root().join("assets/scenes/fig1-lambert.toml");
    let fig1 = fig1.to_str().unwrap();
    let output = sweep_grey_kd("0.1", &sheet, &["--columns", "0"]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(2), "{stderr}");
    assert_eq!(stderr.trim_end(), "error: invalid value '0' for '--columns <COLUMNS>': 0 is not in 1..=64");
    let image = folder.path().join("traced.png");
    let same = folder.path().join("./traced.png");
    let output = vk_render(&["reference", fig1, "-o", image.to_str().unwrap(), "--ids", same.to_str().unwrap()]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("the same file as -o"), "{stderr}");
    assert_eq!(std::fs::read_dir(folder.path()).unwrap().count(), 0, "a file was written");
}

#[test]
fn a_bad_command_line_is_one_line_with_status_2() {
    let fig1 = root().join("assets/scenes/fig1-lambert.toml");
    let fig1 = fig1.to_str().unwrap();
    for (args, needle) in [
        (vec!["render", fig1], "the following required arguments were not provided: --output <OUT>"),
        (vec!["render", fig1, "-o", "x.png", "--width", "wide"], "invalid value 'wide' for '--width <WIDTH>'"),
        (vec!["draw", fig1], "unrecognized subcommand 'draw'"),
    ] {
        let output = vk_render(&args);
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(2), "{args:?}: {stderr}");
        assert_eq!(stderr.lines().count(), 1, "{args:?}: {stderr}");
        assert!(stderr.starts_with("error: ") && stderr.contains(needle), "{args:?}: {stderr}");
    }
}

#[test]
fn a_huge_string_value_is_quoted_short() {
    let folder = temp_dir();
    let long = "x".repeat(5_000_000);
    let scene = scene_file(folder.path(), |t| t.replacen("tonemap = \"clamp\"", &format!("tonemap = \"{long}\""), 1));
    let stderr =
        fails_with(&scene, &[], &["scene.toml", "image.tonemap = \"xxxx", "(5000000 characters)", "unknown tonemap"]);
    assert!(stderr.len() < 1000, "{} bytes of message", stderr.len());
}

#[test]
fn a_set_value_is_one_value_and_a_table_merges() {
    let folder = temp_dir();
    let scene = scene_file(folder.path(), |t| t.to_string());
    let out = folder.path().join("small.png");
    let output = render_to(&scene, &out, &["--set", "image.width=8\nimage.height = 9"]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(2), "a usage error: {stderr}");
    assert!(stderr.contains("--set image.width") && stderr.contains("more than one value"), "{stderr}");
    assert!(!out.exists());
    let output = render_to(&scene, &out, &["--height", "64", "--set", "image={width=96}"]);
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    assert_eq!(image::image_dimensions(&out).unwrap(), (96, 64), "the table override dropped --height");
}

#[test]
fn device_memory_exhaustion_names_the_setting_and_the_need() {
    // lavapipe (the CI's device) cannot give 24 GiB of targets or 7 GiB of shadow cubes; a large GPU may.
    let devices = vk_render(&["devices"]);
    let default =
        String::from_utf8_lossy(&devices.stdout).lines().find(|l| l.starts_with('*')).unwrap_or("").to_string();
    if !default.contains("llvmpipe") {
        eprintln!("NOTE: the default device is not lavapipe ({default}): memory exhaustion not provoked");
        return;
    }
    let folder = temp_dir();
    let scene = scene_file(folder.path(), |t| t.to_string());
    fails_with(
        &scene,
        &["--width", "16384", "--height", "16384"],
        &["scene.toml", "image.width x height x samples = 16384 x 16384 x 4", "24.0 GiB of device memory"],
    );
    fails_with(&scene, &["--set", "image.shadow_map_size=16384"], &["image.shadow_map_size = 16384", "7.0 GiB"]);
}

#[test]
fn a_sweep_that_cannot_write_a_tile_leaves_nothing() {
    let folder = temp_dir();
    let sheet = folder.path().join("sheet.png");
    // The third tile's path is taken by a folder: writing it fails after two tiles were written.
    std::fs::create_dir(folder.path().join("sheet-0.3.png")).unwrap();
    let output = sweep_grey_kd("0.1,0.2,0.3,0.4", &sheet, &["--width", "60", "--height", "40"]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("sheet-0.3.png") && stderr.contains("2 file(s) written before it were removed"),
        "{stderr}"
    );
    let left: Vec<_> = std::fs::read_dir(folder.path()).unwrap().flatten().map(|e| e.file_name()).collect();
    assert_eq!(left, vec![std::ffi::OsString::from("sheet-0.3.png")], "files left behind");
}

/// Renders Figure 1 small into an empty folder with every write held for 20 s, sends `signal` (by name)
/// once the partial file exists, and returns the exit code, stderr and what the folder holds after.
fn signalled_during_a_write(signal: &str) -> (Option<i32>, String, Vec<std::ffi::OsString>) {
    let folder = temp_dir();
    let out = folder.path().join("out.png");
    let fig1 = root().join("assets/scenes/fig1-lambert.toml");
    let child = Command::new(env!("CARGO_BIN_EXE_vk-render"))
        .args(["render", fig1.to_str().unwrap(), "-o", out.to_str().unwrap(), "--width", "60", "--height", "40"])
        .env("VK_RENDER_TEST_WRITE_PAUSE_MS", "20000")
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let deadline = std::time::Instant::now() + std::time::Duration::from_secs(60);
    let partial = format!("out.png.partial-{}", child.id());
    while !folder.path().join(&partial).exists() {
        assert!(std::time::Instant::now() < deadline, "no {partial} appeared");
        std::thread::sleep(std::time::Duration::from_millis(10));
    }
    // The shell's own kill: no procps needed.
    let kill = format!("kill -{signal} {}", child.id());
    assert!(Command::new("sh").args(["-c", &kill]).status().unwrap().success());
    let output = child.wait_with_output().unwrap();
    let left = std::fs::read_dir(folder.path()).unwrap().flatten().map(|e| e.file_name()).collect();
    (output.status.code(), String::from_utf8_lossy(&output.stderr).into_owned(), left)
}

#[test]
fn sigterm_and_sigint_during_a_write_leave_nothing() {
    for (signal, code) in [("TERM", 143), ("INT", 130)] {
        let (status, stderr, left) = signalled_during_a_write(signal);
        assert_eq!(status, Some(code), "SIG{signal}: {stderr}");
        assert!(stderr.contains(&format!("stopped by SIG{signal}; 1 partial file(s) removed")), "{stderr}");
        assert_eq!(stderr.lines().count(), 1, "{stderr}");
        assert!(left.is_empty(), "SIG{signal} left {left:?}");
    }
}

#[test]
fn a_partial_file_a_killed_process_left_is_removed_by_the_next_write() {
    let folder = temp_dir();
    let out = folder.path().join("out.png");
    // No process has PID 4194304 (Linux's largest is 4194303): its partial file is abandoned.
    let abandoned = folder.path().join("out.png.partial-4194304");
    std::fs::write(&abandoned, b"half an image").unwrap();
    let fig1 = root().join("assets/scenes/fig1-lambert.toml");
    let output = render_to(&fig1, &out, &["--width", "60", "--height", "40"]);
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    assert!(out.exists() && !abandoned.exists(), "the abandoned partial file is still there");
}

#[test]
fn a_500_value_sweep_stays_within_200_mb() {
    // Each tile is written when it is done and the sheet made band by band: one row of tiles in memory. (Mesa
    // 22's lavapipe had kept 0.7 MB a sphere's image while the sphere's shader looped over a uniform: see
    // shaders/forward_sphere.frag.)
    let folder = temp_dir();
    let sheet = folder.path().join("sheet.png");
    let values: Vec<String> = (0..500).map(|i| format!("{:.3}", 0.001 + 0.002 * f64::from(i))).collect();
    let fig1 = root().join("assets/scenes/fig1-lambert.toml");
    let values = values.join(",");
    let args = ["sweep", fig1.to_str().unwrap(), "--param", "material.grey.kd", "--values", &values];
    let (peak, _) = common::peak_resident_mb(&[&args[..], &["-o", sheet.to_str().unwrap()]].concat());
    assert_eq!(std::fs::read_dir(folder.path()).unwrap().count(), 501, "500 tiles and the sheet");
    eprintln!("500-value sweep: peak resident size {peak} MB");
    assert!(peak < 200, "peak resident size {peak} MB");
}

#[test]
fn missing_obj() {
    mesh_fails("missing.obj", None, "No such file");
}

#[test]
fn malformed_obj() {
    mesh_fails("broken.obj", Some("v 0 0 0\nv 1 0 zero\nf 1 2 3\n"), "not a valid OBJ file");
}

#[test]
fn obj_without_triangles() {
    mesh_fails("empty.obj", Some("# nothing here\nv 0 0 0\n"), "no triangles");
}

#[test]
fn output_in_a_folder_that_does_not_exist() {
    let folder = temp_dir();
    let scene = root().join("assets/scenes/fig1-lambert.toml");
    let out = folder.path().join("no/such/folder/fig1.png");
    let output = vk_render(&["render", scene.to_str().unwrap(), "-o", out.to_str().unwrap()]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("no/such/folder") && stderr.contains("does not exist"), "{stderr}");
    assert!(!out.exists());
}

#[test]
fn unsupported_output_type() {
    let folder = temp_dir();
    let scene = scene_file(folder.path(), |t| t.to_string());
    let out = folder.path().join("fig1.jpg");
    let output = vk_render(&["render", scene.to_str().unwrap(), "-o", out.to_str().unwrap()]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("fig1.jpg") && stderr.contains(".png or .exr"), "{stderr}");
    assert!(!out.exists());
}

#[test]
fn unknown_set_path() {
    let folder = temp_dir();
    let scene = scene_file(folder.path(), |t| t.to_string());
    fails_with(&scene, &["--set", "image.widht=3"], &["scene.toml", "--set image.widht=3", "unknown field `widht`"]);
    fails_with(&scene, &["--set", "material.blue.kd=0.3"], &["--set material.blue.kd=0.3", "no `material.blue`"]);
    fails_with(&scene, &["--set", "light.3.power=3"], &["--set light.3.power=3", "no `light.3`", "has 1 light"]);
}

#[test]
fn set_overrides_a_value() {
    let folder = temp_dir();
    let out = folder.path().join("o.png");
    let scene = root().join("assets/scenes/fig1-lambert.toml");
    // Half the power halves the centre's radiance: 0.2984 -> 76.
    let output = vk_render(&[
        "render",
        scene.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--set",
        "light.0.power=30",
        "--set",
        "image.width=300",
        "--height=200",
    ]);
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    let image = image::open(&out).unwrap().into_rgb8();
    assert_eq!(image.get_pixel(150, 100).0, [76, 76, 76]);
}

#[test]
fn no_vulkan_driver_says_how_to_install_lavapipe() {
    // With no driver manifest the loader finds no device: the error must say what to install.
    let folder = temp_dir();
    let scene = root().join("assets/scenes/fig1-lambert.toml");
    let out = folder.path().join("o.png");
    let output = Command::new(env!("CARGO_BIN_EXE_vk-render"))
        .args(["render", scene.to_str().unwrap(), "-o", out.to_str().unwrap()])
        .env("VK_ICD_FILENAMES", folder.path().join("none.json"))
        .env("VK_DRIVER_FILES", folder.path().join("none.json"))
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("mesa-vulkan-drivers") && stderr.contains("lavapipe"), "{stderr}");
    assert!(!out.exists());
}

#[test]
fn reference_writes_the_ray_traced_image_and_the_object_ids() {
    let folder = temp_dir();
    let (out, ids) = (folder.path().join("ref.png"), folder.path().join("ids.png"));
    let scene = root().join("assets/scenes/fig1-lambert.toml");
    let output = Command::new(env!("CARGO_BIN_EXE_vk-render"))
        .args(["reference", scene.to_str().unwrap(), "-o", out.to_str().unwrap(), "--ids", ids.to_str().unwrap()])
        .args(["--width", "150", "--height", "100"])
        .output()
        .unwrap();
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    let image = image::open(&out).unwrap().into_rgb8();
    assert_eq!(image.get_pixel(75, 50).0, [152, 152, 152]);
    let ids = image::open(&ids).unwrap().into_rgb8();
    // Background black; sphere and plane in two other colours.
    let (sky, sphere, plane) = (ids.get_pixel(2, 2).0, ids.get_pixel(75, 50).0, ids.get_pixel(2, 97).0);
    assert_eq!(sky, [0, 0, 0]);
    assert!(sphere != sky && plane != sky && sphere != plane, "{sky:?} {sphere:?} {plane:?}");
}

#[test]
fn shadow_map_above_the_device_limit() {
    let folder = temp_dir();
    let scene = scene_file(folder.path(), |t| t.to_string());
    fails_with(
        &scene,
        &["--set", "image.shadow_map_size=1000000"],
        &["scene.toml", "image.shadow_map_size = 1000000", "above the limit"],
    );
}

/// Figure 1 with `environment` as its [environment] table, in `folder`.
fn scene_with_environment(folder: &Path, environment: &str) -> PathBuf {
    let table = format!("\n[environment]\n{environment}\n");
    scene_file(folder, move |t| format!("{t}{table}"))
}

#[test]
fn a_missing_unreadable_or_misshapen_map_is_named_and_nothing_is_written() {
    let folder = temp_dir();
    let dir = folder.path();
    let scene = scene_with_environment(dir, "map = \"sky.hdr\"");
    fails_with(&scene, &[], &["scene.toml: environment.map = ", "sky.hdr", "cannot read the environment map"]);
    std::fs::create_dir(dir.join("sky.hdr")).unwrap();
    fails_with(&scene, &[], &["environment.map = ", "sky.hdr", "is a folder, not a regular file"]);
    std::fs::remove_dir(dir.join("sky.hdr")).unwrap();
    std::fs::write(dir.join("sky.hdr"), "not an image").unwrap();
    fails_with(
        &scene,
        &[],
        &["environment.map = ", "sky.hdr", "not a map vk-render can read (Radiance .hdr or OpenEXR)"],
    );
    let square = dir.join("square.exr");
    image::Rgb32FImage::from_pixel(30, 20, image::Rgb([1.0; 3])).save(&square).unwrap();
    let scene = scene_with_environment(dir, "map = \"square.exr\"");
    fails_with(
        &scene,
        &[],
        &["square.exr", "the map is 30 x 20 texels: an equirectangular map is twice as wide as high"],
    );
    let negative = dir.join("negative.exr");
    let mut map = image::Rgb32FImage::from_pixel(8, 4, image::Rgb([1.0; 3]));
    map.put_pixel(5, 2, image::Rgb([1.0, -2.0, 1.0]));
    map.save(&negative).unwrap();
    let scene = scene_with_environment(dir, "map = \"negative.exr\"");
    fails_with(&scene, &[], &["negative.exr", "texel (5, 2) holds [1, -2, 1]: radiance must be finite and at least 0"]);
}

#[test]
fn a_bad_environment_setting_names_its_key_and_value() {
    let folder = temp_dir();
    let dir = folder.path();
    let cases = [
        ("builtin = \"sky\"\nintensity = -1", "environment.intensity = -1: must be a finite number, at least 0"),
        (
            "builtin = \"forest\"",
            "environment.builtin = \"forest\": unknown environment (expected \"white\", \"sky\" or \"studio\")",
        ),
        (
            "builtin = \"sky\"\nmap = \"a.hdr\"",
            "environment.builtin = \"sky\": the environment already has map = \"a.hdr\"",
        ),
        ("intensity = 2", "environment: has neither map = \"PATH.hdr\" (or .exr) nor builtin"),
        (
            "builtin = \"sky\"\nmode = \"quick\"",
            "environment.mode = \"quick\": unknown mode (expected \"exact\" or \"fast\")",
        ),
    ];
    for (table, message) in cases {
        let scene = scene_with_environment(dir, table);
        fails_with(&scene, &[], &["scene.toml", message]);
    }
    // A scene without [environment] is given one by --set; --environment-mode alone names what is missing.
    let plain = scene_file(dir, |t| t.to_string());
    fails_with(&plain, &["--environment-mode", "fast"], &["environment: has neither map"]);
}

#[test]
fn an_environment_renders_in_both_modes_and_states_its_accuracy() {
    let folder = temp_dir();
    let scene = scene_file(folder.path(), |t| t.to_string());
    let out = folder.path().join("sky.png");
    let small = ["--width", "48", "--height", "32", "--set", "environment.builtin=\"sky\""];
    let exact = render_to(&scene, &out, &small);
    let stdout = String::from_utf8_lossy(&exact.stdout);
    assert!(exact.status.success(), "{}", String::from_utf8_lossy(&exact.stderr));
    assert!(stdout.contains("environment (exact): ") && stdout.contains("samples a pixel in"), "{stdout}");
    let exact_image = image::open(&out).unwrap().into_rgb8();
    let fast = render_to(&scene, &out, &[&small[..], &["--environment-mode", "fast"]].concat());
    assert!(fast.status.success(), "{}", String::from_utf8_lossy(&fast.stderr));
    assert!(!String::from_utf8_lossy(&fast.stdout).contains("environment (exact)"));
    assert_ne!(image::open(&out).unwrap().into_rgb8(), exact_image, "the fast mode is its own approximation");
}

#[test]
fn a_sweep_turns_an_environment() {
    let folder = temp_dir();
    let sheet = folder.path().join("turn.png");
    let spheres = root().join("assets/environment/spheres-sky.toml");
    let args = [
        "sweep",
        spheres.to_str().unwrap(),
        "--param",
        "environment.rotation",
        "--values",
        "0,180",
        "--environment-mode",
        "fast",
        "--width",
        "64",
        "--height",
        "32",
        "-o",
        sheet.to_str().unwrap(),
    ];
    let output = vk_render(&args);
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    let tile = |value: &str| image::open(folder.path().join(format!("turn-{value}.png"))).unwrap().into_rgb8();
    assert_ne!(tile("0"), tile("180"), "turning the sky moved nothing");
}

#[test]
fn figures_take_an_environment() {
    let folder = temp_dir();
    let sky = "environment.builtin=\"sky\"";
    let args = ["figures", "-o", folder.path().to_str().unwrap(), "--set", sky, "--environment-mode", "fast"];
    let output = vk_render(&[&args[..], &["--width", "48", "--height", "32"]].concat());
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    // Figure 1's grey sphere under the sky is no longer the point light's alone.
    let lit = image::open(folder.path().join("fig1-lambert.png")).unwrap().into_rgb8();
    let plain = folder.path().join("plain");
    let output = vk_render(&["figures", "-o", plain.to_str().unwrap(), "--width", "48", "--height", "32"]);
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    assert_ne!(lit, image::open(plain.join("fig1-lambert.png")).unwrap().into_rgb8());
}

/// Every command that prints, its output read by a reader that closes the pipe at once (`| head -1`): it
/// ends quietly, as Unix tools do (done, or ended by SIGPIPE), never with a panic's "Broken pipe" and a
/// backtrace.
#[test]
fn every_printing_command_stops_quietly_on_a_closed_pipe() {
    use std::os::unix::process::ExitStatusExt;
    let dir = temp_dir();
    let out = |name: &str| dir.path().join(name).to_str().unwrap().to_string();
    let fig1 = root().join("assets/scenes/fig1-lambert.toml").to_str().unwrap().to_string();
    let materials = root().join("assets/analysis/course-materials.toml").to_str().unwrap().to_string();
    let small = ["--width", "48", "--height", "32", "--samples", "1"];
    let png = out("mine.png");
    assert!(vk_render(&[&["render", &fig1, "-o", &png], &small[..]].concat()).status.success());
    let (brdf, sheet, furnace, albedo, compared) =
        (out("brdf.png"), out("s.png"), out("f.csv"), out("a.csv"), out("c.png"));
    let commands: Vec<Vec<&str>> = vec![
        vec!["devices"],
        [&["render", &fig1, "--view", "brdf", "-o", &brdf][..], &small[..]].concat(),
        [&["sweep", &fig1, "--param", "material.grey.kd", "--values", "0.2,0.4", "-o", &sheet][..], &small[..]]
            .concat(),
        [&["sheet", &fig1, "--param", "material.grey.kd", "--values", "0.2,0.4", "-o", &sheet][..], &small[..]]
            .concat(),
        vec!["furnace", &materials, "--material", "lambert", "-o", &furnace],
        vec!["plot", "albedo", &materials, "--material", "lambert", "-o", &albedo],
        vec!["fit", &materials, "--material", "phong", "--to", "blinn-phong"],
        [&["compare", &fig1, &fig1, "-o", &compared][..], &small[..]].concat(),
        vec!["check", "--list"],
        vec!["check", &png, "--scene", "fig1-lambert"],
    ];
    for args in commands {
        let mut child = Command::new(env!("CARGO_BIN_EXE_vk-render"))
            .args(&args)
            .stdout(std::process::Stdio::piped())
            .stderr(std::process::Stdio::piped())
            .spawn()
            .expect("run vk-render");
        drop(child.stdout.take()); // the reader is gone before the first line
        let output = child.wait_with_output().expect("vk-render's output");
        let stderr = String::from_utf8_lossy(&output.stderr);
        let quiet = output.status.success() || output.status.signal() == Some(13);
        assert!(quiet && !stderr.contains("panicked"), "vk-render {args:?}: {:?}\n{stderr}", output.status);
        assert!(!stderr.contains("Broken pipe"), "vk-render {args:?}: {stderr}");
    }
}

/// `preview` with no display says so in one line, and how to get one; with a display where no server
/// answers, that.
#[cfg(feature = "preview")]
#[test]
fn a_preview_without_a_display_says_how_to_get_one() {
    let fig1 = root().join("assets/scenes/fig1-lambert.toml");
    let run = |display: Option<&str>| {
        let mut command = Command::new(env!("CARGO_BIN_EXE_vk-render"));
        command.args(["preview", fig1.to_str().unwrap()]).env_remove("WAYLAND_DISPLAY").env_remove("WAYLAND_SOCKET");
        match display {
            Some(display) => command.env("DISPLAY", display),
            None => command.env_remove("DISPLAY"),
        };
        command.output().expect("run vk-render")
    };
    let none = run(None);
    let stderr = String::from_utf8_lossy(&none.stderr);
    assert_eq!(none.status.code(), Some(1));
    assert_eq!(stderr.lines().count(), 1, "{stderr}");
    assert!(stderr.contains("no display: neither DISPLAY nor WAYLAND_DISPLAY is set"), "{stderr}");
    assert!(stderr.contains("xvfb-run -a vk-render preview"), "{stderr}");
    assert!(!stderr.contains(".rs:"), "a source path in: {stderr}");
    let nobody = run(Some(":4711"));
    let stderr = String::from_utf8_lossy(&nobody.stderr);
    assert_eq!(nobody.status.code(), Some(1));
    assert!(stderr.contains("no X server answers on DISPLAY=:4711") && !stderr.contains(".rs:"), "{stderr}");
}
