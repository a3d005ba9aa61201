//! `vk-render furnace`: the white furnace as a table (.csv, or a picture of it: .png, .svg), printed too.

use clap::Args;
use plotters::style::RGBColor;

use super::{progress, StudyArgs, StudyFile};
use vk_render::analysis::albedo::ALBEDO_TOLERANCE;
use vk_render::analysis::describe;
use vk_render::analysis::furnace::{furnace, FurnaceRow};
use vk_render::pictures::chart::{write_chart, TableChart};
use vk_render::{Renderer, RendererOptions};

#[derive(Args)]
pub struct FurnaceArgs {
    #[command(flatten)]
    study: StudyArgs,
}

const HEADER: [&str; 6] = ["material", "model and parameters", "max albedo", "error bound", "theta_o", "verdict"];

/// Integrates every row, prints the table and writes it.
pub fn run(args: FurnaceArgs, options: RendererOptions) -> anyhow::Result<()> {
    let materials = args.study.materials()?;
    let file = args.study.output_file()?;
    let mut renderer = super::CommandRenderer::new(Renderer::new(options)?);
    let bar = progress(0, "furnace");
    let rows = furnace(&mut renderer, &materials, ALBEDO_TOLERANCE, |done, total| {
        bar.set_length(total as u64);
        bar.set_position(done as u64);
    })?;
    bar.finish_and_clear();
    let cells: Vec<[String; 6]> = rows.iter().map(cells).collect();
    for row in &cells {
        println!("{:<10} {:<70} {:>10} {:>11} {:>7}  {}", row[0], row[1], row[2], row[3], row[4], row[5]);
    }
    let mut csv = HEADER.join(",") + "\n";
    for (row, cells) in rows.iter().zip(&cells) {
        csv.push_str(&format!(
            "{},\"{}\",{},{},{},\"{}\"\n",
            row.material, cells[1], row.max_albedo, row.error_bound, row.theta_o, cells[5]
        ));
    }
    let chart = TableChart {
        title: format!("White furnace: {}", args.study.scene.display()),
        header: HEADER.iter().map(|h| h.to_string()).collect(),
        rows: rows.iter().zip(cells).map(|(row, cells)| (cells.to_vec(), colour(row))).collect(),
        note: format!(
            "largest directional albedo over θo = 0..89.9°, any channel; each within its error bound \
             (asked {ALBEDO_TOLERANCE:.0e}); white rows: each lobe alone at full strength"
        ),
    };
    match file {
        StudyFile::Csv => args.study.write(&csv, |_| Ok(())),
        StudyFile::Chart(_) => args.study.write(&csv, |path| write_chart(&chart, path)),
    }
}

fn cells(row: &FurnaceRow) -> [String; 6] {
    [
        row.material.clone(),
        describe(&row.brdf),
        format!("{:.5}", row.max_albedo),
        format!("{:.1e}", row.error_bound),
        format!("{}", row.theta_o),
        row.verdict(),
    ]
}

/// Red where energy is created, blue where a white lobe loses some, black otherwise.
fn colour(row: &FurnaceRow) -> RGBColor {
    match row.verdict() {
        v if v.starts_with("creates") => RGBColor(200, 30, 30),
        v if v.starts_with("loses") => RGBColor(30, 70, 200),
        _ => RGBColor(0, 0, 0),
    }
}
