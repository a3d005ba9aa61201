//! `vk-render preview`: the scene live in a window.

use std::path::PathBuf;

use clap::Args;

use super::ImageArgs;
use vk_render::pictures::output::OutputFormat;
use vk_render::RendererOptions;

#[derive(Args)]
pub struct PreviewArgs {
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

/// Opens the window and runs until it is closed (or its frames are done).
pub fn run(args: PreviewArgs, renderer: RendererOptions) -> anyhow::Result<()> {
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
