//! Helpers shared by the integration tests: one validating renderer per test binary, scene loading, and
//! comparison against the CPU reference with pictures written on failure.
#![allow(dead_code)] // each test binary uses its own subset

pub mod golden;
pub mod server;
pub mod webdriver;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::sync::{Mutex, MutexGuard, OnceLock};

use vk_render::pictures::compare::{compare, silhouette_band, write_failure_images, Comparison};
use vk_render::{reference, HdrImage, Override, Renderer, RendererOptions, Scene};

/// A `.brdf` model the project ships (`assets/brdfs/FILE`).
pub fn shipped(file: &str) -> std::sync::Arc<vk_render::brdf::AnalyticModel> {
    vk_render::brdf::AnalyticModel::load(&root().join("assets/brdfs").join(file)).expect("a shipped model loads")
}

/// The repository's root.
pub fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// One renderer for the whole test binary, with the validation layer on: tests share the compiled shaders
/// and pipelines, and the lock keeps the two cores for one render at a time.
pub fn renderer() -> MutexGuard<'static, Renderer> {
    static RENDERER: OnceLock<Mutex<Renderer>> = OnceLock::new();
    RENDERER
        .get_or_init(|| {
            let options = RendererOptions { validate: true, ..Default::default() };
            Mutex::new(Renderer::new(options).expect("a Vulkan device with the validation layer (run `make setup`)"))
        })
        .lock()
        .unwrap_or_else(|poisoned| poisoned.into_inner())
}

/// Renders a scene; the render fails on any validation message.
pub fn render(scene: &Scene) -> HdrImage {
    renderer().render(scene).expect("render with no validation message")
}

/// Loads a scene of assets/scenes/ with overrides.
pub fn asset_scene(name: &str, overrides: &[&str]) -> Scene {
    let overrides: Vec<Override> = overrides.iter().map(|o| o.parse().expect("KEY=VALUE")).collect();
    Scene::load(&root().join("assets/scenes").join(name), &overrides).expect("valid scene")
}

/// Parses scene text as if it were the file `tests/<name>.toml`.
pub fn scene_from_text(name: &str, text: &str) -> Scene {
    Scene::parse(text, &root().join("tests").join(format!("{name}.toml")), &[]).expect("valid scene")
}

/// The GPU-against-reference acceptance: mean absolute error <= 1 level, 99th percentile <= 4 levels, at
/// most 1% of the pixels more than 3 levels off (away from silhouettes).
pub fn acceptable(c: &Comparison) -> bool {
    c.mean_abs <= 1.0 && c.p99 <= 4 && c.fraction_over_3 <= 0.01
}

/// Loads a scene of tests/scenes/.
pub fn test_scene(name: &str) -> Scene {
    Scene::load(&root().join("tests/scenes").join(name), &[]).expect("valid scene")
}

/// Renders on the GPU and with the CPU reference, and compares away from silhouettes (2 px band).
/// On failure of `accept`, writes the images under target/test-output/ and panics with their paths.
pub fn check_against_reference(name: &str, scene: &Scene, accept: impl Fn(&Comparison) -> bool) -> Comparison {
    let gpu = render(scene).to_rgb8(&scene.image);
    compare_with_reference(name, scene, &gpu, accept)
}

/// Samples a pixel the tests' reference takes for an environment's light: a quarter of the command's 8192,
/// and a quarter of its time (tests/environment.rs: 218 to 120 s with the changes beside it). Its standard
/// error at 99% of the pixels of tests/environment.rs's five spheres is then 0.62 of an 8-bit level under
/// the sky and 0.79 under the studio, against exact-mode differences of mean 0.32 and 0.41 levels, p99 2;
/// [`compare_with_reference`] fails if it is ever above 1 level.
pub const REFERENCE_SAMPLES: u32 = 2048;

/// Compares an 8-bit image with the reference of `scene`, as [`check_against_reference`].
pub fn compare_with_reference(
    name: &str,
    scene: &Scene,
    gpu: &image::RgbImage,
    accept: impl Fn(&Comparison) -> bool,
) -> Comparison {
    let reference = reference::render_with_samples(scene, REFERENCE_SAMPLES).expect("the reference renders this scene");
    if scene.environment.is_some() {
        // The reference's own error, which the acceptance below must leave room for.
        let error = reference.p99_error_levels(&scene.image);
        eprintln!("{name}: the reference's environment light: standard error at most {error:.2} levels at 99%");
        assert!(error <= 1.0, "{name}: the reference is not exact enough to judge: {error:.2} levels");
    }
    let expected = reference.image.to_rgb8(&scene.image);
    let band = silhouette_band(&reference.object_ids, scene.image.width, scene.image.height, 2);
    let comparison = compare(gpu, &expected, &band);
    if !accept(&comparison) {
        let folder = root().join("target/test-output");
        let paths = write_failure_images(&folder, name, gpu, &expected, &band).expect("write failure images");
        let list: Vec<_> = paths.iter().map(|p| p.display().to_string()).collect();
        panic!("{name}: GPU differs from the CPU reference: {comparison}\nsee {}", list.join(", "));
    }
    comparison
}

/// A path under a fresh temporary folder, removed when the returned guard drops.
pub fn temp_dir() -> tempfile::TempDir {
    tempfile::tempdir().expect("a temporary folder")
}

/// Whether a path exists.
pub fn exists(path: &Path) -> bool {
    path.exists()
}

/// Runs vk-render with validation, failing the test if it has not exited within ten minutes (a hang must
/// fail a test, not stall it; a machine busy with other work may take a few minutes over what takes
/// seconds alone). Its output is read while it runs, so that a long one never fills a pipe and waits.
pub fn vk_render(args: &[&str]) -> Output {
    let mut child = Command::new(env!("CARGO_BIN_EXE_vk-render"))
        .arg("--validate")
        .args(args)
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("run vk-render");
    let stdout = read_on_a_thread(child.stdout.take().expect("a piped stdout"));
    let stderr = read_on_a_thread(child.stderr.take().expect("a piped stderr"));
    let deadline = std::time::Instant::now() + std::time::Duration::from_secs(600);
    let status = loop {
        if let Some(status) = child.try_wait().expect("wait for vk-render") {
            break status;
        }
        if std::time::Instant::now() > deadline {
            let _ = child.kill();
            panic!("vk-render {args:?} hung: killed after ten minutes");
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    };
    Output { status, stdout: stdout.join().expect("a pipe's reader"), stderr: stderr.join().expect("a pipe's reader") }
}

/// Everything `reader` gives until its end, read on a thread of its own (so that a child's full pipe never
/// stalls it while the test waits for it, or reads its other pipe).
pub fn read_on_a_thread(mut reader: impl std::io::Read + Send + 'static) -> std::thread::JoinHandle<Vec<u8>> {
    std::thread::spawn(move || {
        let mut bytes = Vec::new();
        reader.read_to_end(&mut bytes).ok();
        bytes
    })
}

/// Runs `vk-render ARGS` (which must succeed) and returns its peak resident size in MB (VmHWM, read until
/// the process exits) with its standard error.
pub fn peak_resident_mb(args: &[&str]) -> (u64, String) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_vk-render"))
        .args(args)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("run vk-render");
    let stderr = read_on_a_thread(child.stderr.take().expect("a piped stderr"));
    let status = format!("/proc/{}/status", child.id());
    let mut peak_kb = 0u64;
    let deadline = std::time::Instant::now() + std::time::Duration::from_secs(300);
    let exit = loop {
        if let Some(exit) = child.try_wait().expect("wait for vk-render") {
            break exit;
        }
        if std::time::Instant::now() > deadline {
            let _ = child.kill();
            panic!("vk-render {args:?} hung: killed after five minutes");
        }
        let hwm = std::fs::read_to_string(&status).ok().and_then(|s| {
            s.lines().find(|l| l.starts_with("VmHWM:")).and_then(|l| l.split_whitespace().nth(1)?.parse().ok())
        });
        peak_kb = peak_kb.max(hwm.unwrap_or(0));
        std::thread::sleep(std::time::Duration::from_millis(5));
    };
    let stderr = String::from_utf8_lossy(&stderr.join().expect("a pipe's reader")).to_string();
    assert!(exit.success(), "vk-render {args:?}: {stderr}");
    assert!(peak_kb > 0, "no peak resident size read");
    (peak_kb / 1024, stderr)
}

/// A validating renderer whose shaders have one edit: `from` (found exactly once) replaced by `to` in
/// `file` under shaders/, the way tests break a shader on purpose.
pub fn mutant_renderer(file: &str, from: &str, to: &str) -> Renderer {
    let shaders = vk_render::vulkan::ShaderSources::default().with_replaced(file, from, to).expect("the edit fits");
    renderer_with_shaders(shaders)
}

/// A validating renderer of its own with `shaders`.
pub fn renderer_with_shaders(shaders: vk_render::vulkan::ShaderSources) -> Renderer {
    Renderer::new(RendererOptions { validate: true, shaders, ..Default::default() }).expect("a renderer")
}
