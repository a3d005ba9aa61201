//! `vk-render plot`: lobes and directional albedos of a scene's materials, as pictures (.png, .svg) or
//! numbers (.csv), computed on the GPU by the probe pass.

use clap::{Args, Subcommand, ValueEnum};

use super::{StudyArgs, StudyFile};
use vk_render::analysis::albedo::{albedo_angles, directional_albedos, ALBEDO_TOLERANCE};
use vk_render::analysis::lobe::{lobe_angles, lobes, LobeCut};
use vk_render::analysis::{angle_table, describe, rgb, Channel};
use vk_render::chart::{value_range, write_chart, LineChart, LobeChart, Series, PALETTE};
use vk_render::output::write_file;
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

/// Runs the plot asked for.
pub fn run(args: PlotArgs, options: RendererOptions) -> anyhow::Result<()> {
    match args.plot {
        Plot::Lobe(args) => lobe(args, options),
        Plot::Albedo(args) => albedo(args, options),
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
    let mut renderer = Renderer::new(options)?;
    let brdfs: Vec<_> = materials.iter().map(|m| m.brdf).collect();
    let angles = lobe_angles();
    let cut = |theta_i| LobeCut { theta_i, phi: args.phi, cosine: !args.no_cosine };
    let quantity = if args.no_cosine { "f_r" } else { "f_r cos θo" };
    if file == StudyFile::Csv {
        let values = lobes(&mut renderer, &brdfs, &cut(args.theta_i[0]))?;
        let series: Vec<_> = materials
            .iter()
            .zip(values)
            .map(|(m, lobe)| (m.name.clone(), lobe.into_iter().map(rgb).collect()))
            .collect();
        write_file(&args.study.output, angle_table("theta_o", &angles, &series).as_bytes())?;
        return Ok(());
    }
    let channel = Channel::from(args.channel);
    let mut series = Vec::new();
    let mut incident = Vec::new();
    for (k, &theta_i) in args.theta_i.iter().enumerate() {
        let values = lobes(&mut renderer, &brdfs, &cut(theta_i))?;
        for (m, (material, lobe)) in materials.iter().zip(values).enumerate() {
            let colour = PALETTE[(k * materials.len() + m) % PALETTE.len()];
            if m == 0 {
                incident.push((theta_i, colour));
            }
            let shown = |v: f64| if args.log { (1.0 + v).log10() } else { v };
            series.push(Series {
                label: format!("{}: {}, θi {theta_i}°", material.name, describe(&material.brdf)),
                colour,
                points: angles.iter().zip(lobe).map(|(&a, f)| (a, shown(channel.of(rgb(f))))).collect(),
                dashed: false,
            });
        }
    }
    let plane = if args.phi == 0.0 { "plane of incidence".to_string() } else { format!("cut at φ = {}°", args.phi) };
    let quantity = if args.log { format!("log10(1 + {quantity})") } else { quantity.to_string() };
    let chart = LobeChart {
        title: format!("Lobes: {quantity}, {plane}, {}", channel.name()),
        quantity: format!("{quantity} ({})", channel.name()),
        series,
        incident,
    };
    write_chart(&chart, &args.study.output)?;
    Ok(())
}

fn albedo(args: AlbedoArgs, options: RendererOptions) -> anyhow::Result<()> {
    let materials = args.study.materials()?;
    let file = args.study.output_file()?;
    let mut renderer = Renderer::new(options)?;
    let angles = albedo_angles();
    let radians: Vec<f64> = angles.iter().map(|a| a.to_radians()).collect();
    let mut curves = Vec::new();
    let mut bound = 0.0f64;
    for material in &materials {
        let albedos = directional_albedos(&mut renderer, &material.brdf, &radians, ALBEDO_TOLERANCE)?;
        bound = albedos.iter().fold(bound, |b, a| b.max(a.error_bound));
        curves.push(albedos.iter().map(|a| a.rho).collect::<Vec<_>>());
    }
    println!(
        "directional albedo of {} material(s) at {} angles from 0 to 89.9 degrees, each within {bound:.1e} \
         (asked: {ALBEDO_TOLERANCE:.0e}; adaptive Gauss-Kronrod cubature on the GPU)",
        materials.len(),
        angles.len()
    );
    if file == StudyFile::Csv {
        let series: Vec<_> = materials.iter().map(|m| m.name.clone()).zip(curves).collect();
        write_file(&args.study.output, angle_table("theta_o", &angles, &series).as_bytes())?;
        return Ok(());
    }
    let channel = Channel::from(args.channel);
    let series: Vec<Series> = materials
        .iter()
        .zip(&curves)
        .enumerate()
        .map(|(k, (material, curve))| Series {
            label: format!("{}: {}", material.name, describe(&material.brdf)),
            colour: PALETTE[k % PALETTE.len()],
            points: angles.iter().zip(curve).map(|(&a, &rho)| (a, channel.of(rho))).collect(),
            dashed: false,
        })
        .collect();
    let y_range = value_range(series.iter().flat_map(|s| s.points.iter().map(|p| &p.1)).chain([&1.0]));
    let chart = LineChart {
        title: format!("Directional albedo ρ(θo) = ∫ f_r cos θi dωi ({}, error ≤ {bound:.0e})", channel.name()),
        x_label: "θo (degrees)".into(),
        y_label: format!("ρ ({})", channel.name()),
        x_range: (0.0, 90.0),
        y_range,
        series,
        horizontal_rules: vec![1.0],
        size: (1100, 620),
    };
    write_chart(&chart, &args.study.output)?;
    Ok(())
}
