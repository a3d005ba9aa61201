//! `vk_render.Scene`: a scene file's text, where it is read from (messages and relative mesh paths), and
//! the validated scene it makes. Immutable: `with_set` makes a new one.

use std::path::PathBuf;

use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList, PyTuple};
use vk_render::scene::{overridden, Shape};
use vk_render::{Override, Scene};

use crate::convert::overrides;
use crate::errors::to_py;

/// A scene (SCENE_FORMAT version 1), validated as `vk-render render` validates it.
///
/// Make one with `Scene.load(path)` or `Scene.from_toml(text, base_dir=".")`; `with_set({...})` returns a
/// new scene with values replaced as `--set KEY=VALUE` replaces them; `to_toml()` gives its text. Render it
/// with `Renderer.render(scene)` or `vk_render.render(scene)`.
#[pyclass(module = "vk_render._native", name = "Scene", frozen)]
pub struct PyScene {
    /// The scene's TOML text, overrides included.
    pub text: String,
    /// The file it stands for: named in messages; meshes and maps are found beside it.
    pub path: PathBuf,
    pub scene: Scene,
}

impl PyScene {
    /// A scene of this one's text with `more` overrides: what a render with `set=` draws.
    pub fn with_overrides(&self, more: &[Override]) -> vk_render::Result<Scene> {
        if more.is_empty() {
            return Ok(self.scene.clone());
        }
        Scene::parse(&self.text, &self.path, more)
    }

    fn from_text(text: String, path: PathBuf) -> vk_render::Result<Self> {
        let scene = Scene::parse(&text, &path, &[])?;
        Ok(Self { text, path, scene })
    }
}

/// A `Scene` or a path (str or os.PathLike) with the overrides of a call: the validated scene to draw.
pub fn resolve(py: Python<'_>, scene: &Bound<'_, PyAny>, more: &[Override]) -> PyResult<Scene> {
    if let Ok(given) = scene.downcast::<PyScene>() {
        return given.get().with_overrides(more).map_err(|e| to_py(py, e));
    }
    let path: PathBuf = scene.extract().map_err(|_| {
        pyo3::exceptions::PyTypeError::new_err(format!(
            "scene: expected a vk_render.Scene or a path (str or os.PathLike), got {}",
            scene.get_type().name().map_or_else(|_| "?".into(), |n| n.to_string())
        ))
    })?;
    py.allow_threads(|| Scene::load(&path, more)).map_err(|e| to_py(py, e))
}

#[pymethods]
impl PyScene {
    /// Reads and validates a scene file. Raises SceneError naming the file, key and value when it is not a
    /// valid scene.
    #[staticmethod]
    fn load(py: Python<'_>, path: PathBuf) -> PyResult<Self> {
        let text = vk_render::files::read_regular_text(&path, "scene file", vk_render::files::MAX_SCENE_BYTES)
            .map_err(|message| to_py(py, vk_render::Error::Scene { file: path.clone(), message }))?;
        Self::from_text(text, path).map_err(|e| to_py(py, e))
    }

    /// A scene from TOML text; meshes and maps named by relative paths are found in `base_dir`.
    #[staticmethod]
    #[pyo3(signature = (text, base_dir = PathBuf::from(".")))]
    fn from_toml(py: Python<'_>, text: String, base_dir: PathBuf) -> PyResult<Self> {
        Self::from_text(text, base_dir.join("<toml>")).map_err(|e| to_py(py, e))
    }

    /// A new scene with values replaced, `{"material.grey.kd": 0.8, "image.width": 300}`, exactly as
    /// `--set material.grey.kd=0.8 --set image.width=300` replaces them (in the dict's order).
    fn with_set(&self, py: Python<'_>, set: &Bound<'_, PyDict>) -> PyResult<Self> {
        let more = overrides(py, Some(set))?;
        let (scene, text) = overridden(&self.text, &self.path, &more).map_err(|e| to_py(py, e))?;
        Ok(Self { text, path: self.path.clone(), scene })
    }

    /// The scene as TOML text (values set by `with_set` included; the file's comments are not kept).
    fn to_toml(&self, py: Python<'_>) -> PyResult<String> {
        Ok(overridden(&self.text, &self.path, &[]).map_err(|e| to_py(py, e))?.1)
    }

    /// The file the scene was read from (or `base_dir/<toml>` for `from_toml`).
    #[getter]
    fn path(&self) -> PathBuf {
        self.path.clone()
    }

    /// Image width in pixels.
    #[getter]
    fn width(&self) -> u32 {
        self.scene.image.width
    }

    /// Image height in pixels.
    #[getter]
    fn height(&self) -> u32 {
        self.scene.image.height
    }

    /// MSAA samples per pixel.
    #[getter]
    fn samples(&self) -> u32 {
        self.scene.image.samples
    }

    /// What the image shows: "radiance", or one term of the shading ("normal", "brdf", "d", ...).
    #[getter]
    fn view(&self) -> &'static str {
        self.scene.image.view.name()
    }

    /// The names of the scene's [material.NAME] tables, sorted.
    #[getter]
    fn materials(&self) -> Vec<String> {
        self.scene.materials.keys().cloned().collect()
    }

    /// One dict per [[object]]: its shape ("sphere", "plane", "mesh"), material name and BRDF model.
    #[getter]
    fn objects<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        let list = PyList::empty(py);
        for object in &self.scene.objects {
            let entry = PyDict::new(py);
            entry.set_item("shape", object.shape.kind())?;
            entry.set_item("material", &object.material)?;
            entry.set_item("brdf", object.brdf.name())?;
            match &object.shape {
                Shape::Sphere { center, radius } => {
                    entry.set_item("center", center.to_array())?;
                    entry.set_item("radius", radius)?;
                }
                Shape::Plane { point, normal } => {
                    entry.set_item("point", point.to_array())?;
                    entry.set_item("normal", normal.to_array())?;
                }
                Shape::Mesh { path, .. } => entry.set_item("path", path)?,
                Shape::Triangles(_) => {}
            }
            list.append(entry)?;
        }
        Ok(list)
    }

    /// One dict per [[light]]: position, color, power and whether it casts shadows.
    #[getter]
    fn lights<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        let list = PyList::empty(py);
        for light in &self.scene.lights {
            let entry = PyDict::new(py);
            entry.set_item("position", light.position.to_array())?;
            entry.set_item("color", light.color.to_array())?;
            entry.set_item("power", light.power)?;
            entry.set_item("shadows", light.shadows)?;
            list.append(entry)?;
        }
        Ok(list)
    }

    /// Whether the scene has an [environment].
    #[getter]
    fn has_environment(&self) -> bool {
        self.scene.environment.is_some()
    }

    /// The scene's warnings: what is legal but probably not meant (no object, no light, ...).
    #[getter]
    fn warnings(&self) -> Vec<String> {
        self.scene.warnings()
    }

    fn __repr__(&self) -> String {
        format!(
            "vk_render.Scene({:?}: {} x {}, {} object(s), {} light(s), materials {:?})",
            self.path.display().to_string(),
            self.scene.image.width,
            self.scene.image.height,
            self.scene.objects.len(),
            self.scene.lights.len(),
            self.materials()
        )
    }

    fn __eq__(&self, other: &Self) -> bool {
        self.path == other.path && self.scene == other.scene
    }

    /// Pickling (Dask sends scenes to its workers): the text and the path, made absolute so that meshes are
    /// found beside it from another process's folder.
    fn __reduce__<'py>(slf: &Bound<'py, Self>) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyTuple>)> {
        let (py, this) = (slf.py(), slf.get());
        let restore = slf.get_type().getattr("_restore")?;
        let path = std::path::absolute(&this.path).unwrap_or_else(|_| this.path.clone());
        let args = [this.text.clone().into_pyobject(py)?.into_any(), path.into_pyobject(py)?.into_any()];
        Ok((restore, PyTuple::new(py, args)?))
    }

    /// The inverse of `__reduce__`.
    #[staticmethod]
    fn _restore(py: Python<'_>, text: String, path: PathBuf) -> PyResult<Self> {
        Self::from_text(text, path).map_err(|e| to_py(py, e))
    }
}
