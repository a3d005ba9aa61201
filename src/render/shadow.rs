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

use super::forward::DEPTH_FORMAT;
use super::passes::{begin_rendering, build_pipeline, CompiledShader, PassTargets};
use crate::error::Result;
use crate::mesh::PlacedMesh;
use crate::scene::Scene;
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
        let build = |fragment| {
            let fragment = CompiledShader::new(compiler, fragment)?;
            build_pipeline(device, layout, (&vertex, &fragment), (DISTANCE_FORMAT, vk::SampleCountFlags::TYPE_1), &[])
        };
        Ok(Self { meshes: build("shadow.frag")?, spheres: build("shadow_sphere.frag")? })
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
/// none does) and the depth image every face is drawn with in turn. They are drawn again only when what
/// they show changes (see [`ShadowKey`]), so that a sweep over a material or a camera orbiting in the
/// preview reuse them.
pub struct ShadowCubes {
    pub maps: Image,
    pub depth: Image,
    /// One view per face of each cube, in the order the faces are drawn.
    pub face_views: Vec<ImageView>,
    /// What the cubes hold, once drawn and ready to be read; `None` until then.
    drawn: Option<ShadowKey>,
}

/// What shadow cubes show: the map size, the positions of the lights that cast shadows (in cube order),
/// and every object's mesh (by identity), placement and kind.
pub struct ShadowKey {
    size: u32,
    lights: Vec<Vec3>,
    geometry: Vec<PlacedMesh>,
}

impl PartialEq for ShadowKey {
    fn eq(&self, other: &Self) -> bool {
        let same_object = |(a, b): (&PlacedMesh, &PlacedMesh)| {
            Arc::ptr_eq(&a.mesh, &b.mesh) && a.model == b.model && a.exact_sphere == b.exact_sphere
        };
        self.size == other.size
            && self.lights == other.lights
            && self.geometry.len() == other.geometry.len()
            && self.geometry.iter().zip(&other.geometry).all(same_object)
    }
}

impl ShadowKey {
    /// What the cubes of `scene` show, `casters` being its lights that cast shadows.
    pub fn new(scene: &Scene, placed: &[PlacedMesh], casters: &[usize]) -> Self {
        Self {
            size: scene.image.shadow_map_size,
            lights: casters.iter().map(|&i| scene.lights[i].position).collect(),
            // The geometry only matters to the cubes when there are any to draw.
            geometry: if casters.is_empty() { Vec::new() } else { placed.to_vec() },
        }
    }

    /// The size of the cubes: the scene's, or 1 when no light casts shadows.
    fn cube_size(&self) -> u32 {
        if self.lights.is_empty() {
            1
        } else {
            self.size
        }
    }
}

impl ShadowCubes {
    /// Cubes for `key`: `kept` when they are of its size and count (drawn again if they show something
    /// else), new ones otherwise.
    ///
    /// # Errors
    /// `Error::Vulkan` or `Error::Allocation`.
    pub fn for_key(device: &Arc<Device>, kept: Option<Self>, key: &ShadowKey) -> Result<Self> {
        let size = key.cube_size();
        let cubes = key.lights.len() as u32;
        if let Some(kept) = kept {
            if kept.depth.desc.width == size && kept.maps.desc.layers == 6 * cubes.max(1) {
                return Ok(kept);
            }
        }
        let maps = device.create_image(
            ImageDesc {
                width: size,
                height: size,
                layers: 6 * cubes.max(1),
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
        let face_views = (0..6 * cubes).map(|layer| maps.layer_view(layer, 1)).collect::<Result<Vec<_>>>()?;
        Ok(Self { maps, depth, face_views, drawn: None })
    }

    /// Whether the cubes already show `key`.
    pub fn show(&self, key: &ShadowKey) -> bool {
        self.drawn.as_ref() == Some(key)
    }

    /// Records that the cubes were drawn for `key` (`Some`, once the drawing finished) or that what they hold
    /// is unknown (`None`: before drawing, or after the shaders changed).
    pub fn set_drawn(&mut self, key: Option<ShadowKey>) {
        self.drawn = key;
    }
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
    begin_rendering(device, cmd, targets, color, vk::AttachmentLoadOp::CLEAR);
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
}
