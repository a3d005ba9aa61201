//! The browser's shaders (WebGL2) made from the very sources the renderer compiles: every entry file under
//! shaders/ that says `// webgl` is compiled by glslc with WEBGL defined (which swaps what WebGL2 lacks for
//! what it has: shaders/common/scene.glsl), its SPIR-V translated by SPIRV-Cross to GLSL ES 3.00 (a vertex
//! shader's Vulkan depth range [0, w] made GL's [-w, w]), and the text checked by glslangValidator.
//! Specialization constants stay as SPIRV-Cross writes them (`SPIRV_CROSS_CONSTANT_ID_n` macros with their
//! defaults), which the page defines per program. An entry's variants (`// variant: A+B`, as build.rs
//! compiles them for the renderer) are translated too, as `FILE+A+B` (the environment's, WITH_ENVIRONMENT, in
//! its fast mode alone: common/environment.glsl). Used by build.rs, by the server for an analytic model's
//! entries (src/render/webgl.rs), and by the browser test, which translates shaders broken on purpose to show that its
//! comparison catches them.

use std::path::{Path, PathBuf};
use std::process::Command;

/// The entries that evaluate a material's BRDF in the browser's passes: the forward passes, and the probes
/// (the page's lobe and albedo of a model). An analytic model's are translated with it: on the server per
/// `.brdf` file (src/render/webgl.rs), and at build time as templates for the browser's own editor
/// ([`translate_templates`]).
pub const ANALYTIC_ENTRIES: [&str; 4] = ["forward.frag", "forward_sphere.frag", "web/probe.frag", "web/albedo.frag"];

/// The line of an analytic template that a model's GLSL ES replaces (`brdf_file::wrap` for WebGL: the
/// browser's editor runs it as WebAssembly), where the stand-in's `analytic_brdf` was.
pub const TEMPLATE_HOOK: &str = "// ANALYTIC_BRDF_HOOK";

/// The stand-in model the templates are translated with: `brdf/analytic.glsl` with only `analytic_brdf`,
/// which reads the parameter values and sets `analytic_stopped`, so that SPIRV-Cross keeps both (and the
/// block) for the model that takes its place.
const STAND_IN_MODEL: &str =
    "#ifndef BRDF_ANALYTIC_GLSL\n#define BRDF_ANALYTIC_GLSL\nvec3 analytic_brdf(uint first, vec3 n, \
                              vec3 t, vec3 wi, vec3 wo) {\n    analytic_stopped = false;\n    return \
                              vec3(analytic_parameter(first));\n}\n#endif\n";

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
            let es = translate_one(root, out, &relative, &entry, &macros, None, validate, &tools)?;
            translated.push((entry, es));
        }
    }
    Ok(translated)
}

/// The tools: glslc, spirv-cross and glslangValidator (each overridden by its environment variable).
pub struct Tools {
    glslc: String,
    spirv_cross: String,
    /// glslangValidator's name (the tests check texts with it too).
    pub validator: String,
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

/// The analytic templates of the browser's editor: each of [`ANALYTIC_ENTRIES`] and its variants but the
/// environment's (a model's fast mode under an environment needs its albedo table, which only the server
/// makes), compiled with WEBGL, ANALYTIC_BRDF and the stand-in model, translated and checked, then its
/// `analytic_brdf` cut out for [`TEMPLATE_HOOK`], followed by a `#line` that gives the lines after it their own
/// numbers again (GLSL ES: the next line's number and source string 0), whatever the model's text holds. Each
/// entry's name (`forward.frag+TERM_VIEWS`) with its template's file.
pub fn translate_templates(root: &Path, out: &Path, validate: bool) -> Result<Vec<(String, PathBuf)>, String> {
    let tools = Tools::from_environment();
    let includes = out.join("stand-in");
    let stand_in = includes.join("brdf/analytic.glsl");
    std::fs::create_dir_all(includes.join("brdf")).map_err(|e| format!("{}: {e}", includes.display()))?;
    std::fs::write(&stand_in, STAND_IN_MODEL).map_err(|e| format!("{}: {e}", stand_in.display()))?;
    let mut templates = Vec::new();
    for relative in ANALYTIC_ENTRIES {
        let file = root.join(relative);
        let text = std::fs::read_to_string(&file).map_err(|e| format!("{}: {e}", file.display()))?;
        let variants = variants(&text).filter(|v| !v.split('+').any(|m| m == "WITH_ENVIRONMENT"));
        for variant in std::iter::once(None).chain(variants.map(Some)) {
            let mut macros: Vec<&str> = variant.iter().flat_map(|v| v.split('+')).collect();
            macros.push("ANALYTIC_BRDF");
            let entry = variant.map_or(relative.to_string(), |v| format!("{relative}+{v}"));
            let es = translate_one(
                root,
                out,
                relative,
                &format!("{entry}+ANALYTIC_BRDF"),
                &macros,
                Some(&includes),
                validate,
                &tools,
            )?;
            let translated = std::fs::read_to_string(&es).map_err(|e| format!("{}: {e}", es.display()))?;
            let template = out.join(format!("{entry}.template.es.frag"));
            let cut = cut_stand_in(&translated)
                .ok_or_else(|| format!("the translation of shaders/{entry} has no `analytic_brdf` to cut"))?;
            std::fs::write(&template, cut).map_err(|e| format!("{}: {e}", template.display()))?;
            templates.push((entry, template));
        }
    }
    Ok(templates)
}

/// `es` with the stand-in's `analytic_brdf` (its first line to the `}` that closes it) replaced by
/// [`TEMPLATE_HOOK`] and a `#line` directive; `None` where it has none.
fn cut_stand_in(es: &str) -> Option<String> {
    let lines: Vec<&str> = es.lines().collect();
    let start = lines.iter().position(|line| line.contains(" analytic_brdf(") && !line.trim_end().ends_with(';'))?;
    let end = start + lines[start..].iter().position(|line| *line == "}")?;
    let mut out: Vec<String> = lines[..start].iter().map(|l| l.to_string()).collect();
    out.push(TEMPLATE_HOOK.to_string());
    // The directive is line start + 2 (from 1); the line after it is numbered start + 3 in the template.
    out.push(format!("#line {} 0", start + 3));
    out.extend(lines[end + 1..].iter().map(|l| l.to_string()));
    Some(out.join("\n") + "\n")
}

/// Entry `relative` compiled with WEBGL and `macros` defined (and `includes` searched after shaders/),
/// translated and checked: its GLSL ES file.
#[allow(clippy::too_many_arguments)]
fn translate_one(
    root: &Path,
    out: &Path,
    relative: &str,
    entry: &str,
    macros: &[&str],
    includes: Option<&Path>,
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
    if let Some(folder) = includes {
        compile.arg("-I").arg(folder);
    }
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
/// the renderer's entries and at run time for an analytic model's (src/render/webgl.rs).
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
