//! Turns the file's structures into a `Scene`: defaults, ranges and cross-references, each error naming
//! the key (as a `--set` path) and its value.

use std::collections::BTreeMap;
use std::path::Path;

use glam::Vec3;

use super::file::{
    CameraSection, EnvironmentSection, ImageSection, LightSection, MaterialSection, ObjectSection, Rgb, SceneFile,
};
use super::{
    BuiltinEnvironment, Camera, Encoding, Environment, EnvironmentMode, EnvironmentSource, ImageSettings, Object,
    PointLight, Scene, ShadowFilter, Shape, Tonemap, View, BUNNY_PATH, MAX_IMAGE_SIDE, MAX_LIGHTS,
};
use crate::brdf::{Analytic, AnalyticModel, Brdf, DiffuseModel, Measured, ParameterKind, ParameterValue};

type Check<T> = Result<T, String>;

/// A string the user gave, quoted for a message: at most its first 40 characters.
fn quoted(text: &str) -> String {
    format!("{:?}", super::overrides::shortened(text))
}

/// Validates a deserialized scene file read from `path`.
pub(super) fn validate(raw: SceneFile, path: &Path) -> Check<Scene> {
    let image = image(&raw.image)?;
    let camera = camera(&raw.camera)?;
    if raw.lights.len() > MAX_LIGHTS {
        return Err(format!(
            "light.{MAX_LIGHTS}: the scene has {} lights, and vk-render takes at most {MAX_LIGHTS} (each has its own shadow cube)",
            raw.lights.len()
        ));
    }
    let lights = raw.lights.iter().enumerate().map(|(i, l)| light(i, l)).collect::<Check<Vec<_>>>()?;
    let materials = raw
        .materials
        .iter()
        .map(|(name, m)| Ok((name.clone(), material(name, m, path)?)))
        .collect::<Check<BTreeMap<_, _>>>()?;
    let objects =
        raw.objects.iter().enumerate().map(|(i, o)| object(i, o, &materials, path)).collect::<Check<Vec<_>>>()?;
    if image.view.is_microfacet_term() && !objects.iter().any(|o| matches!(o.brdf, Brdf::CookTorrance { .. })) {
        // A .brdf file is one function: vk-render cannot tell its terms apart.
        let analytic = objects.iter().enumerate().find_map(|(i, o)| match &o.brdf {
            Brdf::Analytic(material) => Some(format!(
                " (object.{i}'s {} is a .brdf file, which has no separable terms)",
                material.model().name()
            )),
            _ => None,
        });
        return Err(format!(
            "image.view = \"{}\": no object is Cook-Torrance, the only model with a microfacet {} term{}",
            image.view.name(),
            image.view.name().to_uppercase(),
            analytic.unwrap_or_default()
        ));
    }
    let environment = raw.environment.as_ref().map(|e| environment(e, path)).transpose()?;
    Ok(Scene { source: path.to_path_buf(), image, camera, lights, objects, materials, environment })
}

fn image(s: &ImageSection) -> Check<ImageSettings> {
    let size = |key: &str, value: i64| -> Check<u32> {
        u32::try_from(value).ok().filter(|v| (1..=MAX_IMAGE_SIDE).contains(v)).ok_or_else(|| {
            format!(
                "image.{key} = {value}: must be a whole number of pixels from 1 to {MAX_IMAGE_SIDE} (and within the \
                 device's own limit, checked when it renders)"
            )
        })
    };
    let tonemap = match s.tonemap.as_str() {
        "clamp" => Tonemap::Clamp,
        "reinhard" => Tonemap::Reinhard,
        "aces" => Tonemap::Aces,
        other => {
            return Err(format!(
                "image.tonemap = {}: unknown tonemap (expected \"clamp\", \"reinhard\" or \"aces\")",
                quoted(other)
            ))
        }
    };
    let encoding = match s.encoding.as_str() {
        "linear" => Encoding::Linear,
        "srgb" => Encoding::Srgb,
        other => {
            return Err(format!(
                "image.encoding = {}: unknown encoding (expected \"linear\" or \"srgb\")",
                quoted(other)
            ))
        }
    };
    let shadow_filter = match s.shadow_filter.as_str() {
        "hard" => ShadowFilter::Hard,
        "pcf" => ShadowFilter::Pcf,
        other => {
            return Err(format!(
                "image.shadow_filter = {}: unknown filter (expected \"hard\" or \"pcf\")",
                quoted(other)
            ))
        }
    };
    let view = View::ALL.iter().copied().find(|view| view.name() == s.view).ok_or_else(|| {
        let names: Vec<String> = View::ALL.iter().map(|view| format!("\"{}\"", view.name())).collect();
        format!("image.view = {}: unknown view (expected one of {})", quoted(&s.view), names.join(", "))
    })?;
    let shadow_map_size = u32::try_from(s.shadow_map_size).ok().filter(|v| *v >= 16).ok_or_else(|| {
        format!("image.shadow_map_size = {}: must be a whole number of texels, at least 16", s.shadow_map_size)
    })?;
    let samples = u32::try_from(s.samples)
        .ok()
        .filter(|v| v.is_power_of_two())
        .ok_or_else(|| format!("image.samples = {}: must be a power of two such as 1 or 4", s.samples))?;
    Ok(ImageSettings {
        width: size("width", s.width)?,
        height: size("height", s.height)?,
        samples,
        background: non_negative("image.background", s.background)?,
        tonemap,
        exposure: at_least("image.exposure", s.exposure, 0.0)?,
        encoding,
        shadow_map_size,
        shadow_filter,
        view,
    })
}

fn environment(s: &EnvironmentSection, scene_path: &Path) -> Check<Environment> {
    let source =
        match (&s.map, &s.builtin) {
            (Some(map), None) => EnvironmentSource::Map(beside_scene(map, scene_path)),
            (None, Some(name)) => EnvironmentSource::Builtin(
                BuiltinEnvironment::ALL.into_iter().find(|b| b.name() == name).ok_or_else(|| {
                    format!(
                        "environment.builtin = {}: unknown environment (expected \"white\", \"sky\" or \"studio\")",
                        quoted(name)
                    )
                })?,
            ),
            (Some(map), Some(name)) => {
                return Err(format!(
                    "environment.builtin = {}: the environment already has map = {}: give one of the two",
                    quoted(name),
                    quoted(map)
                ))
            }
            (None, None) => return Err(
                "environment: has neither map = \"PATH.hdr\" (or .exr) nor builtin = \"white\", \"sky\" or \"studio\" \
                        (a scene without [environment] takes no environment.* setting alone)"
                    .into(),
            ),
        };
    if !(s.intensity.is_finite() && s.intensity >= 0.0) {
        return Err(format!("environment.intensity = {}: must be a finite number, at least 0", s.intensity));
    }
    if !s.rotation.is_finite() {
        return Err(format!("environment.rotation = {}: must be a finite number of degrees", s.rotation));
    }
    let mode = EnvironmentMode::from_name(&s.mode).ok_or_else(|| {
        format!("environment.mode = {}: unknown mode (expected \"exact\" or \"fast\")", quoted(&s.mode))
    })?;
    Ok(Environment { source, intensity: s.intensity, rotation: s.rotation, visible: s.visible, mode })
}

fn camera(s: &CameraSection) -> Check<Camera> {
    let position = finite("camera.position", s.position.0)?;
    let look_at = finite("camera.look_at", s.look_at.0)?;
    let up = nonzero("camera.up", s.up.0)?;
    // Closer than a millionth of the position's magnitude, the view direction is rounding noise.
    let distance = (look_at - position).length();
    if distance <= 1e-6 * position.length().max(1.0) {
        return Err(format!(
            "camera.look_at = {:?}: {} camera.position, so the camera looks nowhere",
            s.look_at.0,
            if distance == 0.0 { "equal to".to_string() } else { format!("{distance:e} from") }
        ));
    }
    if (look_at - position).cross(up).length_squared()
        <= 1e-12 * (look_at - position).length_squared() * up.length_squared()
    {
        return Err(format!(
            "camera.up = {:?}: parallel to the view direction, so the image has no defined up",
            s.up.0
        ));
    }
    if !(s.fov_y > 0.0 && s.fov_y < 180.0) {
        return Err(format!("camera.fov_y = {}: must be between 0 and 180 degrees (exclusive)", s.fov_y));
    }
    Ok(Camera { position, look_at, up, fov_y: s.fov_y })
}

fn light(index: usize, s: &LightSection) -> Check<PointLight> {
    let key = |name: &str| format!("light.{index}.{name}");
    if s.kind != "point" {
        return Err(format!("{} = {}: unknown light type (expected \"point\")", key("type"), quoted(&s.kind)));
    }
    Ok(PointLight {
        position: finite(&key("position"), s.position.0)?,
        color: non_negative(&key("color"), s.color)?,
        power: at_least(&key("power"), s.power, 0.0)?,
        shadows: s.shadows,
    })
}

/// The BRDF names, and the parameters each one takes.
const BRDF_PARAMETERS: [(&str, &[&str]); 7] = [
    ("lambert", &["kd"]),
    ("oren-nayar", &["kd", "sigma"]),
    ("phong", &["kd", "ks", "shininess"]),
    ("blinn-phong", &["kd", "ks", "shininess"]),
    ("cook-torrance", &["kd", "f0", "roughness", "metalness", "diffuse"]),
    ("measured", &["file", "sampler"]),
    ("analytic", &["file", "params"]),
];

fn material(name: &str, s: &MaterialSection, scene_path: &Path) -> Check<Brdf> {
    let key = |param: &str| format!("material.{name}.{param}");
    let Some(&(_, accepted)) = BRDF_PARAMETERS.iter().find(|(brdf, _)| *brdf == s.brdf) else {
        let names: Vec<_> = BRDF_PARAMETERS.iter().map(|(brdf, _)| format!("\"{brdf}\"")).collect();
        return Err(format!(
            "{} = {}: unknown brdf (expected one of {})",
            key("brdf"),
            quoted(&s.brdf),
            names.join(", ")
        ));
    };
    let present = [
        ("kd", s.kd.is_some()),
        ("ks", s.ks.is_some()),
        ("f0", s.f0.is_some()),
        ("shininess", s.shininess.is_some()),
        ("sigma", s.sigma.is_some()),
        ("roughness", s.roughness.is_some()),
        ("metalness", s.metalness.is_some()),
        ("diffuse", s.diffuse.is_some()),
        ("file", s.file.is_some()),
        ("params", s.params.is_some()),
        ("sampler", s.sampler.is_some()),
    ];
    if let Some((param, _)) = present.iter().find(|(param, set)| *set && !accepted.contains(param)) {
        return Err(format!("{}: not a parameter of brdf {:?} (it takes {})", key(param), s.brdf, accepted.join(", ")));
    }
    let required = |param: &str, value: Option<f32>| -> Check<f32> {
        value.ok_or_else(|| format!("{}: missing, and brdf {:?} needs it", key(param), s.brdf))
    };
    let reflectance = |param: &str, value: Option<Rgb>| -> Check<Vec3> {
        let rgb = value.ok_or_else(|| format!("{}: missing, and brdf {:?} needs it", key(param), s.brdf))?;
        unit_interval(&key(param), rgb)
    };
    if s.brdf == "measured" {
        let file =
            s.file.as_deref().ok_or_else(|| format!("{}: missing, and brdf \"measured\" needs it", key("file")))?;
        // Read now, so that a bad file stops the scene like any bad value (and every object naming the
        // material shares the one table).
        let path = beside_scene(file, scene_path);
        return Measured::load(&path)
            .map(|table| Brdf::Measured(table.with_sampler(s.sampler.unwrap_or(true))))
            .map_err(|e| format!("{} = {}: {e}", key("file"), quoted(file)));
    }
    if s.brdf == "analytic" {
        let file =
            s.file.as_deref().ok_or_else(|| format!("{}: missing, and brdf \"analytic\" needs it", key("file")))?;
        let path = beside_scene(file, scene_path);
        let model = AnalyticModel::load(&path).map_err(|e| format!("{} = {}: {e}", key("file"), quoted(file)))?;
        return analytic_values(&key("params"), Analytic::defaults(model), s.params.as_ref()).map(Brdf::Analytic);
    }
    let kd = reflectance("kd", s.kd)?;
    Ok(match s.brdf.as_str() {
        "lambert" => Brdf::Lambert { kd },
        "oren-nayar" => Brdf::OrenNayar { kd, sigma: at_least(&key("sigma"), required("sigma", s.sigma)?, 0.0)? },
        "phong" | "blinn-phong" => {
            let ks = reflectance("ks", s.ks)?;
            let shininess = at_least(&key("shininess"), required("shininess", s.shininess)?, 0.0)?;
            if s.brdf == "phong" {
                Brdf::Phong { kd, ks, shininess }
            } else {
                Brdf::BlinnPhong { kd, ks, shininess }
            }
        }
        _ => {
            let f0 = reflectance("f0", s.f0)?;
            let roughness = required("roughness", s.roughness)?;
            if !(roughness > 0.0 && roughness <= 1.0) {
                return Err(format!("{} = {roughness}: must be in (0, 1]", key("roughness")));
            }
            let metalness = s.metalness.unwrap_or(0.0);
            if !(0.0..=1.0).contains(&metalness) {
                return Err(format!("{} = {metalness}: must be in [0, 1]", key("metalness")));
            }
            let diffuse = match s.diffuse.as_deref().unwrap_or("oren-nayar") {
                "oren-nayar" => DiffuseModel::OrenNayar,
                "lambert" => DiffuseModel::Lambert,
                other => {
                    return Err(format!(
                        "{} = {}: unknown diffuse model (expected \"oren-nayar\" or \"lambert\")",
                        key("diffuse"),
                        quoted(other)
                    ))
                }
            };
            Brdf::CookTorrance { kd, f0, roughness, metalness, diffuse }
        }
    })
}

/// An analytic material's `params`: each a parameter its file declares, of its type (a float a number; a
/// bool true or false, or 0 or 1; a colour three numbers, or one for a grey), a float within the file's
/// range. The others keep the file's defaults.
fn analytic_values(key: &str, mut material: Analytic, params: Option<&toml::Table>) -> Check<Analytic> {
    for (name, given) in params.into_iter().flatten() {
        let shown = |value: &toml::Value| super::overrides::shortened(&value.to_string());
        let model = material.model().clone();
        let Some(parameter) = model.parameter(name) else {
            let error = material.with(name, ParameterValue::Float(0.0)).err().unwrap_or_default();
            return Err(format!("{key}.{name} = {}{error}", shown(given)));
        };
        let number = |value: &toml::Value| match value {
            toml::Value::Float(v) => Some(*v as f32),
            toml::Value::Integer(v) => Some(*v as f32),
            _ => None,
        };
        let value = match (parameter.kind, given) {
            (ParameterKind::Float { .. }, value) => number(value).map(ParameterValue::Float),
            (ParameterKind::Bool { .. }, toml::Value::Boolean(b)) => Some(ParameterValue::Bool(*b)),
            (ParameterKind::Bool { .. }, toml::Value::Integer(v @ (0 | 1))) => Some(ParameterValue::Bool(*v == 1)),
            (ParameterKind::Bool { .. }, _) => None,
            (ParameterKind::Color { .. }, toml::Value::Array(items)) => {
                let components: Option<Vec<f32>> = items.iter().map(number).collect();
                components.filter(|c| c.len() == 3).map(|c| ParameterValue::Color(Vec3::from_slice(&c)))
            }
            (ParameterKind::Color { .. }, value) => number(value).map(|v| ParameterValue::Color(Vec3::splat(v))),
        };
        let Some(value) = value else {
            let wanted = match parameter.kind {
                ParameterKind::Float { .. } => "a number",
                ParameterKind::Bool { .. } => "true or false (or 0 or 1)",
                ParameterKind::Color { .. } => "a colour: three numbers, or one for a grey",
            };
            return Err(format!(
                "{key}.{name} = {}: {name} is a {} parameter of {} (line {}): it takes {wanted}",
                shown(given),
                parameter.kind.type_name(),
                model.name(),
                parameter.line
            ));
        };
        material = material.with(name, value).map_err(|e| format!("{key}.{name}{e}"))?;
    }
    Ok(material)
}

/// The keys each shape takes besides `shape` and `material`.
const SHAPE_KEYS: [(&str, &[&str]); 3] = [
    ("sphere", &["center", "radius"]),
    ("plane", &["point", "normal"]),
    ("mesh", &["path", "scale", "rotate", "translate"]),
];

fn object(index: usize, s: &ObjectSection, materials: &BTreeMap<String, Brdf>, scene_path: &Path) -> Check<Object> {
    let key = |name: &str| format!("object.{index}.{name}");
    let Some(&(_, accepted)) = SHAPE_KEYS.iter().find(|(shape, _)| *shape == s.shape) else {
        return Err(format!(
            "{} = {}: unknown shape (expected \"sphere\", \"plane\" or \"mesh\")",
            key("shape"),
            quoted(&s.shape)
        ));
    };
    let present = [
        ("center", s.center.is_some()),
        ("radius", s.radius.is_some()),
        ("point", s.point.is_some()),
        ("normal", s.normal.is_some()),
        ("path", s.path.is_some()),
        ("scale", s.scale.is_some()),
        ("rotate", s.rotate.is_some()),
        ("translate", s.translate.is_some()),
    ];
    if let Some((name, _)) = present.iter().find(|(name, set)| *set && !accepted.contains(name)) {
        return Err(format!("{}: not a key of a {} (it takes {})", key(name), s.shape, accepted.join(", ")));
    }
    let brdf = materials.get(&s.material).cloned().ok_or_else(|| {
        let defined: Vec<_> = materials.keys().map(String::as_str).collect();
        let defined = if defined.is_empty() { "none".to_string() } else { defined.join(", ") };
        format!("{} = {:?}: no [material.{}] is defined (defined: {defined})", key("material"), s.material, s.material)
    })?;
    let missing = |name: &str| format!("{}: missing, and a {} needs it", key(name), s.shape);
    let shape = match s.shape.as_str() {
        "sphere" => {
            let center = finite(&key("center"), s.center.ok_or_else(|| missing("center"))?.0)?;
            let radius = s.radius.ok_or_else(|| missing("radius"))?;
            positive(&key("radius"), radius)?;
            Shape::Sphere { center, radius }
        }
        "plane" => {
            let point = finite(&key("point"), s.point.ok_or_else(|| missing("point"))?.0)?;
            let normal = nonzero(&key("normal"), s.normal.ok_or_else(|| missing("normal"))?.0)?;
            Shape::Plane { point, normal: normal.normalize() }
        }
        _ => {
            let path = s.path.as_deref().ok_or_else(|| missing("path"))?;
            let scale = s.scale.unwrap_or(1.0);
            positive(&key("scale"), scale)?;
            Shape::Mesh {
                path: resolve_mesh_path(path, scene_path),
                scale,
                rotate: finite(&key("rotate"), s.rotate.map_or([0.0; 3], |r| r.0))?,
                translate: finite(&key("translate"), s.translate.map_or([0.0; 3], |t| t.0))?,
            }
        }
    };
    Ok(Object { shape, material: s.material.clone(), brdf, casts_shadow: true })
}

/// `"bunny"` is the installed Stanford bunny; any other path is relative to the scene file's folder.
fn resolve_mesh_path(path: &str, scene_path: &Path) -> std::path::PathBuf {
    if path == "bunny" {
        return BUNNY_PATH.into();
    }
    beside_scene(path, scene_path)
}

/// A path a scene file names, relative to the scene file's folder (or absolute).
fn beside_scene(path: &str, scene_path: &Path) -> std::path::PathBuf {
    scene_path.parent().unwrap_or(Path::new("")).join(path)
}

fn finite(key: &str, v: [f32; 3]) -> Check<Vec3> {
    if v.iter().all(|c| c.is_finite()) {
        Ok(Vec3::from(v))
    } else {
        Err(format!("{key} = {v:?}: every component must be a finite number"))
    }
}

fn nonzero(key: &str, v: [f32; 3]) -> Check<Vec3> {
    let vector = finite(key, v)?;
    if vector.length_squared() > 0.0 {
        Ok(vector)
    } else {
        Err(format!("{key} = {v:?}: a direction of zero length"))
    }
}

fn non_negative(key: &str, rgb: Rgb) -> Check<Vec3> {
    if rgb.0.iter().all(|c| c.is_finite() && *c >= 0.0) {
        Ok(Vec3::from(rgb.0))
    } else {
        Err(format!("{key} = {:?}: every component must be a finite number >= 0", rgb.0))
    }
}

fn unit_interval(key: &str, rgb: Rgb) -> Check<Vec3> {
    if rgb.0.iter().all(|c| (0.0..=1.0).contains(c)) {
        Ok(Vec3::from(rgb.0))
    } else {
        Err(format!("{key} = {:?}: every component must be in [0, 1]", rgb.0))
    }
}

fn at_least(key: &str, value: f32, min: f32) -> Check<f32> {
    if value.is_finite() && value >= min {
        Ok(value)
    } else {
        Err(format!("{key} = {value}: must be a finite number >= {min}"))
    }
}

fn positive(key: &str, value: f32) -> Check<f32> {
    if value.is_finite() && value > 0.0 {
        Ok(value)
    } else {
        Err(format!("{key} = {value}: must be greater than 0"))
    }
}
