//! Python values and numpy arrays to and from what the library takes: TOML values for `set`, overrides,
//! images as (height, width, 3) arrays.

use numpy::{PyArray1, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};
use toml::Value;
use vk_render::Override;

use crate::errors::scene_error;

/// A Python value as the TOML value `--set` would take: bool, int, float, str, a list or tuple (or a numpy
/// array, through its `tolist`), a dict of them. `key` names it in the error.
pub fn toml_value(py: Python<'_>, key: &str, value: &Bound<'_, PyAny>) -> PyResult<Value> {
    if value.is_instance_of::<PyBool>() {
        return Ok(Value::Boolean(value.extract()?));
    }
    if value.is_instance_of::<PyInt>() {
        return value
            .extract::<i64>()
            .map(Value::Integer)
            .map_err(|_| scene_error(py, format!("set {key}: {value} does not fit a 64-bit integer")));
    }
    if value.is_instance_of::<PyFloat>() {
        return Ok(Value::Float(value.extract()?));
    }
    if let Ok(text) = value.downcast::<PyString>() {
        return Ok(Value::String(text.to_cow()?.into_owned()));
    }
    if let Ok(table) = value.downcast::<PyDict>() {
        let mut converted = toml::Table::new();
        for (k, v) in table.iter() {
            let k: String = k.extract().map_err(|_| scene_error(py, format!("set {key}: a key {k} is not a str")))?;
            let inner = toml_value(py, &format!("{key}.{k}"), &v)?;
            converted.insert(k, inner);
        }
        return Ok(Value::Table(converted));
    }
    if value.is_instance_of::<PyList>() || value.is_instance_of::<PyTuple>() {
        let items = value.try_iter()?.map(|item| toml_value(py, key, &item?)).collect::<PyResult<Vec<_>>>()?;
        return Ok(Value::Array(items));
    }
    // numpy arrays and scalars: their Python equivalents.
    if value.hasattr("tolist")? {
        let plain = value.call_method0("tolist")?;
        if !plain.is(value) {
            return toml_value(py, key, &plain);
        }
    }
    // Other numbers (fractions, decimals): as a float when Python can make one.
    if let Ok(number) = value.extract::<f64>() {
        return Ok(Value::Float(number));
    }
    Err(scene_error(
        py,
        format!("set {key}: {} is not a value of a scene (a number, str, bool, list or dict)", value.repr()?),
    ))
}

/// `set={...}` as overrides, in the dict's order (as --set flags in the order given).
pub fn overrides(py: Python<'_>, set: Option<&Bound<'_, PyDict>>) -> PyResult<Vec<Override>> {
    let Some(set) = set else { return Ok(Vec::new()) };
    set.iter()
        .map(|(key, value)| {
            let key: String = key.extract().map_err(|_| scene_error(py, format!("set: the key {key} is not a str")))?;
            let path_ok = !key.is_empty() && !key.split('.').any(str::is_empty);
            if !path_ok {
                return Err(scene_error(
                    py,
                    format!("set: `{key}` is not a dotted key path (e.g. material.grey.sigma)"),
                ));
            }
            Ok(Override::new(key.clone(), toml_value(py, &key, &value)?))
        })
        .collect()
}

/// An image's channels as a (height, width, 3) numpy array.
pub fn image_array<'py, T: numpy::Element>(
    py: Python<'py>,
    (width, height): (u32, u32),
    channels: Vec<T>,
) -> PyResult<Bound<'py, PyAny>> {
    Ok(PyArray1::from_vec(py, channels).reshape([height as usize, width as usize, 3])?.into_any())
}

/// A (height, width, 3) uint8 array as an 8-bit RGB image.
pub fn rgb_image(py: Python<'_>, array: &Bound<'_, numpy::PyArray3<u8>>) -> PyResult<image::RgbImage> {
    let shape = array.shape();
    if shape[2] != 3 {
        return Err(scene_error(py, format!("the image is {shape:?}: expected (height, width, 3) RGB")));
    }
    // In logical order, whatever the array's strides.
    let bytes: Vec<u8> = array.readonly().as_array().iter().copied().collect();
    image::RgbImage::from_raw(shape[1] as u32, shape[0] as u32, bytes)
        .ok_or_else(|| scene_error(py, format!("the image is {shape:?}: too large")))
}
