//! The `vk-render` command line.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Args, Parser, Subcommand};

use vk_render::output::{write_image, OutputFormat};
use vk_render::vulkan::{list_devices, Instance};
use vk_render::{Override, Renderer, RendererOptions, Scene};

/// Renders classic BRDFs (Lambert, Oren-Nayar, Phong, Blinn-Phong, Cook-Torrance) through Vulkan.
#[derive(Parser)]
#[command(name = "vk-render", version, about)]
struct Cli {
    /// More log output: -v info, -vv debug, -vvv trace.
    #[arg(short, long, action = clap::ArgAction::Count, global = true)]
    verbose: u8,

    /// The Vulkan device: an index from `vk-render devices` or part of its name (default: a GPU, else lavapipe).
    #[arg(long, global = true, value_name = "NAME-or-INDEX")]
    device: Option<String>,

    /// Turn on the Khronos validation layer and fail on any message it reports.
    #[arg(long, global = true)]
    validate: bool,

    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Render a scene file to a PNG (8-bit, after the output transform) or an EXR (linear float).
    Render(RenderArgs),
    /// List the Vulkan devices and which one is used by default.
    Devices,
}

#[derive(Args)]
struct RenderArgs {
    /// The scene file (TOML, SCENE_FORMAT version 1).
    scene: PathBuf,

    /// The output image: .png or .exr.
    #[arg(short, long, value_name = "OUT")]
    output: PathBuf,

    /// Image width in pixels (same as --set image.width=W).
    #[arg(long)]
    width: Option<i64>,

    /// Image height in pixels (same as --set image.height=H).
    #[arg(long)]
    height: Option<i64>,

    /// MSAA samples per pixel (same as --set image.samples=N).
    #[arg(long)]
    samples: Option<i64>,

    /// Override one scene value by its dotted path, e.g. material.grey.kd=0.8 or light.0.power=30.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    overrides: Vec<Override>,
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let level = match cli.verbose {
        0 => log::LevelFilter::Warn,
        1 => log::LevelFilter::Info,
        2 => log::LevelFilter::Debug,
        _ => log::LevelFilter::Trace,
    };
    env_logger::Builder::new().filter_level(level).format_timestamp(None).init();
    match run(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::FAILURE
        }
    }
}

fn run(cli: Cli) -> anyhow::Result<()> {
    match cli.command {
        Command::Devices => devices(cli.validate),
        Command::Render(args) => {
            let options = RendererOptions { device: cli.device, validate: cli.validate, ..Default::default() };
            render(args, options)
        }
    }
}

fn devices(validate: bool) -> anyhow::Result<()> {
    let instance = Instance::new(validate)?;
    let devices = list_devices(&instance)?;
    if devices.is_empty() {
        anyhow::bail!("no Vulkan device was found. {}", vk_render::vulkan::INSTALL_HINT);
    }
    let default = vk_render::vulkan::Device::new(std::sync::Arc::new(instance), None).map(|d| d.info.index).ok();
    for (_, info) in &devices {
        let marker = if Some(info.index) == default { "*" } else { " " };
        println!(
            "{marker} {}: {} ({}, Vulkan {}) {}",
            info.index,
            info.name,
            info.kind_name(),
            info.api_version_string(),
            info.driver
        );
    }
    println!("(* = used when --device is not given)");
    Ok(())
}

fn render(args: RenderArgs, options: RendererOptions) -> anyhow::Result<()> {
    let mut overrides = Vec::new();
    for (key, value) in [("width", args.width), ("height", args.height), ("samples", args.samples)] {
        if let Some(value) = value {
            overrides.push(Override::new(format!("image.{key}"), value));
        }
    }
    overrides.extend(args.overrides);
    // Everything that can be checked without a device is checked before one is opened.
    let scene = Scene::load(&args.scene, &overrides)?;
    OutputFormat::for_path(&args.output)?;
    let mut renderer = Renderer::new(options)?;
    let image = renderer.render(&scene)?;
    write_image(&image, &scene.image, &args.output)?;
    log::info!("wrote {}", args.output.display());
    Ok(())
}
