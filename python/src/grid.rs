//! `vk_render._native.Grid`: the library's grid of parameter values (`vk_render::scene::grid`), the one that
//! `vk-render sweep` renders: the same order of combinations, shards, labels and tile names.

use std::path::PathBuf;

use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList, PyString};
use vk_render::scene::grid::{Grid, GridParam, GridValue, Shard};

use crate::convert::toml_value;
use crate::errors::scene_error;

/// The product of a few parameters' values: `Grid({"material.grey.kd": [0.2, 0.5], ...})`.
#[pyclass(module = "vk_render._native", name = "Grid", frozen)]
pub struct PyGrid {
    grid: Grid,
}

/// A Python value as a grid value: its TOML value, and the text a label and file name show (a str as it
/// is, anything else as TOML writes it: 0.3, true, [1, 2]), as `--values` text would show it.
fn grid_value(py: Python<'_>, key: &str, value: &Bound<'_, PyAny>) -> PyResult<GridValue> {
    let converted = toml_value(py, key, value)?;
    let text = match value.downcast::<PyString>() {
        Ok(text) => text.to_cow()?.into_owned(),
        Err(_) => converted.to_string(),
    };
    if text.trim().is_empty() {
        return Err(scene_error(py, format!("grid {key}: a value is empty")));
    }
    Ok(GridValue { text, value: converted })
}

#[pymethods]
impl PyGrid {
    /// A grid from a dict of key -> list of values (the first key varies slowest, as in the sheet's rows).
    #[new]
    fn new(py: Python<'_>, grid: &Bound<'_, PyDict>) -> PyResult<Self> {
        let mut params = Vec::new();
        for (key, values) in grid.iter() {
            let key: String =
                key.extract().map_err(|_| scene_error(py, format!("grid: the key {key} is not a str")))?;
            if values.is_instance_of::<PyString>() {
                return Err(scene_error(py, format!("grid {key}: give a list of values, not one str")));
            }
            let values = values
                .try_iter()
                .map_err(|_| scene_error(py, format!("grid {key}: give a list of values")))?
                .map(|value| grid_value(py, &key, &value?))
                .collect::<PyResult<Vec<_>>>()?;
            params.push(GridParam { key, values });
        }
        Ok(Self { grid: Grid::new(params).map_err(|message| scene_error(py, message))? })
    }

    /// The number of combinations.
    fn __len__(&self) -> usize {
        self.grid.len()
    }

    /// The indices of shard `k` of `n` (1-based, as `--shard K/N`).
    fn shard(&self, py: Python<'_>, k: usize, n: usize) -> PyResult<Vec<usize>> {
        let shard: Shard = format!("{k}/{n}").parse().map_err(|message: String| scene_error(py, message))?;
        Ok((0..self.grid.len()).filter(|&i| shard.contains(i)).collect())
    }

    /// Combination `index`: a dict with "index", "text" (key -> each value as labels show it),
    /// "positions" (which of each key's values), "label" and "tile" (its file beside a sheet named
    /// `sheet`, as `vk-render sweep -o SHEET` names it).
    #[pyo3(signature = (index, sheet = PathBuf::from("sweep.png")))]
    fn combination<'py>(&self, py: Python<'py>, index: usize, sheet: PathBuf) -> PyResult<Bound<'py, PyDict>> {
        if index >= self.grid.len() {
            return Err(pyo3::exceptions::PyIndexError::new_err(format!(
                "combination {index} of a grid of {}",
                self.grid.len()
            )));
        }
        let combination = self.grid.combination(index);
        let entry = PyDict::new(py);
        entry.set_item("index", index)?;
        let texts = PyDict::new(py);
        for (key, value) in &combination.values {
            texts.set_item(key, &value.text)?;
        }
        entry.set_item("text", texts)?;
        // Which of each parameter's values it takes, so that the caller sets the very Python value given.
        let positions = self.grid.positions(index);
        entry.set_item("positions", positions)?;
        entry.set_item("label", combination.label(&self.grid))?;
        let tile: PathBuf = combination.tile_path(&self.grid, &sheet);
        entry.set_item("tile", tile)?;
        Ok(entry)
    }

    /// The keys, in order.
    #[getter]
    fn keys<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        PyList::new(py, self.grid.params().iter().map(|p| p.key.clone()))
    }

    fn __repr__(&self) -> String {
        let sizes: Vec<String> = self.grid.params().iter().map(|p| format!("{}: {}", p.key, p.values.len())).collect();
        format!("vk_render.Grid({{{}}}: {} combinations)", sizes.join(", "), self.grid.len())
    }
}
