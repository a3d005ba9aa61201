//! What a light's shadow cube needs to hold: the objects that can shadow something from it, and the faces of
//! its cube they fall on.
//!
//! A plane shadows only what lies on its far side from the light: a point on the light's side, or on the
//! plane itself, is reached before the plane is crossed. And a camera on the light's side sees nothing of
//! that far side, the plane being infinite and opaque. So a plane is left out of the cube unless the camera
//! is beyond it too and an object reaches there, and a light whose cube would hold nothing gets none
//! (Figure 6's light over its lone plane drew six faces of nothing but that plane; Figure 5's bunny dips
//! 0.4 mm through its plane, where no one sees it). Each face is drawn only where an object left in can fall on it;
//! the shader counts a lookup in a face not drawn as lit (shading.glsl's `lit_in`), which is what that face
//! would have held everywhere. Objects are bounded by spheres, and every test errs towards drawing.

use std::sync::Arc;

use glam::{Vec3, Vec4};

use crate::mesh::{unit_plane, PlacedMesh};

/// Which of `placed` can shadow a point from `light` that the camera at `eye` sees: each one that casts
/// shadows, but a plane with the camera on the light's side or with no object (any of `placed`, shadows or
/// not) beyond it.
pub fn occluders(light: Vec3, eye: Vec3, placed: &[PlacedMesh]) -> Vec<bool> {
    placed
        .iter()
        .enumerate()
        .map(|(index, p)| {
            p.casts_shadow
                && match Plane::of(p) {
                    Some(plane) => plane.towards(light).is_none_or(|facing| {
                        facing.height(eye) <= tolerance(facing.point, eye)
                            && placed.iter().enumerate().any(|(other, q)| other != index && facing.reaches_behind(q))
                    }),
                    None => true,
                }
        })
        .collect()
}

/// Which faces of the cube of `light` (+x, -x, +y, -y, +z, -z) an object of `occluders` may fall on: those
/// whose pyramid from the light, widened by `margin` (in units of the face's half-width, as
/// [`super::shadow::faces_seen`]'s, so that lookups near an edge find what the next face holds), meets an
/// occluder's bounding sphere.
pub fn faces_with_occluders(light: Vec3, placed: &[PlacedMesh], occluders: &[bool], margin: f32) -> [bool; 6] {
    let bounds: Vec<Option<(Vec3, f32)>> =
        placed.iter().zip(occluders).filter(|(_, &occludes)| occludes).map(|(p, _)| bounding_sphere(p)).collect();
    std::array::from_fn(|face| {
        let (axis, sign) = (face / 2, if face % 2 == 0 { 1.0 } else { -1.0 });
        bounds.iter().any(|bound| {
            let Some((centre, radius)) = *bound else {
                return true; // unbounded: a plane
            };
            let d = centre - light;
            // The pyramid's four sides: sign * (1 + margin) * d[axis] >= |d[other]|, each a half-space through
            // the light that the sphere must reach.
            (0..3).filter(|&other| other != axis).all(|other| {
                [1.0, -1.0].iter().all(|&other_sign| {
                    let mut n = Vec3::ZERO;
                    n[axis] = sign * (1.0 + margin);
                    n[other] = -other_sign;
                    n.dot(d) >= -radius * n.length()
                })
            })
        })
    })
}

/// A sphere around everything `placed` draws, `None` when that is unbounded (a plane).
fn bounding_sphere(placed: &PlacedMesh) -> Option<(Vec3, f32)> {
    if placed.exact_sphere {
        // The bounding mesh stands outside the sphere; the shadow pass draws the sphere itself.
        return Some((placed.model.transform_point3(Vec3::ZERO), placed.model.x_axis.truncate().length()));
    }
    let mut points = Vec::with_capacity(placed.mesh.vertices.len());
    for vertex in &placed.mesh.vertices {
        let world = placed.model * Vec4::from(vertex.position);
        if world.w == 0.0 {
            return None;
        }
        points.push(world.truncate() / world.w);
    }
    let (min, max) = points.iter().fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), &p| (lo.min(p), hi.max(p)));
    let centre = 0.5 * (min + max);
    let radius = points.iter().map(|p| p.distance(centre)).fold(0.0, f32::max);
    Some((centre, radius * (1.0 + 1e-5) + 1e-6))
}

/// An infinite plane of the scene (the [`unit_plane`] mesh placed).
struct Plane {
    point: Vec3,
    normal: Vec3,
}

impl Plane {
    fn of(placed: &PlacedMesh) -> Option<Self> {
        Arc::ptr_eq(&placed.mesh, &unit_plane()).then(|| Self {
            point: placed.model.transform_point3(Vec3::ZERO),
            normal: placed.model.transform_vector3(Vec3::Y).normalize(),
        })
    }

    /// The plane with its normal towards `light`; `None` when the light lies in it (within rounding), where
    /// it is counted as shadowing anything.
    fn towards(&self, light: Vec3) -> Option<Self> {
        let side = (light - self.point).dot(self.normal);
        (side.abs() > tolerance(self.point, light))
            .then(|| Self { point: self.point, normal: if side > 0.0 { self.normal } else { -self.normal } })
    }

    /// How far `p` is from the plane along its normal.
    fn height(&self, p: Vec3) -> f32 {
        (p - self.point).dot(self.normal)
    }

    /// Whether any part of `placed` lies beyond the plane (its normal towards the light), where the plane
    /// could shadow it. A point in the plane within rounding does not: the shadow's bias, far larger, would
    /// count it lit anyway.
    fn reaches_behind(&self, placed: &PlacedMesh) -> bool {
        let height = |p: Vec3| self.height(p);
        if let Some(other) = Plane::of(placed) {
            // Planes that are not parallel cross; a parallel one is behind, or in it, or not.
            return other.normal.cross(self.normal).length() > 1e-6
                || height(other.point) <= tolerance(self.point, other.point);
        }
        if placed.exact_sphere {
            let (centre, radius) = bounding_sphere(placed).unwrap_or((Vec3::ZERO, f32::INFINITY));
            return height(centre) < radius - tolerance(self.point, centre) * (1.0 + radius);
        }
        placed.mesh.vertices.iter().any(|vertex| {
            let world = placed.model * Vec4::from(vertex.position);
            if world.w == 0.0 {
                world.truncate().dot(self.normal) < 0.0
            } else {
                let p = world.truncate() / world.w;
                height(p) < -tolerance(self.point, p)
            }
        })
    }
}

/// Float rounding at the scale of two points.
fn tolerance(a: Vec3, b: Vec3) -> f32 {
    1e-5 * (1.0 + a.length().max(b.length()))
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use glam::Vec3;

    use super::*;
    use crate::mesh::place_objects;
    use crate::scene::Scene;

    /// A scene's placed objects: a plane through the origin facing +y and the given extra objects.
    fn placed(objects: &str) -> Vec<PlacedMesh> {
        let text = format!(
            "[material.m]\nbrdf = \"lambert\"\nkd = 0.5\n\n\
             [[object]]\nshape = \"plane\"\npoint = [0.0, 0.0, 0.0]\nnormal = [0.0, 1.0, 0.0]\nmaterial = \"m\"\n\n{objects}"
        );
        let scene = Scene::parse(&text, Path::new("test.toml"), &[]).unwrap();
        place_objects(&scene).unwrap()
    }

    fn sphere(center: Vec3, radius: f32) -> String {
        format!(
            "[[object]]\nshape = \"sphere\"\ncenter = [{}, {}, {}]\nradius = {radius}\nmaterial = \"m\"\n",
            center.x, center.y, center.z
        )
    }

    const LIGHT: Vec3 = Vec3::new(1.0, 4.0, 2.0);
    const ABOVE: Vec3 = Vec3::new(0.0, 1.0, -5.0);
    const BELOW: Vec3 = Vec3::new(0.0, -1.0, -5.0);

    #[test]
    fn a_plane_shadows_only_what_lies_beyond_it_where_the_camera_sees_it() {
        // Alone, the plane shadows nothing from any side.
        assert_eq!(occluders(LIGHT, ABOVE, &placed("")), [false]);
        assert_eq!(occluders(LIGHT, BELOW, &placed("")), [false]);
        // A sphere resting on it is not beyond it, wherever the camera is; the sphere itself may shadow.
        let resting = placed(&sphere(Vec3::new(0.0, 1.0, 3.0), 1.0));
        assert_eq!(occluders(LIGHT, BELOW, &resting), [false, true]);
        // A sphere dipping through it is, but only a camera beyond the plane sees that part.
        let dipping = placed(&sphere(Vec3::new(0.0, 0.9, 3.0), 1.0));
        assert_eq!(occluders(LIGHT, ABOVE, &dipping), [false, true]);
        assert_eq!(occluders(LIGHT, BELOW, &dipping), [true, true]);
        // A light below the plane: the sphere is beyond it from there, and the camera above is beyond too.
        assert_eq!(occluders(Vec3::new(0.0, -3.0, 0.0), ABOVE, &resting), [true, true]);
        // The bunny's 0.4 mm dip below Figure 5's plane counts as beyond it (vertex by vertex).
        let mesh = "[[object]]\nshape = \"mesh\"\npath = \"bunny\"\nscale = 1.1\ntranslate = [0.0, 1.09, 3.0]\nmaterial = \"m\"\n";
        if Path::new(crate::scene::BUNNY_PATH).exists() {
            assert_eq!(occluders(LIGHT, BELOW, &placed(mesh)), [true, true]);
        }
    }

    #[test]
    fn crossing_planes_reach_beyond_each_other() {
        let wall =
            "[[object]]\nshape = \"plane\"\npoint = [2.0, 0.0, 0.0]\nnormal = [-1.0, 0.0, 0.0]\nmaterial = \"m\"\n";
        let light = Vec3::new(0.0, 3.0, 0.0);
        // The camera on the light's side of both: neither plane's shadow can be seen.
        assert_eq!(occluders(light, Vec3::new(0.0, 1.0, -5.0), &placed(wall)), [false, false]);
        // Behind the wall (x > 2), the floor beyond it is in the wall's shadow.
        assert_eq!(occluders(light, Vec3::new(3.0, 1.0, -5.0), &placed(wall)), [false, true]);
        // A parallel plane above the floor, on the light's side of it: the floor hides nothing of it.
        let shelf =
            "[[object]]\nshape = \"plane\"\npoint = [0.0, 1.0, 0.0]\nnormal = [0.0, 1.0, 0.0]\nmaterial = \"m\"\n";
        assert_eq!(occluders(Vec3::new(0.0, 3.0, 0.0), BELOW, &placed(shelf)), [false, true]);
    }

    /// The faces a lookup in direction d may read: its major axis's and any within the shader's tie.
    fn faces_read(d: Vec3) -> Vec<usize> {
        let a = d.abs();
        let least = a.max_element() * (1.0 - 1e-3);
        (0..3).filter(|&axis| a[axis] >= least).map(|axis| 2 * axis + usize::from(d[axis] < 0.0)).collect()
    }

    #[test]
    fn every_point_of_an_occluder_falls_on_a_face_kept() {
        let mut state = 99u32;
        let mut random = move || {
            state = state.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            (state >> 8) as f32 / (1u32 << 24) as f32 * 2.0 - 1.0
        };
        let mut culled = 0;
        for _ in 0..200 {
            let centre = Vec3::new(random(), 1.5 + random(), random()) * 4.0;
            let radius = 0.2 + 0.8 * random().abs();
            let placed = placed(&sphere(centre, radius));
            let light = Vec3::new(random(), 4.0 + random(), random()) * 3.0;
            let kept = faces_with_occluders(light, &placed, &[false, true], 2e-3);
            culled += kept.iter().filter(|&&k| !k).count();
            for _ in 0..500 {
                let on_sphere = centre + radius * Vec3::new(random(), random(), random()).normalize();
                for face in faces_read(on_sphere - light) {
                    assert!(kept[face], "light {light}, sphere {centre} r {radius}: face {face} dropped, {kept:?}");
                }
            }
        }
        assert!(culled > 500, "only {culled} faces culled in 200 cubes");
        // A plane among the occluders falls on every face.
        assert_eq!(faces_with_occluders(LIGHT, &placed(""), &[true], 2e-3), [true; 6]);
    }
}
