//! Timings of the renderer: start-up (instance, device, pipeline layout, shader modules; in fresh processes),
//! whole renders of the figures, the work a sweep and the preview repeat for each image, and how the cost
//! grows with pixels and triangles.
//! Run with `cargo bench --bench render`; each figure is the median of several runs. `scripts/bench-pyrender.sh`
//! sets whole commands against pyrender's.

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use vk_render::pictures::output::TexelOrder;
use vk_render::preview::{draw_motion_frame, Controls, ORBIT_STEP_PIXELS};
use vk_render::{Override, Renderer, RendererOptions, Scene};

fn median(mut samples: Vec<Duration>) -> Duration {
    samples.sort();
    samples[samples.len() / 2]
}

/// The median of `runs` calls of `f`, after one untimed call (which builds the pipelines the scene needs).
fn time(runs: usize, mut f: impl FnMut() -> vk_render::Result<()>) -> vk_render::Result<Duration> {
    f()?;
    let mut samples = Vec::with_capacity(runs);
    for _ in 0..runs {
        let start = Instant::now();
        f()?;
        samples.push(start.elapsed());
    }
    Ok(median(samples))
}

fn ms(d: Duration) -> f64 {
    d.as_secs_f64() * 1e3
}

fn scene(file: &str, overrides: &[String]) -> vk_render::Result<Scene> {
    let overrides: Vec<Override> = overrides.iter().map(|o| o.parse().expect("KEY=VALUE")).collect();
    Scene::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scenes").join(file), &overrides)
}

fn strings(items: &[&str]) -> Vec<String> {
    items.iter().map(|s| (*s).to_string()).collect()
}

/// Set in the children that time the start-up: each makes one renderer, prints its milliseconds and exits.
const START_UP_CHILD: &str = "VK_RENDER_BENCH_START_UP";

/// Fresh processes timed for the start-up: one measurement each, the first paying whatever the page cache
/// lacks (the drivers and LLVM from disk: 118 to 132 ms on Debian 13 where the median is 60).
const START_UP_RUNS: usize = 9;

fn start_up_ms() -> vk_render::Result<f64> {
    let start = Instant::now();
    drop(Renderer::new(RendererOptions::default())?);
    Ok(ms(start.elapsed()))
}

/// The start-up of `START_UP_RUNS` fresh processes (this benchmark run again as a child): a process
/// measures it once, since a second renderer in the same process finds the loader and drivers loaded.
fn start_up_in_fresh_processes() -> std::io::Result<Vec<f64>> {
    let exe = std::env::current_exe()?;
    (0..START_UP_RUNS)
        .map(|_| {
            let child = std::process::Command::new(&exe).env(START_UP_CHILD, "1").output()?;
            let text = String::from_utf8_lossy(&child.stdout);
            text.trim().parse::<f64>().map_err(|_| {
                let stderr = String::from_utf8_lossy(&child.stderr);
                std::io::Error::other(format!("the start-up child printed {text:?} ({}): {stderr}", child.status))
            })
        })
        .collect()
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    if std::env::var_os(START_UP_CHILD).is_some() {
        println!("{:.2}", start_up_ms()?);
        return Ok(());
    }
    let mut start_ups = start_up_in_fresh_processes()?;
    start_ups.sort_by(f64::total_cmp);
    let mut renderer = Renderer::new(RendererOptions::default())?;
    println!("device: {}", renderer.device_info().name);
    println!(
        "{:<56} {:>10.1} ms (median of {START_UP_RUNS} processes; {:.1} to {:.1})",
        "start-up (instance, device, layout, shader modules)",
        start_ups[START_UP_RUNS / 2],
        start_ups[0],
        start_ups[START_UP_RUNS - 1]
    );

    let cases: [(&str, &str, &[&str]); 6] = [
        ("fig1 600x400, 4 samples", "fig1-lambert.toml", &[]),
        ("fig1 600x400, 1 sample", "fig1-lambert.toml", &["image.samples=1"]),
        ("fig1 1200x800, 4 samples", "fig1-lambert.toml", &["image.width=1200", "image.height=800"]),
        ("fig4 gold metalness 0.5, 600x400, 4 samples", "fig4-gold-metalness-0.5.toml", &[]),
        ("fig5 bunny, two shadow cubes, 600x400, 4 samples", "fig5-golden-bunny.toml", &[]),
        ("fig6 blinn-phong plane, 600x400, 4 samples", "fig6-blinn-phong.toml", &[]),
    ];
    println!("\nwhole renders (what changed nothing is kept, as in a long process):");
    for (name, file, overrides) in cases {
        let scene = scene(file, &strings(overrides))?;
        let t = time(9, || renderer.render(&scene).map(drop))?;
        println!("  {name:<54} {:>10.1} ms", ms(t));
    }

    println!("\nwhat each further image costs:");
    // A sweep varies a material: the meshes, targets and shadow cubes stay.
    let mut kd = 0.0_f32;
    let t = time(15, || {
        kd = (kd + 0.05) % 1.0;
        renderer.render(&scene("fig1-lambert.toml", &[format!("material.grey.kd={kd}")])?).map(drop)
    })?;
    println!("  {:<54} {:>10.1} ms", "sweep image: fig1, grey kd varied, shadows on", ms(t));
    // The preview orbiting: a new camera each frame, the image encoded to 8-bit texels (not presented).
    let studio = ["environment.builtin=\"studio\"", "environment.mode=\"fast\""];
    for (name, file, overrides) in [
        ("fig1", "fig1-lambert.toml", &[][..]),
        ("bunny", "fig5-golden-bunny.toml", &[][..]),
        ("bunny + studio", "fig5-golden-bunny.toml", &studio[..]),
    ] {
        let mut frame = scene(file, &strings(overrides))?;
        let mut controls = Controls::new(&frame);
        let mut texels = vec![0u8; (frame.image.width * frame.image.height * 4) as usize];
        let t = time(15, || {
            controls.orbit.drag(ORBIT_STEP_PIXELS, 0.0);
            frame.camera.position = controls.orbit.position(frame.camera.look_at);
            renderer.render_texels(&frame, TexelOrder::Bgra, &mut texels)
        })?;
        println!("  {:<54} {:>10.1} ms", format!("preview frame orbiting, {name} (render and encode)"), ms(t));
        // What the window shows while the camera moves: the motion frame, rendered small and scaled up.
        let mut small = Vec::new();
        let t = time(15, || {
            controls.orbit.drag(ORBIT_STEP_PIXELS, 0.0);
            frame.camera.position = controls.orbit.position(frame.camera.look_at);
            draw_motion_frame(&mut renderer, &mut small, &frame, TexelOrder::Bgra, &mut texels)
        })?;
        println!("  {:<54} {:>10.1} ms", format!("preview motion frame orbiting, {name}"), ms(t));
    }

    Ok(scaling(&mut renderer)?)
}

/// Render time against pixels and against triangles, less the fixed cost of an image (the same scene at
/// 16 x 16, and without its mesh): what grows should grow no faster than the work.
fn scaling(renderer: &mut Renderer) -> vk_render::Result<()> {
    let size = |w: u32, h: u32| strings(&[&format!("image.width={w}"), &format!("image.height={h}")]);
    let fixed = time(9, || renderer.render(&scene("fig1-lambert.toml", &size(16, 16))?).map(drop))?;
    println!("\nfig1 against pixels (4 samples; less the {:.1} ms of a 16 x 16 image):", ms(fixed));
    println!("  {:>12} {:>12} {:>12} {:>16}", "size", "pixels", "time", "ns per pixel");
    for (w, h) in [(600, 400), (1280, 720), (1920, 1080), (3840, 2160)] {
        let image = scene("fig1-lambert.toml", &size(w, h))?;
        let t = time(if w > 2000 { 3 } else { 7 }, || renderer.render(&image).map(drop))?;
        let pixels = f64::from(w * h);
        let grown = ms(t) - ms(fixed);
        println!("  {:>12} {:>12} {:>9.1} ms {:>16.1}", format!("{w}x{h}"), w * h, grown, grown * 1e6 / pixels);
    }

    // A UV sphere written as an OBJ (drawn as a mesh, not an exact sphere) in place of Figure 1's sphere.
    let folder = std::env::temp_dir().join(format!("vk-render-bench-{}", std::process::id()));
    std::fs::create_dir_all(&folder).map_err(|e| output_error(&folder, &e))?;
    let without = scene("fig1-lambert.toml", &strings(&["object.0.radius=0.001"]))?;
    let base = time(9, || renderer.render(&without).map(drop))?;
    println!("\nfig1 against triangles (600 x 400, 4 samples, shadows; less the {:.1} ms without the mesh):", ms(base));
    println!("  {:>12} {:>12} {:>16}", "triangles", "time", "ns per triangle");
    for (segments, rings) in [(128, 64), (362, 181), (724, 362), (1448, 724)] {
        let path = folder.join(format!("sphere-{segments}x{rings}.obj"));
        let mesh = vk_render::mesh::uv_sphere(segments, rings);
        write_obj(&mesh, &path)?;
        let mut image = scene("fig1-lambert.toml", &[])?;
        image.objects[0].shape = vk_render::scene::Shape::Mesh {
            path: path.clone(),
            scale: 1.0,
            rotate: glam::Vec3::ZERO,
            translate: glam::Vec3::new(0.0, 0.0, 3.0),
        };
        // Moving the light redraws the shadow cube every time, as a new scene would.
        let mut light_x = 0.0_f32;
        let t = time(5, || {
            light_x = -light_x + 1e-3;
            image.lights[0].position.x = light_x;
            renderer.render(&image).map(drop)
        })?;
        let grown = ms(t) - ms(base);
        let triangles = mesh.triangle_count();
        println!("  {triangles:>12} {grown:>9.1} ms {:>16.1}", grown * 1e6 / triangles as f64);
    }
    std::fs::remove_dir_all(&folder).map_err(|e| output_error(&folder, &e))
}

fn write_obj(mesh: &vk_render::mesh::Mesh, path: &PathBuf) -> vk_render::Result<()> {
    use std::fmt::Write;
    let mut text = String::new();
    for v in &mesh.vertices {
        let _ = writeln!(
            text,
            "v {} {} {}\nvn {} {} {}",
            v.position[0], v.position[1], v.position[2], v.normal[0], v.normal[1], v.normal[2]
        );
    }
    for t in mesh.indices.chunks_exact(3) {
        let [a, b, c] = [t[0] + 1, t[1] + 1, t[2] + 1];
        let _ = writeln!(text, "f {a}//{a} {b}//{b} {c}//{c}");
    }
    std::fs::write(path, text).map_err(|e| output_error(path, &e))
}

fn output_error(path: &Path, e: &std::io::Error) -> vk_render::Error {
    vk_render::Error::Output { path: path.to_path_buf(), message: e.to_string() }
}
