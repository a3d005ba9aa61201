//! `vk-render fit`: the parameters of one model (or of several, ranked) that best match a material, printed
//! with their standard errors, and with `-o` the lobes overlaid; a measured material by the measure of Ngan et
//! al. 2005; a folder of MERL files as the table of every material by every model; an object's pixels in an
//! image of its scene. A model is one of the course's or a `.brdf` file (or every file of a folder).

use std::path::{Path, PathBuf};

use clap::Args;

use super::{counter, SetArgs};
use vk_render::analysis::fit::{
    fit, fit_measurement, parameters, Determined, Fit, FitModel, BASE_COLOUR_MODEL, DEFAULT_THETA_I, FIT_MODELS,
    NGAN_MAX_THETA,
};
use vk_render::analysis::image_fit::{object_of, SceneImage};
use vk_render::analysis::lobe::{lobe_angles, lobes, LobeCut};
use vk_render::analysis::{describe, rgb, select_materials, Channel, NamedBrdf};
use vk_render::brdf::{ggx_alpha, Analytic, AnalyticModel, Brdf, Measured};
use vk_render::check::report::read_image;
use vk_render::export::{export, CourseMaterial, Format, EXPORTED_MODELS};
use vk_render::pictures::chart::{write_chart, ChartFile, LineChart, LobeChart, Series, PALETTE};
use vk_render::pictures::output::write_file;
use vk_render::{Renderer, RendererOptions, Scene};

/// What `--to` takes besides a model: every model, ranked.
const ALL: &str = "all";

#[derive(Args)]
pub struct FitArgs {
    /// The scene file that defines the material, or a folder of MERL files (.binary) to fit every one of.
    #[arg(required_unless_present = "image")]
    scene: Option<PathBuf>,

    /// Fit to an image instead: an 8-bit PNG or JPEG of the scene of --scene, at its size, whose object
    /// --object is fitted from its pixels (point lights; clipped pixels and edges left out).
    #[arg(long, value_name = "IMAGE", requires_all = ["image_scene", "object"], conflicts_with = "scene")]
    image: Option<PathBuf>,

    /// With --image: the scene the image shows.
    #[arg(long = "scene", id = "image_scene", value_name = "SCENE", requires = "image")]
    image_scene: Option<PathBuf>,

    /// With --image: the object fitted, by its place among the scene's [[object]]s (from 0).
    #[arg(long, value_name = "N", requires = "image")]
    object: Option<usize>,

    /// The material to match, by its [material.NAME] (not with a folder).
    #[arg(long, value_name = "NAME")]
    material: Option<String>,

    /// The model to fit to it: one of the course's (lambert, oren-nayar, phong, blinn-phong, cook-torrance),
    /// "all" for every one of those, metallic-roughness (Cook-Torrance with one base colour, kd = f0, as glTF,
    /// Standard Surface and OpenPBR have it), a .brdf file, or a folder of .brdf files; several,
    /// comma-separated, are ranked by their residuals.
    #[arg(long, value_name = "MODEL,...", value_delimiter = ',', required = true)]
    to: Vec<String>,

    /// Parameters of a .brdf model kept at their values (the file's defaults) instead of fitted; its bools
    /// always are.
    #[arg(long, value_name = "NAME,...", value_delimiter = ',')]
    hold: Vec<String>,

    /// The incidence angles the lobes are matched over (an analytic material) or drawn at (-o), degrees
    /// from the normal, 0 to below 90.
    #[arg(long, value_name = "DEGREES,...", value_delimiter = ',', default_values_t = DEFAULT_THETA_I)]
    theta_i: Vec<f64>,

    /// A material: also draw its lobe and the fits' at each incidence angle, overlaid (.png or .svg). A
    /// folder: the table of every material by every model (.csv).
    #[arg(short, long, value_name = "OUT")]
    output: Option<PathBuf>,

    /// A folder: also draw each model's residuals over the materials, sorted (.png or .svg), as Ngan et
    /// al. 2005 show them.
    #[arg(long, value_name = "OUT")]
    chart: Option<PathBuf>,

    /// A material: also write the best fit for another renderer, in this format, to --export-to (see
    /// docs/export.md); for a format with one base colour (materialx, openpbr), metallic-roughness is fitted
    /// too where the best Cook-Torrance fit has two colours.
    #[arg(long, value_name = "FORMAT", value_parser = super::export::format_names(), requires = "export_to")]
    export: Option<String>,

    /// With --export: the file to write.
    #[arg(long, value_name = "OUT", requires = "export")]
    export_to: Option<PathBuf>,

    #[command(flatten)]
    set: SetArgs,
}

/// Fits, prints the parameters and the residuals, and draws what is asked.
pub fn run(args: FitArgs, options: RendererOptions) -> anyhow::Result<()> {
    for &theta_i in &args.theta_i {
        if !(0.0..90.0).contains(&theta_i) {
            anyhow::bail!("--theta-i {theta_i}: an incidence angle is from 0 to below 90 degrees");
        }
    }
    let models = fit_models(&args.to, &args.hold)?;
    if args.export.is_some() && !models.iter().any(|m| m.scene_model().is_some_and(|n| EXPORTED_MODELS.contains(&n))) {
        anyhow::bail!("--export: the formats take a fit to {} (add one to --to)", EXPORTED_MODELS.join(", "));
    }
    if let (Some(image), Some(scene), Some(object)) = (&args.image, &args.image_scene, args.object) {
        return run_image(&args, image, scene, object, &models, options);
    }
    let Some(scene_path) = &args.scene else {
        anyhow::bail!("fit: give a scene file, a folder of MERL files, or --image with --scene and --object");
    };
    if scene_path.is_dir() {
        return run_folder(&args, scene_path, &models, options);
    }
    if args.chart.is_some() {
        anyhow::bail!("--chart: the sorted residuals are drawn for a folder of MERL files");
    }
    let Some(material) = &args.material else {
        anyhow::bail!("--material: which [material.NAME] of {} to fit", scene_path.display());
    };
    let scene = Scene::load(scene_path, &args.set.overrides)?;
    let target = select_materials(&scene, Some(std::slice::from_ref(material)))?.remove(0);
    if let Some(output) = &args.output {
        if ChartFile::for_path(output).is_none() {
            anyhow::bail!("{}: the lobes are drawn as .png or .svg", output.display());
        }
    }
    let mut renderer = super::CommandRenderer::new(Renderer::new(options)?);
    let mut fits = Vec::new();
    for model in &models {
        fits.push((model.name(), fit_to(&mut renderer, &target.brdf, model, &args.theta_i)?));
    }
    let format = args.export.as_deref().and_then(Format::named);
    if let Some(format) = format.filter(|&format| base_colour_fit_needed(&target.name, &fits, format)) {
        println!(
            "{} has one base colour for both lobes: fitting {BASE_COLOUR_MODEL} too (Cook-Torrance with kd = f0)",
            format.title()
        );
        let base_colour = FitModel::BuiltIn(BASE_COLOUR_MODEL);
        fits.push((base_colour.name(), fit_to(&mut renderer, &target.brdf, &base_colour, &args.theta_i)?));
    }
    print_fits(&target, &fits, &args.theta_i);
    if let Some(output) = &args.output {
        draw_lobes(&mut renderer, &target, &fits, &args.theta_i, output)?;
    }
    if let (Some(format), Some(export_to)) = (format, &args.export_to) {
        // The best of the fits the format can hold (a Phong fit may rank first).
        if let Some((model, best)) = best_fit(&fits, |f| export(&target.name, &f.brdf, format).is_ok()) {
            if fits.len() > 1 {
                println!("exporting the {model} fit, the best of those {} holds", format.title());
            }
            let fitted = NamedBrdf { name: target.name.clone(), brdf: best.brdf.clone() };
            super::export::write_export(&fitted, format.name(), export_to)?;
        }
    }
    Ok(())
}

/// Whether the base colour model is to be fitted too: when the best fit of a model the formats hold is a
/// Cook-Torrance with two colours that `format` (Standard Surface, OpenPBR: one base colour) cannot hold, and
/// it was not fitted already.
fn base_colour_fit_needed(name: &str, fits: &[(String, Fit)], format: Format) -> bool {
    let Some((_, best)) = best_fit(fits, |f| CourseMaterial::of(&f.brdf).is_ok()) else { return false };
    let refused = matches!(best.brdf, Brdf::CookTorrance { .. }) && export(name, &best.brdf, format).is_err();
    refused && !fits.iter().any(|(model, _)| model == BASE_COLOUR_MODEL)
}

/// The fit of least residual among those `kept`.
fn best_fit(fits: &[(String, Fit)], kept: impl Fn(&Fit) -> bool) -> Option<&(String, Fit)> {
    fits.iter().filter(|(_, f)| kept(f)).min_by(|a, b| a.1.residual.total_cmp(&b.1.residual))
}

/// The models `--to` names (see [`FitArgs`]), each analytic one holding those of `held` it has.
fn fit_models(to: &[String], held: &[String]) -> anyhow::Result<Vec<FitModel>> {
    let mut models = Vec::new();
    let mut analytic = Vec::new();
    for name in to {
        if name == ALL {
            models.extend(FIT_MODELS.iter().filter_map(|m| FitModel::named(m)));
        } else if let Some(model) = FitModel::named(name) {
            models.push(model);
        } else if Path::new(name).is_dir() {
            analytic.extend(files_in(Path::new(name), "brdf", &format!("--to {name}"), ".brdf file")?);
        } else if name.ends_with(".brdf") {
            analytic.push(PathBuf::from(name));
        } else {
            anyhow::bail!(
                "--to {name}: not a model (expected one of {}, {ALL}, a .brdf file or a folder of them)",
                FIT_MODELS.join(", ")
            );
        }
    }
    for file in &analytic {
        let model = AnalyticModel::load(file).map_err(|e| anyhow::anyhow!("--to: {e}"))?;
        let start = Analytic::defaults(model);
        let kept: Vec<String> = held.iter().filter(|h| start.value(h).is_some()).cloned().collect();
        models.push(FitModel::analytic(start, kept).map_err(anyhow::Error::msg)?);
    }
    if let Some(missing) = held
        .iter()
        .find(|h| !models.iter().any(|m| matches!(m, FitModel::Analytic { start, .. } if start.value(h).is_some())))
    {
        let names: Vec<String> = models.iter().map(FitModel::name).collect();
        anyhow::bail!("--hold {missing}: none of the models fitted ({}) has such a parameter", names.join(", "));
    }
    Ok(models)
}

/// The files of `folder` whose extension is `extension`, sorted; an error naming the folder (`what`: how the
/// message calls it) when it cannot be read or holds none, `none` saying what it lacks.
fn files_in(folder: &Path, extension: &str, what: &str, none: &str) -> anyhow::Result<Vec<PathBuf>> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(folder)
        .map_err(|e| anyhow::anyhow!("{what}: cannot be read: {e}"))?
        .filter_map(|entry| entry.ok().map(|e| e.path()))
        .filter(|path| path.extension().and_then(|e| e.to_str()) == Some(extension))
        .collect();
    files.sort();
    if files.is_empty() {
        anyhow::bail!("{what}: holds no {none}");
    }
    Ok(files)
}

/// One fit, with a counter of the models evaluated: by Ngan et al.'s measure for a measurement, over the
/// hemisphere otherwise.
fn fit_to(renderer: &mut Renderer, target: &Brdf, model: &FitModel, theta_i: &[f64]) -> anyhow::Result<Fit> {
    let bar = counter(&model.name(), "models evaluated");
    let tried = |tried: usize| bar.set_position(tried as u64);
    let fitted = match target {
        Brdf::Measured(measured) => fit_measurement(renderer, measured, model, tried)?,
        _ => fit(renderer, target, model, theta_i, tried)?,
    };
    bar.finish_and_clear();
    Ok(fitted)
}

/// The measure's words, for the printed lines.
fn measure_words(target: &Brdf, theta_i: &[f64]) -> String {
    match target {
        Brdf::Measured(_) => format!(
            "by the measure of Ngan et al. 2005 (f_r cos theta_i over the measured entries with theta_i and \
             theta_o below {NGAN_MAX_THETA} degrees, solid-angle weighted, root mean square over red, green and \
             blue)"
        ),
        _ => {
            let angles: Vec<String> = theta_i.iter().map(f64::to_string).collect();
            format!(
                "over theta_i = {} degrees (root mean square of f_r cos theta_o over the hemispheres and red, green and blue)",
                angles.join(", ")
            )
        }
    }
}

fn print_fits(target: &NamedBrdf, fits: &[(String, Fit)], theta_i: &[f64]) {
    let relative = |fit: &Fit| 100.0 * fit.residual / fit.target_rms.max(f64::MIN_POSITIVE);
    if let [(model, fitted)] = fits {
        println!(
            "{} ({}) fitted with {model} {}:",
            target.name,
            describe(&target.brdf),
            measure_words(&target.brdf, theta_i)
        );
        for line in parameter_lines(fitted, "samples") {
            println!("{line}");
        }
        println!(
            "residual = {:.6} (the material's own: {:.6}, so {:.2}%)",
            fitted.residual,
            fitted.target_rms,
            relative(fitted)
        );
        if let (Brdf::CookTorrance { roughness, .. }, "blinn-phong" | "phong") = (&target.brdf, model.as_str()) {
            let alpha = f64::from(ggx_alpha(*roughness));
            println!(
                "Walter et al. 2007: shininess = 2 / alpha^2 - 2 = {:.1} for alpha = roughness^2 = {alpha:.4} (that \
                 mapping is Beckmann's, and Blinn-Phong's; this lobe is GGX)",
                2.0 / (alpha * alpha) - 2.0
            );
        }
        return;
    }
    println!(
        "{} ({}) fitted with {} models {}, best first:",
        target.name,
        describe(&target.brdf),
        fits.len(),
        measure_words(&target.brdf, theta_i)
    );
    let mut ranked: Vec<&(String, Fit)> = fits.iter().collect();
    ranked.sort_by(|a, b| a.1.residual.total_cmp(&b.1.residual));
    for (rank, (model, fitted)) in ranked.into_iter().enumerate() {
        let values: Vec<String> =
            parameter_values(&fitted.brdf).into_iter().map(|(n, v)| format!("{n} = {v}")).collect();
        println!(
            "{}. {model:<18} residual {:.6} ({:.2}%)  {}",
            rank + 1,
            fitted.residual,
            relative(fitted),
            values.join(", ")
        );
    }
}

/// The material's lobe and each fit's at every incidence angle, overlaid: one colour per incidence angle
/// for one fit, one per model for several.
fn draw_lobes(
    renderer: &mut Renderer,
    target: &NamedBrdf,
    fits: &[(String, Fit)],
    theta_i: &[f64],
    output: &Path,
) -> anyhow::Result<()> {
    let angles = lobe_angles();
    let mut series = Vec::new();
    let mut incident = Vec::new();
    let several = fits.len() > 1;
    for (k, &theta) in theta_i.iter().enumerate() {
        let cut = LobeCut { theta_i: theta, phi: 0.0, cosine: true };
        let brdfs: Vec<Brdf> =
            std::iter::once(target.brdf.clone()).chain(fits.iter().map(|(_, f)| f.brdf.clone())).collect();
        let values = lobes(renderer, &brdfs, &cut)?;
        let angle_colour = PALETTE[k % PALETTE.len()];
        incident.push((theta, if several { plotters::style::BLACK } else { angle_colour }));
        let labels = std::iter::once(target.name.as_str()).chain(fits.iter().map(|(m, _)| m.as_str()));
        for (index, (values, label)) in values.into_iter().zip(labels).enumerate() {
            let colour = match (several, index) {
                (true, 0) => plotters::style::BLACK,
                (true, _) => PALETTE[(index - 1) % PALETTE.len()],
                (false, _) => angle_colour,
            };
            let fitted = index > 0;
            // With several incidence angles and models, the legend names each model once.
            let label = match (several, k) {
                (true, 0) | (false, _) => format!("{label}{}, θi {theta}°", if fitted { " (fit)" } else { "" }),
                (true, _) => String::new(),
            };
            series.push(Series {
                label,
                colour,
                points: angles.iter().zip(values).map(|(&a, f)| (a, Channel::Luminance.of(rgb(f)))).collect(),
                dashed: fitted,
            });
        }
    }
    let models: Vec<&str> = fits.iter().map(|(m, _)| m.as_str()).collect();
    let chart = LobeChart {
        title: format!(
            "{} and its {} fit{} (dashed): f_r cos θo, plane of incidence",
            target.name,
            models.join(", "),
            if several { "s" } else { "" }
        ),
        quantity: "f_r cos θo (luminance)".into(),
        series,
        incident,
    };
    write_chart(&chart, output)?;
    Ok(())
}

/// Every MERL file of a folder fitted with every model: printed as each is done, then the CSV table and the
/// sorted residuals' chart.
fn run_folder(args: &FitArgs, folder: &Path, models: &[FitModel], options: RendererOptions) -> anyhow::Result<()> {
    if args.material.is_some() {
        anyhow::bail!("--material: a folder's materials are its MERL files, every one fitted");
    }
    if args.export.is_some() {
        anyhow::bail!("--export: one material's fit is exported, not a folder's (fit each file's scene)");
    }
    if let Some(output) = &args.output {
        if output.extension().and_then(|e| e.to_str()) != Some("csv") {
            anyhow::bail!("{}: a folder's table is written as .csv", output.display());
        }
    }
    if let Some(chart) = &args.chart {
        if ChartFile::for_path(chart).is_none() {
            anyhow::bail!("{}: the residuals are drawn as .png or .svg", chart.display());
        }
    }
    let files = files_in(folder, "binary", &folder.display().to_string(), "MERL file (NAME.binary)")?;
    let mut renderer = super::CommandRenderer::new(Renderer::new(options)?);
    let mut table: Vec<(String, Vec<f64>)> = Vec::new();
    for file in &files {
        let name = file.file_stem().map_or_else(String::new, |s| s.to_string_lossy().into_owned());
        let measured = Measured::load(file).map_err(|e| anyhow::anyhow!("{e}"))?;
        let mut residuals = Vec::new();
        for model in models {
            let fitted = fit_to(&mut renderer, &Brdf::Measured(measured.clone()), model, &args.theta_i)?;
            residuals.push(fitted.residual);
        }
        let cells: Vec<String> = models.iter().zip(&residuals).map(|(m, r)| format!("{} {r:.6}", m.name())).collect();
        println!("{name}: {}", cells.join(", "));
        table.push((name, residuals));
    }
    let names: Vec<String> = models.iter().map(FitModel::name).collect();
    if let Some(output) = &args.output {
        let mut csv = format!("material,{}\n", names.join(","));
        for (name, residuals) in &table {
            let cells: Vec<String> = residuals.iter().map(f64::to_string).collect();
            csv.push_str(&format!("{name},{}\n", cells.join(",")));
        }
        write_file(output, csv.as_bytes())?;
    }
    if let Some(chart) = &args.chart {
        write_chart(&sorted_residuals(&names, &table), chart)?;
    }
    Ok(())
}

/// Each model's residuals over the materials, sorted, on a log scale (Ngan et al. 2005's figure of the
/// fitting errors).
fn sorted_residuals(models: &[String], table: &[(String, Vec<f64>)]) -> LineChart {
    let series: Vec<Series> = models
        .iter()
        .enumerate()
        .map(|(k, model)| {
            let mut residuals: Vec<f64> = table.iter().map(|(_, r)| r[k].max(1e-12).log10()).collect();
            residuals.sort_by(f64::total_cmp);
            Series {
                label: model.clone(),
                colour: PALETTE[k % PALETTE.len()],
                points: residuals.into_iter().enumerate().map(|(i, r)| ((i + 1) as f64, r)).collect(),
                dashed: false,
            }
        })
        .collect();
    let values: Vec<f64> = series.iter().flat_map(|s| s.points.iter().map(|p| p.1)).collect();
    let (low, high) = values.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &v| (l.min(v), h.max(v)));
    LineChart {
        title: format!("Fitting residuals of {} materials, each model's sorted", table.len()),
        x_label: "material, by rank".into(),
        y_label: "log10 E (Ngan et al. 2005)".into(),
        x_range: (1.0, table.len().max(2) as f64),
        y_range: (low.floor(), high.ceil().max(low.floor() + 1.0)),
        series,
        horizontal_rules: Vec::new(),
        size: (900, 560),
    }
}

/// An object's pixels in an image fitted with each model: the parameters with their standard errors, and the
/// residuals in levels (ranked for several models).
fn run_image(
    args: &FitArgs,
    image_path: &Path,
    scene_path: &Path,
    object: usize,
    models: &[FitModel],
    options: RendererOptions,
) -> anyhow::Result<()> {
    if args.material.is_some() || args.output.is_some() || args.chart.is_some() || args.export.is_some() {
        anyhow::bail!(
            "--image: the object's own material is fitted, and nothing is drawn or exported (no --material, -o, \
             --chart or --export)"
        );
    }
    let scene = Scene::load(scene_path, &args.set.overrides)?;
    let target = object_of(&scene, object)?;
    let image = read_image(image_path)?;
    let mut renderer = super::CommandRenderer::new(Renderer::new(options)?);
    let image = SceneImage::new(&scene, &image, image_path)?;
    let mut fits = Vec::new();
    for model in models {
        let bar = counter(&model.name(), "models evaluated");
        let fitted = image.fit(&mut renderer, object, model, |t| bar.set_position(t as u64))?;
        bar.finish_and_clear();
        fits.push((model.name(), fitted));
    }
    fits.sort_by(|a, b| a.1.residual_levels.total_cmp(&b.1.residual_levels));
    for (rank, (model, fitted)) in fits.iter().enumerate() {
        let heading = if fits.len() > 1 { format!("{}. ", rank + 1) } else { String::new() };
        println!(
            "{heading}object {object} ({}, material {}) of {} fitted with {model} over {} pixels:",
            target.shape.kind(),
            target.material,
            image_path.display(),
            fitted.pixels
        );
        for line in parameter_lines(&fitted.fit, "pixels") {
            println!("{line}");
        }
        println!(
            "residual = {:.2} levels (root mean square over the pixels' channels; the scene's own {}: {:.2})",
            fitted.residual_levels,
            describe(&target.brdf),
            fitted.scene_levels
        );
    }
    Ok(())
}

/// `name = value ± error`, colours as `[r, g, b] ± [er, eg, eb]`, each value to the digits its error
/// allows (two of the error's, at most the six significant digits an f32 fit holds and six decimals);
/// "(? : not determined by these SAMPLES)" for an error there is none of.
fn determined_line(parameter: &Determined, samples: &str) -> String {
    let shown = |value: f32, error: Option<f64>| {
        let magnitude = if value == 0.0 { 0 } else { f64::from(value.abs()).log10().floor() as i32 };
        let most = (5 - magnitude).clamp(0, 6);
        match error {
            Some(error) => {
                let decimals = if error > 0.0 { (1 - error.log10().floor() as i32).min(most) } else { most };
                let decimals = decimals.max(0) as usize;
                (format!("{value:.decimals$}"), format!("{error:.decimals$}"))
            }
            None => (value.to_string(), "?".into()),
        }
    };
    let pairs: Vec<(String, String)> =
        parameter.values.iter().zip(&parameter.errors).map(|(&v, &e)| shown(v, e)).collect();
    let undetermined = parameter.errors.iter().any(Option::is_none);
    let note = if undetermined { format!(" (? : not determined by these {samples})") } else { String::new() };
    if let [(value, error)] = &pairs[..] {
        return format!("{} = {value} ± {error}{note}", parameter.name);
    }
    let values: Vec<&str> = pairs.iter().map(|p| p.0.as_str()).collect();
    let errors: Vec<&str> = pairs.iter().map(|p| p.1.as_str()).collect();
    format!("{} = [{}] ± [{}]{note}", parameter.name, values.join(", "), errors.join(", "))
}

/// A fit's parameters, one line each: those it determined with their errors ([`determined_line`]), those it
/// held (an analytic model's) as they were.
fn parameter_lines(fitted: &Fit, samples: &str) -> Vec<String> {
    let mut lines: Vec<String> = parameter_values(&fitted.brdf)
        .into_iter()
        .map(|(name, value)| match fitted.parameters.iter().find(|p| p.name == name) {
            Some(determined) => determined_line(determined, samples),
            None => format!("{name} = {value} (held)"),
        })
        .collect();
    if let Brdf::Analytic(material) = &fitted.brdf {
        let bools = material.values().filter(|(p, _)| matches!(p.kind, vk_render::brdf::ParameterKind::Bool { .. }));
        lines.extend(bools.map(|(p, v)| format!("{} = {v} (held)", p.name)));
    }
    lines
}

/// The model's parameters as `name = value` lines would name them.
fn parameter_values(brdf: &Brdf) -> Vec<(String, String)> {
    if let Brdf::Measured(table) = brdf {
        return vec![("file".into(), format!("{:?}", table.path().display().to_string()))];
    }
    parameters(brdf)
        .into_iter()
        .map(|(name, values)| {
            let shown: Vec<String> = values.iter().map(f32::to_string).collect();
            (name, if let [one] = &shown[..] { one.clone() } else { format!("[{}]", shown.join(", ")) })
        })
        .collect()
}
