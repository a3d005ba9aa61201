//! Triangle meshes: the tessellated sphere, the infinite plane and OBJ files (through tobj), their tangents
//! from texture coordinates (`tangents.rs`), and the lighter meshes of the browser's motion frames (`motion.rs`).

pub mod motion;
mod tangents;

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex, OnceLock};

use glam::{Mat4, Vec3};

use crate::error::{Error, Result};
use crate::scene::{Scene, Shape, BUNNY_PATH};

/// One vertex as the vertex shader reads it.
///
/// The position is homogeneous so that the infinite plane can put vertices at infinity (w = 0); every
/// other mesh has w = 1. The tangent is zero where the mesh gives none (no texture coordinates): the
/// shaders then take the default rule (`default_tangent`).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Vertex {
    /// Object-space position, homogeneous: w = 1, or 0 for the plane's vertices at infinity.
    pub position: [f32; 4],
    /// Object-space normal.
    pub normal: [f32; 3],
    /// Object-space tangent from the texture coordinates (MikkTSpace), or zero where the mesh has none.
    pub tangent: [f32; 3],
}

impl Vertex {
    /// A vertex without a tangent.
    pub fn new(position: [f32; 4], normal: [f32; 3]) -> Self {
        Vertex { position, normal, tangent: [0.0; 3] }
    }
}

/// An indexed triangle list.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Mesh {
    /// The vertices, each once.
    pub vertices: Vec<Vertex>,
    /// Three indices into `vertices` a triangle (front faces counter-clockwise, as OBJ files wind them).
    pub indices: Vec<u32>,
}

impl Mesh {
    /// The number of triangles.
    pub fn triangle_count(&self) -> usize {
        self.indices.len() / 3
    }

    /// Whether the mesh is closed and wound counter-clockwise seen from outside: every edge is run by
    /// exactly two triangles, in opposite directions, and the volume they enclose is positive. From any
    /// viewpoint outside such a mesh every back face lies behind a front face, so culling them changes
    /// nothing that is seen.
    pub fn is_closed_outward(&self) -> bool {
        // The directed edges leaving each vertex, packed vertex after vertex: a hash set of the bunny's
        // 209,000 edges took 10 ms of Figure 5's first image, these lists 2.
        let count = self.vertices.len();
        let directed = || self.indices.chunks_exact(3).flat_map(|t| [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])]);
        if self.indices.iter().any(|&i| i as usize >= count) {
            return false;
        }
        let mut start = vec![0usize; count + 1];
        for (from, _) in directed() {
            start[from as usize + 1] += 1;
        }
        for v in 0..count {
            start[v + 1] += start[v];
        }
        let mut next = start.clone();
        let mut to = vec![0u32; self.indices.len()];
        for (from, target) in directed() {
            to[next[from as usize]] = target;
            next[from as usize] += 1;
        }
        let leaving = |v: u32| &to[start[v as usize]..start[v as usize + 1]];
        for from in 0..count as u32 {
            let edges = leaving(from);
            for (i, &target) in edges.iter().enumerate() {
                if edges[..i].contains(&target) || !leaving(target).contains(&from) {
                    return false; // an edge run twice in the same direction, or never back
                }
            }
        }
        let position = |i: u32| {
            let p = self.vertices[i as usize].position;
            glam::DVec3::new(f64::from(p[0]), f64::from(p[1]), f64::from(p[2]))
        };
        // Points at infinity (w = 0) bound no volume.
        let finite = self.vertices.iter().all(|v| v.position[3] == 1.0);
        let volume: f64 =
            self.indices.chunks_exact(3).map(|t| position(t[0]).dot(position(t[1]).cross(position(t[2])))).sum();
        finite && volume > 0.0
    }

    /// The bounding box of the vertices: (min, max).
    pub fn bounds(&self) -> (Vec3, Vec3) {
        self.vertices
            .iter()
            .map(|v| Vec3::from_slice(&v.position[..3]))
            .fold((Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)), |(min, max), p| {
                (min.min(p), max.max(p))
            })
    }
}

/// A mesh placed in the world.
#[derive(Clone, Debug)]
pub struct PlacedMesh {
    /// The mesh in object space, shared by every object that uses it.
    pub mesh: Arc<Mesh>,
    /// Object to world.
    pub model: Mat4,
    /// The mesh bounds a sphere (of model translate(center) * scale(radius)) that is drawn exactly.
    pub exact_sphere: bool,
    /// Drawn into the shadow cubes (the object's [`crate::scene::Object::casts_shadow`]).
    pub casts_shadow: bool,
}

/// Longitude and latitude steps of the mesh that stands for every sphere.
///
/// The fragments of a sphere find the exact sphere along their rays (shaders/common/sphere.glsl), so the mesh
/// only has to bound it: its facets decide which fragments look, not what is covered or shaded. With 32 x 16
/// steps they stand at most 2% of the radius outside the sphere, and a sphere costs 960 triangles.
pub const BOUNDING_SPHERE_SEGMENTS: u32 = 32;
/// Latitude steps of the bounding sphere: see [`BOUNDING_SPHERE_SEGMENTS`].
pub const BOUNDING_SPHERE_RINGS: u32 = 16;

/// How far outside the unit sphere the nearest facet of [`bounding_sphere`] stands, over float rounding.
const BOUNDING_MARGIN: f32 = 1e-3;

/// The mesh that bounds the unit sphere at the origin, built once per process and shared by every sphere.
pub fn bounding_sphere() -> Arc<Mesh> {
    static SPHERE: OnceLock<Arc<Mesh>> = OnceLock::new();
    SPHERE.get_or_init(|| Arc::new(bounding_uv_sphere(BOUNDING_SPHERE_SEGMENTS, BOUNDING_SPHERE_RINGS))).clone()
}

/// [`uv_sphere`] scaled so that every facet lies outside the unit sphere, by `BOUNDING_MARGIN` at least.
pub fn bounding_uv_sphere(segments: u32, rings: u32) -> Mesh {
    let mut mesh = uv_sphere(segments, rings);
    let position = |i: u32| Vec3::from_slice(&mesh.vertices[i as usize].position[..3]);
    // A facet's plane is as far from the centre as its normal's component along any of its vertices.
    let nearest = mesh
        .indices
        .chunks_exact(3)
        .map(|t| {
            let [a, b, c] = [t[0], t[1], t[2]].map(position);
            (b - a).cross(c - a).normalize().dot(a).abs()
        })
        .fold(f32::INFINITY, f32::min);
    let scale = (1.0 + BOUNDING_MARGIN) / nearest;
    for vertex in &mut mesh.vertices {
        for coordinate in &mut vertex.position[..3] {
            *coordinate *= scale;
        }
    }
    mesh
}

/// A unit sphere with `segments` steps of longitude and `rings` of latitude; normals are exact. Each pole is
/// one vertex and the seam is not doubled, so that the mesh is closed (see [`Mesh::is_closed_outward`]).
pub fn uv_sphere(segments: u32, rings: u32) -> Mesh {
    let at = |theta: f32, phi: f32| {
        let n = Vec3::new(theta.sin() * phi.cos(), theta.cos(), theta.sin() * phi.sin());
        Vertex::new(n.extend(1.0).into(), n.into())
    };
    // The north pole, the rings between the poles, the south pole.
    let mut vertices = Vec::with_capacity((segments * (rings - 1) + 2) as usize);
    vertices.push(at(0.0, 0.0));
    for ring in 1..rings {
        let theta = std::f32::consts::PI * ring as f32 / rings as f32;
        vertices
            .extend((0..segments).map(|segment| at(theta, std::f32::consts::TAU * segment as f32 / segments as f32)));
    }
    vertices.push(at(std::f32::consts::PI, 0.0));
    let south = vertices.len() as u32 - 1;
    // Vertex `segment` (wrapping around) of ring `ring` (1..rings), or the pole at either end.
    let vertex = |ring: u32, segment: u32| match ring {
        0 => 0,
        r if r == rings => south,
        r => 1 + (r - 1) * segments + segment % segments,
    };
    let mut indices = Vec::with_capacity((segments * rings * 6) as usize);
    for ring in 0..rings {
        for segment in 0..segments {
            let (a, a1) = (vertex(ring, segment), vertex(ring, segment + 1));
            let (b, b1) = (vertex(ring + 1, segment), vertex(ring + 1, segment + 1));
            // At the poles the quad is a triangle: skip the one that would have zero area.
            if ring != 0 {
                indices.extend([a, a1, b]);
            }
            if ring != rings - 1 {
                indices.extend([a1, b1, b]);
            }
        }
    }
    Mesh { vertices, indices }
}

/// The infinite plane through the origin of normal +y, built once per process and shared by every plane,
/// each placed by its model matrix.
pub fn unit_plane() -> Arc<Mesh> {
    static PLANE: OnceLock<Arc<Mesh>> = OnceLock::new();
    PLANE.get_or_init(|| Arc::new(infinite_plane(Vec3::ZERO, Vec3::Y))).clone()
}

/// An infinite plane: a fan of four triangles from `point` to four vertices at infinity (w = 0).
///
/// Clipping happens in homogeneous space, so the rasterizer draws the plane up to the horizon with no far
/// edge, as the course's ray-traced infinite plane; the projection must have an infinite far plane.
pub fn infinite_plane(point: Vec3, normal: Vec3) -> Mesh {
    let normal = normal.normalize();
    let (t1, t2) = normal.any_orthonormal_pair();
    let n: [f32; 3] = normal.into();
    let at_infinity = |d: Vec3| Vertex::new(d.extend(0.0).into(), n);
    Mesh {
        vertices: vec![
            Vertex::new(point.extend(1.0).into(), n),
            at_infinity(t1),
            at_infinity(t2),
            at_infinity(-t1),
            at_infinity(-t2),
        ],
        indices: vec![0, 1, 2, 0, 2, 3, 0, 3, 4, 0, 4, 1],
    }
}

/// Loads an OBJ file as one triangle mesh; smooth normals are computed when the file has none, tangents
/// when it has texture coordinates (`tangents::with_tangents`).
///
/// # Errors
/// A message saying why the file could not be read or holds no usable triangles.
pub fn load_obj(path: &Path) -> Result<Mesh, String> {
    let options = tobj::LoadOptions { single_index: true, triangulate: true, ignore_points: true, ignore_lines: true };
    let bytes = match std::fs::metadata(path) {
        Err(io) => return Err(cannot_open(path, &io)),
        Ok(_) => crate::files::read_regular(path, "OBJ file", crate::files::MAX_MESH_BYTES)?,
    };
    // Material libraries are not read: the scene gives every object its material.
    let no_materials = |_: &Path| Err(tobj::LoadError::OpenFileFailed);
    let (models, _materials) = tobj::load_obj_buf(&mut bytes.as_slice(), &options, no_materials)
        .map_err(|e| format!("{} is not a valid OBJ file: {e}", path.display()))?;
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
        let vertices = positions.iter().zip(&normals).map(|(p, n)| Vertex::new(p.extend(1.0).into(), (*n).into()));
        let mut part = Mesh { vertices: vertices.collect(), indices: m.indices };
        if m.texcoords.len() == 2 * count {
            let texcoords: Vec<[f32; 2]> = m.texcoords.chunks_exact(2).map(|uv| [uv[0], uv[1]]).collect();
            part = tangents::with_tangents(part, &texcoords).map_err(|e| format!("{}: {e}", path.display()))?;
        }
        mesh.vertices.extend(part.vertices);
        mesh.indices.extend(part.indices.iter().map(|i| first + i));
    }
    if mesh.indices.is_empty() {
        return Err(format!("{} holds no triangles", path.display()));
    }
    Ok(mesh)
}

/// [`load_obj`], parsed once per process while the file's modification time and size hold: sweeps, the
/// figures and the preview's frames draw the same files again and again. An edited file is read again
/// and replaces the old mesh.
///
/// # Errors
/// As [`load_obj`].
pub fn load_obj_kept(path: &Path) -> Result<Arc<Mesh>, String> {
    type Kept = HashMap<PathBuf, (FileStamp, Arc<Mesh>)>;
    static KEPT: OnceLock<Mutex<Kept>> = OnceLock::new();
    let kept = KEPT.get_or_init(Mutex::default);
    let stamp = std::fs::metadata(path).ok().map(|m| (m.modified().ok(), m.len()));
    let Some(stamp) = stamp else { return load_obj(path).map(Arc::new) };
    let lock = || kept.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
    if let Some((kept_stamp, mesh)) = lock().get(path) {
        if *kept_stamp == stamp {
            return Ok(mesh.clone());
        }
    }
    let mesh = Arc::new(load_obj(path)?);
    lock().insert(path.to_path_buf(), (stamp, mesh.clone()));
    Ok(mesh)
}

/// What tells an edited file: its modification time and size.
type FileStamp = (Option<std::time::SystemTime>, u64);

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
            let placed = match &object.shape {
                Shape::Sphere { center, radius } => PlacedMesh {
                    mesh: bounding_sphere(),
                    model: Mat4::from_translation(*center) * Mat4::from_scale(Vec3::splat(*radius)),
                    exact_sphere: true,
                    casts_shadow: true,
                },
                Shape::Plane { point, normal } => PlacedMesh {
                    mesh: unit_plane(),
                    model: Mat4::from_translation(*point)
                        * Mat4::from_quat(glam::Quat::from_rotation_arc(Vec3::Y, normal.normalize())),
                    exact_sphere: false,
                    casts_shadow: true,
                },
                Shape::Mesh { path, scale, rotate, translate } => {
                    let mesh = load_obj_kept(path).map_err(|message| Error::Mesh {
                        scene: scene.source.clone(),
                        key: format!("object.{index}.path"),
                        value: path.display().to_string(),
                        message,
                    })?;
                    let model = Shape::mesh_transform(*scale, *rotate, *translate);
                    PlacedMesh { mesh, model, exact_sphere: false, casts_shadow: true }
                }
                Shape::Triangles(triangles) => {
                    let vertices = triangles
                        .positions
                        .iter()
                        .zip(&triangles.normals)
                        .map(|(p, n)| Vertex::new(p.extend(1.0).into(), (*n).into()))
                        .collect();
                    let mesh = Arc::new(Mesh { vertices, indices: triangles.indices.clone() });
                    PlacedMesh { mesh, model: Mat4::IDENTITY, exact_sphere: false, casts_shadow: true }
                }
            };
            Ok(PlacedMesh { casts_shadow: object.casts_shadow, ..placed })
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

    #[test]
    fn the_bounding_sphere_holds_the_unit_sphere_closely() {
        let mesh = bounding_uv_sphere(BOUNDING_SPHERE_SEGMENTS, BOUNDING_SPHERE_RINGS);
        let position = |i: u32| Vec3::from_slice(&mesh.vertices[i as usize].position[..3]).as_dvec3();
        let mut nearest = f64::INFINITY;
        for t in mesh.indices.chunks_exact(3) {
            let [a, b, c] = [t[0], t[1], t[2]].map(position);
            let normal = (b - a).cross(c - a).normalize();
            // Wound counter-clockwise seen from outside, and every facet's plane outside the sphere.
            assert!(normal.dot(a + b + c) > 0.0);
            nearest = nearest.min(normal.dot(a));
        }
        assert!(nearest > 1.0 + 0.5 * f64::from(BOUNDING_MARGIN), "{nearest}");
        let farthest = mesh.vertices.iter().map(|v| Vec3::from_slice(&v.position[..3]).length()).fold(0.0, f32::max);
        assert!(farthest < 1.025, "{farthest}");
        assert_eq!(mesh.triangle_count(), 960);
    }

    #[test]
    fn a_kept_obj_is_read_again_once_edited() {
        let folder = std::env::temp_dir().join(format!("vk-render-obj-{}", std::process::id()));
        std::fs::create_dir_all(&folder).unwrap();
        let path = folder.join("tri.obj");
        std::fs::write(&path, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
        let first = load_obj_kept(&path).unwrap();
        assert!(Arc::ptr_eq(&first, &load_obj_kept(&path).unwrap()), "parsed twice");
        std::fs::write(&path, "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nf 2 4 3\n").unwrap();
        assert_eq!(load_obj_kept(&path).unwrap().triangle_count(), 2, "an edited file kept its old mesh");
        std::fs::remove_dir_all(&folder).unwrap();
    }

    #[test]
    fn closed_outward_meshes_are_told_from_open_or_inside_out_ones() {
        assert!(uv_sphere(16, 8).is_closed_outward());
        assert!(bounding_uv_sphere(32, 16).is_closed_outward());
        assert!(!infinite_plane(Vec3::ZERO, Vec3::Y).is_closed_outward());
        let mut inside_out = uv_sphere(16, 8);
        inside_out.indices.chunks_exact_mut(3).for_each(|t| t.swap(1, 2));
        assert!(!inside_out.is_closed_outward());
        let mut open = uv_sphere(16, 8);
        open.indices.truncate(open.indices.len() - 3);
        assert!(!open.is_closed_outward());
    }

    #[test]
    fn the_torus_s_tangents_follow_its_ring_where_its_u_grows() {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/analytic/torus.obj");
        let mesh = load_obj(&path).unwrap();
        // scripts/make-torus-obj.py: 97 x 25 vertices (the seams doubled), u around the ring about +y.
        assert_eq!(mesh.vertices.len(), 97 * 25, "no vertex needed splitting");
        for vertex in &mesh.vertices {
            let p = Vec3::from_slice(&vertex.position[..3]);
            let (t, n) = (Vec3::from(vertex.tangent), Vec3::from(vertex.normal));
            // The ring's direction, d/du of (R cos 2 pi u, y, R sin 2 pi u); at a seam vertex, which has
            // triangles on one side only, MikkTSpace's is the chord's, half a step (1.9 degrees) off.
            let ring = Vec3::new(-p.z, 0.0, p.x).normalize();
            assert!(t.dot(ring) > (1.9f32).to_radians().cos() - 1e-5, "at {p}: {t} is not along the ring {ring}");
            assert!(t.dot(n).abs() < 1e-5 && (t.length() - 1.0).abs() < 1e-5, "at {p}: {t} is not a unit tangent");
        }
    }

    #[test]
    fn an_obj_naming_a_material_library_loads_without_it() {
        let path = std::env::temp_dir().join(format!("vk-render-mtl-{}.obj", std::process::id()));
        std::fs::write(&path, "mtllib nowhere.mtl\nusemtl gold\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
        let mesh = load_obj(&path);
        std::fs::remove_file(&path).unwrap();
        let mesh = mesh.unwrap();
        assert_eq!(mesh.triangle_count(), 1);
        assert!(mesh.vertices.iter().all(|v| v.tangent == [0.0; 3]), "tangents without texture coordinates");
    }
}
