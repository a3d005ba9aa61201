//! An independent CPU reference: one ray per pixel centre through the same camera, exact spheres and
//! planes, shading with the Rust BRDF mirror. It shares no code with the GPU path but the scene, the
//! BRDF mirror and the output transform, so the rasterized images can be checked against it.

use glam::Vec3;

use crate::error::{Error, Result};
use crate::output::HdrImage;
use crate::scene::{Scene, Shape};

/// The reference image and, per pixel, the index of the object seen (`None` for the background).
pub struct ReferenceImage {
    pub image: HdrImage,
    pub object_ids: Vec<Option<usize>>,
}

/// Ray-traces the scene (no shadows yet: the rasterizer has none either).
///
/// # Errors
/// `Error::Scene` if the scene holds a mesh, which the reference cannot trace yet.
pub fn render(scene: &Scene) -> Result<ReferenceImage> {
    let unsupported = |message: String| Error::Scene { file: scene.source.clone(), message };
    for (index, object) in scene.objects.iter().enumerate() {
        if matches!(object.shape, Shape::Mesh { .. }) {
            return Err(unsupported(format!(
                "object.{index}.shape = \"mesh\": not supported by the CPU reference yet"
            )));
        }
    }
    let (width, height) = (scene.image.width, scene.image.height);
    let camera = &scene.camera;
    // The course's camera frame: w points backwards, u to the image's right, v up.
    let w = (camera.position - camera.look_at).normalize();
    let u = camera.up.cross(w).normalize();
    let v = w.cross(u);
    let half_height = (camera.fov_y.to_radians() * 0.5).tan();
    let half_width = half_height * width as f32 / height as f32;

    let mut pixels = Vec::with_capacity((width * height) as usize);
    let mut object_ids = Vec::with_capacity(pixels.capacity());
    for y in 0..height {
        for x in 0..width {
            let sx = (2.0 * (x as f32 + 0.5) / width as f32 - 1.0) * half_width;
            let sy = (1.0 - 2.0 * (y as f32 + 0.5) / height as f32) * half_height;
            let direction = (sx * u + sy * v - w).normalize();
            match nearest_hit(scene, camera.position, direction) {
                Some((index, t)) => {
                    pixels.push(shade(scene, index, camera.position + t * direction, -direction));
                    object_ids.push(Some(index));
                }
                None => {
                    pixels.push(scene.image.background);
                    object_ids.push(None);
                }
            }
        }
    }
    Ok(ReferenceImage { image: HdrImage { width, height, pixels }, object_ids })
}

/// The nearest object along the ray and the distance to it.
fn nearest_hit(scene: &Scene, origin: Vec3, direction: Vec3) -> Option<(usize, f32)> {
    scene
        .objects
        .iter()
        .enumerate()
        .filter_map(|(index, object)| intersect(&object.shape, origin, direction).map(|t| (index, t)))
        .min_by(|a, b| a.1.total_cmp(&b.1))
}

/// The distance to the first intersection in front of the origin.
fn intersect(shape: &Shape, origin: Vec3, direction: Vec3) -> Option<f32> {
    match *shape {
        Shape::Sphere { center, radius } => {
            let oc = origin - center;
            let b = oc.dot(direction);
            let c = oc.length_squared() - radius * radius;
            let discriminant = b * b - c;
            if discriminant < 0.0 {
                return None;
            }
            let root = discriminant.sqrt();
            [-b - root, -b + root].into_iter().find(|&t| t > 1e-4)
        }
        Shape::Plane { point, normal } => {
            let denominator = normal.dot(direction);
            if denominator.abs() < 1e-12 {
                return None;
            }
            Some((point - origin).dot(normal) / denominator).filter(|&t| t > 1e-4)
        }
        Shape::Mesh { .. } => None,
    }
}

/// Direct lighting at `p` on object `index`, seen from direction `wo`.
fn shade(scene: &Scene, index: usize, p: Vec3, wo: Vec3) -> Vec3 {
    let object = &scene.objects[index];
    let n = match object.shape {
        Shape::Sphere { center, .. } => (p - center).normalize(),
        // A plane is seen from either side: its normal faces the viewer.
        Shape::Plane { normal, .. } => normal * normal.dot(wo).signum(),
        // Refused before tracing; `intersect` never hits one.
        Shape::Mesh { .. } => return Vec3::ZERO,
    };
    scene
        .lights
        .iter()
        .map(|light| {
            let to_light = light.position - p;
            let d2 = to_light.length_squared();
            let wi = to_light / d2.sqrt();
            let cos = n.dot(wi);
            if cos <= 0.0 {
                return Vec3::ZERO;
            }
            let f = object.brdf.eval(n, wi, wo);
            f * light.color * light.power / d2 * cos
        })
        .sum()
}
