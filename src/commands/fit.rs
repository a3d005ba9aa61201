//! `vk-render fit`: the parameters of one model that best match a material's lobe, printed, and with `-o` the
//! lobes overlaid.

use std::path::PathBuf;

use clap::Args;

use super::{progress, SetArgs};
use vk_render::analysis::fit::{fit, DEFAULT_THETA_I, FIT_MODELS, FIT_STEPS};
use vk_render::analysis::lobe::{lobe_angles, lobes, LobeCut};
use vk_render::analysis::{describe, rgb, select_materials, Channel};
use vk_render::brdf::Brdf;
use vk_render::chart::{write_chart, ChartFile, LobeChart, Series, PALETTE};
use vk_render::{Renderer, RendererOptions, Scene};

#[derive(Args)]
pub struct FitArgs {
    /// The scene file that defines the material.
    scene: PathBuf,

    /// The material to match, by its [material.NAME].
    #[arg(long, value_name = "NAME")]
    material: String,

    /// The model to fit to it.
    #[arg(long, value_name = "MODEL", value_parser = clap::builder::PossibleValuesParser::new(FIT_MODELS))]
    to: String,

    /// The incidence angles the lobes are matched over, degrees from the normal, 0 to below 90.
    #[arg(long, value_name = "DEGREES,...", value_delimiter = ',', default_values_t = DEFAULT_THETA_I)]
    theta_i: Vec<f64>,

    /// Also draw both lobes at each incidence angle, overlaid: .png or .svg.
    #[arg(short, long, value_name = "OUT")]
    output: Option<PathBuf>,

    #[command(flatten)]
    set: SetArgs,
}

/// Fits, prints the parameters and the residual, and draws the lobes if asked.
pub fn run(args: FitArgs, options: RendererOptions) -> anyhow::Result<()> {
    let scene = Scene::load(&args.scene, &args.set.overrides)?;
    let target = select_materials(&scene, Some(std::slice::from_ref(&args.material)))?.remove(0);
    for &theta_i in &args.theta_i {
        if !(0.0..90.0).contains(&theta_i) {
            anyhow::bail!("--theta-i {theta_i}: an incidence angle is from 0 to below 90 degrees");
        }
    }
    if let Some(output) = &args.output {
        if ChartFile::for_path(output).is_none() {
            anyhow::bail!("{}: the lobes are drawn as .png or .svg", output.display());
        }
    }
    let mut renderer = Renderer::new(options)?;
    let bar = progress(FIT_STEPS, "fit");
    let fitted = fit(&mut renderer, &target.brdf, &args.to, &args.theta_i, |tried| bar.set_position(tried as u64))?;
    bar.finish_and_clear();
    let Some(fitted) = fitted else {
        anyhow::bail!("--to {}: not a model (expected one of {})", args.to, FIT_MODELS.join(", "));
    };
    let angles: Vec<String> = args.theta_i.iter().map(f64::to_string).collect();
    println!(
        "{} ({}) fitted with {} over theta_i = {} degrees:",
        target.name,
        describe(&target.brdf),
        args.to,
        angles.join(", ")
    );
    for (name, value) in parameters(&fitted.brdf) {
        println!("{name} = {value}");
    }
    println!(
        "residual = {:.6} (root mean square of f_r cos theta_o over the hemispheres, luminance; the material's own: \
         {:.6}, so {:.2}%)",
        fitted.residual,
        fitted.target_rms,
        100.0 * fitted.residual / fitted.target_rms.max(f64::MIN_POSITIVE)
    );
    if let (Brdf::CookTorrance { roughness, .. }, "blinn-phong" | "phong") = (&target.brdf, args.to.as_str()) {
        let alpha = f64::from(*roughness * *roughness);
        println!(
            "Walter et al. 2007: shininess = 2 / alpha^2 - 2 = {:.1} for alpha = roughness^2 = {alpha:.4} (that mapping is \
             Beckmann's, and Blinn-Phong's; this lobe is GGX)",
            2.0 / (alpha * alpha) - 2.0
        );
    }
    if let Some(output) = &args.output {
        let angles = lobe_angles();
        let mut series = Vec::new();
        let mut incident = Vec::new();
        for (k, &theta_i) in args.theta_i.iter().enumerate() {
            let cut = LobeCut { theta_i, phi: 0.0, cosine: true };
            let values = lobes(&mut renderer, &[target.brdf.clone(), fitted.brdf.clone()], &cut)?;
            let colour = PALETTE[k % PALETTE.len()];
            incident.push((theta_i, colour));
            for (values, (label, dashed)) in
                values.into_iter().zip([(target.name.as_str(), false), (args.to.as_str(), true)])
            {
                series.push(Series {
                    label: format!("{label}{}, θi {theta_i}°", if dashed { " (fit)" } else { "" }),
                    colour,
                    points: angles.iter().zip(values).map(|(&a, f)| (a, Channel::Luminance.of(rgb(f)))).collect(),
                    dashed,
                });
            }
        }
        let chart = LobeChart {
            title: format!("{} and its {} fit (dashed): f_r cos θo, plane of incidence", target.name, args.to),
            quantity: "f_r cos θo (luminance)".into(),
            series,
            incident,
        };
        write_chart(&chart, output)?;
    }
    Ok(())
}

/// The model's parameters as `name = value` lines would name them.
fn parameters(brdf: &Brdf) -> Vec<(&'static str, String)> {
    let colour = |c: glam::Vec3| format!("[{}, {}, {}]", c.x, c.y, c.z);
    match *brdf {
        Brdf::Lambert { kd } => vec![("kd", colour(kd))],
        Brdf::OrenNayar { kd, sigma } => vec![("kd", colour(kd)), ("sigma", sigma.to_string())],
        Brdf::Phong { kd, ks, shininess } | Brdf::BlinnPhong { kd, ks, shininess } => {
            vec![("kd", colour(kd)), ("ks", colour(ks)), ("shininess", shininess.to_string())]
        }
        Brdf::CookTorrance { kd, f0, roughness, metalness, .. } => vec![
            ("kd", colour(kd)),
            ("f0", colour(f0)),
            ("roughness", roughness.to_string()),
            ("metalness", metalness.to_string()),
        ],
        Brdf::Measured(ref table) => vec![("file", format!("{:?}", table.path().display().to_string()))],
    }
}
