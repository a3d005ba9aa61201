//! BRDF Explorer's 3D lobe, drawn by vk-render's own Vulkan pipeline: a scene whose objects are the lobe as a
//! mesh (its radius in each direction wo is f_r(wi, wo) cos(theta_o), luminance, from the probe pass), arrows
//! along the incident direction, the normal and the mirror direction, and a disc for the surface, seen from a
//! stated angle; rendered like any scene.
//!
//! The BRDF frame (n = +z, wi in the xz-plane at +x) is turned into the world so that the normal is up:
//! world = R_x(-90 degrees) brdf, which takes z to +y and y to -z.

use std::collections::BTreeMap;
use std::f32::consts::{FRAC_PI_2, PI};
use std::path::Path;
use std::sync::Arc;

use glam::{Quat, Vec3};

use super::{Channel, NamedBrdf};
use crate::brdf::Brdf;
use crate::error::Result;
use crate::render::{ProbeCase, Renderer};
use crate::scene::{
    Camera, Encoding, ImageSettings, Object, PointLight, Scene, ShadowFilter, Shape, Tonemap, Triangles, View,
    DEFAULT_SHADOW_MAP_SIZE,
};

/// The lobe's grid: theta every degree, phi every 2 degrees.
const THETA_STEPS: usize = 90;
const PHI_STEPS: usize = 180;

/// Where the lobe is seen from: degrees above the surface, and round the normal from the plane of incidence's
/// front (0: looking along -z of the world, wi to the right).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Viewpoint {
    /// Degrees above the surface (90: looking down the normal).
    pub elevation: f32,
    /// Degrees round the normal from the plane of incidence's front.
    pub azimuth: f32,
}

/// The colours of the arrows and the lobe, for a legend.
pub const LOBE_COLOUR: Vec3 = Vec3::new(0.25, 0.55, 0.95);
/// The incident direction's arrow, linear RGB.
pub const INCIDENT_COLOUR: Vec3 = Vec3::new(1.0, 0.8, 0.15);
/// The normal's arrow, linear RGB.
pub const NORMAL_COLOUR: Vec3 = Vec3::new(0.9, 0.9, 0.9);
/// The mirror direction's arrow, linear RGB.
pub const MIRROR_COLOUR: Vec3 = Vec3::new(0.95, 0.25, 0.2);

/// The turn from the BRDF frame to the world of [`lobe_scene`], the normal up.
fn to_world(v: Vec3) -> Vec3 {
    Quat::from_rotation_x(-FRAC_PI_2) * v
}

/// The scene of `material`'s lobe at incidence `theta_i` (degrees) seen from `from`, `size` pixels, its
/// messages naming `source`.
///
/// # Errors
/// What the probe pass returns.
pub fn lobe_scene(
    renderer: &mut Renderer,
    material: &NamedBrdf,
    theta_i: f32,
    from: Viewpoint,
    (width, height): (u32, u32),
    source: &Path,
) -> Result<Scene> {
    let incidence = theta_i.to_radians();
    let wi = Vec3::new(incidence.sin(), 0.0, incidence.cos());
    let lobe = placed(&lobe_mesh(renderer, &material.brdf, wi)?, Quat::from_rotation_x(-FRAC_PI_2), 1.0, Vec3::ZERO);
    let reach = lobe.positions.iter().map(|p| p.length()).fold(0.0f32, f32::max).max(1e-6);
    let arrow_length = 1.25 * reach;
    let radius = 0.012 * reach;
    let mirror = Vec3::new(-wi.x, 0.0, wi.z);
    let mut objects = vec![
        object(Arc::new(lobe), "lobe", LOBE_COLOUR),
        object(Arc::new(arrow(to_world(wi), arrow_length, radius)), "wi", INCIDENT_COLOUR),
        object(Arc::new(arrow(to_world(Vec3::Z), arrow_length, radius)), "n", NORMAL_COLOUR),
        object(Arc::new(disc(1.3 * reach)), "surface", Vec3::splat(0.25)),
    ];
    if theta_i > 0.0 {
        objects.push(object(Arc::new(arrow(to_world(mirror), arrow_length, radius)), "mirror", MIRROR_COLOUR));
    }
    let materials: BTreeMap<String, Brdf> = objects.iter().map(|o| (o.material.clone(), o.brdf.clone())).collect();
    let (elevation, azimuth) = (from.elevation.to_radians(), from.azimuth.to_radians());
    let target = Vec3::new(0.0, 0.4 * reach, 0.0);
    let eye = target
        + 3.4 * reach * Vec3::new(elevation.cos() * azimuth.sin(), elevation.sin(), elevation.cos() * azimuth.cos());
    // A head light and one above: radiance about 0.8 on a facing Lambert of kd 0.6.
    let power = 4.0 * (eye - target).length_squared();
    let light = |position| PointLight { position, color: Vec3::ONE, power, shadows: false };
    Ok(Scene {
        source: source.to_path_buf(),
        image: ImageSettings {
            width,
            height,
            samples: 4,
            background: Vec3::splat(0.06),
            tonemap: Tonemap::Clamp,
            exposure: 1.0,
            encoding: Encoding::Srgb,
            shadow_map_size: DEFAULT_SHADOW_MAP_SIZE,
            shadow_filter: ShadowFilter::Hard,
            view: View::Radiance,
        },
        camera: Camera { position: eye, look_at: target, up: Vec3::Y, fov_y: 40.0 },
        lights: vec![light(eye), light(target + Vec3::new(0.0, 4.0 * reach, 0.0))],
        objects,
        materials,
        environment: None,
    })
}

/// An object of the lobe's picture: it casts no shadow (a lobe shown in a scene must not darken it).
fn object(triangles: Arc<Triangles>, name: &str, colour: Vec3) -> Object {
    Object {
        shape: Shape::Triangles(triangles),
        material: name.to_string(),
        brdf: Brdf::Lambert { kd: 0.6 * colour },
        casts_shadow: false,
    }
}

/// The lobe as a mesh in the BRDF frame (n = +z, `wi` given in it): the point r(wo) wo for each wo of the grid,
/// r = f_r(wi, wo) cos(theta_o) (luminance), with normals averaged from the faces.
///
/// # Errors
/// What the probe pass returns.
pub fn lobe_mesh(renderer: &mut Renderer, brdf: &Brdf, wi: Vec3) -> Result<Triangles> {
    let direction = |t: usize, p: usize| {
        let (theta, phi) = (t as f32 * FRAC_PI_2 / THETA_STEPS as f32, p as f32 * 2.0 * PI / PHI_STEPS as f32);
        Vec3::new(theta.sin() * phi.cos(), theta.sin() * phi.sin(), theta.cos())
    };
    let directions: Vec<Vec3> = (0..=THETA_STEPS).flat_map(|t| (0..PHI_STEPS).map(move |p| direction(t, p))).collect();
    let cases: Vec<ProbeCase> =
        directions.iter().map(|&wo| ProbeCase { brdf: brdf.clone(), n: Vec3::Z, wi, wo }).collect();
    let values = renderer.probe_brdfs(&cases)?;
    let positions: Vec<Vec3> = directions
        .iter()
        .zip(values)
        .map(|(&wo, f)| {
            let r = Channel::Luminance.of(f.as_dvec3().to_array()) as f32 * wo.z.max(0.0);
            r.max(0.0) * wo
        })
        .collect();
    let index = |t: usize, p: usize| (t * PHI_STEPS + p % PHI_STEPS) as u32;
    let mut indices = Vec::with_capacity(THETA_STEPS * PHI_STEPS * 6);
    for t in 0..THETA_STEPS {
        for p in 0..PHI_STEPS {
            // Along +theta then +phi: counter-clockwise seen from outside (e_theta x e_phi = e_r).
            let (a, b, c, d) = (index(t, p), index(t + 1, p), index(t + 1, p + 1), index(t, p + 1));
            indices.extend([a, b, c, a, c, d]);
        }
    }
    let normals = face_averaged_normals(&positions, &indices, &directions);
    Ok(Triangles { positions, normals, indices })
}

/// Each vertex's normal: the area-weighted mean of its faces', or `fallback`'s direction (in the BRDF frame)
/// where its faces have no area.
fn face_averaged_normals(positions: &[Vec3], indices: &[u32], fallback: &[Vec3]) -> Vec<Vec3> {
    let mut normals = vec![Vec3::ZERO; positions.len()];
    for t in indices.chunks_exact(3) {
        let [a, b, c] = [t[0], t[1], t[2]].map(|i| positions[i as usize]);
        let face = (b - a).cross(c - a);
        for &i in t {
            normals[i as usize] += face;
        }
    }
    normals.iter().zip(fallback).map(|(n, f)| n.try_normalize().unwrap_or(*f)).collect()
}

/// `triangles` turned by `rotation`, scaled by `scale` and moved to `anchor`.
pub fn placed(triangles: &Triangles, rotation: Quat, scale: f32, anchor: Vec3) -> Triangles {
    Triangles {
        positions: triangles.positions.iter().map(|&p| anchor + scale * (rotation * p)).collect(),
        normals: triangles.normals.iter().map(|&n| rotation * n).collect(),
        indices: triangles.indices.clone(),
    }
}

/// The lobe of object `index`'s material for the scene's first light, as objects to add to the scene: the
/// lobe, and an arrow towards the light, standing on the point of a sphere that faces halfway between the
/// light and the camera's up or, on a plane, where the camera's view meets it; neither casts a shadow. None
/// for meshes, or without a light.
///
/// # Errors
/// What the probe pass returns.
pub fn lobe_on_object(renderer: &mut Renderer, scene: &Scene, index: usize) -> Result<Option<Vec<Object>>> {
    let (Some(studied), Some(light)) = (scene.objects.get(index), scene.lights.first()) else { return Ok(None) };
    let eye = scene.camera.position;
    let (anchor, n, size) = match studied.shape {
        Shape::Sphere { center, radius } => {
            // Halfway between the light and the camera's up: lit, and its plane of incidence stands up in
            // the view, so that the lobe is seen from its side rather than end on.
            let to_light = (light.position - center).normalize_or_zero();
            let n = (to_light + scene.camera.up.normalize_or_zero()).try_normalize().unwrap_or(to_light);
            (center + radius * n, n, 0.8 * radius)
        }
        Shape::Plane { point, normal } => {
            let forward = (scene.camera.look_at - eye).normalize_or_zero();
            let t = normal.dot(point - eye) / normal.dot(forward);
            let anchor = if t.is_finite() && t > 0.0 { eye + t * forward } else { point };
            (anchor, normal, 0.25 * (anchor - eye).length())
        }
        Shape::Mesh { .. } | Shape::Triangles(_) => return Ok(None),
    };
    let to_light = (light.position - anchor).normalize_or_zero();
    // The BRDF frame at the anchor: n up, wi in the xz-plane on the +x side.
    let tangent = (to_light - to_light.dot(n) * n).try_normalize().unwrap_or_else(|| n.any_orthonormal_vector());
    let rotation = Quat::from_mat3(&glam::Mat3::from_cols(tangent, n.cross(tangent), n));
    let wi = rotation.inverse() * to_light;
    let lobe = lobe_mesh(renderer, &studied.brdf, wi)?;
    let reach = lobe.positions.iter().map(|p| p.length()).fold(0.0f32, f32::max).max(1e-6);
    let scale = size / reach;
    Ok(Some(vec![
        object(Arc::new(placed(&lobe, rotation, scale, anchor)), "lobe", LOBE_COLOUR),
        object(
            Arc::new(placed(&arrow(to_light, 1.2 * size, 0.012 * size), Quat::IDENTITY, 1.0, anchor)),
            "wi",
            INCIDENT_COLOUR,
        ),
    ]))
}

/// An arrow from the origin along unit `direction`: a cylinder of `radius` and a cone twice as wide over the
/// last tenth of `length`.
fn arrow(direction: Vec3, length: f32, radius: f32) -> Triangles {
    let sides = 24;
    let turn = Quat::from_rotation_arc(Vec3::Y, direction);
    let shaft = 0.88 * length;
    let mut mesh = Triangles::default();
    let ring = |k: usize| {
        let a = k as f32 * 2.0 * PI / sides as f32;
        Vec3::new(a.cos(), 0.0, a.sin())
    };
    // The shaft: a tube (its ends closed by the surface below and the cone above).
    for k in 0..=sides {
        let out = ring(k);
        for y in [0.0, shaft] {
            mesh.positions.push(turn * (radius * out + Vec3::new(0.0, y, 0.0)));
            mesh.normals.push(turn * out);
        }
    }
    for k in 0..sides as u32 {
        let (a, b, c, d) = (2 * k, 2 * k + 1, 2 * k + 3, 2 * k + 2);
        mesh.indices.extend([a, b, c, a, c, d]);
    }
    // The head: a cone from a ring of twice the radius at the shaft's end to the tip.
    let base = mesh.positions.len() as u32;
    let head = 2.5 * radius;
    let slope = head / (length - shaft);
    for k in 0..=sides {
        let out = ring(k);
        let normal = turn * (out + Vec3::new(0.0, slope, 0.0)).normalize();
        mesh.positions.push(turn * (head * out + Vec3::new(0.0, shaft, 0.0)));
        mesh.normals.push(normal);
        mesh.positions.push(turn * Vec3::new(0.0, length, 0.0));
        mesh.normals.push(normal);
    }
    for k in 0..sides as u32 {
        let (a, tip, c) = (base + 2 * k, base + 2 * k + 1, base + 2 * k + 2);
        mesh.indices.extend([a, tip, c]);
    }
    mesh
}

/// The surface: a disc of `radius` in the world's xz-plane, facing up.
fn disc(radius: f32) -> Triangles {
    let sides = 96;
    let mut mesh = Triangles { positions: vec![Vec3::ZERO], normals: vec![Vec3::Y], indices: Vec::new() };
    for k in 0..=sides {
        let a = k as f32 * 2.0 * PI / sides as f32;
        mesh.positions.push(radius * Vec3::new(a.cos(), 0.0, -a.sin()));
        mesh.normals.push(Vec3::Y);
    }
    for k in 1..=sides as u32 {
        mesh.indices.extend([0, k, k + 1]);
    }
    mesh
}
