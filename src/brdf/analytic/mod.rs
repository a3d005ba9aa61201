//! Analytic BRDFs written by users: BRDF Explorer's `.brdf` files (wdas/brdf), each a list of parameters and a
//! GLSL function `vec3 BRDF(vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y)` returning f_r without the cosine.
//!
//! A file is read and its shader wrapped for vk-render's shaders by the crate [`brdf_file`] (the file's names
//! moved out of vk-render's, each line at its own line; the browser's editor runs the same code as
//! WebAssembly), and compiled once on its own, so that a mistake in it is
//! one line naming the file's line when the scene is loaded. On the GPU the model is one more case of
//! `brdf_eval` (`shaders/common/brdf.glsl`), compiled at run time into the pipelines that draw it; a
//! material's parameter values live in a buffer, so that changing one never compiles anything again. The
//! shipped models of `assets/brdfs/` have Rust mirrors ([`mirrors`]), which the CPU reference shades with.
//!
//! A `.brdf` file is code that runs on the device: load only files you trust.

pub mod mirrors;

use std::fmt;
use std::hash::{Hash, Hasher};
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex, Weak};

use glam::Vec3;

use brdf_file::{shortened, ParseError, Target};
pub use brdf_file::{Parameter, ParameterKind, ParameterValue, PREFIX};

/// One `.brdf` file, read and checked: its parameters and its shader wrapped for vk-render's.
pub struct AnalyticModel {
    /// The file, as the scene named it (relative to the scene file's folder).
    pub path: PathBuf,
    /// The parameters it declares, in the file's order.
    pub parameters: Vec<Parameter>,
    /// What loads but will not do what the file may mean (a `#define` dropped, a section vk-render does not
    /// read), one line each naming the file and the line.
    pub warnings: Vec<String>,
    /// The file's text.
    source: String,
    /// `brdf/analytic.glsl` of this model (see [`brdf_file::wrap`]).
    glsl: String,
    /// The same in double precision (see [`brdf_file::wrap_double`]).
    glsl_double: String,
    /// A hash of `glsl`: what compiled shaders and pipelines are kept by.
    key: u64,
    /// Whether the file has an importance sampler (its isFunc section).
    has_sampler: bool,
}

impl fmt::Debug for AnalyticModel {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "AnalyticModel({:?})", self.path)
    }
}

/// The models loaded in this process, by file and text, so that every object and scene that names the same
/// unchanged file shares one model (and its shaders are compiled once).
static LOADED: Mutex<Vec<Weak<AnalyticModel>>> = Mutex::new(Vec::new());

impl AnalyticModel {
    /// Reads `path`, checks it and compiles its GLSL on its own.
    ///
    /// # Errors
    /// One line naming the file and, where it has one, its line: `ward.brdf:12: ...`.
    pub fn load(path: &Path) -> Result<Arc<AnalyticModel>, String> {
        let source = crate::files::read_regular_text(path, "BRDF file", crate::files::MAX_SHADER_BYTES)?;
        let mut loaded = LOADED.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
        loaded.retain(|model| model.strong_count() > 0);
        if let Some(model) = loaded.iter().filter_map(Weak::upgrade).find(|m| m.path == path && m.source == source) {
            return Ok(model);
        }
        let model = Arc::new(Self::from_text(path, source)?);
        loaded.push(Arc::downgrade(&model));
        Ok(model)
    }

    /// A model from the text of a file at `path` (named in messages).
    ///
    /// # Errors
    /// As [`AnalyticModel::load`].
    pub fn from_text(path: &Path, source: String) -> Result<AnalyticModel, String> {
        let at = |error: ParseError| match error.line {
            Some(line) => format!("{}:{line}: {}", path.display(), error.message),
            None => format!("{}: {}", path.display(), error.message),
        };
        let file = brdf_file::parse(&source).map_err(at)?;
        let glsl = brdf_file::wrap(&file.parameters, &file.shader, &file.sampler, Target::Vulkan).map_err(at)?;
        let glsl_double = brdf_file::wrap_double(&file.parameters, &file.shader, &file.sampler).map_err(at)?;
        compile_alone(&glsl).map_err(at)?;
        let mut hasher = std::collections::hash_map::DefaultHasher::new();
        glsl.hash(&mut hasher);
        let warnings = file.warnings.iter().map(|w| format!("{}: {w}", path.display())).collect();
        let has_sampler = !file.sampler.is_empty();
        Ok(Self {
            path: path.to_path_buf(),
            parameters: file.parameters,
            warnings,
            source,
            glsl,
            glsl_double,
            key: hasher.finish(),
            has_sampler,
        })
    }

    /// `brdf/analytic.glsl` for the shaders that evaluate this model.
    pub fn glsl(&self) -> &str {
        &self.glsl
    }

    /// `brdf/analytic.glsl` for `brdf_density64.comp`, which evaluates this model in double precision (it may
    /// not compile: a file that reads a float's bits has no double form).
    pub fn glsl_double(&self) -> &str {
        &self.glsl_double
    }

    /// What compiled shaders and pipelines of this model are kept by: two models with the same key compile
    /// to the same shaders.
    pub fn key(&self) -> u64 {
        self.key
    }

    /// Whether the file has an importance sampler of its own (`sampleBRDF` and `pdfBRDF` in its isFunc
    /// section), which the exact environment mode draws from and `vk-render sampling` tests.
    pub fn has_sampler(&self) -> bool {
        self.has_sampler
    }

    /// The file's text.
    pub fn source(&self) -> &str {
        &self.source
    }

    /// The file's name without its folder, for titles and legends.
    pub fn name(&self) -> String {
        self.path.file_name().map_or_else(|| self.path.display().to_string(), |n| n.to_string_lossy().into_owned())
    }

    /// The parameter named `name`.
    pub fn parameter(&self, name: &str) -> Option<&Parameter> {
        self.parameters.iter().find(|p| p.name == name)
    }
}

/// Compiles a model's GLSL in a translation unit of its own ([`brdf_file::check_unit`]).
fn compile_alone(wrapper: &str) -> Result<(), ParseError> {
    let failed = |message: String| ParseError { line: None, message };
    let compiler = shaderc::Compiler::new().map_err(|e| failed(format!("shaderc could not start: {e}")))?;
    let mut options =
        shaderc::CompileOptions::new().map_err(|e| failed(format!("shaderc options could not be made: {e}")))?;
    options.set_target_env(shaderc::TargetEnv::Vulkan, shaderc::EnvVersion::Vulkan1_3 as u32);
    options.set_target_spirv(shaderc::SpirvVersion::V1_5);
    let unit = brdf_file::check_unit(wrapper);
    match compiler.compile_into_spirv(&unit, shaderc::ShaderKind::Compute, "brdf/analytic.glsl", "main", Some(&options))
    {
        Ok(_) => Ok(()),
        Err(e) => Err(brdf_file::file_error(&e.to_string(), Target::Vulkan)),
    }
}

/// A material of an analytic model: the model and a value for each of its parameters. The values are shared
/// between clones (a fit's probe holds one per sample: a clone is two counts, not an allocation).
#[derive(Clone)]
pub struct Analytic {
    model: Arc<AnalyticModel>,
    values: Arc<Vec<ParameterValue>>,
}

impl PartialEq for Analytic {
    fn eq(&self, other: &Self) -> bool {
        let same_model = Arc::ptr_eq(&self.model, &other.model) || self.model.key == other.model.key;
        same_model && (Arc::ptr_eq(&self.values, &other.values) || self.values == other.values)
    }
}

impl fmt::Debug for Analytic {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "Analytic({:?}, {})", self.model.path, self.describe())
    }
}

impl Analytic {
    /// The model with every parameter at its default.
    pub fn defaults(model: Arc<AnalyticModel>) -> Self {
        let values = Arc::new(model.parameters.iter().map(|p| p.kind.default_value()).collect());
        Self { model, values }
    }

    /// The model.
    pub fn model(&self) -> &Arc<AnalyticModel> {
        &self.model
    }

    /// Each parameter with its value, in the file's order.
    pub fn values(&self) -> impl Iterator<Item = (&Parameter, ParameterValue)> {
        self.model.parameters.iter().zip(self.values.iter().copied())
    }

    /// The value of the parameter `name`.
    pub fn value(&self, name: &str) -> Option<ParameterValue> {
        self.model.parameters.iter().position(|p| p.name == name).map(|i| self.values[i])
    }

    /// The same material with `name` set to `value`, which must be of the parameter's type and, for a
    /// float, within its range.
    ///
    /// # Errors
    /// A message saying what the parameter is: `= 1.5: outside [0, 1], the range ward.brdf gives alpha_x (line
    /// 3)`; or that the file has no such parameter, naming those it has.
    pub fn with(mut self, name: &str, value: ParameterValue) -> Result<Self, String> {
        let model = self.model.clone();
        let Some(index) = model.parameters.iter().position(|p| p.name == name) else {
            let names: Vec<&str> = model.parameters.iter().map(|p| p.name.as_str()).collect();
            let names = if names.is_empty() { "none".to_string() } else { names.join(", ") };
            return Err(format!(": {} has no parameter `{}` (it has {names})", model.name(), shortened(name)));
        };
        let parameter = &model.parameters[index];
        let file = format!("{} (line {})", model.name(), parameter.line);
        let value = match (parameter.kind, value) {
            (ParameterKind::Float { min, max, .. }, ParameterValue::Float(v)) => {
                if !(v.is_finite() && (min..=max).contains(&v)) {
                    return Err(format!(" = {v}: outside [{min}, {max}], the range {file} gives {name}"));
                }
                value
            }
            (ParameterKind::Bool { .. }, ParameterValue::Bool(_)) => value,
            (ParameterKind::Color { .. }, ParameterValue::Color(c)) => {
                if !c.is_finite() {
                    return Err(format!(" = {value}: every component must be a finite number"));
                }
                value
            }
            (kind, given) => {
                let given_type = match given {
                    ParameterValue::Float(_) => "a number",
                    ParameterValue::Bool(_) => "true or false",
                    ParameterValue::Color(_) => "a colour",
                };
                let wanted = match kind {
                    ParameterKind::Float { .. } => "a number",
                    ParameterKind::Bool { .. } => "true or false (or 0 or 1)",
                    ParameterKind::Color { .. } => "a colour: three numbers, or one for a grey",
                };
                return Err(format!(
                    " = {given}: {name} is a {} parameter of {file}: it takes {wanted}, not {given_type}",
                    kind.type_name()
                ));
            }
        };
        Arc::make_mut(&mut self.values)[index] = value;
        Ok(self)
    }

    /// The values as the parameter buffer holds them, in the file's order: a float, a bool as 0 or 1, a
    /// colour's three components (`analytic_brdf` of the model's GLSL reads them so).
    pub fn floats(&self) -> Vec<f32> {
        let mut floats = Vec::with_capacity(self.values.len() + 2);
        for value in self.values.iter() {
            value.extend_floats(&mut floats);
        }
        floats
    }

    /// The file's name and every value: `ward.brdf alpha_x 0.1 alpha_y 0.35 ...`.
    pub fn describe(&self) -> String {
        let mut text = self.model.name();
        for (parameter, value) in self.values() {
            text.push_str(&format!(" {} {value}", parameter.name));
        }
        text
    }

    /// f_r(wi, wo) at a surface of normal n and tangent t (X = t, Y = n x t) by the model's Rust mirror, for
    /// the models shipped in `assets/brdfs/` ([`mirrors`]); `None` for any other file.
    pub fn mirror_eval(&self, n: Vec3, t: Vec3, wi: Vec3, wo: Vec3) -> Option<Vec3> {
        let mirror = mirrors::of(&self.model)?;
        Some(mirror(&Values(self), n, t, wi, wo))
    }

    /// Whether the model has a Rust mirror ([`mirrors`]).
    pub fn has_mirror(&self) -> bool {
        mirrors::of(&self.model).is_some()
    }
}

/// A material's values by name, as the mirrors read them.
pub struct Values<'a>(&'a Analytic);

impl Values<'_> {
    /// A float or bool parameter's value (a bool as 0 or 1); 0 for a name the file lacks.
    pub fn float(&self, name: &str) -> f32 {
        match self.0.value(name) {
            Some(ParameterValue::Float(v)) => v,
            Some(ParameterValue::Bool(b)) => f32::from(u8::from(b)),
            _ => 0.0,
        }
    }

    /// A bool parameter's value.
    pub fn bool(&self, name: &str) -> bool {
        self.float(name) != 0.0
    }

    /// A colour parameter's value.
    pub fn color(&self, name: &str) -> Vec3 {
        match self.0.value(name) {
            Some(ParameterValue::Color(c)) => c,
            _ => Vec3::ZERO,
        }
    }
}

/// The tangent vk-render gives a surface of unit normal n where the shape gives none (spheres, meshes
/// without texture coordinates, the probe): BRDF Explorer's lit sphere's, X = normalize(+y x n), so that on
/// the probe's frame (n = +z) X = +x and Y = +y, as BRDF Explorer's plots have them. At the poles (n = +-y),
/// where +y x n vanishes, X = +x. Mirrors `default_tangent` in `shaders/common/brdf.glsl`.
pub fn default_tangent(n: Vec3) -> Vec3 {
    let t = Vec3::Y.cross(n);
    if t.length_squared() > 1e-12 {
        t.normalize()
    } else {
        Vec3::X
    }
}

/// The tangent at a point of unit normal n whose vertices give one (a mesh's, from its texture coordinates by
/// MikkTSpace): the interpolated `vertex_tangent` made perpendicular to n; [`default_tangent`] where there is
/// none (zero) or it is along n. Mirrors `surface_tangent` in `shaders/common/brdf.glsl`.
pub fn surface_tangent(n: Vec3, vertex_tangent: Vec3) -> Vec3 {
    let t = vertex_tangent - n * n.dot(vertex_tangent);
    if t.length_squared() > 1e-8 * vertex_tangent.length_squared() {
        t.normalize()
    } else {
        default_tangent(n)
    }
}

/// A plane's tangent: the world's +x projected on the plane; for a plane whose normal is +-x, the world's +z
/// projected (so that the frame turns with the plane). Mirrors `plane_tangent` in
/// `shaders/common/brdf.glsl`.
pub fn plane_tangent(n: Vec3) -> Vec3 {
    let along_x = Vec3::X - n * n.dot(Vec3::X);
    if along_x.length_squared() > 1e-12 {
        along_x.normalize()
    } else {
        (Vec3::Z - n * n.dot(Vec3::Z)).normalize()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const WARD_LIKE: &str = "analytic\n::begin parameters\nfloat alpha_x 0 1 0.15\nbool isotropic 0\ncolor Cd 1 1 1\n\
                             ::end parameters\n::begin shader\nconst float PI = 3.14159265;\nvec3 BRDF(vec3 L, vec3 V, vec3 \
                             N, vec3 X, vec3 Y) { float alpha_x = 2.0 * alpha_x; return Cd * alpha_x / PI; }\n::end \
                             shader\n";

    fn model(text: &str) -> Result<AnalyticModel, String> {
        AnalyticModel::from_text(Path::new("brdfs/m.brdf"), text.to_string())
    }

    #[test]
    fn a_file_loads_with_its_defaults_and_its_values_pack_in_order() {
        let model = Arc::new(model(WARD_LIKE).unwrap());
        let material = Analytic::defaults(model.clone());
        assert_eq!(material.floats(), vec![0.15, 0.0, 1.0, 1.0, 1.0]);
        let changed = material
            .clone()
            .with("alpha_x", ParameterValue::Float(0.5))
            .unwrap()
            .with("isotropic", ParameterValue::Bool(true))
            .unwrap()
            .with("Cd", ParameterValue::Color(Vec3::new(0.1, 0.2, 0.3)))
            .unwrap();
        assert_eq!(changed.floats(), vec![0.5, 1.0, 0.1, 0.2, 0.3]);
        assert_ne!(changed, material);
        assert_eq!(changed.describe(), "m.brdf alpha_x 0.5 isotropic true Cd [0.1, 0.2, 0.3]");
        assert!(model.glsl().contains("float usr_alpha_x;\nbool usr_isotropic;\nvec3 usr_Cd;\n"), "{}", model.glsl());
    }

    #[test]
    fn a_value_of_the_wrong_type_or_out_of_range_or_unknown_is_named() {
        let material = Analytic::defaults(Arc::new(model(WARD_LIKE).unwrap()));
        let error = |name: &str, value| material.clone().with(name, value).unwrap_err();
        assert_eq!(
            error("alpha_x", ParameterValue::Float(1.5)),
            " = 1.5: outside [0, 1], the range m.brdf (line 3) gives alpha_x"
        );
        assert!(
            error("alpha_x", ParameterValue::Bool(true)).contains("alpha_x is a float parameter of m.brdf (line 3)")
        );
        assert!(error("Cd", ParameterValue::Float(0.5)).contains("it takes a colour"));
        assert_eq!(
            error("alpha_y", ParameterValue::Float(0.5)),
            ": m.brdf has no parameter `alpha_y` (it has alpha_x, isotropic, Cd)"
        );
    }

    #[test]
    fn glsl_errors_name_the_files_line_and_its_own_names() {
        let text = WARD_LIKE.replace("return Cd * alpha_x / PI;", "return Cd * alpha_z / PI;");
        assert_eq!(model(&text).unwrap_err(), "brdfs/m.brdf:9: GLSL: 'alpha_z' : undeclared identifier");
        let syntax = WARD_LIKE.replace("const float PI = 3.14159265;", "const float PI = 3.14159265");
        let message = model(&syntax).unwrap_err();
        assert!(message.starts_with("brdfs/m.brdf:9: GLSL: "), "{message}");
        let typed = WARD_LIKE.replace("return Cd * alpha_x / PI;", "return alpha_x;");
        let message = model(&typed).unwrap_err();
        assert!(message.starts_with("brdfs/m.brdf:9: GLSL: ") && message.contains("return"), "{message}");
        let signature =
            WARD_LIKE.replace("vec3 BRDF(vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y)", "vec3 BRDF(vec3 L, vec3 V)");
        assert_eq!(
            model(&signature).unwrap_err(),
            "brdfs/m.brdf:9: the shader section defines `vec3 BRDF(vec3, vec3)`: vk-render calls `vec3 BRDF(vec3 L, vec3 V, vec3 \
             N, vec3 X, vec3 Y)`"
        );
    }

    #[test]
    fn brdf_explorers_traps_compile_a_redefined_reflect_and_smoothstep_and_shadowing_arguments() {
        let text = "analytic\n::begin parameters\nfloat n 1 1000 100\nfloat f0 0 1 0.5\n::end parameters\n::begin shader\n\
                    vec3 reflect(vec3 I, vec3 N) { return 2*dot(I,N)*N - I; }\n\
                    float smoothstep(float a, float b, float x) { return x < a ? 0.0 : 1.0; }\n\
                    float F(float f0, float c) { return f0 + (1 - f0) * pow(1 - c, 5); }\n\
                    float sqr(float x) { return x*x; }\nconst float PI = 3.14159265358979323846;\nfloat G = 1.0;\n\
                    vec3 BRDF(vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y) {\n    vec3 R = reflect(L, N);\n    return \
                    vec3(pow(max(0, dot(R, V)), n) * F(f0, dot(V, N)) * smoothstep(0, 1, sqr(G)) / PI);\n}\n::end shader\n";
        let model = model(text).unwrap();
        assert!(model.glsl().contains("vec3 usr_reflect(vec3 usr_I, vec3 usr_N)"), "{}", model.glsl());
    }

    #[test]
    fn a_define_dropped_is_a_warning_naming_the_file_and_line() {
        let text =
            WARD_LIKE.replace("const float PI = 3.14159265;", "#define PI 3.14159265\nconst float PI = 3.14159265;");
        let model = model(&text).unwrap();
        assert_eq!(model.warnings.len(), 1);
        assert!(
            model.warnings[0].starts_with("brdfs/m.brdf: line 8: `#define PI 3.14159265` is dropped"),
            "{:?}",
            model.warnings
        );
    }

    #[test]
    fn no_name_of_vk_renders_shaders_has_the_prefix() {
        let folder = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("shaders");
        let sources = crate::vulkan::ShaderSources::from_directory(&folder).unwrap();
        assert_eq!(sources, crate::vulkan::ShaderSources::default());
        for path in sources.paths() {
            let text = std::fs::read_to_string(folder.join(path)).unwrap();
            for word in text.split(|c: char| !(c.is_ascii_alphanumeric() || c == '_')) {
                assert!(!word.starts_with(PREFIX), "shaders/{path} names {word}");
            }
        }
    }

    #[test]
    fn the_default_and_plane_tangents_follow_their_rules() {
        assert_eq!(default_tangent(Vec3::Z), Vec3::X);
        assert_eq!(default_tangent(Vec3::Y), Vec3::X);
        assert_eq!(default_tangent(-Vec3::Y), Vec3::X);
        let n = Vec3::new(1.0, 0.0, 0.0);
        assert!(default_tangent(n).abs_diff_eq(-Vec3::Z, 1e-6));
        assert_eq!(plane_tangent(Vec3::Y), Vec3::X);
        assert!(plane_tangent(Vec3::X).abs_diff_eq(Vec3::Z, 1e-6));
        let tilted = Vec3::new(1.0, 1.0, 0.0).normalize();
        let t = plane_tangent(tilted);
        assert!(t.dot(tilted).abs() < 1e-6 && t.x > 0.0);
    }

    #[test]
    fn a_vertex_tangent_is_made_perpendicular_to_the_normal_or_replaced_where_there_is_none() {
        // A tangent interpolated off the surface: (1, 0, 1) on n = +z keeps its part along +x, at any length.
        assert!(surface_tangent(Vec3::Z, Vec3::new(1.0, 0.0, 1.0)).abs_diff_eq(Vec3::X, 1e-6));
        assert!(surface_tangent(Vec3::Z, Vec3::new(0.0, -0.01, 0.02)).abs_diff_eq(-Vec3::Y, 1e-6));
        // None (a sphere, a mesh without texture coordinates) or one along n: the default rule.
        let n = Vec3::new(1.0, 0.0, 0.0);
        assert_eq!(surface_tangent(n, Vec3::ZERO), default_tangent(n));
        assert_eq!(surface_tangent(n, 3.0 * n), default_tangent(n));
    }
}
