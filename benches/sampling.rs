//! Faster exact images from a material's own sampler, measured side by side in one run: a sphere of each
//! shipped `.brdf` model that has a sampler (its isFunc section), `assets/analytic/anisotropic-spheres.toml`
//! (four such files) and a sphere of a measured gold, under the sky in the exact mode, rendered pass by pass
//! until the standard error of 99% of its pixels is at most [`TARGET_LEVELS`] 8-bit levels, with its sampler
//! and without (the file's isFunc section taken out; the table's `sampler = false`: the exact mode then draws
//! by the cosine and the sky alone), the two taking turns; the passes each needs and the median time of its
//! runs. A variant stopped at [`MAX_PASSES`] states the error it reached and the time the target would take
//! by the error's 1/√N (marked ~). Run with `cargo bench --bench sampling` (`make bench-sampling`).

use std::path::Path;
use std::time::{Duration, Instant};

use glam::Vec3;
use vk_render::brdf::{Brdf, DiffuseModel, MeasuredTable};
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

/// The measured material: the course's gold at roughness 0.2, tabulated.
const MEASURED_GOLD: &str = "gold.binary";

/// A sphere of `material` (its section's keys) under the sky, 64 x 64, in the exact mode.
fn sphere(material: &str) -> Result<Scene, Box<dyn std::error::Error>> {
    let text = format!(
        "[image]\nwidth = 64\nheight = 64\nsamples = 1\ntonemap = \"aces\"\nencoding = \"srgb\"\n[camera]\nposition = \
         [0.0, 0.0, 0.0]\nlook_at = [0.0, 0.0, 1.0]\nfov_y = 14.0\n[environment]\nbuiltin = \"sky\"\n[material.m]\n\
         {material}\n[[object]]\nshape = \"sphere\"\ncenter = [0.0, 0.0, 10.0]\nradius = 1.0\nmaterial = \"m\"\n"
    );
    Ok(Scene::parse(&text, Path::new("sphere.toml"), &[])?)
}

/// A `.brdf` file's material: `file` (a path) with `params`.
fn analytic(file: &Path, params: &str) -> String {
    format!("brdf = \"analytic\"\nfile = \"{}\"\nparams = {params}", file.display())
}

/// A material's (or scene's) name and its scene with its sampler and without.
type Case = (String, [Scene; 2]);

/// The `.brdf` file `text` without its isFunc section: the exact mode then draws by the cosine and the
/// environment alone.
fn without_sampler(text: &str) -> Result<String, Box<dyn std::error::Error>> {
    let begin = text.find("::begin isFunc").ok_or("no isFunc section")?;
    let end = text.find("::end isFunc").ok_or("no end of the isFunc section")? + "::end isFunc".len();
    Ok(format!("{}{}", &text[..begin], &text[end..]))
}

/// The pairs to compare, with their samplers and without, by name: each shipped file with a sampler
/// (its copy without its isFunc section in `plain/brdfs`); `assets/analytic/anisotropic-spheres.toml` under
/// the sky at 192 x 54, its four files as shipped and as copied; the measured gold's table (written to
/// `plain`), sampled and not.
fn cases(assets: &Path, plain: &Path) -> Result<Vec<Case>, Box<dyn std::error::Error>> {
    let brdfs = assets.join("brdfs");
    let plain_brdfs = plain.join("brdfs");
    std::fs::create_dir_all(&plain_brdfs)?;
    for file in ["ward.brdf", "ashikhmin_shirley.brdf", "walter_ggx.brdf", "disney.brdf"] {
        std::fs::write(plain_brdfs.join(file), without_sampler(&std::fs::read_to_string(brdfs.join(file))?)?)?;
    }
    let mut cases = Vec::new();
    for (file, params) in MATERIALS {
        let scenes =
            [sphere(&analytic(&brdfs.join(file), params))?, sphere(&analytic(&plain_brdfs.join(file), params))?];
        cases.push((file.to_string(), scenes));
    }
    let spheres = assets.join("analytic/anisotropic-spheres.toml");
    let text = std::fs::read_to_string(&spheres)? + "\n[environment]\nbuiltin = \"sky\"\n";
    let plain_spheres = plain.join("analytic/anisotropic-spheres.toml");
    std::fs::create_dir_all(plain.join("analytic"))?;
    std::fs::write(&plain_spheres, &text)?;
    let size = ["image.width=192".parse()?, "image.height=54".parse()?];
    let scenes = [Scene::parse(&text, &spheres, &size)?, Scene::parse(&text, &plain_spheres, &size)?];
    cases.push(("anisotropic-spheres.toml".to_string(), scenes));
    let gold = Vec3::new(1.0, 0.85, 0.57);
    let model =
        Brdf::CookTorrance { kd: gold, f0: gold, roughness: 0.2, metalness: 1.0, diffuse: DiffuseModel::Lambert };
    let table = MeasuredTable::tabulate(plain.join(MEASURED_GOLD), |wi, wo| model.eval(Vec3::Z, wi, wo));
    std::fs::write(&table.path, table.to_bytes())?;
    let measured =
        |sampler: bool| format!("brdf = \"measured\"\nfile = \"{}\"\nsampler = {sampler}", table.path.display());
    cases.push((format!("measured {MEASURED_GOLD}"), [sphere(&measured(true))?, sphere(&measured(false))?]));
    Ok(cases)
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
    let assets = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets");
    let plain = tempfile::tempdir()?;
    println!(
        "\nunder the sky in the exact mode (a sphere at 64 x 64, the scene at 192 x 54), to {TARGET_LEVELS} level at \
         99% of the pixels (median of {RUNS}, taking turns):"
    );
    println!("{:<24} {:>24} {:>32} {:>10}", "model", "with its sampler", "cosine and sky alone", "faster");
    for (name, scenes) in cases(&assets, plain.path())? {
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
            "{name:<24} {:>24} {:>32} {:>6}{:.1}x",
            cell(reached[0], with),
            cell(reached[1], without),
            if capped { "~" } else { "" },
            to_target(1, without) / to_target(0, with)
        );
    }
    Ok(())
}
