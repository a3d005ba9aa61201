//! `vk-render check`: a student's image against the exact one: the verdict, the statistics overall and per
//! object, the diagnosis among the catalogue's mistakes, and a report picture.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::Args;

use super::{progress, SetArgs};
use vk_render::check::catalogue::CATALOGUE;
use vk_render::check::report::{check_image, read_image, scene_named};
use vk_render::check::summary::{NamedMistake, Summary};
use vk_render::check::{Verdict, EDGE_MARGIN, MATCH_P99, MATCH_RMS};
use vk_render::pictures::output::{write_png, OutputFormat};
use vk_render::pictures::report::{side_by_side, Difference};
use vk_render::scene::figures::FIGURES;
use vk_render::{Override, Renderer, RendererOptions, Scene};

#[derive(Args)]
pub struct CheckArgs {
    /// Your image: .png or .jpg (8-bit RGB, as the course's skeleton writes it).
    #[arg(required_unless_present = "list")]
    mine: Option<PathBuf>,

    /// The scene: a scene file, or the name of one of the practical's images (see --list).
    #[arg(long, value_name = "SCENE", required_unless_present = "list")]
    scene: Option<String>,

    /// Also write a report: your image, the exact one, the map of their differences and the diagnosed
    /// mistake's render, each labelled (.png).
    #[arg(short, long, value_name = "REPORT")]
    output: Option<PathBuf>,

    /// List the practical's images --scene can name, and the catalogue of mistakes.
    #[arg(long)]
    list: bool,

    #[command(flatten)]
    set: SetArgs,
}

/// Exit status 0 when the image matches, 1 when it differs, 2 on bad input.
pub fn run(args: CheckArgs, options: RendererOptions) -> ExitCode {
    match check(&args, options) {
        Ok(true) => ExitCode::SUCCESS,
        Ok(false) => ExitCode::from(1),
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::from(2)
        }
    }
}

fn check(args: &CheckArgs, options: RendererOptions) -> anyhow::Result<bool> {
    if args.list {
        println!("the practical's images (--scene NAME):");
        for image in FIGURES.iter().flat_map(|figure| figure.images) {
            println!("  {}", image.file.trim_end_matches(".toml"));
        }
        println!("the mistakes vk-render knows:");
        for mistake in CATALOGUE {
            println!("  {}: {}", mistake.name, mistake.explanation);
        }
        return Ok(true);
    }
    let (Some(mine_path), Some(scene_name)) = (&args.mine, &args.scene) else {
        anyhow::bail!("give your image and --scene (or --list)");
    };
    let mine = read_image(mine_path)?;
    if let Some(report) = &args.output {
        if OutputFormat::for_path(report)? != OutputFormat::Png {
            anyhow::bail!("{}: the report is a .png image", report.display());
        }
    }
    // The exact image is rendered at your image's size.
    let mut overrides: Vec<Override> = vec![
        Override::new("image.width", i64::from(mine.width())),
        Override::new("image.height", i64::from(mine.height())),
    ];
    overrides.extend(args.set.overrides.iter().cloned());
    let scene = scene_named(scene_name, &overrides)?;
    let mut renderer = super::CommandRenderer::new(Renderer::new(options)?);
    let bar = progress(CATALOGUE.len(), "rendering the mistakes");
    let checked = check_image(&mut renderer, &mine, &scene, |done, _| bar.set_position(done as u64))?;
    bar.finish_and_clear();
    let summary = Summary::of(&checked, &scene);
    print_summary(&summary, &scene, (mine_path, scene_name, mine.dimensions()));
    let diagnosis = &checked.diagnosis;
    let exact = checked.exact();
    let diagnosed = summary.mistakes.first();
    if let Some(report) = &args.output {
        let difference = Difference::of(&mine, exact);
        let mut panels = vec![
            ("yours".to_string(), mine.clone()),
            ("exact".to_string(), exact.clone()),
            (format!("|yours - exact|, 0 to {} levels", difference.map.scale()), difference.map.heat_map()),
        ];
        if let Some(m) = diagnosed {
            if let Some(candidate) = checked.candidates.iter().find(|c| c.mistake.is_some_and(|c| c.name == m.name)) {
                panels.push((format!("with {}", m.name), candidate.image.clone()));
            }
        }
        let name =
            mine_path.file_name().map_or_else(|| mine_path.display().to_string(), |n| n.to_string_lossy().into_owned());
        let title = format!("{name} against {scene_name}: {}", verdict_line(&diagnosis.verdict));
        write_png(&side_by_side(&title, &panels, Some(difference.map.scale())), report)?;
    }
    Ok(diagnosis.verdict == Verdict::Matches)
}

/// What `vk-render check` prints of a check: the verdict, the tolerance, the differences overall and per
/// region, and the diagnosis, all read from the check's [`Summary`] (as the server and Python give it).
fn print_summary(
    summary: &Summary,
    scene: &Scene,
    (mine_path, scene_name, (width, height)): (&Path, &str, (u32, u32)),
) {
    println!(
        "{} against {scene_name} at {width} x {height}: {}",
        mine_path.display(),
        if summary.matches { "matches" } else { "differs" }
    );
    println!(
        "tolerance (JPEG-fair): both images blurred over 3 x 3 pixels, {EDGE_MARGIN} pixels around hard edges left out; \
         a match is a root mean square within {MATCH_RMS} levels and a 99th percentile within {MATCH_P99}"
    );
    let stats = &summary.statistics;
    println!(
        "differences: root mean square {:.2} levels, mean {:.2}, p99 {:.1}, {:.2}% of the pixels over {MATCH_P99} levels",
        stats.rms,
        stats.mean,
        stats.p99,
        100.0 * stats.over
    );
    for region in &summary.regions {
        let s = &region.statistics;
        println!(
            "  {} {}: root mean square {:.2}, p99 {:.1}, {:.2}% over",
            object_name(scene, region.object),
            region.part,
            s.rms,
            s.p99,
            100.0 * s.over
        );
    }
    let explained = |m: &NamedMistake| {
        format!("{}: {} It should be {}; your image suggests {}.", m.name, m.explanation, m.should_be, m.looks_like)
    };
    match summary.verdict {
        "matches" => println!("diagnosis: none needed, your image is the exact one within the tolerance"),
        "mistake" => {
            for m in &summary.mistakes {
                println!("diagnosis: {}", explained(m));
            }
        }
        "tie" => {
            println!("diagnosis: these mistakes explain your image equally well on this scene:");
            for m in &summary.mistakes {
                println!("  {}", explained(m));
            }
            match (&summary.tells_apart, summary.tells_apart_levels) {
                (Some(shows_on), Some(levels)) => println!(
                    "  the practical's scene that tells them apart: {shows_on} (their renders differ by {levels:.1} levels or \
                     more there): render yours of it and check it"
                ),
                _ => println!("  no scene of the practical tells them apart"),
            }
        }
        _ => {
            for wrong in &summary.wrong_parameters {
                let shown = |values: &[f32]| {
                    let v: Vec<String> = values.iter().map(|x| format!("{:.3}", x)).map(trimmed).collect();
                    if let [one] = &v[..] {
                        one.clone()
                    } else {
                        format!("[{}]", v.join(", "))
                    }
                };
                let fitted: Vec<String> = wrong.fitted.iter().map(|(n, v)| format!("{n} = {}", shown(v))).collect();
                let given: Vec<String> = wrong.scene.iter().map(|(_, g)| shown(g)).collect();
                println!(
                    "diagnosis: {} matches the correct {} with {}; the scene says {} (its pixels fitted within {:.2} \
                     levels, the scene's parameters {:.2})",
                    object_name(scene, Some(wrong.object)),
                    wrong.model,
                    fitted.join(", "),
                    given.join(", "),
                    wrong.residual_levels,
                    wrong.scene_levels
                );
            }
            println!("diagnosis: no known mistake explains your image; the differences lie in:");
            let mut worst: Vec<_> = summary.regions.iter().filter(|r| r.statistics.over > 0.01).collect();
            worst.sort_by(|a, b| b.statistics.over.total_cmp(&a.statistics.over));
            for region in worst.iter().take(3) {
                println!(
                    "  {} {} ({:.1}% of its pixels)",
                    object_name(scene, region.object),
                    region.part,
                    100.0 * region.statistics.over
                );
            }
        }
    }
}

fn verdict_line(verdict: &Verdict) -> String {
    match verdict {
        Verdict::Matches => "matches".into(),
        Verdict::Mistake(name) => format!("differs: {name}"),
        Verdict::Tie(names) => format!("differs: one of {}", names.join(", ")),
        Verdict::Unexplained => "differs: no known mistake explains it".into(),
    }
}

/// A number printed to three decimals without its trailing zeros.
fn trimmed(text: String) -> String {
    if text.contains('.') {
        text.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        text
    }
}

fn object_name(scene: &Scene, object: Option<usize>) -> String {
    match object.and_then(|i| scene.objects.get(i).map(|o| (i, o))) {
        None => "background".into(),
        Some((i, o)) => format!("{} (object {i}, material {})", o.shape.kind(), o.material),
    }
}
