//! What the server takes from a client, and the bounds it holds every request to: the overrides a request
//! may make (values only: nothing that names a file or a model to compile), the size of the images it
//! renders and checks, and what an upload must be before it is decoded.

use std::time::Duration;

use serde_json::Value as Json;

use vk_render::files::shortened;
use vk_render::scene::Shorthands;
use vk_render::{Override, Scene};

use super::error::ApiError;

/// The bounds of one server, stated in `vk-render serve --help` and docs/serve.md.
#[derive(Clone, Copy, Debug)]
pub struct Limits {
    /// The longest side of an image the server renders or checks, in pixels.
    pub max_side: u32,
    /// The most pixels of one image.
    pub max_pixels: u64,
    /// The most samples per pixel.
    pub max_samples: u32,
    /// The largest shadow cube face.
    pub max_shadow_map: u32,
    /// The largest upload, in bytes.
    pub max_upload: usize,
    /// The time a client has to send a request's headers (the connection is closed after it).
    pub header_timeout: Duration,
    /// The longest pause in a request's body (408 after it).
    pub body_timeout: Duration,
}

impl Default for Limits {
    fn default() -> Self {
        Self {
            max_side: 2048,
            max_pixels: 2048 * 1536,
            max_samples: 4,
            max_shadow_map: 2048,
            max_upload: 16 << 20,
            header_timeout: Duration::from_secs(10),
            body_timeout: Duration::from_secs(30),
        }
    }
}

/// The last words of the keys whose value may be a string: each names a choice among the scene format's
/// words (a model, a view, a mode), none a file.
const WORD_KEYS: [&str; 8] = ["brdf", "diffuse", "view", "mode", "tonemap", "encoding", "shadow_filter", "builtin"];

/// Models a request may switch a material to: the course's (a measured or analytic material reads a file).
const MODELS: [&str; 5] = ["lambert", "oren-nayar", "phong", "blinn-phong", "cook-torrance"];

/// The most overrides one request makes.
const MAX_OVERRIDES: usize = 256;

/// The overrides of a request: the image shorthands (`width`, `height`, `samples`, `view`,
/// `environment_mode`) first, then `set`, as the command line applies them. A value is a number, a bool, an
/// array of numbers, or for the keys of [`WORD_KEYS`] a word; `object.N.material` names a material of the
/// scene. Anything else is refused, naming the key.
pub fn overrides(request: &serde_json::Map<String, Json>) -> Result<Vec<Override>, ApiError> {
    let number = |key: &str| -> Result<Option<i64>, ApiError> {
        match request.get(key) {
            None | Some(Json::Null) => Ok(None),
            Some(value) => value
                .as_i64()
                .map(Some)
                .ok_or_else(|| ApiError::bad_request(format!("{key} = {value}: expected a whole number"))),
        }
    };
    let word = |key: &str| -> Result<Option<&str>, ApiError> {
        match request.get(key) {
            None | Some(Json::Null) => Ok(None),
            Some(Json::String(s)) => Ok(Some(s.as_str())),
            Some(value) => Err(ApiError::bad_request(format!("{key} = {value}: expected a word"))),
        }
    };
    let shorthands = Shorthands {
        width: number("width")?,
        height: number("height")?,
        samples: number("samples")?,
        view: word("view")?,
        environment_mode: word("environment_mode")?,
    };
    let mut all = shorthands.overrides();
    match request.get("set") {
        None | Some(Json::Null) => {}
        Some(Json::Object(set)) => {
            if set.len() > MAX_OVERRIDES {
                return Err(ApiError::bad_request(format!("set: {} keys; at most {MAX_OVERRIDES}", set.len())));
            }
            for (key, value) in set {
                all.push(Override::new(key.clone(), override_value(key, value)?));
            }
        }
        Some(other) => return Err(ApiError::bad_request(format!("set = {other}: expected an object of KEY: VALUE"))),
    }
    Ok(all)
}

/// One `set` value as TOML, checked as [`overrides`] says.
fn override_value(key: &str, value: &Json) -> Result<toml::Value, ApiError> {
    let refused = |why: &str| ApiError::bad_request(format!("set {key} = {}: {why}", shortened(&value.to_string())));
    if key.is_empty() || key.len() > 200 || key.split('.').any(str::is_empty) {
        return Err(ApiError::bad_request(format!("set `{}`: not a dotted key path", shortened(key))));
    }
    let last = key.rsplit('.').next().unwrap_or(key);
    match value {
        Json::Bool(b) => Ok(toml::Value::Boolean(*b)),
        Json::Number(n) => number(n).ok_or_else(|| refused("not a finite number")),
        Json::Array(items) if items.len() <= 4 => items
            .iter()
            .map(|item| item.as_number().and_then(number).ok_or_else(|| refused("expected an array of numbers")))
            .collect::<Result<Vec<_>, _>>()
            .map(toml::Value::Array),
        Json::Array(_) => Err(refused("an array of at most 4 numbers")),
        Json::String(word) if last == "brdf" && !MODELS.contains(&word.as_str()) => {
            Err(refused(&format!("the server switches a material to one of {} only", MODELS.join(", "))))
        }
        Json::String(word) if WORD_KEYS.contains(&last) || is_material_choice(key) => {
            if word.len() <= 64 && word.chars().all(|c| c.is_ascii_alphanumeric() || matches!(c, '-' | '_')) {
                Ok(toml::Value::String(word.clone()))
            } else {
                Err(refused("not a word of the scene format"))
            }
        }
        Json::String(_) => Err(refused("this key takes no word here (the server sets no file or path)")),
        Json::Null | Json::Object(_) => Err(refused("expected a number, a bool, an array of numbers or a word")),
    }
}

/// `object.N.material`: a material of the scene, by name.
fn is_material_choice(key: &str) -> bool {
    let parts: Vec<&str> = key.split('.').collect();
    matches!(parts.as_slice(), ["object", index, "material"] if index.parse::<usize>().is_ok())
}

fn number(n: &serde_json::Number) -> Option<toml::Value> {
    if let Some(i) = n.as_i64() {
        return Some(toml::Value::Integer(i));
    }
    n.as_f64().filter(|f| f.is_finite()).map(toml::Value::Float)
}

impl Limits {
    /// Refuses a scene whose image is past the bounds (400, naming the key and the bound).
    pub fn check_scene(&self, scene: &Scene) -> Result<(), ApiError> {
        let image = &scene.image;
        if image.width > self.max_side || image.height > self.max_side {
            return Err(ApiError::bad_request(format!(
                "image {} x {}: this server renders at most {} pixels a side",
                image.width, image.height, self.max_side
            )));
        }
        if u64::from(image.width) * u64::from(image.height) > self.max_pixels {
            return Err(ApiError::bad_request(format!(
                "image {} x {}: this server renders at most {} pixels an image",
                image.width, image.height, self.max_pixels
            )));
        }
        if image.samples > self.max_samples {
            return Err(ApiError::bad_request(format!(
                "image.samples = {}: this server renders at most {} samples a pixel",
                image.samples, self.max_samples
            )));
        }
        if image.shadow_map_size > self.max_shadow_map {
            return Err(ApiError::bad_request(format!(
                "image.shadow_map_size = {}: this server's shadow cubes are at most {} texels a side",
                image.shadow_map_size, self.max_shadow_map
            )));
        }
        Ok(())
    }
}

/// The formats an upload may be, recognised by their first bytes (whatever its name says).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Upload {
    Png,
    Jpeg,
}

impl Upload {
    /// What `bytes` begin as: a PNG's signature or a JPEG's start of image; anything else 415.
    pub fn sniff(bytes: &[u8]) -> Result<Self, ApiError> {
        if bytes.is_empty() {
            return Err(ApiError::bad_request("image: the file is empty".into()));
        }
        if bytes.starts_with(b"\x89PNG\r\n\x1a\n") {
            return Ok(Upload::Png);
        }
        if bytes.starts_with(&[0xFF, 0xD8, 0xFF]) {
            return Ok(Upload::Jpeg);
        }
        Err(ApiError::unsupported("image: not a PNG or JPEG file (recognised by its content, not its name)".into()))
    }

    /// The image's size as its header states it, read without decoding any pixel; refused above the bounds
    /// (413) before anything is allocated for its pixels, and a header that cannot be read 400.
    pub fn dimensions(self, bytes: &[u8], limits: &Limits) -> Result<(u32, u32), ApiError> {
        let format = match self {
            Upload::Png => image::ImageFormat::Png,
            Upload::Jpeg => image::ImageFormat::Jpeg,
        };
        // Reading the header allocates nothing for the pixels.
        let (width, height) = image::ImageReader::with_format(std::io::Cursor::new(bytes), format)
            .into_dimensions()
            .map_err(|e| ApiError::bad_request(format!("image: not a PNG or JPEG image vk-render can read: {e}")))?;
        if width > limits.max_side
            || height > limits.max_side
            || u64::from(width) * u64::from(height) > limits.max_pixels
        {
            return Err(ApiError::too_large(format!(
                "image: {width} x {height} pixels; this server checks images of at most {} pixels a side and {} pixels in all",
                limits.max_side, limits.max_pixels
            )));
        }
        if width == 0 || height == 0 {
            return Err(ApiError::bad_request(format!("image: {width} x {height} pixels")));
        }
        Ok((width, height))
    }
}

/// The decoder's limits for an upload: its sides, and memory for its pixels with room for the decoder's own.
pub fn decoding_limits(limits: &Limits) -> image::Limits {
    let mut decoding = image::Limits::default();
    decoding.max_image_width = Some(limits.max_side);
    decoding.max_image_height = Some(limits.max_side);
    decoding.max_alloc = Some(limits.max_pixels * 4 * 3);
    decoding
}
