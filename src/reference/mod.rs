//! An independent CPU reference: one ray per pixel centre through the same camera, exact spheres and
//! planes, meshes through parry3d's ray queries, hard shadows by shadow rays, shading with the Rust BRDF
//! mirror (a measured material by its own reading of the file, `merl.rs`, or an RGL file's own reader,
//! `brdf::rgl`, where the GPU's is a resampled table), an environment's light by Monte
//! Carlo (`environment.rs`). It shares nothing with the GPU path but the scene, the BRDF mirror, the
//! environment's map and the output transform, so the rasterized images can be checked against it.

mod environment;
mod merl;

// Its generator of uniform numbers, for the statistics' tests (analysis::chi2).
#[cfg(test)]
pub(crate) use environment::SplitMix64;

use std::sync::Arc;

use glam::{Mat3, Vec3};
use parry3d::query::{Ray, RayCast};
use parry3d::shape::TriMesh;

use crate::brdf::rgl::{is_rgl_file, RglTable};
use crate::brdf::Brdf;
use crate::environment::{EnvironmentMap, PlacedEnvironment};
use crate::error::{Error, Result};
use crate::mesh::place_objects;
use crate::pictures::output::HdrImage;
use crate::scene::{Scene, Shape};
use environment::EnvironmentLight;
pub use environment::DEFAULT_SAMPLES;
use merl::MerlFile;

/// The reference image and, per pixel, the index of the object seen (`None` for the background).
pub struct ReferenceImage {
    /// The radiance (or term) the reference computes at each pixel's centre.
    pub image: HdrImage,
    /// Per pixel, row by row from the top, the index in the scene's objects of the object seen.
    pub object_ids: Vec<Option<usize>>,
    /// Per pixel, the standard error of the environment light's estimate (zero without an environment).
    pub standard_errors: Vec<Vec3>,
}

impl ReferenceImage {
    /// The 99th percentile over pixels of the environment light's standard error (the largest channel's),
    /// in 8-bit levels of an image made with `settings`: how exact the reference is.
    pub fn p99_error_levels(&self, settings: &crate::scene::ImageSettings) -> f32 {
        let mut levels: Vec<f32> = self
            .image
            .pixels
            .iter()
            .zip(&self.standard_errors)
            .map(|(&mean, &error)| crate::pictures::output::levels_moved(mean, error, settings))
            .collect();
        crate::pictures::output::percentile_99(&mut levels)
    }

    /// The object-id map as a picture: black background, one distinct colour per object.
    pub fn object_id_picture(&self) -> image::RgbImage {
        let colour = |id: Option<usize>| match id {
            None => [0, 0, 0],
            // Golden-ratio hue steps keep neighbouring ids far apart in colour.
            Some(i) => hue((i as f32 * 0.618_034 + 0.1).fract()),
        };
        let bytes = self.object_ids.iter().flat_map(|&id| colour(id)).collect();
        image::RgbImage::from_raw(self.image.width, self.image.height, bytes).unwrap_or_default()
    }
}

/// A saturated colour of hue `h` in [0, 1).
fn hue(h: f32) -> [u8; 3] {
    let channel = |offset: f32| {
        let x = ((h + offset).fract() * 6.0 - 3.0).abs() - 1.0;
        (x.clamp(0.0, 1.0) * 255.0) as u8
    };
    [channel(0.0), channel(2.0 / 3.0), channel(1.0 / 3.0)]
}

/// The smallest cosine between the view direction and a mesh's interpolated normal, as in forward.frag:
/// at a silhouette the interpolated normal can face away from a camera that still sees the mesh, and both
/// renderers bend it back over the horizon the same way.
const MIN_NOV: f32 = 1e-4;

/// An object's reflectance as the reference evaluates it: a model by the Rust mirror (a `.brdf` file's, for
/// the models shipped in `assets/brdfs/`), a measured one by the reference's own reading of its file.
#[derive(Clone)]
enum Reflectance {
    Model(Brdf),
    Measured(Arc<MerlFile>),
    /// An RGL file, by its own reader (not resampled into a table as the GPU's is).
    Rgl(Arc<RglTable>),
}

impl Reflectance {
    /// Each object's, every file read once.
    fn of_objects(scene: &Scene) -> Result<Vec<Reflectance>> {
        let mut read: Vec<(std::path::PathBuf, Reflectance)> = Vec::new();
        scene
            .objects
            .iter()
            .map(|object| match &object.brdf {
                Brdf::Measured(table) => {
                    let path = table.path();
                    if let Some((_, file)) = read.iter().find(|(p, _)| p == path) {
                        return Ok(file.clone());
                    }
                    let failed = |message| Error::Scene { file: scene.source.clone(), message };
                    let file = if is_rgl_file(path) {
                        Reflectance::Rgl(Arc::new(RglTable::read(path).map_err(failed)?))
                    } else {
                        Reflectance::Measured(Arc::new(MerlFile::read(path).map_err(failed)?))
                    };
                    read.push((path.to_path_buf(), file.clone()));
                    Ok(file)
                }
                Brdf::Analytic(material) if !material.has_mirror() => Err(Error::Scene {
                    file: scene.source.clone(),
                    message: format!(
                        "material.{}.file = {:?}: the CPU reference has no mirror of this BRDF: it shades the models \
                         shipped in assets/brdfs/, as shipped",
                        object.material,
                        material.model().path.display().to_string()
                    ),
                }),
                brdf => Ok(Reflectance::Model(brdf.clone())),
            })
            .collect()
    }

    /// f_r at a surface of normal n and tangent t (which an analytic model and an anisotropic RGL file read).
    fn eval(&self, n: Vec3, t: Vec3, wi: Vec3, wo: Vec3) -> Vec3 {
        if n.dot(wi) <= 0.0 || n.dot(wo) <= 0.0 {
            return Vec3::ZERO;
        }
        match self {
            Reflectance::Model(brdf) => brdf.eval_in_frame(n, t, wi, wo),
            Reflectance::Measured(file) => file.eval(n, wi, wo),
            Reflectance::Rgl(file) => file.eval_in_frame(n, t, wi, wo),
        }
    }

    /// The analytic model, whose specular lobe the environment's light is importance-sampled by.
    fn model(&self) -> Option<&Brdf> {
        match self {
            Reflectance::Model(brdf) => Some(brdf),
            Reflectance::Measured(_) | Reflectance::Rgl(_) => None,
        }
    }
}

/// An object as the ray tracer sees it.
enum Geometry {
    Sphere {
        center: Vec3,
        radius: f32,
    },
    Plane {
        point: Vec3,
        normal: Vec3,
    },
    /// A triangle mesh in world space, with its vertex normals for smooth shading and its vertex tangents
    /// (zero where the mesh has none).
    Mesh {
        triangles: Box<TriMesh>,
        normals: Vec<Vec3>,
        tangents: Vec<Vec3>,
    },
}

impl Geometry {
    /// The tangent the renderer gives the surface at shading normal n, where the interpolated vertex tangent
    /// is `vertex_tangent` (which only an analytic model reads): a plane's is the world's +x projected on it,
    /// a mesh's its vertices' made perpendicular to n, else, as a sphere's, +y x n (see
    /// `brdf::surface_tangent`).
    fn tangent(&self, n: Vec3, vertex_tangent: Vec3) -> Vec3 {
        match self {
            Geometry::Plane { .. } => crate::brdf::plane_tangent(n),
            Geometry::Sphere { .. } | Geometry::Mesh { .. } => crate::brdf::surface_tangent(n, vertex_tangent),
        }
    }
}

/// A ray's nearest hit: the object, the distance, the shading normal (before facing the viewer) and the
/// interpolated vertex tangent (zero where the surface has none).
struct Hit {
    object: usize,
    t: f32,
    normal: Vec3,
    tangent: Vec3,
}

/// What the reference sees at a pixel's centre, without the material: the object, its shading normal (a
/// plane's facing the viewer, a mesh's bent over the horizon as the renders bend it), the direction to the
/// camera and each point light's arrival.
#[derive(Clone, Debug, PartialEq)]
pub struct SurfacePoint {
    /// The object's index in the scene.
    pub object: usize,
    /// The unit shading normal, facing the camera.
    pub n: Vec3,
    /// The unit direction to the camera.
    pub wo: Vec3,
    /// Per light of the scene, in its order.
    pub lights: Vec<LightArrival>,
}

/// A point light as it arrives at a surface point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightArrival {
    /// The unit direction to the light.
    pub wi: Vec3,
    /// Its radiance at the point times cos(theta_i): colour * power / d^2 * max(0, n . wi), so that the
    /// reflected radiance is f_r(wi, wo) times it.
    pub irradiance: Vec3,
    /// Whether the light reaches the point (hard shadows by shadow rays; always for a light that casts none).
    pub visible: bool,
}

impl SurfacePoint {
    /// The radiance the point lights reflect by `f` (f_r of wi, wo about n), the unseen ones left out.
    fn reflected(&self, f: impl Fn(Vec3, Vec3, Vec3) -> Vec3) -> Vec3 {
        self.lights.iter().filter(|l| l.visible).map(|l| f(self.n, l.wi, self.wo) * l.irradiance).sum()
    }
}

/// The surface point seen through each pixel's centre (None where the background is), row after row:
/// the geometry of a render without its materials, which a fit to an image solves for.
///
/// # Errors
/// As [`render`].
pub fn surface_points(scene: &Scene) -> Result<Vec<Option<SurfacePoint>>> {
    let geometry = build_geometry(scene)?;
    let rays = CameraRays::new(scene);
    let points = crate::parallel::rows(scene.image.height, |y| {
        (0..scene.image.width)
            .map(|x| {
                let direction = rays.through(x, y);
                let hit = nearest_hit(&geometry, scene.camera.position, direction, f32::INFINITY)?;
                Some(surface_point(scene, &geometry, &hit, scene.camera.position + hit.t * direction, -direction))
            })
            .collect()
    });
    Ok(points)
}

/// The camera rays through pixel centres, in the course's camera frame (w backwards, u to the image's right,
/// v up).
struct CameraRays {
    u: Vec3,
    v: Vec3,
    w: Vec3,
    half_width: f32,
    half_height: f32,
    width: f32,
    height: f32,
}

impl CameraRays {
    fn new(scene: &Scene) -> Self {
        let camera = &scene.camera;
        let w = (camera.position - camera.look_at).normalize();
        let u = camera.up.cross(w).normalize();
        let v = w.cross(u);
        let half_height = (camera.fov_y.to_radians() * 0.5).tan();
        let (width, height) = (scene.image.width as f32, scene.image.height as f32);
        Self { u, v, w, half_width: half_height * width / height, half_height, width, height }
    }

    /// The unit ray through the centre of pixel (x, y).
    fn through(&self, x: u32, y: u32) -> Vec3 {
        let sx = (2.0 * (x as f32 + 0.5) / self.width - 1.0) * self.half_width;
        let sy = (1.0 - 2.0 * (y as f32 + 0.5) / self.height) * self.half_height;
        (sx * self.u + sy * self.v - self.w).normalize()
    }
}

/// Ray-traces the scene, an environment's light with [`DEFAULT_SAMPLES`] samples a pixel.
///
/// # Errors
/// `Error::Mesh` if an OBJ file cannot be loaded or holds no triangles, `Error::Map` for an unusable
/// environment map.
pub fn render(scene: &Scene) -> Result<ReferenceImage> {
    render_with_samples(scene, DEFAULT_SAMPLES)
}

/// As [`render`], with `samples` samples a pixel for an environment's light.
///
/// # Errors
/// As [`render`].
pub fn render_with_samples(scene: &Scene, samples: u32) -> Result<ReferenceImage> {
    let geometry = build_geometry(scene)?;
    let reflectances = Reflectance::of_objects(scene)?;
    let map = scene.environment.as_ref().map(|e| EnvironmentMap::of(scene, e)).transpose()?;
    let light = scene
        .environment
        .as_ref()
        .zip(map.as_ref())
        .map(|(environment, map)| EnvironmentLight::new(PlacedEnvironment { map, environment }, samples));
    let (width, height) = (scene.image.width, scene.image.height);
    let camera = &scene.camera;
    let rays = CameraRays::new(scene);

    let trace_row = |y: u32| -> Vec<(Vec3, Option<usize>, Vec3)> {
        (0..width)
            .map(|x| {
                let direction = rays.through(x, y);
                let seed = u64::from(y) << 32 | u64::from(x);
                match nearest_hit(&geometry, camera.position, direction, f32::INFINITY) {
                    Some(hit) => {
                        let p = camera.position + hit.t * direction;
                        let (radiance, error) =
                            shade(scene, (&geometry, &reflectances), light.as_ref(), &hit, p, -direction, seed);
                        (radiance, Some(hit.object), error)
                    }
                    None => {
                        let background = match (&light, &scene.environment) {
                            (Some(light), Some(e)) if e.visible => light.radiance(direction),
                            _ => scene.image.background,
                        };
                        (background, None, Vec3::ZERO)
                    }
                }
            })
            .collect()
    };
    // An interrupted reference traces no further rows, and is not returned.
    let traced =
        crate::parallel::rows(height, |y| if crate::interrupt::requested() { Vec::new() } else { trace_row(y) });
    crate::interrupt::check()?;
    Ok(ReferenceImage {
        image: HdrImage { width, height, pixels: traced.iter().map(|t| t.0).collect() },
        object_ids: traced.iter().map(|t| t.1).collect(),
        standard_errors: traced.iter().map(|t| t.2).collect(),
    })
}

/// Exact spheres and planes; meshes loaded and placed in world space.
fn build_geometry(scene: &Scene) -> Result<Vec<Geometry>> {
    let placed = place_objects(scene)?;
    scene
        .objects
        .iter()
        .zip(placed)
        .enumerate()
        .map(|(index, (object, placed))| {
            Ok(match object.shape {
                Shape::Sphere { center, radius } => Geometry::Sphere { center, radius },
                Shape::Plane { point, normal } => Geometry::Plane { point, normal },
                Shape::Mesh { .. } | Shape::Triangles(_) => {
                    let normal_matrix = Mat3::from_mat4(placed.model).inverse().transpose();
                    let positions = placed
                        .mesh
                        .vertices
                        .iter()
                        .map(|v| placed.model.transform_point3(Vec3::from_slice(&v.position[..3])));
                    let normals =
                        placed.mesh.vertices.iter().map(|v| (normal_matrix * Vec3::from(v.normal)).normalize());
                    // As forward.vert: a tangent turns and stretches with the surface, by the model matrix.
                    let tangents =
                        placed.mesh.vertices.iter().map(|v| placed.model.transform_vector3(v.tangent.into()));
                    let indices = placed.mesh.indices.chunks_exact(3).map(|t| [t[0], t[1], t[2]]).collect();
                    let triangles = TriMesh::new(positions.collect(), indices).map_err(|e| Error::Mesh {
                        scene: scene.source.clone(),
                        key: format!("object.{index}.path"),
                        value: match &object.shape {
                            Shape::Mesh { path, .. } => path.display().to_string(),
                            _ => "(triangles)".into(),
                        },
                        message: format!("the reference cannot trace it: {e}"),
                    })?;
                    Geometry::Mesh {
                        triangles: Box::new(triangles),
                        normals: normals.collect(),
                        tangents: tangents.collect(),
                    }
                }
            })
        })
        .collect()
}

/// The nearest hit closer than `max_t`.
fn nearest_hit(geometry: &[Geometry], origin: Vec3, direction: Vec3, max_t: f32) -> Option<Hit> {
    geometry
        .iter()
        .enumerate()
        .filter_map(|(object, g)| {
            intersect(g, origin, direction, max_t).map(|(t, normal, tangent)| Hit { object, t, normal, tangent })
        })
        .min_by(|a, b| a.t.total_cmp(&b.t))
}

/// The first intersection in (1e-4, max_t), the shading normal and the interpolated vertex tangent there.
fn intersect(geometry: &Geometry, origin: Vec3, direction: Vec3, max_t: f32) -> Option<(f32, Vec3, Vec3)> {
    const MIN_T: f32 = 1e-4;
    match *geometry {
        Geometry::Sphere { center, radius } => {
            let oc = origin - center;
            let b = oc.dot(direction);
            let c = oc.length_squared() - radius * radius;
            let discriminant = b * b - c;
            if discriminant < 0.0 {
                return None;
            }
            let root = discriminant.sqrt();
            let t = [-b - root, -b + root].into_iter().find(|&t| t > MIN_T && t < max_t)?;
            Some((t, (origin + t * direction - center) / radius, Vec3::ZERO))
        }
        Geometry::Plane { point, normal } => {
            let denominator = normal.dot(direction);
            if denominator.abs() < 1e-12 {
                return None;
            }
            let t = (point - origin).dot(normal) / denominator;
            (t > MIN_T && t < max_t).then_some((t, normal, Vec3::ZERO))
        }
        Geometry::Mesh { ref triangles, ref normals, ref tangents } => {
            let cast = |from: Vec3| {
                let hit = triangles.cast_local_ray_and_get_normal(&Ray::new(from, direction), max_t, false)?;
                let t = hit.time_of_impact;
                if t <= MIN_T {
                    return None;
                }
                let [a, b, c] = triangles.indices()[hit.subshape as usize].map(|i| i as usize);
                let vertices = triangles.vertices();
                let weights = barycentric(from + t * direction, vertices[a], vertices[b], vertices[c]);
                let interpolate = |at: &[Vec3]| weights.x * at[a] + weights.y * at[b] + weights.z * at[c];
                Some((t, interpolate(normals).normalize_or(hit.normal), interpolate(tangents)))
            };
            let hit = cast(origin)?;
            if hit.1.dot(direction) <= 0.0 {
                return Some(hit);
            }
            // The far side of the surface: seen for real (an open mesh from inside), or through a crack. A
            // ray passing exactly through an edge that two triangles share can miss both, as parry3d's
            // ray-triangle test is not watertight (a rasterizer's coverage is); which rays do depends on the
            // last bit of the vertices (another libm's sin and cos moved one pixel of the test sphere onto
            // its far side). Rays nudged a millionth across the view find the near side if it is there.
            let (u, v) = direction.any_orthonormal_pair();
            let nudge = 1e-6 * origin.abs().max_element().max(1.0);
            [origin + u * nudge, origin + v * nudge, origin - (u + v) * nudge]
                .into_iter()
                .filter_map(cast)
                .chain([hit])
                .min_by(|a, b| a.0.total_cmp(&b.0))
        }
    }
}

/// The barycentric coordinates of `p` in the triangle (a, b, c).
fn barycentric(p: Vec3, a: Vec3, b: Vec3, c: Vec3) -> Vec3 {
    let (ab, ac, ap) = (b - a, c - a, p - a);
    let (d00, d01, d11) = (ab.dot(ab), ab.dot(ac), ac.dot(ac));
    let (d20, d21) = (ap.dot(ab), ap.dot(ac));
    let denominator = d00 * d11 - d01 * d01;
    if denominator.abs() < f32::MIN_POSITIVE {
        return Vec3::new(1.0, 0.0, 0.0);
    }
    let v = (d11 * d20 - d01 * d21) / denominator;
    let w = (d00 * d21 - d01 * d20) / denominator;
    Vec3::new(1.0 - v - w, v, w)
}

/// Direct lighting at `p`, seen from direction `wo`, with hard shadows, and the environment's light (not
/// occluded), with the standard error of its estimate.
fn shade(
    scene: &Scene,
    (geometry, reflectances): (&[Geometry], &[Reflectance]),
    environment: Option<&EnvironmentLight>,
    hit: &Hit,
    p: Vec3,
    wo: Vec3,
    seed: u64,
) -> (Vec3, Vec3) {
    let reflectance = &reflectances[hit.object];
    let point = surface_point(scene, geometry, hit, p, wo);
    let t = geometry[hit.object].tangent(point.n, hit.tangent);
    let from_environment = environment.map(|light| light.reflected(reflectance, (point.n, t), wo, seed));
    let from_lights = point.reflected(|n, wi, wo| reflectance.eval(n, t, wi, wo));
    match from_environment {
        Some(estimate) => (from_lights + estimate.radiance, estimate.standard_error),
        None => (from_lights, Vec3::ZERO),
    }
}

/// The shading normal at a hit, and how each light arrives there.
fn surface_point(scene: &Scene, geometry: &[Geometry], hit: &Hit, p: Vec3, wo: Vec3) -> SurfacePoint {
    let mut n = hit.normal;
    match geometry[hit.object] {
        // A plane is seen from either side: its normal faces the viewer.
        Geometry::Plane { .. } => n *= n.dot(wo).signum(),
        Geometry::Mesh { .. } if n.dot(wo) < MIN_NOV => n = (n + (MIN_NOV - n.dot(wo)) * wo).normalize(),
        _ => {}
    }
    // Shadow rays leave from just above the surface so that it does not shadow itself.
    let origin = p + n * (1e-4 * p.abs().max_element().max(1.0));
    let lights = scene
        .lights
        .iter()
        .map(|light| {
            let to_light = light.position - p;
            let d2 = to_light.length_squared();
            let wi = to_light / d2.sqrt();
            let cos = n.dot(wi);
            let visible = cos > 0.0
                && !(light.shadows && nearest_hit(geometry, origin, wi, (light.position - origin).length()).is_some());
            LightArrival { wi, irradiance: light.color * light.power / d2 * cos.max(0.0), visible }
        })
        .collect();
    SurfacePoint { object: hit.object, n, wo, lights }
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use super::*;

    /// A small sphere between a light and the plane, seen from above.
    fn shadow_scene(shadows: bool) -> Scene {
        let text = format!(
            "[image]\nwidth = 64\nheight = 64\nsamples = 1\n\
             [camera]\nposition = [0, 5, 0]\nlook_at = [0, 0, 0]\nup = [0, 0, 1]\n\
             [[light]]\nposition = [0, 4, 0]\npower = 16\nshadows = {shadows}\n\
             [material.m]\nbrdf = \"lambert\"\nkd = 1\n\
             [[object]]\nshape = \"plane\"\npoint = [0, 0, 0]\nnormal = [0, 1, 0]\nmaterial = \"m\"\n\
             [[object]]\nshape = \"sphere\"\ncenter = [0.8, 2, 0]\nradius = 0.5\nmaterial = \"m\"\n"
        );
        Scene::parse(&text, Path::new("shadow.toml"), &[]).unwrap()
    }

    #[test]
    fn shadow_rays_darken_what_the_light_cannot_see() {
        // The light at height 4 casts the sphere (height 2, x = 0.8, radius 0.5) onto the plane as an ellipse
        // of semi-axes 1.1 and 1.0 around x = 1.7, some 430 pixels at 11 pixels a unit, of which the sphere
        // itself hides more than half from the camera above.
        let lit = render(&shadow_scene(false)).unwrap();
        let shadowed = render(&shadow_scene(true)).unwrap();
        let (mut darkened, mut unchanged) = (0, 0);
        for (i, (a, b)) in lit.image.pixels.iter().zip(&shadowed.image.pixels).enumerate() {
            if lit.object_ids[i] != Some(0) {
                continue;
            }
            if b.x == 0.0 && a.x > 0.0 {
                darkened += 1;
            } else if a == b {
                unchanged += 1;
            }
        }
        assert!((100..430).contains(&darkened), "{darkened} plane pixels in shadow");
        assert_eq!(darkened + unchanged, lit.object_ids.iter().filter(|id| **id == Some(0)).count());
        // Straight under the light, at the image centre, the plane is lit: 1/pi * 16/16 * 1.
        let centre = shadowed.image.at(32, 32);
        assert!((centre.x - std::f32::consts::FRAC_1_PI).abs() < 2e-3, "{centre}");
    }

    #[test]
    fn barycentric_coordinates_by_hand() {
        let (a, b, c) = (Vec3::ZERO, Vec3::X, Vec3::Y);
        assert!(barycentric(Vec3::new(0.25, 0.5, 0.0), a, b, c).abs_diff_eq(Vec3::new(0.25, 0.25, 0.5), 1e-6));
    }
}
