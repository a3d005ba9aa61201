//! `vk-render sampling`: a material's own sampler tested on the GPU (the exact mode's GLSL): Pearson's χ² per
//! view, the density's integral and support, the estimator against the albedo, and the BRDF's reciprocity
//! and energy. Exit status 0 when every test passes, 1 when one fails, 2 on bad input.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Args;

use super::{progress, SetArgs};
use vk_render::analysis::sampling::report::{views_csv, SamplingChart};
use vk_render::analysis::sampling::{
    test_sampler, views, SamplingOptions, SamplingReport, DEFAULT_LEVEL, DEFAULT_SAMPLES, DEFAULT_THETA_O, GRID,
};
use vk_render::analysis::{describe, select_materials};
use vk_render::pictures::chart::{write_chart, ChartFile};
use vk_render::pictures::output::write_file;
use vk_render::{Renderer, RendererOptions, Scene};

#[derive(Args)]
pub struct SamplingArgs {
    /// The scene file whose [material.NAME] is tested (objects and lights are not needed).
    scene: PathBuf,

    /// The material whose sampler is tested.
    #[arg(long, value_name = "NAME")]
    material: String,

    /// The view directions' angles from the normal, in degrees, 0 to below 90, separated by commas (default
    /// 0,20,40,60,75,85).
    #[arg(long, value_name = "DEGREES,...", value_delimiter = ',')]
    theta_o: Option<Vec<f64>>,

    /// Their azimuths from the tangent, in degrees, separated by commas (default: 0, and for an anisotropic
    /// model 0,45,90).
    #[arg(long, value_name = "DEGREES,...", value_delimiter = ',', allow_negative_numbers = true)]
    phi_o: Option<Vec<f64>>,

    /// Samples drawn per view (at least 1,000; at most 2^32).
    #[arg(long, value_name = "N", default_value_t = DEFAULT_SAMPLES)]
    samples: u64,

    /// The random stream's seed: the same seed draws the same samples.
    #[arg(long, default_value_t = 1)]
    seed: u32,

    /// The level α of all the tests together (Šidák's correction shares it out).
    #[arg(long, default_value_t = DEFAULT_LEVEL)]
    level: f64,

    /// Also write the report: per view the samples' histogram, the density's and their difference (.png,
    /// .svg).
    #[arg(short, long, value_name = "REPORT")]
    output: Option<PathBuf>,

    /// Also write the numbers per view (.csv).
    #[arg(long, value_name = "FILE")]
    csv: Option<PathBuf>,

    #[command(flatten)]
    set: SetArgs,
}

/// Exit status 0 when every test passes, 1 when one fails, 2 on bad input.
pub fn run(args: SamplingArgs, options: RendererOptions) -> ExitCode {
    match sampling(&args, options) {
        Ok(true) => ExitCode::SUCCESS,
        Ok(false) => ExitCode::from(1),
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::from(2)
        }
    }
}

/// The views' angles checked, before a device is opened.
fn checked_angles(theta_o: &[f64], phi_o: &[f64]) -> anyhow::Result<()> {
    if let Some(bad) = theta_o.iter().find(|t| !(t.is_finite() && (0.0..90.0).contains(*t))) {
        anyhow::bail!("--theta-o {bad}: a view's angle from the normal is from 0 to below 90 degrees");
    }
    if let Some(bad) = phi_o.iter().find(|p| !p.is_finite()) {
        anyhow::bail!("--phi-o {bad}: not an angle");
    }
    Ok(())
}

fn sampling(args: &SamplingArgs, options: RendererOptions) -> anyhow::Result<bool> {
    let scene = Scene::load(&args.scene, &args.set.overrides)?;
    let material = select_materials(&scene, Some(std::slice::from_ref(&args.material)))?.remove(0);
    let theta_o = args.theta_o.clone().unwrap_or_else(|| DEFAULT_THETA_O.to_vec());
    checked_angles(&theta_o, args.phi_o.as_deref().unwrap_or(&[]))?;
    if !(1000..=u64::from(u32::MAX)).contains(&args.samples) {
        anyhow::bail!("--samples {}: from 1000 to {}", args.samples, u32::MAX);
    }
    if !(args.level > 0.0 && args.level < 1.0) {
        anyhow::bail!("--level {}: a probability between 0 and 1", args.level);
    }
    if let Some(report) = &args.output {
        if ChartFile::for_path(report).is_none() {
            anyhow::bail!("{}: the report is a .png or .svg picture", report.display());
        }
    }
    if let Some(csv) = &args.csv {
        if !csv.extension().is_some_and(|e| e.eq_ignore_ascii_case("csv")) {
            anyhow::bail!("{}: --csv writes a .csv file", csv.display());
        }
    }
    let mut renderer = super::CommandRenderer::new(Renderer::new(options)?);
    let views = views(&mut renderer, &material.brdf, &theta_o, args.phi_o.as_deref())?;
    let sampling = SamplingOptions { views, samples: args.samples, seed: args.seed, level: args.level };
    let bar = progress(sampling.views.len(), "sampling");
    let report = test_sampler(&mut renderer, &material.brdf, &sampling, || bar.inc(1))?;
    bar.finish_and_clear();
    let title = format!("{} ({})", material.name, describe(&material.brdf));
    print(&title, &sampling, &report);
    if let Some(csv) = &args.csv {
        write_file(csv, views_csv(&report).as_bytes())?;
    }
    if let Some(path) = &args.output {
        write_chart(&SamplingChart { title: format!("Sampling test: {title}"), report: &report }, path)?;
    }
    Ok(report.passed())
}

/// The report on standard output: each test's verdict, then the failures named with their worst cells.
fn print(title: &str, options: &SamplingOptions, report: &SamplingReport) {
    println!(
        "{title}: {} samples a view, α = {} for all the tests ({:.2e} each)",
        options.samples, options.level, report.level_each
    );
    for verdict in &report.verdicts {
        let at = verdict.view.map_or(String::new(), |(t, p)| format!("θo {t}° φo {p}° "));
        let mark = if verdict.passed { "pass" } else { "FAIL" };
        println!("  {mark}  {at}{}: {}", verdict.test, verdict.detail);
    }
    let failed: Vec<_> = report.verdicts.iter().filter(|v| !v.passed).collect();
    if failed.is_empty() {
        println!("sampling: every test passed");
        return;
    }
    for view in &report.views {
        let chi_failed = failed.iter().any(|v| v.test == "chi-square" && v.view == Some((view.theta_o, view.phi_o)));
        if !chi_failed {
            continue;
        }
        println!("  worst cells at θo {}° φo {}°:", view.theta_o, view.phi_o);
        for cell in &view.worst_cells {
            let (c0, c1, p0, p1) = GRID.bounds(cell.cell);
            println!(
                "    θ {:.1}° to {:.1}°, φ {:.1}° to {:.1}°: {} samples, {:.1} expected",
                c1.acos().to_degrees(),
                c0.acos().to_degrees(),
                p0.to_degrees(),
                p1.to_degrees(),
                cell.observed,
                cell.expected
            );
        }
    }
    let names: Vec<String> = failed
        .iter()
        .map(|v| match v.view {
            Some((t, p)) => format!("{} at θo {t}° φo {p}°", v.test),
            None => v.test.to_string(),
        })
        .collect();
    println!("sampling: FAILED: {}", names.join("; "));
}
