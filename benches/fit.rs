//! The fit of a `.brdf` model against the course's Cook-Torrance fit, on the same measured material, in one
//! run: a copy of a copper-like Cook-Torrance material tabulated as a MERL table in memory (as `vk-render
//! tabulate` writes it), fitted by Ngan et al.'s measure with the built-in Cook-Torrance (one parameter searched,
//! three colours solved) and with `assets/brdfs/ward.brdf` (four parameters: two widths searched, two colours
//! solved), the two taking turns, each the median of its runs. The mark: the Ward fit within twice the
//! Cook-Torrance one. Run with `cargo bench --bench fit` (`make bench-fit`).

use std::path::Path;
use std::time::{Duration, Instant};

use glam::Vec3;
use vk_render::analysis::fit::{fit_measurement, FitModel};
use vk_render::brdf::{Analytic, AnalyticModel, Brdf, DiffuseModel, Measured, MeasuredTable};
use vk_render::{Renderer, RendererOptions};

const RUNS: usize = 3;

fn median(mut samples: Vec<Duration>) -> Duration {
    samples.sort();
    samples[samples.len() / 2]
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut renderer = Renderer::new(RendererOptions::default())?;
    println!("device: {}", renderer.device_info().name);
    let copper = Brdf::CookTorrance {
        kd: Vec3::new(0.5, 0.35, 0.3),
        f0: Vec3::new(0.95, 0.64, 0.54),
        roughness: 0.4,
        metalness: 0.5,
        diffuse: DiffuseModel::OrenNayar,
    };
    let table = MeasuredTable::tabulate("copper.binary".into(), |wi, wo| copper.eval(Vec3::Z, wi, wo));
    let measured = Measured::from_table(table);
    let ward_file = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/brdfs/ward.brdf");
    let ward = AnalyticModel::load(&ward_file)?;
    let models = [
        ("cook-torrance (built-in)", FitModel::named("cook-torrance").ok_or("no cook-torrance")?),
        ("ward.brdf (4 parameters)", FitModel::analytic(Analytic::defaults(ward), Vec::new())?),
    ];
    // One untimed fit of each builds its pipelines.
    for (_, model) in &models {
        fit_measurement(&mut renderer, &measured, model, |_| {})?;
    }
    let mut samples = vec![Vec::new(); models.len()];
    let mut residuals = vec![0.0; models.len()];
    for _ in 0..RUNS {
        for (k, (_, model)) in models.iter().enumerate() {
            let start = Instant::now();
            let mut evaluated = 0;
            let fitted = fit_measurement(&mut renderer, &measured, model, |n| evaluated = n)?;
            samples[k].push(start.elapsed());
            residuals[k] = fitted.residual;
        }
    }
    let medians: Vec<Duration> = samples.into_iter().map(median).collect();
    println!("\na copper-like Cook-Torrance copy, fitted by Ngan et al.'s measure (median of {RUNS}, taking turns):");
    for ((name, _), (median, residual)) in models.iter().zip(medians.iter().zip(&residuals)) {
        println!("{name:<28} {:>8.2} s   residual {residual:.6}", median.as_secs_f64());
    }
    let ratio = medians[1].as_secs_f64() / medians[0].as_secs_f64();
    let verdict = if ratio <= 2.0 { "met" } else { "MISSED" };
    println!("ward.brdf / cook-torrance {ratio:>13.2}x   (mark: at most 2x: {verdict})");
    Ok(())
}
