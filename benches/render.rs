//! Timings of the renderer: start-up (device, shader compilation, pipelines) and whole renders.
//! Run with `cargo bench --bench render`; each figure is the median of several runs.

use std::path::Path;
use std::time::{Duration, Instant};

use vk_render::{Override, Renderer, RendererOptions, Scene};

fn median(mut samples: Vec<Duration>) -> Duration {
    samples.sort();
    samples[samples.len() / 2]
}

fn time(runs: usize, mut f: impl FnMut()) -> Duration {
    f(); // warm-up: the pipeline for the sample count is built on first use
    median(
        (0..runs)
            .map(|_| {
                let start = Instant::now();
                f();
                start.elapsed()
            })
            .collect(),
    )
}

fn main() -> vk_render::Result<()> {
    let start = Instant::now();
    let mut renderer = Renderer::new(RendererOptions::default())?;
    println!("device: {}", renderer.device_info().name);
    println!("{:<48} {:>10.1} ms", "start-up (instance, device, shaders, layout)", start.elapsed().as_secs_f64() * 1e3);

    let cases: [(&str, &str, &[&str]); 5] = [
        ("fig1 600x400, 4 samples", "fig1-lambert.toml", &[]),
        ("fig1 600x400, 1 sample", "fig1-lambert.toml", &["image.samples=1"]),
        ("fig1 1200x800, 4 samples", "fig1-lambert.toml", &["image.width=1200", "image.height=800"]),
        ("fig4 gold metalness 0.5, 600x400, 4 samples", "fig4-gold-metalness-0.5.toml", &[]),
        ("fig6 blinn-phong plane, 600x400, 4 samples", "fig6-blinn-phong.toml", &[]),
    ];
    for (name, file, overrides) in cases {
        let overrides: Vec<Override> = overrides.iter().map(|o| o.parse().expect("KEY=VALUE")).collect();
        let scene = Scene::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scenes").join(file), &overrides)?;
        let mut result = Ok(());
        let t = time(9, || {
            if let Err(e) = renderer.render(&scene) {
                result = Err(e);
            }
        });
        result?;
        println!("{name:<48} {:>10.1} ms", t.as_secs_f64() * 1e3);
    }
    Ok(())
}
