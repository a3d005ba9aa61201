//! `--set KEY=VALUE`: one value of the scene replaced through a dotted path such as `material.grey.sigma`,
//! `image.width` or `light.0.power` (arrays of tables take an index).

use std::fmt;
use std::str::FromStr;

use serde::Deserialize;
use toml::{Table, Value};

use super::file::SceneFile;
pub use crate::files::shortened;

/// One `KEY=VALUE` override from the command line.
#[derive(Clone, Debug, PartialEq)]
pub struct Override {
    /// The dotted path, e.g. `light.0.power`.
    pub path: String,
    /// The value as TOML; text that is not a TOML value is taken as a string (`brdf=phong`).
    pub value: Value,
}

impl Override {
    /// An override of `path` with an already typed value.
    pub fn new(path: impl Into<String>, value: impl Into<Value>) -> Self {
        Self { path: path.into(), value: value.into() }
    }
}

impl FromStr for Override {
    type Err = String;

    fn from_str(text: &str) -> Result<Self, String> {
        let (path, value_text) =
            text.split_once('=').ok_or_else(|| format!("`{text}` is not KEY=VALUE (e.g. image.width=1200)"))?;
        let path = path.trim();
        if path.is_empty() || path.split('.').any(str::is_empty) {
            return Err(format!("`{path}` is not a dotted key path (e.g. material.grey.sigma)"));
        }
        let value = Self::parse_value(value_text).map_err(|e| format!("--set {path}: {e}"))?;
        Ok(Self { path: path.to_string(), value })
    }
}

impl Override {
    /// A value as `--set KEY=VALUE` and `sweep --values` take it (trimmed): one TOML value, parsed as the
    /// document `v = VALUE`, which must then hold `v` alone (a newline and a second assignment is not a
    /// value). Text that is no TOML value at all, on one line, is taken as a string (`brdf=phong`, a path
    /// with spaces).
    ///
    /// # Errors
    /// A message quoting the text (cut at 40 characters) when it holds several values or several lines.
    pub fn parse_value(text: &str) -> Result<Value, String> {
        let text = text.trim();
        match toml::from_str::<Table>(&format!("v = {text}")) {
            Ok(mut document) if document.len() == 1 => document.remove("v").ok_or_else(|| "no value".to_string()),
            Ok(_) => Err(format!("`{}` holds more than one value", shortened(text))),
            Err(_) if text.contains(['\n', '\r']) => Err(format!("`{}` is not one TOML value", shortened(text))),
            Err(_) => Ok(Value::String(text.to_string())),
        }
    }
}

/// The image options' shorthands (`--width`, `--height`, `--samples`, `--view`, `--environment-mode`), which
/// the command line and the Python package apply as overrides before any `--set`.
#[derive(Clone, Copy, Debug, Default)]
pub struct Shorthands<'a> {
    /// `--width`: `image.width`, in pixels.
    pub width: Option<i64>,
    /// `--height`: `image.height`, in pixels.
    pub height: Option<i64>,
    /// `--samples`: `image.samples`, MSAA samples per pixel.
    pub samples: Option<i64>,
    /// `--view`: `image.view`, a [`View`](super::View) name such as `"n-dot-l"`.
    pub view: Option<&'a str>,
    /// `--environment-mode`: `environment.mode`, `"exact"` or `"fast"`.
    pub environment_mode: Option<&'a str>,
}

impl Shorthands<'_> {
    /// The overrides they stand for, in that order: `image.width`, ..., `environment.mode`.
    pub fn overrides(&self) -> Vec<Override> {
        let numbers = [("image.width", self.width), ("image.height", self.height), ("image.samples", self.samples)];
        let words = [("image.view", self.view), ("environment.mode", self.environment_mode)];
        let numbers = numbers.into_iter().filter_map(|(key, value)| value.map(|v| Override::new(key, v)));
        numbers.chain(words.into_iter().filter_map(|(key, value)| value.map(|v| Override::new(key, v)))).collect()
    }
}

impl fmt::Display for Override {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "--set {}={}", self.path, self.value)
    }
}

/// Top-level tables an override may create: [image] and [camera], whose every key has a default, and
/// [environment], so that `--set environment.builtin="sky"` lights any scene (validation says what a
/// created [environment] still lacks).
const OPTIONAL_TABLES: [&str; 3] = ["image", "camera", "environment"];

/// Applies each override to the parsed table in turn and deserializes the result.
///
/// Each override is checked on its own, so an error names the one that broke the scene.
pub(super) fn apply(table: &mut Table, overrides: &[Override]) -> Result<SceneFile, String> {
    let mut scene = None;
    for item in overrides {
        set(table, item).map_err(|e| format!("{item}: {e}"))?;
        let parsed = SceneFile::deserialize(Value::Table(table.clone()))
            .map_err(|e| format!("{item}: {}", e.message().trim_end()))?;
        scene = Some(parsed);
    }
    scene.ok_or_else(|| "no override to apply".to_string())
}

/// Writes one value at its dotted path; every step but the last must already exist.
fn set(table: &mut Table, item: &Override) -> Result<(), String> {
    let segments: Vec<&str> = item.path.split('.').collect();
    let (last, parents) = segments.split_last().ok_or("empty key path")?;
    let mut current = table;
    let mut walked = String::new();
    let mut iter = parents.iter().peekable();
    while let Some(&segment) = iter.next() {
        let here = if walked.is_empty() { segment.to_string() } else { format!("{walked}.{segment}") };
        if walked.is_empty() && OPTIONAL_TABLES.contains(&segment) {
            // [image], [camera] and [environment] may be left out of a file entirely.
            current.entry(segment).or_insert_with(|| Value::Table(Table::new()));
        }
        if segment == "params" && walked.starts_with("material.") && walked.matches('.').count() == 1 {
            // A material's `params` (an analytic model's) may be left out: its parameters take the file's
            // defaults, and validation says whether the material takes any.
            current.entry(segment).or_insert_with(|| Value::Table(Table::new()));
        }
        let value = current.get_mut(segment).ok_or_else(|| format!("unknown key path: the scene has no `{here}`"))?;
        current = match value {
            Value::Table(child) => child,
            Value::Array(array) => {
                let index_text =
                    iter.next().ok_or_else(|| format!("`{here}` is a list: add an index, e.g. {here}.0"))?;
                let count = array.len();
                let index: usize = index_text
                    .parse()
                    .map_err(|_| format!("`{index_text}` is not an index into `{here}` (the scene has {count})"))?;
                match array.get_mut(index) {
                    Some(Value::Table(child)) => child,
                    Some(_) => return Err(format!("`{here}.{index}` is not a table")),
                    None => return Err(format!("there is no `{here}.{index}`: the scene has {count} {segment}(s)")),
                }
            }
            _ => return Err(format!("`{here}` is a value, not a table: it has no key `{}`", item.path)),
        };
        walked = here;
    }
    match (current.get_mut(*last), &item.value) {
        // A table given for a table changes the keys it names and keeps the others: `image={width=8}`
        // is `image.width=8`, not an [image] of defaults but for its width.
        (Some(Value::Table(existing)), Value::Table(given)) => merge(existing, given),
        _ => {
            current.insert((*last).to_string(), item.value.clone());
        }
    }
    Ok(())
}

/// Writes every key of `given` into `table`, tables into tables key by key.
fn merge(table: &mut Table, given: &Table) {
    for (key, value) in given {
        match (table.get_mut(key), value) {
            (Some(Value::Table(existing)), Value::Table(inner)) => merge(existing, inner),
            _ => {
                table.insert(key.clone(), value.clone());
            }
        }
    }
}
