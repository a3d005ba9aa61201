//! The `vk-render` command line: the table of commands (each in its module of `commands/`), the one-line
//! error, and the signal handler that leaves no partial file.

use std::process::ExitCode;

use clap::{Parser, Subcommand};

use vk_render::RendererOptions;

mod commands;
#[cfg(feature = "serve")]
mod serve;

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

    /// How long to wait for the device to finish a piece of work before giving up, in seconds (a .brdf
    /// file's BRDF that never ends is reported so).
    #[arg(long, global = true, value_name = "SECONDS", default_value_t = vk_render::render::DEFAULT_TIMEOUT.as_secs_f64(), value_parser = positive_seconds)]
    timeout: f64,

    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Render a scene file to a PNG (8-bit, after the output transform) or an EXR (linear float).
    Render(commands::render::RenderArgs),
    /// Ray-trace a scene on the CPU (the independent reference the tests compare the GPU with).
    Reference(commands::reference::ReferenceArgs),
    /// Render one image per value of a scene key, or per combination of the values of several, and a
    /// labelled contact sheet of them (PNG); in shares (--shard K/N) or resumed (--resume).
    Sweep(commands::sweep::SweepArgs),
    /// Make a sweep's contact sheet from its tiles on disk (rendered by `sweep --shard K/N`), with the same
    /// arguments as the sweep; nothing is rendered.
    Sheet(commands::sweep::GridArgs),
    /// Show a scene live in a window: drag to orbit, wheel to zoom, R to reset, Tab to select an object,
    /// 1-5 to switch its BRDF, Up/Down its main parameter, Left/Right its metalness, L shadows, B the selected object's BRDF lobe, S a
    /// screenshot, Esc to quit. The scene file and shaders/ are reloaded when they change.
    #[cfg(feature = "preview")]
    Preview(commands::preview::PreviewArgs),
    /// Render every figure of the practical and one labelled contact sheet per figure into a folder.
    Figures(commands::figures::FiguresArgs),
    /// Plot a scene's materials: lobes, directional albedos (pictures or CSV, computed on the GPU by the
    /// very GLSL that renders).
    Plot(commands::plot::PlotArgs),
    /// The white furnace as a table: each material's largest directional albedo, and its model's made white
    /// over a grid of its main parameter, flagged where energy is created or lost.
    Furnace(commands::furnace::FurnaceArgs),
    /// Check your image against the exact one: the verdict, the differences, and which known mistake explains
    /// them (exit status 0 matches, 1 differs, 2 bad input).
    Check(commands::check::CheckArgs),
    /// Fit a model to a material: the parameters that best match its lobe in least squares over the
    /// hemisphere for a set of incidence angles, printed as `name = value ± standard error` with the residual.
    Fit(commands::fit::FitArgs),
    /// Write a material as a MERL file, as if measured (each entry its BRDF at the entry's centre), to load
    /// with brdf = "measured" or into another tool that reads MERL files.
    Tabulate(commands::tabulate::TabulateArgs),
    /// Write a material for another renderer: glTF 2.0, MaterialX (Standard Surface or OpenPBR), Mitsuba 3 or
    /// pbrt-v4, each parameter mapped by the format's own definition (see docs/export.md).
    Export(commands::export::ExportArgs),
    /// Test a material's own sampler, the exact mode's, on the GPU: Pearson's χ² per view, the density's
    /// integral, the estimator against the albedo, reciprocity and energy (exit status 0 passes, 1 fails, 2
    /// bad input).
    Sampling(commands::sampling::SamplingArgs),
    /// Render two scenes and compare them: side by side with the map of their differences and its colour
    /// bar (PNG), mean / p99 / max differences printed.
    Compare(commands::compare::CompareArgs),
    /// Serve the checker and a material explorer to browsers, with an HTTP API (see docs/serve.md, the guide's
    /// page for a course's staff): prints `listening on http://ADDR:PORT` once it accepts connections.
    #[cfg(feature = "serve")]
    Serve(serve::ServeArgs),
    /// Write the explorer as a static folder that any static file server serves, with no vk-render process
    /// behind it (see docs/serve.md): prints the folder's size.
    #[cfg(feature = "serve")]
    Site(serve::site::SiteArgs),
    /// List the Vulkan devices and which one is used by default.
    Devices,
}

impl Command {
    /// Whether the command handles SIGINT and SIGTERM itself (the server answers the requests in flight).
    fn stops_itself(&self) -> bool {
        #[cfg(feature = "serve")]
        if matches!(self, Command::Serve(_)) {
            return true;
        }
        false
    }
}

fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => return command_line_error(e),
    };
    stop_quietly_on_a_closed_pipe();
    if !cli.command.stops_itself() {
        remove_partial_files_on_signals();
    }
    let level = match cli.verbose {
        0 => log::LevelFilter::Warn,
        1 => log::LevelFilter::Info,
        2 => log::LevelFilter::Debug,
        _ => log::LevelFilter::Trace,
    };
    env_logger::Builder::new().filter_level(level).format_timestamp(None).init();
    match run(cli) {
        Ok(status) => status,
        Err(e) => {
            eprintln!("error: {e:#}");
            if matches!(e.downcast_ref::<vk_render::Error>(), Some(vk_render::Error::Timeout { .. })) {
                exit_leaving_the_device();
            }
            ExitCode::FAILURE
        }
    }
}

/// Ends the process at once with status 1, after a device was given up on work that may never end: the
/// driver's threads may still run that work, and an ordinary exit runs the driver's exit handlers, which
/// wait for them.
fn exit_leaving_the_device() -> ! {
    use std::io::Write;
    let _ = std::io::stderr().flush();
    let _ = std::io::stdout().flush();
    // SAFETY: _exit ends the process without running exit handlers; the output above is flushed and every
    // file vk-render writes is renamed into place whole or not at all.
    unsafe { libc::_exit(1) }
}

/// `--timeout`: a number of seconds above 0.
fn positive_seconds(text: &str) -> Result<f64, String> {
    match text.parse::<f64>() {
        Ok(seconds) if seconds.is_finite() && seconds > 0.0 => Ok(seconds),
        _ => Err(format!("`{text}` is not a number of seconds above 0")),
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

/// A reader that stops early (`vk-render furnace ... | head -3`) closes the pipe: like Unix tools, the
/// process then ends quietly by SIGPIPE's default action at its next print. Rust starts programs with SIGPIPE
/// ignored, which turns that print into a panic ("failed printing to stdout: Broken pipe") and exit status
/// 101. The files a command writes are renamed into place whole or not at all, so none is left half-written.
fn stop_quietly_on_a_closed_pipe() {
    // SAFETY: called first thing in main, before any thread is started; SIG_DFL is a valid disposition.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
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
            let removed = vk_render::pictures::output::remove_partial_files();
            let name = if signal == SIGINT { "SIGINT" } else { "SIGTERM" };
            eprintln!("vk-render: stopped by {name}; {removed} partial file(s) removed");
            std::process::exit(128 + signal);
        }
    });
}

/// Runs the command: its exit status, or its error (exit status 1). `check` has its own statuses.
fn run(cli: Cli) -> anyhow::Result<ExitCode> {
    let options = RendererOptions {
        device: cli.device,
        validate: cli.validate,
        timeout: Some(std::time::Duration::from_secs_f64(cli.timeout)),
        ..Default::default()
    };
    let done = match cli.command {
        Command::Devices => commands::devices::run(cli.validate),
        Command::Render(args) => commands::render::run(args, options),
        Command::Reference(args) => commands::reference::run(args),
        Command::Sweep(args) => commands::sweep::run(args, options),
        Command::Sheet(args) => commands::sweep::run_sheet(args),
        Command::Figures(args) => commands::figures::run(args, options),
        Command::Plot(args) => commands::plot::run(args, options),
        Command::Furnace(args) => commands::furnace::run(args, options),
        Command::Compare(args) => commands::compare::run(args, options),
        Command::Fit(args) => commands::fit::run(args, options),
        Command::Tabulate(args) => commands::tabulate::run(args, options),
        Command::Export(args) => commands::export::run(args),
        Command::Check(args) => return Ok(commands::check::run(args, options)),
        Command::Sampling(args) => return Ok(commands::sampling::run(args, options)),
        #[cfg(feature = "preview")]
        Command::Preview(args) => commands::preview::run(args, options),
        #[cfg(feature = "serve")]
        Command::Serve(args) => serve::run(args, options),
        #[cfg(feature = "serve")]
        Command::Site(args) => serve::site::run(args, options),
    };
    done.map(|()| ExitCode::SUCCESS)
}
