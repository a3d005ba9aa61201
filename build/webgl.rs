//! The browser's shaders (WebGL2) made from the very sources the renderer compiles: every entry file under
//! shaders/ that says `// webgl` is compiled by glslc with WEBGL defined (which swaps what WebGL2 lacks for
//! what it has: shaders/common/scene.glsl), its SPIR-V translated by SPIRV-Cross to GLSL ES 3.00 (a vertex
//! shader's Vulkan depth range [0, w] made GL's [-w, w]), and the text checked by glslangValidator.
//! Specialization constants stay as SPIRV-Cross writes them (`SPIRV_CROSS_CONSTANT_ID_n` macros with their
//! defaults), which the page defines per program. An entry's variants (`// variant: A+B`, as build.rs
//! compiles them for the renderer) are translated too, as `FILE+A+B` (the environment's, WITH_ENVIRONMENT, in
//! its fast mode alone: common/environment.glsl). Used by build.rs, by the server for an analytic model's
//! entries (src/webgl.rs), and by the browser test, which translates shaders broken on purpose to show that its
//! comparison catches them.

use std::path::{Path, PathBuf};
use std::process::Command;

/// The interface locations between stages that the translation renames (see [`translate`]): more than any
/// entry uses.
const INTERFACE_LOCATIONS: u32 = 8;

/// glslc's options for every entry, the renderer's and the browser's alike: the run-time compiler's
/// (ShaderCompiler::compile: Vulkan 1.3, SPIR-V 1.5; includes beside the including file, then from shaders/).
pub const GLSLC_OPTIONS: [&str; 4] = ["--target-env=vulkan1.3", "--target-spv=spv1.5", "-I", "."];

/// An entry file's variants, each compiled again with its macros defined: each `// variant: A+B` line's
/// `A+B` (the entry `FILE+A+B`).
pub fn variants(text: &str) -> impl Iterator<Item = &str> {
    text.lines().filter_map(|line| line.strip_prefix("// variant: ")).map(str::trim)
}

/// Whether a file of shaders/ is an entry shader (a stage's `main`) rather than an included one.
pub fn is_entry(relative: &str) -> bool {
    ["vert", "frag", "comp"].iter().any(|stage| relative.ends_with(&format!(".{stage}")))
}

/// Translates the `// webgl` entries of the shader tree at `root` into `out`: each entry file's name (relative
/// to `root`) with the file of its GLSL ES 3.00, or the first tool's failure with its messages. `validate` checks each text with glslangValidator too.
pub fn translate(root: &Path, out: &Path, validate: bool) -> Result<Vec<(String, PathBuf)>, String> {
    let mut files = Vec::new();
    collect(root, &mut files);
    files.sort();
    let tools = Tools::from_environment();
    let mut translated = Vec::new();
    for file in &files {
        let relative = file.strip_prefix(root).map_err(|e| e.to_string())?.to_string_lossy().replace('\\', "/");
        let text = std::fs::read_to_string(file).map_err(|e| format!("{}: {e}", file.display()))?;
        if !is_entry(&relative) || !text.lines().any(|line| line.trim() == "// webgl") {
            continue;
        }
        for variant in std::iter::once(None).chain(variants(&text).map(Some)) {
            let macros: Vec<&str> = variant.iter().flat_map(|v| v.split('+')).collect();
            let entry = variant.map_or(relative.clone(), |v| format!("{relative}+{v}"));
            translated.push((entry.clone(), translate_one(root, out, &relative, &entry, &macros, validate, &tools)?));
        }
    }
    Ok(translated)
}

/// The tools: glslc, spirv-cross and glslangValidator (each overridden by its environment variable).
pub struct Tools {
    glslc: String,
    spirv_cross: String,
    validator: String,
}

impl Tools {
    /// The tools by their names, or those of the variables GLSLC, SPIRV_CROSS and GLSLANG_VALIDATOR.
    pub fn from_environment() -> Self {
        let tool = |variable: &str, default: &str| std::env::var(variable).unwrap_or_else(|_| default.into());
        Self {
            glslc: tool("GLSLC", "glslc"),
            spirv_cross: tool("SPIRV_CROSS", "spirv-cross"),
            validator: tool("GLSLANG_VALIDATOR", "glslangValidator"),
        }
    }
}

/// Entry `relative` compiled with WEBGL and `macros` defined, translated and checked: its GLSL ES file.
fn translate_one(
    root: &Path,
    out: &Path,
    relative: &str,
    entry: &str,
    macros: &[&str],
    validate: bool,
    tools: &Tools,
) -> Result<PathBuf, String> {
    let spirv = out.join(format!("{entry}.spv"));
    // The stage stays the last extension, which glslangValidator reads the stage from.
    let stage = relative.rsplit('.').next().unwrap_or_default();
    let es =
        out.join(format!("{}{}.es.{stage}", relative.trim_end_matches(&format!(".{stage}")), &entry[relative.len()..]));
    std::fs::create_dir_all(spirv.parent().unwrap_or(out)).map_err(|e| format!("{}: {e}", out.display()))?;
    let mut compile = Command::new(&tools.glslc);
    compile.current_dir(root).args(GLSLC_OPTIONS).arg("-DWEBGL");
    compile.args(macros.iter().map(|m| format!("-D{m}")));
    run(
        compile.arg("-o").arg(&spirv).arg(relative),
        &format!("glslc could not compile shaders/{entry} with WEBGL defined"),
        "the Debian package glslc",
    )?;
    to_glsl_es(&spirv, &es, entry, validate, tools)?;
    Ok(es)
}

/// Translates the SPIR-V file `spirv` of entry `entry` (its stage the last extension of the file's name,
/// before any `+VARIANT`) to GLSL ES 3.00 in the file `es` (whose last extension must be the stage, which
/// glslangValidator reads), and checks it with glslangValidator when `validate` is set. Used at build time for
/// the renderer's entries and at run time for an analytic model's (src/webgl.rs).
pub fn to_glsl_es(spirv: &Path, es: &Path, entry: &str, validate: bool, tools: &Tools) -> Result<(), String> {
    let stage = entry.split('+').next().unwrap_or(entry).rsplit('.').next().unwrap_or_default();
    let mut translate = Command::new(&tools.spirv_cross);
    translate.args(["--es", "--version", "300", "--remove-unused-variables"]);
    // GLSL ES 3.00 matches a vertex shader's outputs to a fragment shader's inputs by name, not by
    // location as Vulkan does: each is renamed after its location.
    let direction = if stage == "vert" { "out" } else { "in" };
    for location in 0..INTERFACE_LOCATIONS {
        translate.args([
            "--rename-interface-variable",
            direction,
            &location.to_string(),
            &format!("location_{location}"),
        ]);
    }
    if stage == "vert" {
        translate.arg("--fixup-clipspace");
    }
    run(
        translate.arg("--output").arg(es).arg(spirv),
        &format!("SPIRV-Cross could not translate shaders/{entry} to GLSL ES 3.00"),
        "the Debian package spirv-cross",
    )?;
    if validate {
        run(
            Command::new(&tools.validator).arg(es),
            &format!("the translation of shaders/{entry} is not valid GLSL ES 3.00"),
            "the Debian package glslang-tools",
        )?;
    }
    Ok(())
}

/// Runs a tool: `failed` and the tool's own messages when it fails, naming `package` when it is missing.
fn run(command: &mut Command, failed: &str, package: &str) -> Result<(), String> {
    let program = command.get_program().to_string_lossy().into_owned();
    let output =
        command.output().map_err(|e| format!("cannot run {program} ({e}): install {package} (`make setup`)"))?;
    if output.status.success() {
        Ok(())
    } else {
        let said = [&output.stderr[..], &output.stdout[..]].map(String::from_utf8_lossy).join("\n");
        Err(format!("{failed}: {}", said.trim()))
    }
}

/// Every file under `dir`, its subfolders' too.
pub fn collect(dir: &Path, files: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).into_iter().flatten().flatten() {
        let path = entry.path();
        if path.is_dir() {
            collect(&path, files);
        } else {
            files.push(path);
        }
    }
}
