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

use super::passes::{begin_rendering, vertex_input, PassTargets};
use crate::error::Result;
use crate::vulkan::{Device, GraphicsPipelineDesc, Pipeline, PipelineLayout, ShaderCompiler};

/// Distance from the light, in 32-bit float.
pub const DISTANCE_FORMAT: vk::Format = vk::Format::R32_SFLOAT;
/// What a texel that sees nothing holds (the attachment's clear value; shadow.frag's FAR_AWAY).
pub const FAR_AWAY: f32 = 3.0e38;

/// The shadow pass's pipeline, made once per renderer.
pub struct ShadowPass {
    pub pipeline: Pipeline,
}

impl ShadowPass {
    /// Compiles the shadow shaders and builds the pipeline.
    ///
    /// # Errors
    /// `Error::Shader` or `Error::Vulkan`.
    pub fn new(device: &Arc<Device>, compiler: &ShaderCompiler, layout: &Arc<PipelineLayout>) -> Result<Self> {
        let vertex = device.create_shader_module(&compiler.compile("shadow.vert")?, "shadow.vert")?;
        let fragment = device.create_shader_module(&compiler.compile("shadow.frag")?, "shadow.frag")?;
        let (bindings, attributes) = vertex_input();
        let desc = GraphicsPipelineDesc {
            vertex: &vertex,
            fragment: &fragment,
            vertex_bindings: &bindings,
            vertex_attributes: &attributes,
            color_formats: &[DISTANCE_FORMAT],
            depth_format: super::forward::DEPTH_FORMAT,
            depth_compare: vk::CompareOp::GREATER_OR_EQUAL,
            samples: vk::SampleCountFlags::TYPE_1,
            layout,
        };
        Ok(Self { pipeline: device.create_graphics_pipeline(&desc, "shadow")? })
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
    begin_rendering(device, cmd, targets, color);
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
