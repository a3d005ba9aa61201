//! Faster exact images from a material's own sampler, measured side by side in one run: a sphere of each
//! shipped `.brdf` model that has a sampler (its isFunc section) under the sky in the exact mode, rendered
//! pass by pass until the standard error of 99% of its pixels is at most [`TARGET_LEVELS`] 8-bit levels,
//! with the file as shipped and with its isFunc section taken out (the exact mode then draws by the cosine and
//! the sky alone), the two taking turns; the passes each needs and the median time of its runs. A variant
//! stopped at [`MAX_PASSES`] states the error it reached and the time the target would take by the error's
//! 1/√N (marked ~). Run with `cargo bench --bench sampling` (`make bench-sampling`).

use std::path::Path;
use std::time::{Duration, Instant};

use vk_render::render::exact::Passes;
use vk_render::{Renderer, RendererOptions, Scene};

const RUNS: usize = 3;

/// The error both variants are taken to, in 8-bit levels at 99% of the pixels.
const TARGET_LEVELS: f32 = 1.0;

/// Past this many passes (32 samples a pixel each) a variant is stopped and its error stated.
const MAX_PASSES: u32 = 1024;

/// The materials: a shipped file and its parameters, as the scene format writes them.
const MATERIALS: [(&str, &str); 3] = [
    ("ward.brdf", "{ rho_d = [0.08, 0.06, 0.05], rho_s = 0.6, alpha_x = 0.05, alpha_y = 0.4 }"),
    ("ashikhmin_shirley.brdf", "{ Rd = [0.25, 0.12, 0.06], Rs = [0.9, 0.7, 0.5], nu = 20.0, nv = 800.0 }"),
    ("walter_ggx.brdf", "{ kd = 0.05, f0 = [0.95, 0.64, 0.54], alpha = 0.1 }"),
];

/// A sphere of `file` (a path) with `params` under the sky, 64 x 64, in the exact mode.
fn sphere(file: &Path, params: &str) -> Result<Scene, Box<dyn std::error::Error>> {
    let text = format!(
        "[image]\nwidth = 64\nheight = 64\nsamples = 1\ntonemap = \"aces\"\nencoding = \"srgb\"\n[camera]\nposition = \
         [0.0, 0.0, 0.0]\nlook_at = [0.0, 0.0, 1.0]\nfov_y = 14.0\n[environment]\nbuiltin = \"sky\"\n[material.m]\n\
         brdf = \"analytic\"\nfile = \"{}\"\nparams = {params}\n[[object]]\nshape = \"sphere\"\ncenter = [0.0, 0.0, \
         10.0]\nradius = 1.0\nmaterial = \"m\"\n",
        file.display()
    );
    Ok(Scene::parse(&text, &file.with_extension("toml"), &[])?)
}

/// Passes until the target error (or the cap): how many, the error reached, how long.
fn converge(renderer: &mut Renderer, scene: &Scene) -> Result<(u32, f32, Duration), Box<dyn std::error::Error>> {
    let start = Instant::now();
    let mut passes = Passes::new(scene.image.width, scene.image.height);
    loop {
        renderer.refine(scene, &mut passes)?;
        let error = passes.accuracy(&scene.image).p99_levels;
        if (passes.count >= 4 && error <= TARGET_LEVELS) || passes.count >= MAX_PASSES {
            return Ok((passes.count, error, start.elapsed()));
        }
    }
}

fn median(mut samples: Vec<Duration>) -> Duration {
    samples.sort();
    samples[samples.len() / 2]
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut renderer = Renderer::new(RendererOptions::default())?;
    println!("device: {}", renderer.device_info().name);
    let brdfs = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/brdfs");
    let plain = tempfile::tempdir()?;
    println!(
        "\na sphere under the sky in the exact mode, 64 x 64, to {TARGET_LEVELS} level at 99% of the pixels \
         (median of {RUNS}, taking turns):"
    );
    println!("{:<24} {:>24} {:>32} {:>10}", "model", "with its sampler", "cosine and sky alone", "faster");
    for (file, params) in MATERIALS {
        let text = std::fs::read_to_string(brdfs.join(file))?;
        let begin = text.find("::begin isFunc").ok_or("no isFunc section")?;
        let end = text.find("::end isFunc").ok_or("no end of the isFunc section")? + "::end isFunc".len();
        std::fs::write(plain.path().join(file), format!("{}{}", &text[..begin], &text[end..]))?;
        let scenes = [sphere(&brdfs.join(file), params)?, sphere(&plain.path().join(file), params)?];
        // One untimed pass of each builds its pipelines.
        for scene in &scenes {
            renderer.refine(scene, &mut Passes::new(scene.image.width, scene.image.height))?;
        }
        let mut times = [Vec::new(), Vec::new()];
        let mut reached = [(0, 0.0); 2];
        for _ in 0..RUNS {
            for (k, scene) in scenes.iter().enumerate() {
                let (passes, error, time) = converge(&mut renderer, scene)?;
                times[k].push(time);
                reached[k] = (passes, error);
            }
        }
        // The time to the target: measured, or by 1/√N from the error reached at the cap.
        let to_target = |k: usize, time: Duration| {
            let (_, error) = reached[k];
            time.as_secs_f64() * f64::from((error / TARGET_LEVELS).max(1.0)).powi(2)
        };
        let [with, without] = times.map(median);
        let cell = |(passes, error): (u32, f32), time: Duration| {
            if error > TARGET_LEVELS {
                format!("{passes} passes {:.1} s, {error:.2} levels", time.as_secs_f64())
            } else {
                format!("{passes} passes {:.1} s", time.as_secs_f64())
            }
        };
        let capped = reached.iter().any(|&(_, error)| error > TARGET_LEVELS);
        println!(
            "{file:<24} {:>24} {:>32} {:>6}{:.1}x",
            cell(reached[0], with),
            cell(reached[1], without),
            if capped { "~" } else { "" },
            to_target(1, without) / to_target(0, with)
        );
    }
    Ok(())
}
