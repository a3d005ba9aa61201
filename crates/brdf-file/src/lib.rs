//! BRDF Explorer's analytic `.brdf` files (wdas/brdf) read and wrapped for vk-render's shaders: a list of
//! parameters and a GLSL function `vec3 BRDF(vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y)` returning f_r without
//! the cosine.
//!
//! A file is read ([`parse`]) and its shader wrapped ([`wrap`]: the file's names moved out of vk-render's,
//! each line at its own line), for the renderer's Vulkan shaders or for the browser's WebGL2 ones
//! ([`Target`]). This crate needs no device, so that the same code runs in the renderer (`vk-render`'s
//! `brdf::analytic`, which compiles the result) and, compiled to WebAssembly, in the page where a student
//! writes a model (`crates/web/`, whose browser compiles the result).

mod glsl;
mod names;
mod parse;

use std::fmt;

use glam::Vec3;

pub use glsl::{
    check_unit, file_error, included_file, shader_in_double, wrap, wrap_double, Target, DOUBLE_FOLDER, PREFIX,
};
pub use parse::{parse, BrdfFile, ParseError};

/// At most the first 40 characters of `text`, for messages that quote what the user gave.
pub fn shortened(text: &str) -> String {
    match text.char_indices().nth(40) {
        Some((end, _)) => format!("{}... ({} characters)", &text[..end], text.chars().count()),
        None => text.to_string(),
    }
}

/// A parameter a file declares.
#[derive(Clone, Debug, PartialEq)]
pub struct Parameter {
    /// Its name in the file: what its GLSL and a scene's `params` call it.
    pub name: String,
    /// Its type, range and default.
    pub kind: ParameterKind,
    /// Its line in the file, from 1.
    pub line: usize,
}

/// A parameter's type, range and default.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ParameterKind {
    /// `float NAME MIN MAX DEFAULT`.
    Float {
        /// The least value a material may give it.
        min: f32,
        /// The greatest value a material may give it.
        max: f32,
        /// The value of a material that gives none, within `min..=max`.
        default: f32,
    },
    /// `bool NAME 0|1`.
    Bool {
        /// The value of a material that gives none.
        default: bool,
    },
    /// `color NAME R G B`: any three numbers (BRDF Explorer gives colours no range).
    Color {
        /// The value of a material that gives none, RGB as the file writes it.
        default: Vec3,
    },
}

impl ParameterKind {
    /// The floats the parameter takes in the parameter buffer.
    pub fn floats(self) -> usize {
        match self {
            ParameterKind::Float { .. } | ParameterKind::Bool { .. } => 1,
            ParameterKind::Color { .. } => 3,
        }
    }

    /// The type's name as the file writes it.
    pub fn type_name(self) -> &'static str {
        match self {
            ParameterKind::Float { .. } => "float",
            ParameterKind::Bool { .. } => "bool",
            ParameterKind::Color { .. } => "color",
        }
    }

    /// How the explore page's control of such a parameter moves: its kind (`number`, `colour` or `bool`) and
    /// the range it spans, if any (a float over the file's range, each component of a colour over 0..1).
    pub fn control(self) -> (&'static str, Option<(f32, f32)>) {
        match self {
            ParameterKind::Float { min, max, .. } => ("number", Some((min, max))),
            ParameterKind::Bool { .. } => ("bool", None),
            ParameterKind::Color { .. } => ("colour", Some((0.0, 1.0))),
        }
    }

    /// The default value.
    pub fn default_value(self) -> ParameterValue {
        match self {
            ParameterKind::Float { default, .. } => ParameterValue::Float(default),
            ParameterKind::Bool { default } => ParameterValue::Bool(default),
            ParameterKind::Color { default } => ParameterValue::Color(default),
        }
    }
}

/// A parameter's value.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ParameterValue {
    /// A `float` parameter's, within its range.
    Float(f32),
    /// A `bool` parameter's (1.0 or 0.0 in the parameter buffer).
    Bool(bool),
    /// A `color` parameter's: three numbers, RGB.
    Color(Vec3),
}

impl ParameterValue {
    /// Appends the value as the parameter buffer holds it ([`ParameterKind::floats`] of them): a float, a bool
    /// as 1 or 0, a colour's three components (the wrapper's `analytic_set_parameters` reads them so).
    pub fn extend_floats(self, floats: &mut Vec<f32>) {
        match self {
            ParameterValue::Float(v) => floats.push(v),
            ParameterValue::Bool(b) => floats.push(if b { 1.0 } else { 0.0 }),
            ParameterValue::Color(c) => floats.extend(c.to_array()),
        }
    }
}

impl fmt::Display for ParameterValue {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ParameterValue::Float(v) => write!(f, "{v}"),
            ParameterValue::Bool(v) => write!(f, "{v}"),
            ParameterValue::Color(c) => write!(f, "[{}, {}, {}]", c.x, c.y, c.z),
        }
    }
}
