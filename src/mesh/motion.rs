//! A lighter mesh for the explore page's motion frames in the browser: vertex clustering (Rossignac and
//! Borrel 1993). A CPU's WebGL (SwiftShader) spends on each triangle's set-up what a GPU does not: the
//! bunny's 69,666 triangles cost 12 ms of a motion frame at any size. Motion frames are half the picture's
//! size, where the bunny's triangles are a quarter of a pixel each; merging the vertices of each cell of a
//! grid a motion frame's pixel or less across draws the same picture from far fewer triangles. The still
//! frame draws the mesh itself.

use std::collections::HashMap;

use glam::Vec3;

use super::{Mesh, Vertex};

/// A mesh past this many triangles gets a lighter one for motion frames.
pub const MOTION_TRIANGLES: usize = 16_384;

/// The cells along the bounding box's longest side, from this down by a fifth at a time until the mesh has at
/// most [`MOTION_TRIANGLES`] triangles (halving them took the bunny from 25,000 triangles to 6,400, whose
/// highlights showed its facets).
const FIRST_CELLS: u32 = 256;

/// Whether [`motion_mesh`] makes a lighter mesh of `mesh`: it has more than [`MOTION_TRIANGLES`] triangles and
/// no vertex at infinity.
pub fn has_motion_mesh(mesh: &Mesh) -> bool {
    mesh.triangle_count() > MOTION_TRIANGLES && mesh.vertices.iter().all(|v| v.position[3] == 1.0)
}

/// `mesh` with at most [`MOTION_TRIANGLES`] triangles, or None when it has no more than that already (or
/// has vertices at infinity, as the plane's): its vertices merged cell by cell of the finest of the grids of
/// 256, 204, 163 ... cells along its longest side that brings it there. Each cell's vertex is the mean of
/// its vertices, its normal and tangent their normalized sums; a triangle whose corners share a cell is
/// dropped, and the others keep their winding.
pub fn motion_mesh(mesh: &Mesh) -> Option<Mesh> {
    if !has_motion_mesh(mesh) {
        return None;
    }
    let mut cells = FIRST_CELLS;
    loop {
        let clustered = clustered(mesh, cells);
        if clustered.triangle_count() <= MOTION_TRIANGLES || cells <= 2 {
            return Some(clustered);
        }
        cells = cells * 4 / 5;
    }
}

/// `mesh`'s vertices merged in the cells of a grid of `cells` cells along its bounding box's longest side.
pub fn clustered(mesh: &Mesh, cells: u32) -> Mesh {
    let (least, greatest) = mesh.bounds();
    let size = (greatest - least).max_element().max(f32::MIN_POSITIVE) / cells as f32;
    let cell_of = |v: &Vertex| {
        let p = (Vec3::from_slice(&v.position[..3]) - least) / size;
        let c = |x: f32| (x.floor() as i64).clamp(0, cells as i64 - 1);
        (c(p.x), c(p.y), c(p.z))
    };
    // Each cell's index, in the order the vertices meet them (deterministic), and its sums.
    let mut index_of_cell = HashMap::new();
    let mut sums: Vec<(Vec3, Vec3, Vec3, u32)> = Vec::new();
    let remap: Vec<u32> = mesh
        .vertices
        .iter()
        .map(|v| {
            let next = sums.len() as u32;
            let index = *index_of_cell.entry(cell_of(v)).or_insert(next);
            if index == next {
                sums.push((Vec3::ZERO, Vec3::ZERO, Vec3::ZERO, 0));
            }
            let sum = &mut sums[index as usize];
            sum.0 += Vec3::from_slice(&v.position[..3]);
            sum.1 += Vec3::from(v.normal);
            sum.2 += Vec3::from(v.tangent);
            sum.3 += 1;
            index
        })
        .collect();
    let vertices = sums
        .iter()
        .map(|(position, normal, tangent, count)| Vertex {
            position: (*position / *count as f32).extend(1.0).to_array(),
            normal: normal.normalize_or_zero().to_array(),
            tangent: tangent.normalize_or_zero().to_array(),
        })
        .collect();
    let indices = mesh
        .indices
        .chunks_exact(3)
        .map(|t| [remap[t[0] as usize], remap[t[1] as usize], remap[t[2] as usize]])
        .filter(|t| t[0] != t[1] && t[1] != t[2] && t[0] != t[2])
        .flatten()
        .collect();
    Mesh { vertices, indices }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_mesh_under_the_limit_keeps_its_own() {
        let sphere = crate::mesh::uv_sphere(64, 32);
        assert!(sphere.triangle_count() < MOTION_TRIANGLES);
        assert!(motion_mesh(&sphere).is_none());
    }

    #[test]
    fn a_fine_sphere_merged_stays_a_sphere_of_its_size_and_facing() {
        let sphere = crate::mesh::uv_sphere(256, 128);
        assert!(sphere.triangle_count() > MOTION_TRIANGLES);
        let light = motion_mesh(&sphere).expect("a lighter mesh");
        assert!(light.triangle_count() <= MOTION_TRIANGLES, "{}", light.triangle_count());
        assert!(light.triangle_count() > MOTION_TRIANGLES / 2, "not coarser than it needs: {}", light.triangle_count());
        // Every vertex within a cell of the unit sphere, its normal outwards.
        for v in &light.vertices {
            let p = Vec3::from_slice(&v.position[..3]);
            assert!((p.length() - 1.0).abs() < 2.0 / 64.0, "{p}");
            assert!(Vec3::from(v.normal).dot(p.normalize()) > 0.9, "{p}");
        }
        // Its triangles still wound outwards: their normals agree with the vertices'.
        for t in light.indices.chunks_exact(3) {
            let [a, b, c] = [0, 1, 2].map(|k| Vec3::from_slice(&light.vertices[t[k] as usize].position[..3]));
            assert!((b - a).cross(c - a).dot(a + b + c) > 0.0);
        }
        let (least, greatest) = light.bounds();
        assert!((least + Vec3::ONE).abs().max_element() < 0.05 && (greatest - Vec3::ONE).abs().max_element() < 0.05);
    }

    #[test]
    fn the_plane_keeps_its_own() {
        let plane = crate::mesh::infinite_plane(Vec3::ZERO, Vec3::Y);
        assert!(motion_mesh(&plane).is_none());
    }
}
