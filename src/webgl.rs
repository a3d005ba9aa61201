//! The browser's shaders (WebGL2, GLSL ES 3.00), made from the renderer's own sources by the translation of
//! [`translation`] (build/webgl.rs): the renderer's entries at build time (build.rs), and an analytic model's
//! at run time ([`analytic_shaders`]): a `.brdf` file is read when a scene is, so its shaders cannot be
//! translated before.

#[path = "../build/webgl.rs"]
pub mod translation;

use std::collections::BTreeMap;
use std::sync::atomic::{AtomicU64, Ordering};

use crate::brdf::AnalyticModel;
use crate::error::{Error, Result};
use crate::vulkan::{ShaderCompiler, ShaderSources};

/// The entries that evaluate a material's BRDF in the browser's passes: the forward passes.
pub const ANALYTIC_ENTRIES: [&str; 2] = ["forward.frag", "forward_sphere.frag"];

/// `model`'s browser shaders: each of [`ANALYTIC_ENTRIES`] and its variants (as
/// [`translation::translate`] translates them), by entry name (`forward.frag+TERM_VIEWS`), compiled from `sources`
/// (the embedded ones but in a test) by shaderc with WEBGL and ANALYTIC_BRDF defined, translated by
/// SPIRV-Cross and checked by glslangValidator. Most of a second of work: its caller keeps what it made.
///
/// # Errors
/// `Error::Shader` naming the entry: shaderc's log, or the tool's messages (a tool that is not installed is
/// named with its Debian package).
pub fn analytic_shaders(model: &AnalyticModel, sources: &ShaderSources) -> Result<BTreeMap<String, String>> {
    let compiler = ShaderCompiler::new(sources.clone())?;
    let tools = translation::Tools::from_environment();
    let folder = Scratch::new()?;
    let mut shaders = BTreeMap::new();
    for entry in ANALYTIC_ENTRIES {
        let text = sources.text(entry).unwrap_or_default();
        for variant in std::iter::once(None).chain(translation::variants(text).map(Some)) {
            let name = variant.map_or(entry.to_string(), |v| format!("{entry}+{v}"));
            let with_webgl = format!("{entry}+WEBGL{}", variant.map_or(String::new(), |v| format!("+{v}")));
            let spirv = compiler.compile_analytic(&with_webgl, model.glsl())?;
            let error = |log: String| Error::Shader { path: name.clone(), log };
            let spirv_file = folder.0.join("entry.spv");
            let stage = entry.rsplit('.').next().unwrap_or_default();
            let es_file = folder.0.join(format!("entry.es.{stage}"));
            std::fs::write(&spirv_file, spirv.iter().flat_map(|w| w.to_ne_bytes()).collect::<Vec<u8>>())
                .map_err(|e| error(format!("{}: {e}", spirv_file.display())))?;
            translation::to_glsl_es(&spirv_file, &es_file, &name, true, &tools).map_err(error)?;
            let es = std::fs::read_to_string(&es_file).map_err(|e| error(format!("{}: {e}", es_file.display())))?;
            shaders.insert(name, es);
        }
    }
    Ok(shaders)
}

/// A folder of its own under the temporary folder for the tools' files, removed in Drop.
struct Scratch(std::path::PathBuf);

impl Scratch {
    fn new() -> Result<Self> {
        static NEXT: AtomicU64 = AtomicU64::new(0);
        let name = format!("vk-render-webgl-{}-{}", std::process::id(), NEXT.fetch_add(1, Ordering::Relaxed));
        let path = std::env::temp_dir().join(name);
        std::fs::create_dir_all(&path)
            .map_err(|e| Error::Shader { path: "(translation)".into(), log: format!("{}: {e}", path.display()) })?;
        Ok(Self(path))
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}
