//! `vk_render._native`: the Rust half of the Python package, a thin layer over vk-render's public types.
//! The pure-Python half (python/vk_render/) adds what Python users expect: the process-wide renderer,
//! numpy shapes and dtypes, sweeps on Dask.

mod convert;
mod errors;
mod grid;
mod scene;

use std::path::PathBuf;
use std::sync::Mutex;

use glam::Vec3;
use numpy::{PyArray2, PyArray3, PyArrayMethods, PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList, PyTuple};
use vk_render::analysis::albedo::{directional_albedos, ALBEDO_TOLERANCE};
use vk_render::brdf::Brdf;
use vk_render::check::report::{check_image, scene_named};
use vk_render::check::summary::Summary;
use vk_render::render::ProbeCase;
use vk_render::scene::{Shorthands, View};
use vk_render::vulkan::{list_devices, preferred_device, Instance};
use vk_render::{Override, Renderer, RendererOptions, Scene};

use convert::{image_array, overrides, rgb_image, toml_value};
use errors::{detached, scene_error, to_py};
use scene::{resolve, PyScene};

/// A Vulkan device with vk-render's shaders compiled, kept with its pipelines, meshes and shadow maps
/// between calls, as a sweep keeps them: make one and render many images with it.
///
/// `device` chooses the device as `--device` does: an index from `vk_render.devices()` or part of its
/// name (default: a GPU, else lavapipe). `validate=True` turns the Khronos validation layer on; any message
/// it reports then raises DeviceError.
///
/// Each call releases the GIL while the device works: two threads with a renderer each render at once.
/// A renderer used from several threads renders for one at a time.
#[pyclass(module = "vk_render._native", name = "Renderer", frozen, subclass)]
struct PyRenderer {
    renderer: Mutex<Renderer>,
    device: String,
}

impl PyRenderer {
    /// Runs `work` on this renderer, detached from the GIL (see `errors::detached`); where an analytic model
    /// gave NaN, an infinity or a negative value, a SceneWarning says so, as `vk-render` prints it.
    fn with<T: Send>(
        &self,
        py: Python<'_>,
        work: impl FnOnce(&mut Renderer) -> vk_render::Result<T> + Send,
    ) -> PyResult<T> {
        let mut invalid = None;
        let result = detached(py, || {
            // A panic in an earlier call poisoned the lock; the renderer itself is whole between calls.
            let mut renderer = self.renderer.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
            let result = work(&mut renderer);
            invalid = renderer.take_invalid_values();
            result
        });
        errors::warn(py, invalid.iter().map(ToString::to_string).collect())?;
        result
    }
}

/// The overrides of a render call, in the command line's order: the shorthands, then `set`.
fn call_overrides(
    py: Python<'_>,
    set: Option<&Bound<'_, PyDict>>,
    width: Option<i64>,
    height: Option<i64>,
    samples: Option<i64>,
    view: Option<&str>,
) -> PyResult<Vec<Override>> {
    let mut all = Shorthands { width, height, samples, view, environment_mode: None }.overrides();
    all.extend(overrides(py, set)?);
    Ok(all)
}

/// A material given as a dict in the scene format's words, or a pair (scene, "name").
fn material(py: Python<'_>, given: &Bound<'_, PyAny>) -> PyResult<Brdf> {
    if let Ok(table) = given.downcast::<PyDict>() {
        let mut document = toml::Table::new();
        let mut materials = toml::Table::new();
        materials.insert("given".into(), toml_value(py, "material", table)?);
        document.insert("material".into(), toml::Value::Table(materials));
        let text = toml::to_string(&document).map_err(|e| scene_error(py, format!("material: {e}")))?;
        let scene = Scene::parse(&text, std::path::Path::new("<material>"), &[]).map_err(|e| to_py(py, e))?;
        return scene.materials.get("given").cloned().ok_or_else(|| scene_error(py, "material: empty".into()));
    }
    if let Ok(pair) = given.downcast::<PyTuple>() {
        if pair.len() == 2 {
            let scene = resolve(py, &pair.get_item(0)?, &[])?;
            let name: String = pair.get_item(1)?.extract()?;
            return scene.materials.get(&name).cloned().ok_or_else(|| {
                let known: Vec<&str> = scene.materials.keys().map(String::as_str).collect();
                scene_error(
                    py,
                    format!("{}: no [material.{name}] (the scene has: {})", scene.source.display(), known.join(", ")),
                )
            });
        }
    }
    Err(pyo3::exceptions::PyTypeError::new_err(
        "material: expected a dict in the scene format's words ({\"brdf\": \"lambert\", \"kd\": [0.5, 0.5, 0.5]}) \
         or a pair (scene, \"name\")",
    ))
}

/// Unit directions from an (N, 3) float32 array, each checked.
fn directions(array: &PyReadonlyArray2<'_, f32>, what: &str) -> PyResult<Vec<Vec3>> {
    let view = array.as_array();
    if view.ncols() != 3 {
        return Err(PyValueError::new_err(format!("{what}: expected an (N, 3) array, got {:?}", array.shape())));
    }
    view.rows()
        .into_iter()
        .enumerate()
        .map(|(i, row)| {
            let v = Vec3::new(row[0], row[1], row[2]);
            if !v.is_finite() || (v.length() - 1.0).abs() > 1e-3 {
                return Err(PyValueError::new_err(format!(
                    "{what}[{i}] = {:?} is not a unit direction (length {})",
                    v.to_array(),
                    v.length()
                )));
            }
            Ok(v)
        })
        .collect()
}

/// The cases of a `brdf` call: the material, and one (wi, wo) pair per row, in the frame whose normal is +z.
fn probe_cases(
    py: Python<'_>,
    material: &Bound<'_, PyAny>,
    wi: &PyReadonlyArray2<'_, f32>,
    wo: &PyReadonlyArray2<'_, f32>,
) -> PyResult<Vec<ProbeCase>> {
    let brdf = self::material(py, material)?;
    let (wi, wo) = (directions(wi, "wi")?, directions(wo, "wo")?);
    if wi.len() != wo.len() {
        return Err(PyValueError::new_err(format!("wi has {} rows and wo {}: give one wo per wi", wi.len(), wo.len())));
    }
    Ok(wi.into_iter().zip(wo).map(|(wi, wo)| ProbeCase { brdf: brdf.clone(), n: Vec3::Z, wi, wo }).collect())
}

/// Values as an (N, 3) float32 array.
fn rows_of_three<'py>(py: Python<'py>, values: &[Vec3]) -> PyResult<Bound<'py, PyArray2<f32>>> {
    let flat: Vec<f32> = values.iter().flat_map(|v| v.to_array()).collect();
    numpy::PyArray1::from_vec(py, flat).reshape([values.len(), 3])
}

/// A sampler's draws as Python sees them: directions (n, 3) and densities (n,).
type Draws<'py> = (Bound<'py, PyArray2<f32>>, Bound<'py, numpy::PyArray1<f32>>);

#[pymethods]
impl PyRenderer {
    #[new]
    #[pyo3(signature = (device = None, validate = false, timeout = None))]
    fn new(py: Python<'_>, device: Option<&Bound<'_, PyAny>>, validate: bool, timeout: Option<f64>) -> PyResult<Self> {
        let device = device.map(|d| d.str().map(|s| s.to_string())).transpose()?;
        let timeout = match timeout {
            Some(seconds) if !(seconds.is_finite() && seconds > 0.0) => {
                return Err(PyValueError::new_err(format!("timeout = {seconds}: a number of seconds above 0")))
            }
            seconds => seconds.map(std::time::Duration::from_secs_f64),
        };
        let options = RendererOptions { device, validate, timeout, ..RendererOptions::default() };
        let renderer = detached(py, || Renderer::new(options))?;
        let name = renderer.device_info().name.clone();
        Ok(Self { renderer: Mutex::new(renderer), device: name })
    }

    /// The name of the Vulkan device this renderer draws with.
    #[getter]
    fn device(&self) -> &str {
        &self.device
    }

    /// How exact the last image's environment light was, when it was integrated in the exact mode (what
    /// `vk-render render` prints): a dict with "samples" (a pixel), "passes" and "p99_levels" (the standard
    /// error at 99% of the pixels, in 8-bit levels); None for any other image.
    #[getter]
    fn accuracy<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyDict>>> {
        // The GIL released while the lock is awaited: a render of another thread may hold it.
        let accuracy =
            py.allow_threads(|| self.renderer.lock().unwrap_or_else(std::sync::PoisonError::into_inner).accuracy());
        let Some(accuracy) = accuracy else { return Ok(None) };
        let entry = PyDict::new(py);
        entry.set_item("samples", accuracy.samples)?;
        entry.set_item("passes", accuracy.passes)?;
        entry.set_item("p99_levels", accuracy.p99_levels)?;
        Ok(Some(entry))
    }

    /// Renders a scene (a path or a Scene) to a numpy array of shape (height, width, 3).
    ///
    /// Without `hdr`: uint8, exactly the bytes of the PNG that `vk-render render` writes for the same
    /// arguments. With `hdr=True`: float32, the values of the EXR it writes (linear, after exposure).
    /// `set` replaces scene values as `--set` does: {"material.grey.kd": 0.8}; `width`, `height`,
    /// `samples` and `view` are its shorthands, applied first.
    #[pyo3(signature = (scene, *, set = None, width = None, height = None, samples = None, view = None, hdr = false))]
    #[allow(clippy::too_many_arguments)]
    fn render<'py>(
        &self,
        py: Python<'py>,
        scene: &Bound<'py, PyAny>,
        set: Option<&Bound<'py, PyDict>>,
        width: Option<i64>,
        height: Option<i64>,
        samples: Option<i64>,
        view: Option<&str>,
        hdr: bool,
    ) -> PyResult<Bound<'py, PyAny>> {
        let scene = resolve(py, scene, &call_overrides(py, set, width, height, samples, view)?)?;
        errors::warn(py, scene.warnings())?;
        let size = (scene.image.width, scene.image.height);
        if hdr {
            let image = self.with(py, |r| r.render(&scene))?;
            return image_array(py, size, image.exposed(&scene.image).into_raw());
        }
        let picture = self.with(py, |r| r.render_picture(&scene))?;
        image_array(py, size, picture.pixels.into_raw())
    }

    /// f_r(wi, wo) of a material, evaluated on the GPU by the shaders' own `brdf_eval` (the probe pass), as
    /// float32 (N, 3). `wi` and `wo` are (N, 3) float32 arrays of unit directions in the frame whose normal
    /// is +z. `material` is a dict in the scene format's words or a pair (scene, "name").
    fn brdf<'py>(
        &self,
        py: Python<'py>,
        material: &Bound<'py, PyAny>,
        wi: PyReadonlyArray2<'py, f32>,
        wo: PyReadonlyArray2<'py, f32>,
    ) -> PyResult<Bound<'py, PyArray2<f32>>> {
        let cases = probe_cases(py, material, &wi, &wo)?;
        let values = if cases.is_empty() { Vec::new() } else { self.with(py, |r| r.probe_brdfs(&cases))? };
        rows_of_three(py, &values)
    }

    /// The directional albedo rho(theta_o) = integral of f_r cos(theta_i) over the hemisphere, for each
    /// theta_o in degrees (from 0 up to, not including, 90), as `vk-render plot albedo` computes it (adaptive
    /// Gauss-Kronrod cubature of `brdf_eval` on the GPU). Returns (albedo as float64 (N, 3), the largest
    /// error bound reached).
    fn albedo<'py>(
        &self,
        py: Python<'py>,
        material: &Bound<'py, PyAny>,
        theta_o_degrees: Vec<f64>,
    ) -> PyResult<(Bound<'py, PyArray2<f64>>, f64)> {
        let brdf = self::material(py, material)?;
        if let Some(bad) = theta_o_degrees.iter().find(|t| !(0.0..90.0).contains(*t)) {
            return Err(PyValueError::new_err(format!("theta_o_degrees: {bad} is not in [0, 90)")));
        }
        let radians: Vec<f64> = theta_o_degrees.iter().map(|t| t.to_radians()).collect();
        let albedos = if radians.is_empty() {
            Vec::new()
        } else {
            self.with(py, |r| directional_albedos(r, &brdf, &radians, ALBEDO_TOLERANCE))?
        };
        let bound = albedos.iter().fold(0.0f64, |b, a| b.max(a.error_bound));
        let flat: Vec<f64> = albedos.iter().flat_map(|a| a.rho).collect();
        Ok((numpy::PyArray1::from_vec(py, flat).reshape([albedos.len(), 3])?, bound))
    }

    /// `n` draws of a material's own importance sampler (the exact mode's, `material_sample` of the GLSL, or
    /// a .brdf file's sampleBRDF) seen from the unit direction `wo` (frame: normal +z, tangent X +x), from the
    /// random stream `seed`. Returns (directions as float32 (n, 3), their densities per solid angle as float32
    /// (n,)); a direction below the surface (z <= 0) is no sample, its density 0.
    #[pyo3(signature = (material, wo, n, *, seed = 1))]
    fn sample<'py>(
        &self,
        py: Python<'py>,
        material: &Bound<'py, PyAny>,
        wo: [f32; 3],
        n: usize,
        seed: u32,
    ) -> PyResult<Draws<'py>> {
        let brdf = self::material(py, material)?;
        let wo = Vec3::from(wo);
        if !(wo.is_finite() && (wo.length() - 1.0).abs() < 1e-3 && wo.z > 0.0) {
            return Err(PyValueError::new_err(format!("wo = {wo}: a unit direction above the surface (z > 0)")));
        }
        if n > u32::MAX as usize {
            return Err(PyValueError::new_err(format!("n = {n}: at most {}", u32::MAX)));
        }
        let samples =
            if n == 0 { Vec::new() } else { self.with(py, |r| r.draw_brdf_samples(&brdf, wo, (0, n), seed))? };
        let directions: Vec<Vec3> = samples.iter().map(|s| s.wi).collect();
        let densities: Vec<f32> = samples.iter().map(|s| s.pdf).collect();
        Ok((rows_of_three(py, &directions)?, numpy::PyArray1::from_vec(py, densities)))
    }

    /// Tests a material's own importance sampler as `vk-render sampling` does (see its guide page): at each view
    /// (θo, φo in degrees; default θo 0, 20, 40, 60, 75 and 85, φo 0, and 0, 45, 90 for an anisotropic
    /// model), Pearson's χ², the density's integral and support, the estimator against the albedo, energy,
    /// and the BRDF's reciprocity. Returns a dict: "passed", "level_each", "verdicts" (a list of dicts: test,
    /// theta_o, phi_o (None for reciprocity), passed, detail) and "views" (a list of dicts: theta_o, phi_o,
    /// chi_square, degrees_of_freedom, p_value, density_integral, no_sample, estimate, standard_error,
    /// albedo, and "histogram" and "expected", the samples and the counts the density expects on the
    /// upper hemisphere's 40 x 160 cells of the equal-area grid, cos θ by rows from 0, φ by columns from -180°).
    #[pyo3(signature = (material, *, theta_o = None, phi_o = None, samples = 1_000_000, seed = 1, level = 0.01))]
    #[allow(clippy::too_many_arguments)]
    fn sampling_test<'py>(
        &self,
        py: Python<'py>,
        material: &Bound<'py, PyAny>,
        theta_o: Option<Vec<f64>>,
        phi_o: Option<Vec<f64>>,
        samples: u64,
        seed: u32,
        level: f64,
    ) -> PyResult<Bound<'py, PyDict>> {
        use vk_render::analysis::sampling::{self as sampling, SamplingOptions, GRID};
        let brdf = self::material(py, material)?;
        let theta_o = theta_o.unwrap_or_else(|| sampling::DEFAULT_THETA_O.to_vec());
        if let Some(bad) = theta_o.iter().find(|t| !(t.is_finite() && (0.0..90.0).contains(*t))) {
            return Err(PyValueError::new_err(format!("theta_o: {bad} is not in [0, 90)")));
        }
        if !(1000..=u64::from(u32::MAX)).contains(&samples) {
            return Err(PyValueError::new_err(format!("samples = {samples}: from 1000 to {}", u32::MAX)));
        }
        if !(level > 0.0 && level < 1.0) {
            return Err(PyValueError::new_err(format!("level = {level}: a probability between 0 and 1")));
        }
        let report = self.with(py, |r| {
            let views = sampling::views(r, &brdf, &theta_o, phi_o.as_deref())?;
            sampling::test_sampler(r, &brdf, &SamplingOptions { views, samples, seed, level }, || ())
        })?;
        let out = PyDict::new(py);
        out.set_item("passed", report.passed())?;
        out.set_item("level_each", report.level_each)?;
        let verdicts = PyList::empty(py);
        for verdict in &report.verdicts {
            let entry = PyDict::new(py);
            entry.set_item("test", verdict.test)?;
            entry.set_item("theta_o", verdict.view.map(|v| v.0))?;
            entry.set_item("phi_o", verdict.view.map(|v| v.1))?;
            entry.set_item("passed", verdict.passed)?;
            entry.set_item("detail", &verdict.detail)?;
            verdicts.append(entry)?;
        }
        out.set_item("verdicts", verdicts)?;
        let views = PyList::empty(py);
        let (rows, columns) = (GRID.cos_bins / 2, GRID.phi_bins);
        let upper = GRID.cells() / 2;
        for view in &report.views {
            let entry = PyDict::new(py);
            entry.set_item("theta_o", view.theta_o)?;
            entry.set_item("phi_o", view.phi_o)?;
            entry.set_item("chi_square", view.chi_square.statistic)?;
            entry.set_item("degrees_of_freedom", view.chi_square.degrees_of_freedom)?;
            entry.set_item("p_value", view.chi_square.p_value)?;
            entry.set_item("density_integral", view.density_integral().0)?;
            entry.set_item("no_sample", view.no_sample)?;
            entry.set_item("estimate", view.estimate.to_vec())?;
            entry.set_item("standard_error", view.standard_error.to_vec())?;
            entry.set_item("albedo", view.albedo().to_vec())?;
            let histogram: Vec<u64> = view.histogram[upper..].to_vec();
            entry.set_item("histogram", numpy::PyArray1::from_vec(py, histogram).reshape([rows, columns])?)?;
            let expected: Vec<f64> =
                view.cells.probability[upper..].iter().map(|p| p.max(0.0) * view.samples as f64).collect();
            entry.set_item("expected", numpy::PyArray1::from_vec(py, expected).reshape([rows, columns])?)?;
            views.append(entry)?;
        }
        out.set_item("views", views)?;
        Ok(out)
    }

    /// Checks an image (a (height, width, 3) uint8 array, or a PNG or JPEG path) against a scene (one of the
    /// practical's images by name, a scene file, or a Scene) rendered at the image's size, as `vk-render
    /// check` does. Returns a dict: "matches", "verdict", "mistakes", "statistics", "regions",
    /// "tells_apart", "wrong_parameters".
    #[pyo3(signature = (image, scene, *, set = None))]
    fn check<'py>(
        &self,
        py: Python<'py>,
        image: &Bound<'py, PyAny>,
        scene: &Bound<'py, PyAny>,
        set: Option<&Bound<'py, PyDict>>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let mine = match image.downcast::<PyArray3<u8>>() {
            Ok(array) => rgb_image(py, array)?,
            Err(_) => {
                let path: PathBuf = image.extract().map_err(|_| {
                    pyo3::exceptions::PyTypeError::new_err("image: expected a (height, width, 3) uint8 array or a path")
                })?;
                vk_render::check::report::read_image(&path).map_err(|e| to_py(py, e))?
            }
        };
        let mut all = vec![
            Override::new("image.width", i64::from(mine.width())),
            Override::new("image.height", i64::from(mine.height())),
        ];
        all.extend(overrides(py, set)?);
        let scene = match scene.extract::<String>() {
            Ok(name) => scene_named(&name, &all).map_err(|e| to_py(py, e))?,
            Err(_) => resolve(py, scene, &all)?,
        };
        let checked = self.with(py, |r| check_image(r, &mine, &scene, |_, _| {}))?;
        // The summary's JSON, as the server answers it, read by Python's own json: the same keys and values.
        let json = Summary::of(&checked, &scene)
            .to_json()
            .map_err(|e| pyo3::exceptions::PyRuntimeError::new_err(format!("the check's summary: {e}")))?;
        let report = py.import("json")?.call_method1("loads", (json,))?.downcast_into::<PyDict>()?;
        report.set_item("exact", image_array(py, checked.exact().dimensions(), checked.exact().as_raw().clone())?)?;
        Ok(report)
    }

    fn __repr__(&self) -> String {
        format!("vk_render.Renderer(device={:?})", self.device)
    }
}

/// The CPU ray tracer, vk-render's independent reference: the scene (a path or a Scene) as a
/// (height, width, 3) array, uint8 after the output transform like `render`, or float32 with `hdr=True`.
#[pyfunction]
#[pyo3(signature = (scene, *, set = None, width = None, height = None, samples = None, hdr = false))]
#[allow(clippy::too_many_arguments)]
fn reference<'py>(
    py: Python<'py>,
    scene: &Bound<'py, PyAny>,
    set: Option<&Bound<'py, PyDict>>,
    width: Option<i64>,
    height: Option<i64>,
    samples: Option<i64>,
    hdr: bool,
) -> PyResult<Bound<'py, PyAny>> {
    let scene = resolve(py, scene, &call_overrides(py, set, width, height, samples, None)?)?;
    if scene.image.view != View::Radiance {
        return Err(scene_error(
            py,
            format!(
                "{}: image.view = \"{}\": the CPU reference renders the radiance only",
                scene.source.display(),
                scene.image.view.name()
            ),
        ));
    }
    let traced = detached(py, || vk_render::reference::render(&scene))?;
    let size = (scene.image.width, scene.image.height);
    if hdr {
        return image_array(py, size, traced.image.exposed(&scene.image).into_raw());
    }
    image_array(py, size, traced.image.to_rgb8(&scene.image).into_raw())
}

/// The Vulkan devices, in `--device` index order: one dict each (index, name, type, api, driver, default).
#[pyfunction]
fn devices(py: Python<'_>) -> PyResult<Bound<'_, PyList>> {
    let found = detached(py, || {
        let instance = Instance::new(false, &[])?;
        let devices = list_devices(&instance)?;
        if devices.is_empty() {
            return Err(vk_render::Error::NoVulkan(format!(
                "no Vulkan device was found. {}",
                vk_render::vulkan::INSTALL_HINT
            )));
        }
        let preferred = preferred_device(&instance, &devices, None).ok().map(|((_, info), _)| info.index);
        Ok(devices.into_iter().map(|(_, info)| (Some(info.index) == preferred, info)).collect::<Vec<_>>())
    })?;
    let list = PyList::empty(py);
    for (default, info) in found {
        let entry = PyDict::new(py);
        entry.set_item("index", info.index)?;
        entry.set_item("name", &info.name)?;
        entry.set_item("type", info.kind_name())?;
        entry.set_item("api", info.api_version_string())?;
        entry.set_item("driver", &info.driver)?;
        entry.set_item("default", default)?;
        list.append(entry)?;
    }
    Ok(list)
}

/// Writes a (height, width, 3) uint8 array as a PNG, exactly as `vk-render render` writes its images
/// (same encoder, same bytes), through a temporary file renamed into place: a killed process never leaves
/// a partial PNG under `path`.
#[pyfunction]
fn write_png(py: Python<'_>, image: &Bound<'_, PyArray3<u8>>, path: PathBuf) -> PyResult<()> {
    let image = rgb_image(py, image)?;
    detached(py, || vk_render::pictures::output::write_png(&image, &path))
}

/// Reads an image vk-render writes or checks: a PNG or JPEG (8-bit RGB, as `vk-render check` reads it) as
/// a (height, width, 3) uint8 array, an EXR as float32.
#[pyfunction]
fn read_image<'py>(py: Python<'py>, path: PathBuf) -> PyResult<Bound<'py, PyAny>> {
    let exr = path.extension().is_some_and(|e| e.eq_ignore_ascii_case("exr"));
    if exr {
        let image = detached(py, || {
            image::open(&path).map(|i| i.into_rgb32f()).map_err(|e| vk_render::Error::Input {
                path: path.clone(),
                message: format!("not an EXR image vk-render can read: {e}"),
            })
        })?;
        return image_array(py, image.dimensions(), image.into_raw());
    }
    let image = detached(py, || vk_render::check::report::read_image(&path))?;
    image_array(py, image.dimensions(), image.into_raw())
}

/// f_r(wi, wo) of the Rust mirror of the GLSL (on the CPU, in f32): the values `Renderer.brdf` is tested
/// against. Arguments as `Renderer.brdf`.
#[pyfunction]
fn brdf_mirror<'py>(
    py: Python<'py>,
    material: &Bound<'py, PyAny>,
    wi: PyReadonlyArray2<'py, f32>,
    wo: PyReadonlyArray2<'py, f32>,
) -> PyResult<Bound<'py, PyArray2<f32>>> {
    let cases = probe_cases(py, material, &wi, &wo)?;
    if cases.first().is_some_and(|c| !c.brdf.has_mirror()) {
        return Err(PyValueError::new_err(
            "material: this .brdf file has no Rust mirror (only the models shipped in assets/brdfs/ do, unchanged)",
        ));
    }
    let values: Vec<Vec3> = cases.iter().map(|c| c.brdf.eval(c.n, c.wi, c.wo)).collect();
    rows_of_three(py, &values)
}

/// Panics inside Rust on purpose, through the path every call takes (the tests show it becomes
/// vk_render.Error, not an abort).
#[pyfunction]
fn _panic_for_tests(py: Python<'_>, message: String) -> PyResult<()> {
    detached(py, || -> vk_render::Result<()> { panic!("{message}") })
}

/// Sleeps `seconds` inside Rust, waking for `vk_render::interrupt` every 10 ms as long computations do (the
/// tests show Ctrl-C raises KeyboardInterrupt within a second).
#[pyfunction]
fn _busy_for_tests(py: Python<'_>, seconds: f64) -> PyResult<()> {
    detached(py, || {
        let until = std::time::Instant::now() + std::time::Duration::from_secs_f64(seconds);
        while std::time::Instant::now() < until {
            vk_render::interrupt::check()?;
            std::thread::sleep(std::time::Duration::from_millis(10));
        }
        Ok(())
    })
}

#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PyRenderer>()?;
    m.add_class::<PyScene>()?;
    m.add_class::<grid::PyGrid>()?;
    m.add_function(wrap_pyfunction!(reference, m)?)?;
    m.add_function(wrap_pyfunction!(devices, m)?)?;
    m.add_function(wrap_pyfunction!(write_png, m)?)?;
    m.add_function(wrap_pyfunction!(read_image, m)?)?;
    m.add_function(wrap_pyfunction!(brdf_mirror, m)?)?;
    m.add_function(wrap_pyfunction!(_panic_for_tests, m)?)?;
    m.add_function(wrap_pyfunction!(_busy_for_tests, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
