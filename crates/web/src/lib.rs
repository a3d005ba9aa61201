//! The library's code that runs in the visitor's browser, as WebAssembly (`static/vk-render.wasm`, built by
//! vk-render's build.rs for wasm32-unknown-unknown): the explore page's editor reads a student's `.brdf`
//! file and wraps its shader for the page's WebGL2 with the very code the renderer uses (crates/brdf-file),
//! and reads the browser's compiler messages back to the file's own lines and names. Nothing is sent
//! anywhere: the page compiles the result itself (static/explore/editor.js). It also runs the albedo's cubature
//! (crates/cubature) for the page's WebGL2 albedo probe (`albedo`), and the check of a student's image by
//! `vk-render check`'s rules (crates/check-rules) for a site's check page (`check`).
//!
//! The interface is plain WebAssembly, no bindings generator: the page writes a UTF-8 text into memory from
//! [`input`] (an image file's bytes from [`image_input`]), calls a function with its length, and reads the JSON answer of [`output`]'s length at
//! [`output`]. One call at a time (a page's script is one thread).

mod albedo;
mod check;

use std::cell::RefCell;

use brdf_file::{Parameter, ParameterValue, Target};
use serde_json::{json, Value};

/// The longest `.brdf` text the editor takes: 256 KiB (BRDF Explorer's files are under 10 KiB; the page
/// refuses a longer file before reading it, and the renderer takes up to 1 MiB).
pub const MAX_TEXT_BYTES: usize = 256 << 10;

thread_local! {
    static INPUT: RefCell<Vec<u8>> = const { RefCell::new(Vec::new()) };
    pub(crate) static OUTPUT: RefCell<Vec<u8>> = const { RefCell::new(Vec::new()) };
}

/// Room for an input of `length` bytes (at most [`MAX_TEXT_BYTES`] and a log's 64 KiB more): where the page
/// writes it, or 0 when it is longer.
#[no_mangle]
pub extern "C" fn input(length: usize) -> *mut u8 {
    room(length, MAX_TEXT_BYTES + (64 << 10))
}

/// Room for an image file of `length` bytes (at most 16 MiB, `check::MAX_IMAGE_BYTES`) in the input, where the
/// page writes it for the check's calls, or 0 when it is longer.
#[no_mangle]
pub extern "C" fn image_input(length: usize) -> *mut u8 {
    room(length, check::MAX_IMAGE_BYTES)
}

/// The input made `length` bytes long, where the page writes; null when that is over `most`.
fn room(length: usize, most: usize) -> *mut u8 {
    if length > most {
        return std::ptr::null_mut();
    }
    INPUT.with_borrow_mut(|input| {
        input.clear();
        input.resize(length, 0);
        input.as_mut_ptr()
    })
}

/// Where the last call's answer is (its length is what the call returned).
#[no_mangle]
pub extern "C" fn output() -> *const u8 {
    OUTPUT.with_borrow(|output| output.as_ptr())
}

/// [`MAX_TEXT_BYTES`], for the page to refuse a file before reading it.
#[no_mangle]
pub extern "C" fn max_text_bytes() -> usize {
    MAX_TEXT_BYTES
}

/// Reads the input's `length` bytes as a `.brdf` file: the answer of [`read_model`], its length returned.
#[no_mangle]
pub extern "C" fn read_brdf(length: usize) -> usize {
    answer(&read_model(&input_text(length)))
}

/// Reads the input's `length` bytes as the browser's compiler log of a model's shaders: the answer of
/// [`compiler_error`], its length returned.
#[no_mangle]
pub extern "C" fn read_compiler_log(length: usize) -> usize {
    answer(&compiler_error(&input_text(length)))
}

fn input_text(length: usize) -> String {
    INPUT.with_borrow(|input| String::from_utf8_lossy(&input[..length.min(input.len())]).into_owned())
}

/// `read` of the input's first `length` bytes.
fn input_bytes<R>(length: usize, read: impl FnOnce(&[u8]) -> R) -> R {
    INPUT.with_borrow(|input| read(&input[..length.min(input.len())]))
}

fn answer(value: &Value) -> usize {
    OUTPUT.with_borrow_mut(|output| {
        *output = value.to_string().into_bytes();
        output.len()
    })
}

/// A `.brdf` text read and its shader wrapped for WebGL2: `{"glsl", "parameters", "values", "offsets",
/// "warnings", "sampler"}`, or `{"error": {"line", "message"}}` (the line from 1, or null for the file as a
/// whole). `parameters` are the explore page's controls (as the server describes a material's: name, kind
/// "number", "colour" or "bool", value, min and max); `values` the defaults as the renderer's parameter buffer
/// holds them (`Analytic::floats`), `offsets` where each parameter's begin.
pub fn read_model(text: &str) -> Value {
    if text.len() > MAX_TEXT_BYTES {
        let message = format!("the text is {} bytes: the editor takes at most {MAX_TEXT_BYTES}", text.len());
        return json!({ "error": { "line": null, "message": message } });
    }
    let wrapped = brdf_file::parse(text).and_then(|file| {
        brdf_file::wrap(&file.parameters, &file.shader, &file.sampler, Target::WebGl).map(|g| (file, g))
    });
    let (file, glsl) = match wrapped {
        Ok(read) => read,
        Err(error) => return json!({ "error": { "line": error.line, "message": error.message } }),
    };
    let mut values = Vec::new();
    let mut offsets = serde_json::Map::new();
    for parameter in &file.parameters {
        offsets.insert(parameter.name.clone(), json!(values.len()));
        parameter.kind.default_value().extend_floats(&mut values);
    }
    json!({
        "glsl": glsl,
        "parameters": file.parameters.iter().map(control).collect::<Vec<_>>(),
        "values": values,
        "offsets": offsets,
        "warnings": file.warnings,
        "sampler": !file.sampler.is_empty(),
    })
}

/// A parameter as the explore page's control of it, at its default (as the server describes an analytic
/// material's: `ParameterKind::control`).
fn control(parameter: &Parameter) -> Value {
    let (kind, range) = parameter.kind.control();
    let value = match parameter.kind.default_value() {
        ParameterValue::Float(v) => json!(v),
        ParameterValue::Bool(b) => json!(b),
        ParameterValue::Color(c) => json!(c.to_array()),
    };
    let mut control =
        json!({ "name": parameter.name, "kind": kind, "value": value, "log": false, "line": parameter.line });
    if let Some((min, max)) = range {
        control["min"] = json!(min);
        control["max"] = json!(max);
    }
    control
}

/// The browser's compiler log of a model's shaders as the file's first error: `{"line", "message"}` (the
/// line null where it is vk-render's code).
pub fn compiler_error(log: &str) -> Value {
    let error = brdf_file::file_error(log, Target::WebGl);
    json!({ "line": error.line, "message": error.message })
}

#[cfg(test)]
mod tests {
    use super::*;

    const MODEL: &str = "analytic\n::begin parameters\nfloat a 0 2 0.5\ncolor c 0.1 0.2 0.3\nbool b 1\n\
                         ::end parameters\n::begin shader\nvec3 BRDF(vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y)\n{\n    \
                         return c * a;\n}\n::end shader\n";

    #[test]
    fn a_model_is_read_with_its_controls_and_values_in_the_buffers_order() {
        let read = read_model(MODEL);
        assert_eq!(read["values"], json!([0.5, 0.1f32, 0.2f32, 0.3f32, 1.0]));
        assert_eq!(read["offsets"], json!({ "a": 0, "c": 1, "b": 4 }));
        assert_eq!(
            read["parameters"][0],
            json!({ "name": "a", "kind": "number", "value": 0.5, "min": 0.0, "max": 2.0, "log": false, "line": 3 })
        );
        assert_eq!(read["parameters"][1]["kind"], "colour");
        assert_eq!(read["parameters"][2]["value"], true);
        let glsl = read["glsl"].as_str().unwrap();
        assert!(glsl.contains("#line 8 1\nvec3 usr_BRDF("), "{glsl}");
        assert_eq!(read["sampler"], false);
    }

    #[test]
    fn a_mistake_is_the_files_line_and_a_log_is_read_back_to_it() {
        let broken = MODEL.replace("float a 0 2 0.5", "float a 0 2");
        assert_eq!(read_model(&broken)["error"]["line"], 3);
        let no_brdf = MODEL.replace("BRDF(", "brdf(");
        assert_eq!(read_model(&no_brdf)["error"]["line"], Value::Null);
        let long = "x".repeat(MAX_TEXT_BYTES + 1);
        assert!(read_model(&long)["error"]["message"].as_str().unwrap().contains("at most 262144"));
        let log =
            compiler_error("ERROR: 1:10: 'usr_q' : undeclared identifier\nERROR: 1:10: '' : compilation terminated");
        assert_eq!(log, json!({ "line": 10, "message": "GLSL: 'q' : undeclared identifier" }));
    }

    #[test]
    fn the_interface_takes_an_input_and_gives_its_answer() {
        let at = input(MODEL.len());
        assert!(!at.is_null());
        unsafe { std::ptr::copy_nonoverlapping(MODEL.as_ptr(), at, MODEL.len()) };
        let length = read_brdf(MODEL.len());
        let text = unsafe { std::slice::from_raw_parts(output(), length) };
        let read: Value = serde_json::from_slice(text).unwrap();
        assert!(read["glsl"].is_string());
        assert!(input(MAX_TEXT_BYTES + (64 << 10) + 1).is_null());
    }
}
