//! Tangents of a mesh from its texture coordinates by MikkTSpace (Mikkelsen, "Simulation of Wrinkled
//! Surfaces Revisited", 2008), the tangent space that Blender, glTF's tools and game engines agree on: at each
//! vertex, the direction on the surface in which the texture's u grows. An analytic BRDF's X follows it.

use std::collections::HashMap;

use bevy_mikktspace::{generate_tangents, Geometry, TangentSpace};

use super::{Mesh, Vertex};

/// A triangle list as MikkTSpace reads it, corner by corner, and the tangent it gives each corner.
struct Corners<'a> {
    mesh: &'a Mesh,
    texcoords: &'a [[f32; 2]],
    tangents: Vec<[f32; 3]>,
}

impl Corners<'_> {
    fn vertex(&self, face: usize, corner: usize) -> &Vertex {
        &self.mesh.vertices[self.mesh.indices[3 * face + corner] as usize]
    }
}

impl Geometry for Corners<'_> {
    fn num_faces(&self) -> usize {
        self.mesh.triangle_count()
    }

    fn num_vertices_of_face(&self, _face: usize) -> usize {
        3
    }

    fn position(&self, face: usize, corner: usize) -> [f32; 3] {
        let [x, y, z, _] = self.vertex(face, corner).position;
        [x, y, z]
    }

    fn normal(&self, face: usize, corner: usize) -> [f32; 3] {
        self.vertex(face, corner).normal
    }

    fn tex_coord(&self, face: usize, corner: usize) -> [f32; 2] {
        self.texcoords[self.mesh.indices[3 * face + corner] as usize]
    }

    fn set_tangent(&mut self, tangent: Option<TangentSpace>, face: usize, corner: usize) {
        // None: a degenerate triangle with no neighbour to borrow a tangent from. Zero tells the shaders
        // that there is none (they take the default rule, as for a mesh without texture coordinates).
        self.tangents[3 * face + corner] = tangent.map_or([0.0; 3], |t| t.tangent());
    }
}

/// `mesh` (in the object's own space) with each vertex's tangent made from `texcoords`, one per vertex.
/// MikkTSpace gives a tangent per triangle corner; a vertex whose corners were given different ones is
/// split, the first keeping its place, so that each draws with its own.
///
/// The tangent frame stays right-handed (Y = N x X, as BRDF Explorer's), also where the texture is mirrored
/// and the direction of increasing v is -Y: the models the project ships are even in Y.
///
/// # Errors
/// MikkTSpace's, should it ever give one (its error type has no variant yet).
pub fn with_tangents(mut mesh: Mesh, texcoords: &[[f32; 2]]) -> Result<Mesh, String> {
    debug_assert_eq!(texcoords.len(), mesh.vertices.len());
    let mut corners = Corners { mesh: &mesh, texcoords, tangents: vec![[0.0; 3]; mesh.indices.len()] };
    generate_tangents(&mut corners)
        .map_err(|e| format!("MikkTSpace made no tangents of its texture coordinates: {e}"))?;
    let tangents = corners.tangents;
    let mut given: Vec<Option<[f32; 3]>> = vec![None; mesh.vertices.len()];
    let mut splits: HashMap<(u32, [u32; 3]), u32> = HashMap::new();
    for (index, tangent) in mesh.indices.iter_mut().zip(tangents) {
        let vertex = *index as usize;
        match given[vertex] {
            None => {
                given[vertex] = Some(tangent);
                mesh.vertices[vertex].tangent = tangent;
            }
            Some(first) if first == tangent => {}
            Some(_) => {
                let key = (*index, tangent.map(f32::to_bits));
                *index = *splits.entry(key).or_insert_with(|| {
                    mesh.vertices.push(Vertex { tangent, ..mesh.vertices[vertex] });
                    (mesh.vertices.len() - 1) as u32
                });
            }
        }
    }
    Ok(mesh)
}

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use super::*;

    fn vertex(position: Vec3, normal: Vec3) -> Vertex {
        Vertex { position: position.extend(1.0).into(), normal: normal.into(), tangent: [0.0; 3] }
    }

    /// The unit square in the xy-plane facing +z, as two triangles, with texture coordinates `uv` at its
    /// corners (0, 0), (1, 0), (1, 1), (0, 1).
    fn square(uv: [[f32; 2]; 4]) -> Mesh {
        let corners = [Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y];
        let mesh = Mesh { vertices: corners.map(|p| vertex(p, Vec3::Z)).to_vec(), indices: vec![0, 1, 2, 0, 2, 3] };
        with_tangents(mesh, &uv).unwrap()
    }

    fn tangents(mesh: &Mesh) -> Vec<Vec3> {
        mesh.vertices.iter().map(|v| Vec3::from(v.tangent)).collect()
    }

    #[test]
    fn a_square_s_tangent_is_where_u_grows() {
        let along_x = square([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]);
        assert!(tangents(&along_x).iter().all(|t| t.abs_diff_eq(Vec3::X, 1e-6)), "{:?}", tangents(&along_x));
        // The texture turned a quarter: u grows along -y.
        let turned = square([[1.0, 0.0], [1.0, 1.0], [0.0, 1.0], [0.0, 0.0]]);
        assert!(tangents(&turned).iter().all(|t| t.abs_diff_eq(-Vec3::Y, 1e-6)), "{:?}", tangents(&turned));
        // Sheared texture coordinates, u = 2x + y and v = y: the tangent is dP/du, which is (1/2, 0, 0), so +x
        // (not u's gradient, (2, 1, 0)).
        let sheared = square([[0.0, 0.0], [2.0, 0.0], [3.0, 1.0], [1.0, 1.0]]);
        assert!(tangents(&sheared).iter().all(|t| t.abs_diff_eq(Vec3::X, 1e-6)), "{:?}", tangents(&sheared));
        assert_eq!(along_x.vertices.len(), 4, "no vertex needed splitting");
    }

    #[test]
    fn a_vertex_whose_corners_get_two_tangents_is_split() {
        // Two triangles sharing the edge (0, 2) of the square, whose texture coordinates fold along it: on one
        // side u grows along x, on the other along y. MikkTSpace keeps apart corners whose tangents are that
        // far apart, so the shared vertices are split.
        let positions = [Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y];
        let mesh = Mesh { vertices: positions.map(|p| vertex(p, Vec3::Z)).to_vec(), indices: vec![0, 1, 2, 0, 2, 3] };
        let texcoords = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [1.0, 0.0]];
        let split = with_tangents(mesh, &texcoords).unwrap();
        let first: Vec<Vec3> =
            split.indices[..3].iter().map(|&i| Vec3::from(split.vertices[i as usize].tangent)).collect();
        let second: Vec<Vec3> =
            split.indices[3..].iter().map(|&i| Vec3::from(split.vertices[i as usize].tangent)).collect();
        assert!(first.iter().all(|t| t.abs_diff_eq(Vec3::X, 1e-6)), "{first:?}");
        assert!(second.iter().all(|t| t.abs_diff_eq(Vec3::Y, 1e-6)), "{second:?}");
        assert_eq!(split.vertices.len(), 6, "the two shared vertices split");
        assert_eq!(split.vertices[split.indices[3] as usize].position, split.vertices[0].position);
    }
}
