//! Triangle meshes: the tessellated sphere, the infinite plane and OBJ files (through tobj).

use std::path::Path;
use std::sync::{Arc, OnceLock};

use glam::{Mat4, Vec3};

use crate::error::{Error, Result};
use crate::scene::{Scene, Shape, BUNNY_PATH};

/// One vertex as the vertex shader reads it.
///
/// The position is homogeneous so that the infinite plane can put vertices at infinity (w = 0); every
/// other mesh has w = 1.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Vertex {
    pub position: [f32; 4],
    pub normal: [f32; 3],
}

/// An indexed triangle list.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Mesh {
    pub vertices: Vec<Vertex>,
    pub indices: Vec<u32>,
}

impl Mesh {
    /// The number of triangles.
    pub fn triangle_count(&self) -> usize {
        self.indices.len() / 3
    }
}

/// A mesh placed in the world.
#[derive(Clone, Debug)]
pub struct PlacedMesh {
    pub mesh: Arc<Mesh>,
    /// Object to world.
    pub model: Mat4,
}

/// Longitude and latitude steps of the sphere mesh.
///
/// With 256 x 128 steps (1.4 degrees each) the chord's sag is 7.5e-5 of the radius and the interpolated
/// normal is off by under 1e-4 rad, so interior shading stays within one 8-bit level of an exact sphere
/// (checked by `tests/render.rs` against a ray-traced sphere).
pub const SPHERE_SEGMENTS: u32 = 256;
pub const SPHERE_RINGS: u32 = 128;

/// The unit sphere at the origin, built once per process and shared by every sphere.
pub fn unit_sphere() -> Arc<Mesh> {
    static SPHERE: OnceLock<Arc<Mesh>> = OnceLock::new();
    SPHERE.get_or_init(|| Arc::new(uv_sphere(SPHERE_SEGMENTS, SPHERE_RINGS))).clone()
}

/// A unit sphere with `segments` steps of longitude and `rings` of latitude; normals are exact.
pub fn uv_sphere(segments: u32, rings: u32) -> Mesh {
    let mut vertices = Vec::with_capacity(((segments + 1) * (rings + 1)) as usize);
    for ring in 0..=rings {
        let theta = std::f32::consts::PI * ring as f32 / rings as f32;
        for segment in 0..=segments {
            let phi = std::f32::consts::TAU * segment as f32 / segments as f32;
            let n = Vec3::new(theta.sin() * phi.cos(), theta.cos(), theta.sin() * phi.sin());
            vertices.push(Vertex { position: n.extend(1.0).into(), normal: n.into() });
        }
    }
    let stride = segments + 1;
    let mut indices = Vec::with_capacity((segments * rings * 6) as usize);
    for ring in 0..rings {
        for segment in 0..segments {
            let a = ring * stride + segment;
            let b = a + stride;
            // The pole rows are single points: skip the triangle that would have zero area there.
            if ring != 0 {
                indices.extend([a, a + 1, b]);
            }
            if ring != rings - 1 {
                indices.extend([a + 1, b + 1, b]);
            }
        }
    }
    Mesh { vertices, indices }
}

/// An infinite plane: a fan of four triangles from `point` to four vertices at infinity (w = 0).
///
/// Clipping happens in homogeneous space, so the rasterizer draws the plane up to the horizon with no far
/// edge, as the course's ray-traced infinite plane; the projection must have an infinite far plane.
pub fn infinite_plane(point: Vec3, normal: Vec3) -> Mesh {
    let normal = normal.normalize();
    let (t1, t2) = normal.any_orthonormal_pair();
    let n: [f32; 3] = normal.into();
    let at_infinity = |d: Vec3| Vertex { position: d.extend(0.0).into(), normal: n };
    Mesh {
        vertices: vec![
            Vertex { position: point.extend(1.0).into(), normal: n },
            at_infinity(t1),
            at_infinity(t2),
            at_infinity(-t1),
            at_infinity(-t2),
        ],
        indices: vec![0, 1, 2, 0, 2, 3, 0, 3, 4, 0, 4, 1],
    }
}

/// Loads an OBJ file as one triangle mesh; smooth normals are computed when the file has none.
///
/// # Errors
/// A message saying why the file could not be read or holds no usable triangles.
pub fn load_obj(path: &Path) -> Result<Mesh, String> {
    let options = tobj::LoadOptions { single_index: true, triangulate: true, ignore_points: true, ignore_lines: true };
    let (models, _materials) = tobj::load_obj(path, &options).map_err(|e| match e {
        tobj::LoadError::OpenFileFailed => match std::fs::metadata(path) {
            Err(io) => cannot_open(path, &io),
            Ok(_) => format!("cannot open {}", path.display()),
        },
        other => format!("{} is not a valid OBJ file: {other}", path.display()),
    })?;
    let mut mesh = Mesh::default();
    for model in models {
        let m = model.mesh;
        let first = u32::try_from(mesh.vertices.len()).map_err(|_| "too many vertices".to_string())?;
        let count = m.positions.len() / 3;
        let positions: Vec<Vec3> = m.positions.chunks_exact(3).map(|p| Vec3::new(p[0], p[1], p[2])).collect();
        if positions.iter().any(|p| !p.is_finite()) {
            return Err(format!("{} has a vertex position that is not a finite number", path.display()));
        }
        let normals = if m.normals.len() == m.positions.len() {
            m.normals.chunks_exact(3).map(|n| Vec3::new(n[0], n[1], n[2]).normalize_or(Vec3::Y)).collect()
        } else {
            smooth_normals(&positions, &m.indices)
        };
        debug_assert_eq!(normals.len(), count);
        mesh.vertices.extend(
            positions.iter().zip(&normals).map(|(p, n)| Vertex { position: p.extend(1.0).into(), normal: (*n).into() }),
        );
        mesh.indices.extend(m.indices.iter().map(|i| first + i));
    }
    if mesh.indices.is_empty() {
        return Err(format!("{} holds no triangles", path.display()));
    }
    Ok(mesh)
}

/// Why a mesh file could not be opened; for the installed bunny, which package provides it.
fn cannot_open(path: &Path, error: &std::io::Error) -> String {
    if path == Path::new(BUNNY_PATH) {
        format!(
            "cannot open {}: {error}; the Stanford bunny comes with the Debian package glmark2-data \
             (sudo apt-get install glmark2-data, or `make setup`)",
            path.display()
        )
    } else {
        format!("cannot open {}: {error}", path.display())
    }
}

/// Area-weighted vertex normals: each face adds its unnormalized cross product to its three vertices.
pub fn smooth_normals(positions: &[Vec3], indices: &[u32]) -> Vec<Vec3> {
    let mut normals = vec![Vec3::ZERO; positions.len()];
    for triangle in indices.chunks_exact(3) {
        let [a, b, c] = [triangle[0], triangle[1], triangle[2]].map(|i| i as usize);
        let face = (positions[b] - positions[a]).cross(positions[c] - positions[a]);
        for v in [a, b, c] {
            normals[v] += face;
        }
    }
    // A vertex used only by zero-area faces has no defined normal; any unit vector keeps the shader finite.
    normals.into_iter().map(|n| n.normalize_or(Vec3::Y)).collect()
}

/// Builds every object's mesh and transform, loading OBJ files.
///
/// # Errors
/// `Error::Mesh` naming the scene file, the object's `path` key and its value when an OBJ cannot be loaded.
pub fn place_objects(scene: &Scene) -> Result<Vec<PlacedMesh>> {
    scene
        .objects
        .iter()
        .enumerate()
        .map(|(index, object)| {
            Ok(match &object.shape {
                Shape::Sphere { center, radius } => PlacedMesh {
                    mesh: unit_sphere(),
                    model: Mat4::from_translation(*center) * Mat4::from_scale(Vec3::splat(*radius)),
                },
                Shape::Plane { point, normal } => {
                    PlacedMesh { mesh: Arc::new(infinite_plane(*point, *normal)), model: Mat4::IDENTITY }
                }
                Shape::Mesh { path, scale, rotate, translate } => {
                    let mesh = load_obj(path).map_err(|message| Error::Mesh {
                        scene: scene.source.clone(),
                        key: format!("object.{index}.path"),
                        value: path.display().to_string(),
                        message,
                    })?;
                    PlacedMesh { mesh: Arc::new(mesh), model: Shape::mesh_transform(*scale, *rotate, *translate) }
                }
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_missing_bunny_names_its_package() {
        let missing = std::io::Error::from(std::io::ErrorKind::NotFound);
        let message = cannot_open(Path::new(BUNNY_PATH), &missing);
        assert!(message.contains(BUNNY_PATH) && message.contains("glmark2-data"), "{message}");
        assert!(!cannot_open(Path::new("/models/cube.obj"), &missing).contains("glmark2"));
    }

    #[test]
    fn smooth_normals_of_a_tetrahedron_corner_average_its_faces() {
        let positions = [Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z];
        let normals = smooth_normals(&positions, &[0, 2, 1, 0, 1, 3, 0, 3, 2]);
        // The corner at the origin touches three faces of equal area facing -z, -y and -x.
        assert!(normals[0].abs_diff_eq(-Vec3::ONE.normalize(), 1e-6), "{}", normals[0]);
    }
}
