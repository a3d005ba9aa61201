//! The browser's shaders (WebGL2, GLSL ES 3.00), made from the renderer's own sources by the translation of
//! [`translation`] (build/webgl.rs): the renderer's entries at build time (build.rs), and an analytic model's
//! at run time ([`analytic_shaders`]): a `.brdf` file is read when a scene is, so its shaders cannot be
//! translated before.

#[path = "../../build/webgl.rs"]
pub mod translation;

use std::collections::BTreeMap;
use std::sync::atomic::{AtomicU64, Ordering};

use crate::brdf::AnalyticModel;
use crate::error::{Error, Result};
use crate::vulkan::{ShaderCompiler, ShaderSources};

pub use translation::{ANALYTIC_ENTRIES, TEMPLATE_HOOK};

/// The analytic templates of the browser's editor, by entry (`forward.frag+TERM_VIEWS`): the entry's GLSL ES
/// with [`TEMPLATE_HOOK`] where a model's goes (translated by build.rs: [`translation::translate_templates`]).
/// The page puts a student's model there, wrapped by the same code as the renderer's (`brdf_file::wrap` for
/// WebGL, run as WebAssembly), and its browser compiles it.
pub const ANALYTIC_TEMPLATES: &[(&str, &str)] = include!(concat!(env!("OUT_DIR"), "/webgl_templates.rs"));

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

#[cfg(test)]
mod tests {
    use super::*;

    /// Every shipped `.brdf` model wrapped for WebGL and put into every template is valid GLSL ES 3.00
    /// (glslangValidator), its lines numbered as the file's (source string 1); a model that uses a name it
    /// never declared is refused at its own line.
    #[test]
    fn every_shipped_model_in_every_template_is_valid_glsl_es() {
        let folder = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/brdfs");
        let scratch = Scratch::new().unwrap();
        let tools = translation::Tools::from_environment();
        assert_eq!(ANALYTIC_TEMPLATES.len(), 6, "forward and forward_sphere, each with its term views; the probes");
        let mut files: Vec<_> = std::fs::read_dir(&folder).unwrap().map(|e| e.unwrap().path()).collect();
        files.sort();
        for path in files {
            let text = std::fs::read_to_string(&path).unwrap();
            let file = brdf_file::parse(&text).unwrap();
            let glsl =
                brdf_file::wrap(&file.parameters, &file.shader, &file.sampler, brdf_file::Target::WebGl).unwrap();
            for (entry, template) in ANALYTIC_TEMPLATES {
                assert_eq!(template.matches(TEMPLATE_HOOK).count(), 1, "{entry}");
                let es = scratch.0.join("model.frag");
                std::fs::write(&es, template.replace(TEMPLATE_HOOK, &glsl)).unwrap();
                let status = std::process::Command::new(&tools.validator).arg(&es).output().unwrap();
                let said = String::from_utf8_lossy(&status.stdout);
                assert!(status.status.success(), "{} in {entry}: {said}", path.display());
            }
        }
        let undeclared = "analytic\n::begin shader\nvec3 BRDF(vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y)\n{\n    return \
                          vec3(nope);\n}\n::end shader\n";
        let file = brdf_file::parse(undeclared).unwrap();
        let glsl = brdf_file::wrap(&file.parameters, &file.shader, &file.sampler, brdf_file::Target::WebGl).unwrap();
        let es = scratch.0.join("undeclared.frag");
        std::fs::write(&es, ANALYTIC_TEMPLATES[0].1.replace(TEMPLATE_HOOK, &glsl)).unwrap();
        let status = std::process::Command::new(&tools.validator).arg(&es).output().unwrap();
        assert!(!status.status.success());
        let error = brdf_file::file_error(&String::from_utf8_lossy(&status.stdout), brdf_file::Target::WebGl);
        assert_eq!((error.line, error.message.as_str()), (Some(5), "GLSL: 'nope' : undeclared identifier"));
    }
}
