//! The `vk-render` command line.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Args, Parser, Subcommand};

use vk_render::figures::FIGURES;
use vk_render::output::{write_image, write_png, write_png_rows, OutputFormat};
use vk_render::sheet::SheetLayout;
use vk_render::vulkan::{list_devices, preferred_device, Instance};
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
    /// Ray-trace a scene on the CPU (the independent reference the tests compare the GPU with).
    Reference(ReferenceArgs),
    /// Render one image per value of a scene key and a labelled contact sheet of them (PNG).
    Sweep(SweepArgs),
    /// Show a scene live in a window: drag to orbit, wheel to zoom, R to reset, Tab to select an object,
    /// 1-5 to switch its BRDF, Up/Down its main parameter, Left/Right its metalness, L shadows, S a
    /// screenshot, Esc to quit. The scene file and shaders/ are reloaded when they change.
    #[cfg(feature = "preview")]
    Preview(PreviewArgs),
    /// Render every figure of the practical and one labelled contact sheet per figure into a folder.
    Figures(FiguresArgs),
    /// List the Vulkan devices and which one is used by default.
    Devices,
}

#[derive(Args)]
struct ReferenceArgs {
    /// The scene file (TOML, SCENE_FORMAT version 1).
    scene: PathBuf,

    /// The output image: .png or .exr.
    #[arg(short, long, value_name = "OUT")]
    output: PathBuf,

    /// Also write the object-id map (.png): one colour per object, black where no object is seen.
    #[arg(long, value_name = "IDS")]
    ids: Option<PathBuf>,

    #[command(flatten)]
    image: ImageArgs,
}

#[derive(Args)]
struct SweepArgs {
    /// The scene file (TOML, SCENE_FORMAT version 1).
    scene: PathBuf,

    /// The dotted key to vary, e.g. material.grey.sigma.
    #[arg(long, value_name = "KEY")]
    param: String,

    /// The values, separated by commas, e.g. 0,0.2,0.4,0.6.
    #[arg(long, value_name = "V1,V2,...", value_delimiter = ',', required = true)]
    values: Vec<String>,

    /// The contact sheet (.png); each tile is written beside it as SHEET-VALUE.png.
    #[arg(short, long, value_name = "SHEET")]
    output: PathBuf,

    /// Tiles per row of the sheet (1 to 64).
    #[arg(long, default_value_t = 4, value_parser = clap::value_parser!(u32).range(1..=64))]
    columns: u32,

    #[command(flatten)]
    image: ImageArgs,
}

#[cfg(feature = "preview")]
#[derive(Args)]
struct PreviewArgs {
    /// The scene file (TOML, SCENE_FORMAT version 1).
    scene: PathBuf,

    /// Exit after presenting this many frames (headless checks, e.g. under xvfb-run).
    #[arg(long, value_name = "N")]
    frames: Option<u64>,

    /// Test hook: exit after this many seconds (like --frames, saving --screenshot).
    #[arg(long, value_name = "SECONDS", hide = true)]
    seconds: Option<f64>,

    /// Save the last presented frame to this PNG on exit (with --frames).
    #[arg(long, value_name = "OUT.png")]
    screenshot: Option<PathBuf>,

    /// Test hook: keys pressed one per frame, handled as the keyboard's, e.g. "Tab,2,Up,resize:320x200"
    /// (Tab, Up, Down, Left, Right, Esc, or one character as typed).
    #[arg(long, value_name = "KEYS", hide = true)]
    keys: Option<String>,

    /// A shaders/ folder to watch and reload (default: the source tree's, when it is there).
    #[arg(long, value_name = "DIR")]
    shaders: Option<PathBuf>,

    #[command(flatten)]
    image: ImageArgs,
}

#[derive(Args)]
struct FiguresArgs {
    /// The folder to write into (created if needed).
    #[arg(short, long, value_name = "DIR")]
    output: PathBuf,

    #[command(flatten)]
    image: ImageArgs,
}

/// Options that override `[image]` and any other value of the scene(s).
#[derive(Args)]
struct ImageArgs {
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

impl ImageArgs {
    /// The shorthands as overrides, then the --set ones.
    fn overrides(&self) -> Vec<Override> {
        let mut overrides = Vec::new();
        for (key, value) in [("width", self.width), ("height", self.height), ("samples", self.samples)] {
            if let Some(value) = value {
                overrides.push(Override::new(format!("image.{key}"), value));
            }
        }
        overrides.extend(self.overrides.iter().cloned());
        overrides
    }
}

#[derive(Args)]
struct RenderArgs {
    /// The scene file (TOML, SCENE_FORMAT version 1).
    scene: PathBuf,

    /// The output image: .png or .exr.
    #[arg(short, long, value_name = "OUT")]
    output: PathBuf,

    #[command(flatten)]
    image: ImageArgs,
}

fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => return command_line_error(e),
    };
    remove_partial_files_on_signals();
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

/// A bad command line gets one line, like every other bad input: clap's message with its usage and hint
/// left off (`--help` shows them), exit status 2. Help and version are printed whole, as asked.
fn command_line_error(e: clap::Error) -> ExitCode {
    use clap::error::ErrorKind;
    if matches!(
        e.kind(),
        ErrorKind::DisplayHelp | ErrorKind::DisplayVersion | ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand
    ) {
        e.exit();
    }
    let rendered = e.render().to_string();
    let message: Vec<&str> = rendered
        .lines()
        .take_while(|line| !line.starts_with("Usage:") && !line.starts_with("For more information"))
        .map(str::trim)
        .filter(|line| !line.is_empty())
        .collect();
    eprintln!("{}", message.join(" "));
    ExitCode::from(2)
}

/// On SIGINT or SIGTERM: the temporary files being written are removed, one line says so, and the process
/// exits with the conventional status (128 + the signal: 130, 143).
fn remove_partial_files_on_signals() {
    use signal_hook::consts::{SIGINT, SIGTERM};
    let mut signals = match signal_hook::iterator::Signals::new([SIGINT, SIGTERM]) {
        Ok(signals) => signals,
        Err(e) => {
            log::warn!("cannot catch SIGINT and SIGTERM ({e}): an interrupted write may leave a .partial file");
            return;
        }
    };
    std::thread::spawn(move || {
        if let Some(signal) = signals.forever().next() {
            let removed = vk_render::output::remove_partial_files();
            let name = if signal == SIGINT { "SIGINT" } else { "SIGTERM" };
            eprintln!("vk-render: stopped by {name}; {removed} partial file(s) removed");
            std::process::exit(128 + signal);
        }
    });
}

fn run(cli: Cli) -> anyhow::Result<()> {
    let options = RendererOptions { device: cli.device, validate: cli.validate, ..Default::default() };
    match cli.command {
        Command::Devices => devices(cli.validate),
        Command::Render(args) => render(args, options),
        Command::Reference(args) => reference(args),
        Command::Sweep(args) => sweep(args, options),
        Command::Figures(args) => figures(args, options),
        #[cfg(feature = "preview")]
        Command::Preview(args) => preview(args, options),
    }
}

fn devices(validate: bool) -> anyhow::Result<()> {
    let instance = Instance::new(validate, &[])?;
    let devices = list_devices(&instance)?;
    if devices.is_empty() {
        anyhow::bail!("no Vulkan device was found. {}", vk_render::vulkan::INSTALL_HINT);
    }
    let preferred = preferred_device(&instance, &devices, None).ok().map(|((_, info), _)| info.index);
    for (_, info) in &devices {
        let marker = if Some(info.index) == preferred { "*" } else { " " };
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
    let overrides = args.image.overrides();
    // Everything that can be checked without a device is checked before one is opened.
    let scene = Scene::load(&args.scene, &overrides)?;
    OutputFormat::for_path(&args.output)?;
    warn(&scene);
    let mut renderer = Renderer::new(options)?;
    match OutputFormat::for_path(&args.output)? {
        OutputFormat::Png => write_png(&renderer.render_rgb8(&scene)?, &args.output)?,
        OutputFormat::Exr => write_image(&renderer.render(&scene)?, &scene.image, &args.output)?,
    }
    log::info!("wrote {}", args.output.display());
    Ok(())
}

#[cfg(feature = "preview")]
fn preview(args: PreviewArgs, renderer: RendererOptions) -> anyhow::Result<()> {
    use vk_render::preview::{parse_script, run, PreviewOptions};
    let script = match &args.keys {
        Some(keys) => parse_script(keys).map_err(|e| anyhow::anyhow!("--keys: {e}"))?,
        None => Vec::new(),
    };
    if let Some(path) = &args.screenshot {
        if OutputFormat::for_path(path)? != OutputFormat::Png {
            anyhow::bail!("{}: a screenshot is a .png image", path.display());
        }
    }
    let source_shaders = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("shaders");
    let shaders = args.shaders.or_else(|| source_shaders.is_dir().then_some(source_shaders));
    run(PreviewOptions {
        scene: args.scene,
        overrides: args.image.overrides(),
        renderer,
        frames: args.frames,
        duration: args.seconds.map(std::time::Duration::from_secs_f64),
        screenshot: args.screenshot,
        script,
        shaders,
    })?;
    Ok(())
}

fn reference(args: ReferenceArgs) -> anyhow::Result<()> {
    let scene = Scene::load(&args.scene, &args.image.overrides())?;
    OutputFormat::for_path(&args.output)?;
    if let Some(ids) = &args.ids {
        if OutputFormat::for_path(ids)? != OutputFormat::Png {
            anyhow::bail!("{}: the object-id map is a .png image", ids.display());
        }
        if names_the_same_file(ids, &args.output) {
            anyhow::bail!("--ids {}: the same file as -o: give the object-id map a file of its own", ids.display());
        }
    }
    let traced = vk_render::reference::render(&scene)?;
    write_image(&traced.image, &scene.image, &args.output)?;
    if let Some(ids) = &args.ids {
        write_png(&traced.object_id_picture(), ids)?;
    }
    Ok(())
}

/// One tile of a contact sheet: its scene, label and file.
struct Tile {
    scene: Scene,
    label: String,
    path: PathBuf,
}

fn sweep(args: SweepArgs, options: RendererOptions) -> anyhow::Result<()> {
    if OutputFormat::for_path(&args.output)? != OutputFormat::Png {
        anyhow::bail!("{}: a contact sheet is a .png image", args.output.display());
    }
    let stem = args.output.file_stem().unwrap_or_default().to_string_lossy().into_owned();
    let short_key = args.param.rsplit('.').next().unwrap_or(&args.param).to_string();
    // Every scene is loaded and checked before anything is rendered or written.
    if let Some(empty) = args.values.iter().position(|value| value.trim().is_empty()) {
        anyhow::bail!(
            "--values {:?}: value {} of {} is empty (give the values separated by commas: 0,0.2,0.4)",
            args.values.join(","),
            empty + 1,
            args.values.len()
        );
    }
    let mut tiles = Vec::new();
    for value in &args.values {
        let value = value.trim();
        let mut overrides = args.image.overrides();
        overrides.push(format!("{}={value}", args.param).parse().map_err(anyhow::Error::msg)?);
        let scene = Scene::load(&args.scene, &overrides)?;
        let path = args.output.with_file_name(format!("{stem}-{}.png", file_safe(value)));
        tiles.push(Tile { scene, label: format!("{short_key} = {value}"), path });
    }
    if let Some(first) = tiles.first() {
        warn(&first.scene);
    }
    let mut renderer = Renderer::new(options)?;
    renderer.prepare(&tiles.iter().map(|tile| &tile.scene).collect::<Vec<_>>())?;
    render_sheet(&mut renderer, &args.param, &tiles, args.columns as usize, &args.output)
}

fn figures(args: FiguresArgs, options: RendererOptions) -> anyhow::Result<()> {
    std::fs::create_dir_all(&args.output)
        .map_err(|e| anyhow::anyhow!("{}: cannot create the folder: {e}", args.output.display()))?;
    let overrides = args.image.overrides();
    let mut sheets = Vec::new();
    for figure in FIGURES {
        let mut tiles = Vec::new();
        for image in figure.images {
            let scene = image.scene(&overrides)?;
            tiles.push(Tile { scene, label: image.label.to_string(), path: args.output.join(image.png_name()) });
        }
        sheets.push((figure, tiles));
    }
    // One device, one set of compiled shaders and pipelines for every image, the pipelines built first.
    let mut renderer = Renderer::new(options)?;
    renderer.prepare(&sheets.iter().flat_map(|(_, tiles)| tiles.iter().map(|tile| &tile.scene)).collect::<Vec<_>>())?;
    for (figure, tiles) in &sheets {
        let sheet = args.output.join(format!("{}.png", figure.name));
        render_sheet(&mut renderer, figure.title, tiles, 4, &sheet)?;
    }
    Ok(())
}

/// Renders every tile and writes it as soon as it is done, with the labelled contact sheet made band by band
/// beside them: one row of tiles at a time in memory, however long the sweep. If anything fails, the files
/// written are removed and the message says so.
fn render_sheet(
    renderer: &mut Renderer,
    title: &str,
    tiles: &[Tile],
    columns: usize,
    sheet_path: &std::path::Path,
) -> anyhow::Result<()> {
    let tile_size = tiles.iter().fold((0, 0), |(w, h), t| (w.max(t.scene.image.width), h.max(t.scene.image.height)));
    let layout = SheetLayout::new(Some(title), tiles.len(), tile_size, columns);
    let mut written: Vec<&std::path::Path> = Vec::new();
    let result = write_png_rows(sheet_path, layout.size(), |band| {
        band(&layout.title_band())?;
        let mut row = Vec::with_capacity(layout.columns);
        for (index, tile) in tiles.iter().enumerate() {
            let image = renderer.render_rgb8(&tile.scene)?;
            write_png(&image, &tile.path)?;
            written.push(&tile.path);
            row.push((tile.label.clone(), image));
            if row.len() == layout.columns || index + 1 == tiles.len() {
                band(&layout.row_band(&row))?;
                row.clear();
            }
        }
        Ok(())
    });
    if let Err(e) = result {
        for path in &written {
            let _ = std::fs::remove_file(path);
        }
        if written.is_empty() {
            return Err(e.into());
        }
        anyhow::bail!(
            "{e} (nothing is left of this sheet: the {} file(s) written before it were removed)",
            written.len()
        );
    }
    println!("{}", sheet_path.display());
    Ok(())
}

/// Prints the scene's warnings on standard error.
fn warn(scene: &Scene) {
    for warning in scene.warnings() {
        eprintln!("warning: {warning}");
    }
}

/// Whether two output paths name the same file: their folders (which exist) resolved, and the same name.
fn names_the_same_file(a: &std::path::Path, b: &std::path::Path) -> bool {
    let resolved = |path: &std::path::Path| {
        let folder = path.parent().filter(|p| !p.as_os_str().is_empty()).unwrap_or(std::path::Path::new("."));
        folder.canonicalize().ok().map(|folder| folder.join(path.file_name().unwrap_or_default()))
    };
    resolved(a).is_some() && resolved(a) == resolved(b)
}

/// A value as part of a file name: anything but letters, digits, '.', '-' and '_' becomes '_'.
fn file_safe(value: &str) -> String {
    value.chars().map(|c| if c.is_ascii_alphanumeric() || "._-".contains(c) { c } else { '_' }).collect()
}
