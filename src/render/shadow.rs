//! The shadow pass: for each point light that casts shadows, the distance to the nearest surface in every
//! direction, stored in one cube of a cube array and read by the forward pass.
//!
//! The six faces are six passes, the vertex shader picking the face's matrix by a push constant. One pass
//! with multiview (a view per face) would record the objects once per light, but lavapipe (Mesa 22.3)
//! writes every view of a dynamic-rendering multiview pass to the first layer, which showed as a face of
//! the cube holding another face's distances; a geometry shader fanning out to six layers is slow on most
//! GPUs and on lavapipe.

use std::sync::Arc;

use ash::vk;
use glam::{Mat4, Vec3};

use super::gpu_types::PixelRays;
use super::passes::DEPTH_FORMAT;
use super::passes::{begin_rendering, build_pipeline, CompiledShader, DepthStart, PassTargets};
use crate::error::Result;
use crate::mesh::PlacedMesh;
use crate::scene::{Camera, Scene, ShadowFilter};
use crate::vulkan::{Device, Image, ImageDesc, ImageView, Pipeline, PipelineLayout, ShaderCompiler};

/// Distance from the light, in 32-bit float.
pub const DISTANCE_FORMAT: vk::Format = vk::Format::R32_SFLOAT;
/// What a texel that sees nothing holds (the attachment's clear value; shadow.frag's FAR_AWAY).
pub const FAR_AWAY: f32 = 3.0e38;

/// The shadow pass's pipelines, made once per renderer.
pub struct ShadowPass {
    meshes: Pipeline,
    spheres: Pipeline,
}

impl ShadowPass {
    /// Compiles the shadow shaders and builds the pipelines.
    ///
    /// # Errors
    /// `Error::Shader` or `Error::Vulkan`.
    pub fn new(device: &Arc<Device>, compiler: &ShaderCompiler, layout: &Arc<PipelineLayout>) -> Result<Self> {
        let vertex = CompiledShader::new(compiler, "shadow.vert")?;
        let fragments =
            [CompiledShader::new(compiler, "shadow.frag")?, CompiledShader::new(compiler, "shadow_sphere.frag")?];
        let build = |fragment| {
            build_pipeline(device, layout, (&vertex, fragment), (DISTANCE_FORMAT, vk::SampleCountFlags::TYPE_1), &[])
        };
        Ok(Self { meshes: build(&fragments[0])?, spheres: build(&fragments[1])? })
    }

    /// The pipeline that draws `placed`.
    pub fn pipeline(&self, placed: &PlacedMesh) -> vk::Pipeline {
        if placed.exact_sphere {
            self.spheres.raw
        } else {
            self.meshes.raw
        }
    }
}

/// Kept per lighting: the shadow cubes (one per light that casts shadows, a single unused 1-texel cube when
/// none does) and the depth image every face is drawn with in turn. A face is drawn only when the camera
/// can see a point it holds the distance of ([`faces_seen`]) and an object that can shadow it falls on it
/// (`occluders.rs`), with those objects alone, and drawn again only when what it shows
/// changed (see [`FaceKey`]): a sweep over a material reuses every face, a camera orbiting in the preview
/// draws a face once, when it first comes into view.
pub struct ShadowCubes {
    pub maps: Image,
    pub depth: Image,
    /// One view per face of each cube, in the order of the array's layers.
    pub face_views: Vec<ImageView>,
    /// What each layer holds, once drawn and ready to be read; `None` before, or after the shaders changed.
    drawn: Vec<Option<FaceKey>>,
    /// Whether every layer is in the layout the forward pass reads, which the first image sets.
    laid_out: bool,
}

/// What one face of a shadow cube shows: the map size, the light's position, every object's mesh (by
/// identity), placement and kind, and which objects are drawn into it (`occluders.rs`: which depends on the
/// camera too, so a camera crossing a plane can change it with nothing else).
#[derive(Clone)]
pub struct FaceKey {
    size: u32,
    light: Vec3,
    geometry: Arc<[PlacedMesh]>,
    pub occluders: Vec<bool>,
}

impl PartialEq for FaceKey {
    fn eq(&self, other: &Self) -> bool {
        // Whether an object casts shadows is in `occluders`.
        let same_object = |(a, b): (&PlacedMesh, &PlacedMesh)| {
            Arc::ptr_eq(&a.mesh, &b.mesh) && a.model == b.model && a.exact_sphere == b.exact_sphere
        };
        self.size == other.size
            && self.light == other.light
            && self.occluders == other.occluders
            && self.geometry.len() == other.geometry.len()
            && self.geometry.iter().zip(other.geometry.iter()).all(same_object)
    }
}

impl FaceKey {
    pub fn new(size: u32, light: Vec3, geometry: Arc<[PlacedMesh]>, occluders: Vec<bool>) -> Self {
        Self { size, light, geometry, occluders }
    }
}

impl ShadowCubes {
    /// `cubes` cubes of `size` texels (at least one, of one texel, when no light casts shadows): `kept`
    /// when it has that size and count, new ones otherwise.
    ///
    /// # Errors
    /// `Error::Vulkan` or `Error::Allocation`.
    pub fn for_lights(device: &Arc<Device>, kept: Option<Self>, size: u32, cubes: usize) -> Result<Self> {
        let (size, layers) = if cubes == 0 { (1, 6) } else { (size, 6 * cubes as u32) };
        if let Some(kept) = kept.filter(|k| k.depth.desc.width == size && k.maps.desc.layers == layers) {
            return Ok(kept);
        }
        let maps = device.create_image(
            ImageDesc {
                width: size,
                height: size,
                layers,
                cube: true,
                format: DISTANCE_FORMAT,
                samples: vk::SampleCountFlags::TYPE_1,
                usage: vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::SAMPLED,
                aspect: vk::ImageAspectFlags::COLOR,
            },
            "shadow cubes",
        )?;
        let depth = device.create_image(
            ImageDesc::plain(
                size,
                size,
                DEPTH_FORMAT,
                vk::SampleCountFlags::TYPE_1,
                vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT,
                vk::ImageAspectFlags::DEPTH,
            ),
            "shadow depth",
        )?;
        let face_views = (0..layers).map(|layer| maps.layer_view(layer, 1)).collect::<Result<Vec<_>>>()?;
        Ok(Self { maps, depth, face_views, drawn: vec![None; layers as usize], laid_out: false })
    }

    /// Whether `layer` already shows `key`.
    pub fn holds(&self, layer: u32, key: &FaceKey) -> bool {
        self.drawn[layer as usize].as_ref() == Some(key)
    }

    /// Whether the layers still need their first layout transition.
    pub fn need_layout(&self) -> bool {
        !self.laid_out
    }

    /// Records what the faces just drawn hold (`Some`, once the drawing finished), or forgets them all (the
    /// drawing failed, or the shaders changed).
    pub fn set_drawn(&mut self, drawn: Option<&[(u32, FaceKey)]>) {
        match drawn {
            Some(faces) => {
                for (layer, key) in faces {
                    self.drawn[*layer as usize] = Some(key.clone());
                }
                self.laid_out = true;
            }
            None => self.drawn.iter_mut().for_each(|face| *face = None),
        }
    }
}

/// The faces of the cube of `light` that the image of `scene` may read: [`faces_seen`] with the margin its
/// lookups need. The shader counts a lookup within 1e-3 of a face's edge as one that may read the next face
/// (shading.glsl's SEEN_FACES_TIE, where rounding may pick either): twice that covers it. PCF also looks up
/// to 1.75 texels beside the point's own direction (4 texels cover it).
pub fn faces_read_by(scene: &Scene, light: Vec3) -> [bool; 6] {
    faces_seen(&scene.camera, scene.image.width, scene.image.height, light, lookup_margin(scene))
}

/// How far beyond a face's edge, in units of its half-width, a lookup of `scene`'s image for a point in it
/// may read ([`faces_read_by`]).
pub fn lookup_margin(scene: &Scene) -> f64 {
    let tie = 2e-3;
    match scene.image.shadow_filter {
        ShadowFilter::Hard => tie,
        ShadowFilter::Pcf => tie + 8.0 / f64::from(scene.image.shadow_map_size),
    }
}

/// Which faces of a cube centred on `light` hold the distance of a point the camera can see: those whose
/// pyramid (widened by `margin`, in units of the face's half-width, for lookups beside the point's own
/// direction) meets the camera's view frustum, taken out to where the forward pass stops shading (1e7
/// units from the origin; shaders/common/scene.glsl's world_point). A face no visible point needs is never
/// read, so it is not drawn: Figure 1's light, behind the camera, needs only its +z face.
pub fn faces_seen(camera: &Camera, width: u32, height: u32, light: Vec3, margin: f64) -> [bool; 6] {
    use glam::DVec3;
    let rays = PixelRays::new(camera, width, height);
    let eye = camera.position.as_dvec3();
    let (w, h) = (f64::from(width), f64::from(height));
    let corner =
        |x: f64, y: f64| (rays.corner.as_dvec3() + x * rays.per_x.as_dvec3() + y * rays.per_y.as_dvec3()).normalize();
    let corners = [corner(0.0, 0.0), corner(w, 0.0), corner(w, h), corner(0.0, h)];
    let forward = (camera.look_at - camera.position).as_dvec3().normalize();
    // The frustum as half-spaces n . x >= d: four sides through the eye, and the far end, past which no
    // point is shaded. (The near plane only removes points, so leaving it out keeps the test conservative.)
    let far = 2.0e7 + 2.0 * eye.length();
    let centre = (corners[0] + corners[2]) * 0.5;
    let mut planes: Vec<(DVec3, f64)> = (0..4)
        .map(|i| {
            let n = corners[i].cross(corners[(i + 1) % 4]);
            let n = if n.dot(centre) < 0.0 { -n } else { n };
            (n, n.dot(eye))
        })
        .collect();
    planes.push((-forward, -forward.dot(eye) - far));
    let light = light.as_dvec3();
    std::array::from_fn(|face| {
        // Face `face` (+x, -x, +y, -y, +z, -z) holds directions d with s * d[axis] >= |d[other]| / (1 + margin).
        let (axis, sign) = (face / 2, if face % 2 == 0 { 1.0 } else { -1.0 });
        let mut all = planes.clone();
        for other in (0..3).filter(|&a| a != axis) {
            for other_sign in [1.0, -1.0] {
                let mut n = DVec3::ZERO;
                n[axis] = sign * (1.0 + margin);
                n[other] = other_sign;
                all.push((n, n.dot(light)));
            }
        }
        half_spaces_meet(&all)
    })
}

/// Whether the half-spaces n . x >= d meet in a bounded region: it has a vertex, where three of the planes
/// cross and every half-space holds (with a tolerance, so that a region thin as a plane still counts).
fn half_spaces_meet(planes: &[(glam::DVec3, f64)]) -> bool {
    let n = planes.len();
    let scale = planes.iter().map(|(_, d)| d.abs()).fold(1.0, f64::max);
    for i in 0..n {
        for j in i + 1..n {
            for k in j + 1..n {
                let m = glam::DMat3::from_cols(planes[i].0, planes[j].0, planes[k].0).transpose();
                if m.determinant().abs() < 1e-12 {
                    continue;
                }
                let x = m.inverse() * glam::DVec3::new(planes[i].1, planes[j].1, planes[k].1);
                if planes.iter().all(|(normal, d)| normal.dot(x) >= d - 1e-9 * scale * normal.length()) {
                    return true;
                }
            }
        }
    }
    false
}

/// The view-projections of the six faces of a cube centred on `light`, in Vulkan's face order.
///
/// Vulkan picks a cube face by the major axis of the lookup direction and maps the two others to (s, t)
/// with t growing down the face's rows (e.g. +x: s = -z, t = -y). A y-up projection (glam's "directx" one:
/// depth in [0, 1], no y flip) puts +y_view at the bottom rows, so each face's up vector is the world
/// direction that t decreases along: -y for the four side faces, +z for +y and -z for -y.
pub fn cube_face_views(light: Vec3, near: f32) -> [Mat4; 6] {
    let projection =
        glam::camera::rh::proj::directx::perspective_infinite_reverse(std::f32::consts::FRAC_PI_2, 1.0, near);
    let faces = [
        (Vec3::X, Vec3::NEG_Y),
        (Vec3::NEG_X, Vec3::NEG_Y),
        (Vec3::Y, Vec3::Z),
        (Vec3::NEG_Y, Vec3::NEG_Z),
        (Vec3::Z, Vec3::NEG_Y),
        (Vec3::NEG_Z, Vec3::NEG_Y),
    ];
    faces.map(|(forward, up)| projection * glam::camera::rh::view::look_at_mat4(light, light + forward, up))
}

/// Begins rendering one face of a cube: `targets.color` is a view of the face's layer; both it and the
/// depth target are cleared.
pub fn begin(device: &Device, cmd: vk::CommandBuffer, targets: &PassTargets) {
    let color = vk::RenderingAttachmentInfo::default()
        .image_view(targets.color)
        .image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
        .load_op(vk::AttachmentLoadOp::CLEAR)
        .store_op(vk::AttachmentStoreOp::STORE)
        .clear_value(vk::ClearValue { color: vk::ClearColorValue { float32: [FAR_AWAY, 0.0, 0.0, 0.0] } });
    begin_rendering(device, cmd, targets, color, DepthStart::Cleared(0.0), false);
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Vulkan's cube face selection and (s, t) for a direction (the specification's table).
    fn vulkan_face_st(d: Vec3) -> (usize, f32, f32) {
        let a = d.abs();
        let (face, sc, tc, ma) = if a.x >= a.y && a.x >= a.z {
            if d.x > 0.0 {
                (0, -d.z, -d.y, a.x)
            } else {
                (1, d.z, -d.y, a.x)
            }
        } else if a.y >= a.z {
            if d.y > 0.0 {
                (2, d.x, d.z, a.y)
            } else {
                (3, d.x, -d.z, a.y)
            }
        } else if d.z > 0.0 {
            (4, d.x, -d.y, a.z)
        } else {
            (5, -d.x, -d.y, a.z)
        };
        (face, 0.5 * (sc / ma + 1.0), 0.5 * (tc / ma + 1.0))
    }

    #[test]
    fn each_face_renders_where_the_cube_lookup_reads() {
        // A point drawn by face f lands at framebuffer (x, y) = (s, t) of the lookup from the light.
        let light = Vec3::new(0.5, -1.0, 2.0);
        let views = cube_face_views(light, 1e-3);
        for d in [
            Vec3::new(1.0, 0.3, -0.2),
            Vec3::new(-1.0, -0.4, 0.1),
            Vec3::new(0.2, 1.0, 0.5),
            Vec3::new(-0.3, -1.0, 0.6),
            Vec3::new(0.4, -0.2, 1.0),
            Vec3::new(-0.1, 0.5, -1.0),
        ] {
            let (face, s, t) = vulkan_face_st(d);
            let clip = views[face] * (light + d * 3.0).extend(1.0);
            let ndc = clip.truncate() / clip.w;
            // Viewport: x = (ndc.x + 1) / 2, y = (ndc.y + 1) / 2 with row 0 at ndc.y = -1.
            let (x, y) = (0.5 * (ndc.x + 1.0), 0.5 * (ndc.y + 1.0));
            assert!(
                (x - s).abs() < 1e-5 && (y - t).abs() < 1e-5,
                "direction {d}: face {face} drew ({x}, {y}), lookup reads ({s}, {t})"
            );
            assert!(ndc.z > 0.0 && ndc.z <= 1.0, "depth {}", ndc.z);
        }
    }

    fn camera(position: Vec3, look_at: Vec3) -> Camera {
        Camera { position, look_at, up: Vec3::Y, fov_y: 60.0 }
    }

    #[test]
    fn a_light_behind_the_camera_needs_only_the_face_ahead() {
        // Figure 1: the camera at the origin looking down +z, the light 2 units behind it.
        let seen = faces_seen(&camera(Vec3::ZERO, Vec3::Z), 600, 400, Vec3::new(0.0, 0.0, -2.0), 1e-4);
        assert_eq!(seen, [false, false, false, false, true, false]);
        // Above the scene, looking down at it, the light sees the view through its -y face and beside it.
        let seen = faces_seen(&camera(Vec3::ZERO, Vec3::Z), 600, 400, Vec3::new(0.0, 5.0, 3.0), 1e-4);
        assert!(seen[3] && seen[4] && !seen[2], "{seen:?}");
    }

    #[test]
    fn every_point_the_camera_sees_is_on_a_face_marked_seen() {
        // Points in the view frustum, from near to very far, each looked up from lights around the scene:
        // the face the lookup reads (Vulkan's selection) must be one faces_seen keeps.
        let cam = camera(Vec3::new(0.5, 1.0, -1.0), Vec3::new(0.0, 0.0, 3.0));
        let rays = PixelRays::new(&cam, 640, 360);
        let mut state = 12345u32;
        let mut random = move || {
            state = state.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            (state >> 8) as f32 / (1u32 << 24) as f32
        };
        let mut culled = 0;
        for light in
            [Vec3::new(0.0, 0.0, -2.0), Vec3::new(3.0, 3.0, 1.5), Vec3::new(0.2, 0.9, 0.0), Vec3::new(0.0, 0.0, 40.0)]
        {
            let seen = faces_seen(&cam, 640, 360, light, 1e-4);
            culled += seen.iter().filter(|&&s| !s).count();
            for _ in 0..20_000 {
                let d = rays.at(random() * 640.0, random() * 360.0);
                let t = 1e-3 + 10f32.powf(random() * 7.0);
                let (face, _, _) = vulkan_face_st(cam.position + t * d - light);
                assert!(
                    seen[face],
                    "light {light}: a point at distance {t} reads face {face}, marked unseen: {seen:?}"
                );
            }
        }
        assert!(culled >= 4, "only {culled} faces culled");
    }
}
