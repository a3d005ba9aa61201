//! `vk-render plot`: lobes, directional albedos and image slices of a scene's materials, as pictures (.png, .svg) or
//! numbers (.csv), computed on the GPU by the probe pass.

use clap::{Args, Subcommand, ValueEnum};
use glam::Vec3;

use super::{progress, StudyArgs, StudyFile};
use vk_render::analysis::albedo::{albedo_angles, directional_albedos, ALBEDO_TOLERANCE};
use vk_render::analysis::lobe::{lobe_angles, lobes, LobeCut};
use vk_render::analysis::lobe3d::{lobe_scene, Viewpoint};
use vk_render::analysis::plots::{albedo_chart, albedo_table, lobe_chart, lobe_table, LobeStyle};
use vk_render::analysis::slice::{slices, Slice};
use vk_render::analysis::{describe, rgb, Channel, NamedBrdf};
use vk_render::pictures::chart::{value_range, write_chart, ChartFile, HeatMap, HeatMapChart};
use vk_render::pictures::output::write_png;
use vk_render::pictures::report::side_by_side;
use vk_render::{Renderer, RendererOptions};

#[derive(Args)]
pub struct PlotArgs {
    #[command(subcommand)]
    plot: Plot,
}

#[derive(Subcommand)]
enum Plot {
    /// f_r(wi, wo) cos(theta_o) in the plane of incidence, polar and against theta_o, materials and incidence
    /// angles overlaid (BRDF Explorer's lobe plots). A CSV holds the first incidence angle.
    Lobe(LobeArgs),
    /// Directional albedo rho(theta_o) = integral of f_r cos(theta_i) over the hemisphere, every degree,
    /// integrated on the GPU to a stated accuracy.
    Albedo(AlbedoArgs),
    /// BRDF Explorer's 3D lobe, rendered by vk-render's Vulkan pipeline: the lobe as a mesh whose radius in
    /// each direction is f_r cos(theta_o), with wi, the normal and the mirror direction as arrows (PNG).
    Lobe3d(Lobe3dArgs),
    /// BRDF Explorer's image slice: f_r over theta_h (x) and theta_d (y) at a fixed phi_d, in false colour
    /// with a colour bar. A CSV holds theta_h, theta_d, then three columns per material, every degree.
    Slice(SliceArgs),
}

/// The channel a picture shows (a CSV has all three).
#[derive(Clone, Copy, ValueEnum)]
enum ChannelArg {
    R,
    G,
    B,
    Luminance,
}

impl From<ChannelArg> for Channel {
    fn from(channel: ChannelArg) -> Self {
        match channel {
            ChannelArg::R => Channel::Red,
            ChannelArg::G => Channel::Green,
            ChannelArg::B => Channel::Blue,
            ChannelArg::Luminance => Channel::Luminance,
        }
    }
}

#[derive(Args)]
struct LobeArgs {
    #[command(flatten)]
    study: StudyArgs,

    /// Incidence angles in degrees from the normal, 0 to below 90, separated by commas.
    #[arg(long, value_name = "DEGREES,...", value_delimiter = ',', required = true)]
    theta_i: Vec<f64>,

    /// The cut's turn about the normal from the plane of incidence, in degrees (an out-of-plane cut).
    #[arg(long, value_name = "DEGREES", default_value_t = 0.0, allow_negative_numbers = true)]
    phi: f64,

    /// Plot f_r alone, without cos(theta_o) (the CSV too).
    #[arg(long)]
    no_cosine: bool,

    /// Plot log10(1 + x) (the CSV keeps the values).
    #[arg(long)]
    log: bool,

    /// The channel the picture shows.
    #[arg(long, value_enum, default_value = "luminance")]
    channel: ChannelArg,
}

#[derive(Args)]
struct AlbedoArgs {
    #[command(flatten)]
    study: StudyArgs,

    /// The channel the picture shows.
    #[arg(long, value_enum, default_value = "luminance")]
    channel: ChannelArg,
}

#[derive(Args)]
struct SliceArgs {
    #[command(flatten)]
    study: StudyArgs,

    /// The difference vector's azimuth phi_d in degrees (90: BRDF Explorer's default).
    #[arg(long, value_name = "DEGREES", default_value_t = 90.0, allow_negative_numbers = true)]
    phi_d: f64,

    /// Colour log10(1 + f_r) (the CSV keeps the values).
    #[arg(long)]
    log: bool,

    /// The channel the picture shows.
    #[arg(long, value_enum, default_value = "luminance")]
    channel: ChannelArg,
}

#[derive(Args)]
struct Lobe3dArgs {
    #[command(flatten)]
    study: StudyArgs,

    /// The incidence angle in degrees from the normal, 0 to below 90.
    #[arg(long, value_name = "DEGREES", default_value_t = 30.0)]
    theta_i: f32,

    /// Where the lobe is seen from: degrees above the surface, then degrees round the normal from the front
    /// of the plane of incidence.
    #[arg(long, value_name = "ELEVATION,AZIMUTH", value_delimiter = ',', num_args = 1, default_values_t = [25.0, 30.0], allow_negative_numbers = true)]
    from: Vec<f32>,

    /// Each panel's width and height in pixels.
    #[arg(long, value_name = "WIDTH,HEIGHT", value_delimiter = ',', default_values_t = [640, 480])]
    size: Vec<u32>,
}

/// Runs the plot asked for.
pub fn run(args: PlotArgs, options: RendererOptions) -> anyhow::Result<()> {
    match args.plot {
        Plot::Lobe(args) => lobe(args, options),
        Plot::Albedo(args) => albedo(args, options),
        Plot::Slice(args) => slice(args, options),
        Plot::Lobe3d(args) => lobe3d(args, options),
    }
}

fn lobe(args: LobeArgs, options: RendererOptions) -> anyhow::Result<()> {
    let materials = args.study.materials()?;
    let file = args.study.output_file()?;
    for &theta_i in &args.theta_i {
        if !(0.0..90.0).contains(&theta_i) {
            anyhow::bail!("--theta-i {theta_i}: an incidence angle is from 0 to below 90 degrees");
        }
    }
    if !args.phi.is_finite() {
        anyhow::bail!("--phi {}: not a number of degrees", args.phi);
    }
    let mut renderer = super::CommandRenderer::new(Renderer::new(options)?);
    let brdfs: Vec<_> = materials.iter().map(|m| m.brdf.clone()).collect();
    let angles = lobe_angles();
    let cuts: Vec<LobeCut> =
        args.theta_i.iter().map(|&theta_i| LobeCut { theta_i, phi: args.phi, cosine: !args.no_cosine }).collect();
    let values = cuts.iter().map(|cut| lobes(&mut renderer, &brdfs, cut)).collect::<Result<Vec<_>, _>>()?;
    let csv = lobe_table(&materials, &angles, &values[0]);
    if file == StudyFile::Csv {
        return args.study.write(&csv, |_| Ok(()));
    }
    let chart =
        lobe_chart(&materials, &cuts, &angles, &values, LobeStyle { channel: args.channel.into(), log: args.log });
    args.study.write(&csv, |path| write_chart(&chart, path))
}

fn albedo(args: AlbedoArgs, options: RendererOptions) -> anyhow::Result<()> {
    let materials = args.study.materials()?;
    let file = args.study.output_file()?;
    let mut renderer = super::CommandRenderer::new(Renderer::new(options)?);
    let angles = albedo_angles();
    let radians: Vec<f64> = angles.iter().map(|a| a.to_radians()).collect();
    let mut curves = Vec::new();
    let mut bound = 0.0f64;
    let bar = progress(materials.len(), "albedo");
    for material in &materials {
        let albedos = directional_albedos(&mut renderer, &material.brdf, &radians, ALBEDO_TOLERANCE)?;
        bar.inc(1);
        bound = albedos.iter().fold(bound, |b, a| b.max(a.error_bound));
        curves.push(albedos);
    }
    bar.finish_and_clear();
    println!(
        "directional albedo of {} material(s) at {} angles from 0 to 89.9 degrees, each within {bound:.1e} \
         (asked: {ALBEDO_TOLERANCE:.0e}; adaptive Gauss-Kronrod cubature on the GPU)",
        materials.len(),
        angles.len()
    );
    let csv = albedo_table(&materials, &angles, &curves);
    if file == StudyFile::Csv {
        return args.study.write(&csv, |_| Ok(()));
    }
    let chart = albedo_chart(&materials, &angles, &curves, bound, args.channel.into());
    args.study.write(&csv, |path| write_chart(&chart, path))
}

fn slice(args: SliceArgs, options: RendererOptions) -> anyhow::Result<()> {
    let materials = args.study.materials()?;
    let file = args.study.output_file()?;
    if !args.phi_d.is_finite() {
        anyhow::bail!("--phi-d {}: not a number of degrees", args.phi_d);
    }
    // A cell per pixel of a PNG panel; a cell per degree in a CSV, and in an SVG (a rectangle each).
    let mut renderer = super::CommandRenderer::new(Renderer::new(options)?);
    let brdfs: Vec<_> = materials.iter().map(|m| m.brdf.clone()).collect();
    let csv = slice_table(&materials, &slices(&mut renderer, &brdfs, args.phi_d, CSV_CELLS)?);
    if file == StudyFile::Csv {
        return args.study.write(&csv, |_| Ok(()));
    }
    let cells = if file == StudyFile::Chart(ChartFile::Png) { 360 } else { CSV_CELLS };
    let slices = slices(&mut renderer, &brdfs, args.phi_d, cells)?;
    let channel = Channel::from(args.channel);
    let shown = |f: Vec3| {
        let v = channel.of(rgb(f));
        if args.log {
            (1.0 + v).log10()
        } else {
            v
        }
    };
    let panels: Vec<HeatMap> = materials
        .iter()
        .zip(&slices)
        .map(|(material, slice)| HeatMap {
            label: format!("{}: {}", material.name, describe(&material.brdf)),
            cells,
            values: slice.values.iter().map(|f| f.map(shown)).collect(),
        })
        .collect();
    // The colours span the values up to their 99.5th percentile, so that a few extreme ones (the course's
    // Phong divides by cos(theta_i) near grazing) do not leave the rest in one colour; above it, the top one.
    let mut values: Vec<f64> = panels.iter().flat_map(|p| p.values.iter().flatten().copied()).collect();
    values.sort_by(f64::total_cmp);
    let clip = values.get(values.len() * 995 / 1000).copied().unwrap_or(0.0);
    let clipped = values.last().is_some_and(|&top| top > clip * 1.01);
    let range = value_range(values.iter().filter(|&&v| v <= clip));
    let quantity = if args.log { "log10(1 + f_r)" } else { "f_r" };
    let chart = HeatMapChart {
        title: format!("Image slice: {quantity} ({}) at φd = {}°; grey: below the horizon", channel.name(), args.phi_d),
        x_label: "θh (degrees)".into(),
        y_label: "θd (degrees)".into(),
        quantity: format!("{quantity} ({}){}", channel.name(), if clipped { ", top 0.5% clipped" } else { "" }),
        panels,
        range,
    };
    args.study.write(&csv, |path| write_chart(&chart, path))
}

/// A slice's cells in a CSV (and an SVG): one a degree.
const CSV_CELLS: usize = 90;

/// The slices as a CSV: theta_h, theta_d, then three columns per material; 0 below the horizon.
fn slice_table(materials: &[NamedBrdf], slices: &[Slice]) -> String {
    let mut csv = String::from("theta_h,theta_d");
    for material in materials {
        let name = &material.name;
        csv.push_str(&format!(",{name}_r,{name}_g,{name}_b"));
    }
    csv.push('\n');
    let cells = slices[0].cells;
    for k in 0..cells * cells {
        csv.push_str(&format!("{},{}", slices[0].angle(k % cells), slices[0].angle(k / cells)));
        for slice in slices {
            let [r, g, b] = slice.values[k].map_or([0.0; 3], rgb);
            csv.push_str(&format!(",{r},{g},{b}"));
        }
        csv.push('\n');
    }
    csv
}

fn lobe3d(args: Lobe3dArgs, options: RendererOptions) -> anyhow::Result<()> {
    let materials = args.study.materials()?;
    if args.study.output_file()? != StudyFile::Chart(ChartFile::Png) {
        anyhow::bail!("{}: a 3D lobe is rendered, to a .png image", args.study.output.display());
    }
    if !(0.0..90.0).contains(&args.theta_i) {
        anyhow::bail!("--theta-i {}: an incidence angle is from 0 to below 90 degrees", args.theta_i);
    }
    let (&[elevation, azimuth], &[width, height]) = (args.from.as_slice(), args.size.as_slice()) else {
        anyhow::bail!("--from takes ELEVATION,AZIMUTH and --size WIDTH,HEIGHT: two numbers each");
    };
    if !(elevation.is_finite() && azimuth.is_finite() && (-90.0..=90.0).contains(&elevation)) {
        anyhow::bail!("--from {elevation},{azimuth}: the elevation is from -90 to 90 degrees, the azimuth a number");
    }
    if !(16..=4096).contains(&width) || !(16..=4096).contains(&height) {
        anyhow::bail!("--size {width},{height}: each side is from 16 to 4096 pixels");
    }
    let mut renderer = super::CommandRenderer::new(Renderer::new(options)?);
    let from = Viewpoint { elevation, azimuth };
    let mut panels = Vec::new();
    for material in &materials {
        let scene = lobe_scene(&mut renderer, material, args.theta_i, from, (width, height), &args.study.scene)?;
        panels.push((format!("{}: {}", material.name, describe(&material.brdf)), renderer.render_rgb8(&scene)?));
    }
    let title = format!(
        "f_r cos θo (luminance) at θi = {}°, each lobe to its own scale, seen from {elevation}° above and {azimuth}° round: blue the lobe, \
         yellow wi, white n, red the mirror direction",
        args.theta_i
    );
    write_png(&side_by_side(&title, &panels, None), &args.study.output)?;
    Ok(())
}
