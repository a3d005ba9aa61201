//! GLSL to SPIR-V with shaderc, and shader modules.
//!
//! The sources of shaders/ are embedded in the binary at build time with their SPIR-V (build.rs compiles
//! them with glslc): a compiler of those very sources hands out that SPIR-V, and compiles any others (a
//! `--shaders` folder, hot reloading, a test's broken BRDF) with shaderc. `#include "common/math.glsl"` is
//! resolved against the shaders/ root (or the including file's folder first); `double/FILE` is FILE made
//! double (`brdf_file::shader_in_double`), which the built-in models' integrals include.

use std::collections::BTreeMap;
use std::sync::Arc;

use ash::vk;

use super::Device;
use crate::error::{Error, Result};

/// Every file under shaders/, by path relative to it.
const EMBEDDED: &[(&str, &str)] = include!(concat!(env!("OUT_DIR"), "/shaders.rs"));

/// The SPIR-V of every entry file of [`EMBEDDED`], compiled at build time.
const PRECOMPILED: &[(&str, &[u8])] = include!(concat!(env!("OUT_DIR"), "/spirv.rs"));

/// The GLSL sources a compiler reads: those embedded at build time, of which any may be replaced.
#[derive(Clone, Debug, PartialEq)]
pub struct ShaderSources {
    files: BTreeMap<String, String>,
}

impl Default for ShaderSources {
    fn default() -> Self {
        Self { files: EMBEDDED.iter().map(|(path, text)| ((*path).to_string(), (*text).to_string())).collect() }
    }
}

impl ShaderSources {
    /// Replaces (or adds) one file, e.g. a deliberately broken BRDF in a test.
    pub fn with_file(mut self, path: &str, text: impl Into<String>) -> Self {
        self.files.insert(path.to_string(), text.into());
        self
    }

    /// `from` replaced by `to` in one file (a variant of the shaders: `vk-render check`'s mistakes).
    ///
    /// # Errors
    /// A message when the file is not there or `from` is not in it exactly once.
    pub fn with_replaced(mut self, path: &str, from: &str, to: &str) -> std::result::Result<Self, String> {
        let text = self.files.get_mut(path).ok_or_else(|| format!("shaders/{path}: no such shader"))?;
        if text.matches(from).count() != 1 {
            return Err(format!("shaders/{path}: {from:?} is not in it exactly once"));
        }
        *text = text.replacen(from, to, 1);
        Ok(self)
    }

    /// Every file under `folder` (a shaders/ folder on disk, read for hot reloading).
    ///
    /// # Errors
    /// The I/O error of a file or folder that cannot be read.
    pub fn from_directory(folder: &std::path::Path) -> std::io::Result<Self> {
        fn walk(
            root: &std::path::Path,
            dir: &std::path::Path,
            files: &mut BTreeMap<String, String>,
        ) -> std::io::Result<()> {
            for entry in std::fs::read_dir(dir)? {
                let path = entry?.path();
                if path.is_dir() {
                    walk(root, &path, files)?;
                } else {
                    let relative = path.strip_prefix(root).unwrap_or(&path).to_string_lossy().replace('\\', "/");
                    let text = crate::files::read_regular_text(&path, "shader", crate::files::MAX_SHADER_BYTES)
                        .map_err(std::io::Error::other)?;
                    files.insert(relative, text);
                }
            }
            Ok(())
        }
        let mut files = BTreeMap::new();
        walk(folder, folder, &mut files)?;
        Ok(Self { files })
    }

    /// The paths of every file, relative to shaders/.
    pub fn paths(&self) -> impl Iterator<Item = &str> {
        self.files.keys().map(String::as_str)
    }

    /// The text of the file at `path` (relative to shaders/), if there is one.
    pub fn text(&self, path: &str) -> Option<&str> {
        self.files.get(path).map(String::as_str)
    }

    /// The file at `path` and every file it includes, directly or through another (`#include "FILE"` lines,
    /// relative to shaders/): all that an edit can reach through it.
    pub fn included_by(&self, path: &str) -> std::collections::BTreeSet<String> {
        let mut found = std::collections::BTreeSet::new();
        let mut next = vec![path.to_string()];
        while let Some(file) = next.pop() {
            let Some(text) = self.text(&file) else { continue };
            if !found.insert(file.clone()) {
                continue;
            }
            next.extend(
                text.lines().filter_map(|line| brdf_file::included_file(line).map(|(file, _)| file.to_string())),
            );
        }
        found
    }

    /// Whether these are the sources embedded at build time, unchanged.
    fn are_embedded(&self) -> bool {
        self.files.len() == EMBEDDED.len() && EMBEDDED.iter().all(|(path, text)| self.text(path) == Some(*text))
    }
}

/// Compiles GLSL entry files of shaders/ to SPIR-V.
pub struct ShaderCompiler {
    /// `None` for the embedded sources, whose SPIR-V was compiled at build time.
    compiler: Option<shaderc::Compiler>,
    sources: Arc<ShaderSources>,
}

impl ShaderCompiler {
    /// A compiler reading `sources`.
    ///
    /// # Errors
    /// `Error::Shader` if shaderc cannot start (for sources other than the embedded ones).
    pub fn new(sources: ShaderSources) -> Result<Self> {
        let compiler = if sources.are_embedded() {
            None
        } else {
            Some(shaderc::Compiler::new().map_err(|e| Error::Shader {
                path: "(shaderc)".into(),
                log: format!("shaderc could not start: {e}"),
            })?)
        };
        Ok(Self { compiler, sources: Arc::new(sources) })
    }

    /// The sources it reads.
    pub fn sources(&self) -> &ShaderSources {
        &self.sources
    }

    /// The SPIR-V of one entry file (its stage from the extension: .vert, .frag, .comp), or of one of its
    /// variants, `FILE+MACRO` or `FILE+MACRO+OTHER`: the file compiled with those macros defined (the file
    /// names the variant in a line `// variant: MACRO+OTHER`).
    ///
    /// # Errors
    /// `Error::Shader` naming the file, with shaderc's log (file:line: error: ...).
    pub fn compile(&self, path: &str) -> Result<Vec<u32>> {
        match &self.compiler {
            Some(compiler) => self.compile_glsl(compiler, path, None),
            None => {
                PRECOMPILED.iter().find(|(entry, _)| *entry == path).map(|(_, bytes)| spirv_words(bytes)).ok_or_else(
                    || Error::Shader { path: path.to_string(), log: "no such entry file under shaders/".into() },
                )
            }
        }
    }

    /// The SPIR-V of an entry file (or variant, as [`ShaderCompiler::compile`] takes them) with an analytic
    /// model: ANALYTIC_BRDF defined and `brdf/analytic.glsl` the model's GLSL (`analytic_glsl`, made by
    /// `AnalyticModel`), compiled by shaderc at run time whatever the sources.
    ///
    /// # Errors
    /// `Error::Shader` naming the entry file, with shaderc's log (a model's own mistakes are found when it is
    /// loaded, so this is vk-render's).
    pub fn compile_analytic(&self, entry: &str, analytic_glsl: &str) -> Result<Vec<u32>> {
        let error = |log: String| Error::Shader { path: entry.to_string(), log };
        let started;
        let compiler = match &self.compiler {
            Some(compiler) => compiler,
            None => {
                started = shaderc::Compiler::new().map_err(|e| error(format!("shaderc could not start: {e}")))?;
                &started
            }
        };
        self.compile_glsl(compiler, &format!("{entry}+ANALYTIC_BRDF"), Some(analytic_glsl))
    }

    /// Compiles `entry` (FILE or FILE+MACRO+...) with shaderc, `brdf/analytic.glsl` being `analytic_glsl`
    /// when given.
    fn compile_glsl(&self, compiler: &shaderc::Compiler, entry: &str, analytic_glsl: Option<&str>) -> Result<Vec<u32>> {
        let error = |log: String| Error::Shader { path: entry.to_string(), log };
        let (path, variant) = match entry.split_once('+') {
            Some((path, variant)) => (path, Some(variant)),
            None => (entry, None),
        };
        let stage = match path.rsplit('.').next() {
            Some("vert") => shaderc::ShaderKind::Vertex,
            Some("frag") => shaderc::ShaderKind::Fragment,
            Some("comp") => shaderc::ShaderKind::Compute,
            _ => return Err(error("unknown shader stage (expected .vert, .frag or .comp)".into())),
        };
        let text = self.sources.text(path).ok_or_else(|| error("no such file under shaders/".into()))?;
        let mut options =
            shaderc::CompileOptions::new().map_err(|e| error(format!("shaderc options could not be made: {e}")))?;
        options.set_target_env(shaderc::TargetEnv::Vulkan, shaderc::EnvVersion::Vulkan1_3 as u32);
        for name in variant.iter().flat_map(|names| names.split('+')) {
            options.add_macro_definition(name, None);
        }
        // SPIR-V 1.5: at 1.6 glslang declares workgroup sizes with LocalSizeId, which needs the maintenance4
        // feature, and the validation layer of Debian 12 reports it even when the feature is enabled.
        options.set_target_spirv(shaderc::SpirvVersion::V1_5);
        // No debug info (line tables, source text): its file names are the only thing in which glslc, at
        // build time, and this compiler differ ("./brdf/x.glsl" against "brdf/x.glsl"). Names are kept.
        let sources = self.sources.clone();
        let analytic = analytic_glsl.map(str::to_string);
        options.set_include_callback(move |requested, _kind, requesting, _depth| {
            let beside = match requesting.rsplit_once('/') {
                Some((folder, _)) => format!("{folder}/{requested}"),
                None => requested.to_string(),
            };
            [beside, requested.to_string()]
                .into_iter()
                .find_map(|candidate| {
                    let content = match (&analytic, candidate.as_str()) {
                        (Some(glsl), ANALYTIC_FILE) => Some(glsl.clone()),
                        // A file made double (brdf_density64.comp's built-in models), from these sources.
                        _ => match candidate.strip_prefix(brdf_file::DOUBLE_FOLDER) {
                            Some(path) => sources.text(path).map(brdf_file::shader_in_double),
                            None => sources.text(&candidate).map(str::to_string),
                        },
                    };
                    content.map(|content| shaderc::ResolvedInclude { resolved_name: candidate.clone(), content })
                })
                .ok_or_else(|| format!("cannot find {requested} under shaders/"))
        });
        let artifact =
            compiler.compile_into_spirv(text, stage, path, "main", Some(&options)).map_err(|e| error(e.to_string()))?;
        if artifact.get_num_warnings() > 0 {
            log::warn!("{path}: {}", artifact.get_warning_messages());
        }
        Ok(artifact.as_binary().to_vec())
    }
}

/// The file an analytic model's GLSL is included as (by `common/analytic.glsl`).
const ANALYTIC_FILE: &str = "brdf/analytic.glsl";

/// SPIR-V words from the bytes glslc wrote (in this machine's byte order, as it made them here).
fn spirv_words(bytes: &[u8]) -> Vec<u32> {
    bytes.chunks_exact(4).map(|w| u32::from_ne_bytes([w[0], w[1], w[2], w[3]])).collect()
}

/// A shader module, destroyed in Drop.
pub struct ShaderModule {
    /// The Vulkan handle.
    pub raw: vk::ShaderModule,
    device: Arc<Device>,
}

impl Device {
    /// Creates a shader module from SPIR-V words.
    ///
    /// # Errors
    /// `Error::Vulkan` if the driver refuses the module.
    pub fn create_shader_module(self: &Arc<Self>, spirv: &[u32], name: &str) -> Result<ShaderModule> {
        let info = vk::ShaderModuleCreateInfo::default().code(spirv);
        // SAFETY: the device is alive and the code is SPIR-V from shaderc.
        let raw = unsafe { self.raw.create_shader_module(&info, None)? };
        self.set_name(raw, name);
        Ok(ShaderModule { raw, device: self.clone() })
    }
}

impl Drop for ShaderModule {
    fn drop(&mut self) {
        if self.device.is_given_up() {
            return; // work that never ended may still use it (Device::give_up)
        }
        // SAFETY: modules are only needed while pipelines are created.
        unsafe { self.device.raw.destroy_shader_module(self.raw, None) };
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_entry_shader_compiles() {
        let sources = ShaderSources::default();
        let entries: Vec<String> = sources
            .paths()
            .filter(|p| p.ends_with(".vert") || p.ends_with(".frag") || p.ends_with(".comp"))
            // shaders/web/ is the browser's alone, compiled and translated by build.rs (build/webgl.rs).
            .filter(|p| !p.starts_with("web/"))
            .map(String::from)
            .collect();
        assert!(entries.len() >= 2, "{entries:?}");
        let compiler = ShaderCompiler::new(sources).unwrap();
        for entry in entries {
            let spirv = compiler.compile(&entry).unwrap_or_else(|e| panic!("{e}"));
            assert_eq!(spirv[0], 0x0723_0203, "{entry} is not SPIR-V");
        }
    }

    #[test]
    fn the_spirv_compiled_at_build_time_is_the_run_time_compilers() {
        // A source tree on disk is compiled by shaderc (a copy with one more file, so that it is not the
        // embedded one), and must give glslc's words exactly: one compiler behind both.
        let runtime = ShaderCompiler::new(ShaderSources::default().with_file("unused.glsl", "")).unwrap();
        assert!(runtime.compiler.is_some());
        assert!(ShaderCompiler::new(ShaderSources::default()).unwrap().compiler.is_none());
        assert!(PRECOMPILED.len() >= 7, "{}", PRECOMPILED.len());
        for (entry, bytes) in PRECOMPILED {
            assert!(runtime.compile(entry).unwrap() == spirv_words(bytes), "{entry}: glslc and shaderc differ");
        }
    }

    #[test]
    fn a_compile_error_names_the_included_file_and_line() {
        let broken = "#ifndef BRDF_LAMBERT_GLSL\n#define BRDF_LAMBERT_GLSL\n#include \"common/math.glsl\"\n\
                      vec3 lambert(vec3 kd) { return kd * ; }\n#endif\n";
        let sources = ShaderSources::default().with_file("brdf/lambert.glsl", broken);
        let compiler = ShaderCompiler::new(sources).unwrap();
        let message = compiler.compile("forward.frag").unwrap_err().to_string();
        assert!(message.contains("forward.frag"), "{message}");
        assert!(message.contains("brdf/lambert.glsl:4:"), "{message}");
    }

    #[test]
    fn the_shaders_folder_reads_as_the_embedded_sources() {
        let folder = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("shaders");
        assert_eq!(ShaderSources::from_directory(&folder).unwrap(), ShaderSources::default());
    }

    #[test]
    fn a_missing_include_is_named() {
        let sources = ShaderSources::default()
            .with_file("test.frag", "#version 460\n#include \"nowhere.glsl\"\nvoid main() {}\n");
        let message = ShaderCompiler::new(sources).unwrap().compile("test.frag").unwrap_err().to_string();
        assert!(message.contains("test.frag") && message.contains("nowhere.glsl"), "{message}");
    }
}
