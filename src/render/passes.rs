//! What the shadow and forward passes share: the vertex layout, the attachments of a pass, the drawing of
//! every object, and layout transitions.

use std::collections::HashMap;
use std::sync::Arc;

use ash::vk;

use crate::error::{Error, Result};
use crate::mesh::{Mesh, PlacedMesh, Vertex};
use crate::vulkan::{layout_transition, Access, Buffer, Device, Image};

/// The vertex buffer layout: a homogeneous position and a normal.
pub fn vertex_input() -> ([vk::VertexInputBindingDescription; 1], [vk::VertexInputAttributeDescription; 2]) {
    let bindings = [vk::VertexInputBindingDescription {
        binding: 0,
        stride: std::mem::size_of::<Vertex>() as u32,
        input_rate: vk::VertexInputRate::VERTEX,
    }];
    let attributes = [
        vk::VertexInputAttributeDescription {
            location: 0,
            binding: 0,
            format: vk::Format::R32G32B32A32_SFLOAT,
            offset: std::mem::offset_of!(Vertex, position) as u32,
        },
        vk::VertexInputAttributeDescription {
            location: 1,
            binding: 0,
            format: vk::Format::R32G32B32_SFLOAT,
            offset: std::mem::offset_of!(Vertex, normal) as u32,
        },
    ];
    (bindings, attributes)
}

/// The attachments of one pass.
pub struct PassTargets {
    pub color: vk::ImageView,
    /// The single-sample image a multisampled colour target resolves to.
    pub resolve: Option<vk::ImageView>,
    pub depth: vk::ImageView,
    pub width: u32,
    pub height: u32,
}

impl PassTargets {
    /// The whole target.
    pub fn area(&self) -> vk::Rect2D {
        vk::Rect2D { offset: vk::Offset2D::default(), extent: vk::Extent2D { width: self.width, height: self.height } }
    }
}

/// A mesh's vertex and index buffers on the device.
pub struct GpuMesh {
    vertices: Buffer,
    indices: Buffer,
    index_count: u32,
}

/// Meshes are shared between objects (every sphere uses the one unit sphere): key them by address.
fn mesh_key(mesh: &Arc<Mesh>) -> usize {
    Arc::as_ptr(mesh) as usize
}

/// Uploads each distinct mesh once.
///
/// # Errors
/// `Error::Vulkan` or `Error::Allocation`.
pub fn upload_meshes(device: &Arc<Device>, placed: &[PlacedMesh]) -> Result<HashMap<usize, GpuMesh>> {
    let mut meshes = HashMap::new();
    for p in placed {
        if meshes.contains_key(&mesh_key(&p.mesh)) {
            continue;
        }
        let vertices =
            device.create_buffer_with_data(&p.mesh.vertices, vk::BufferUsageFlags::VERTEX_BUFFER, "vertices")?;
        let indices = device.create_buffer_with_data(&p.mesh.indices, vk::BufferUsageFlags::INDEX_BUFFER, "indices")?;
        let index_count =
            u32::try_from(p.mesh.indices.len()).map_err(|_| Error::Vulkan(vk::Result::ERROR_OUT_OF_DEVICE_MEMORY))?;
        meshes.insert(mesh_key(&p.mesh), GpuMesh { vertices, indices, index_count });
    }
    Ok(meshes)
}

/// Sets the viewport and scissor to the target and draws every object, telling the shaders which object
/// each draw is and, for the shadow pass, which light and cube face (`shadow_face`).
pub fn draw_objects(
    device: &Device,
    cmd: vk::CommandBuffer,
    layout: vk::PipelineLayout,
    targets: &PassTargets,
    placed: &[PlacedMesh],
    meshes: &HashMap<usize, GpuMesh>,
    shadow_face: (u32, u32),
) {
    let viewport = vk::Viewport {
        x: 0.0,
        y: 0.0,
        width: targets.width as f32,
        height: targets.height as f32,
        min_depth: 0.0,
        max_depth: 1.0,
    };
    // SAFETY: the command buffer is recording inside a render pass; the buffers outlive the submission.
    unsafe {
        device.raw.cmd_set_viewport(cmd, 0, &[viewport]);
        device.raw.cmd_set_scissor(cmd, 0, &[targets.area()]);
        for (index, p) in placed.iter().enumerate() {
            let mesh = &meshes[&mesh_key(&p.mesh)];
            device.raw.cmd_bind_vertex_buffers(cmd, 0, &[mesh.vertices.raw], &[0]);
            device.raw.cmd_bind_index_buffer(cmd, mesh.indices.raw, 0, vk::IndexType::UINT32);
            let push = [index as u32, shadow_face.0, shadow_face.1];
            let bytes: Vec<u8> = push.iter().flat_map(|v| v.to_ne_bytes()).collect();
            device.raw.cmd_push_constants(
                cmd,
                layout,
                vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT,
                0,
                &bytes,
            );
            device.raw.cmd_draw_indexed(cmd, mesh.index_count, 1, 0, 0, 0);
        }
    }
}

/// A layout transition of every layer of an image, with its source and destination (stage, access).
pub fn image_barrier(
    image: &Image,
    old: vk::ImageLayout,
    new: vk::ImageLayout,
    src: Access,
    dst: Access,
) -> vk::ImageMemoryBarrier2<'static> {
    layout_transition(image.raw, image.full_range(), old, new, src, dst)
}

/// Records image barriers.
pub fn barriers(device: &Device, cmd: vk::CommandBuffer, barriers: &[vk::ImageMemoryBarrier2]) {
    // SAFETY: the command buffer is recording; the images outlive the submission.
    unsafe { device.raw.cmd_pipeline_barrier2(cmd, &vk::DependencyInfo::default().image_memory_barriers(barriers)) };
}

/// Begins dynamic rendering into `color` and the targets' depth image, cleared to 0 (the far end in
/// reverse-Z) and not stored.
pub fn begin_rendering(
    device: &Device,
    cmd: vk::CommandBuffer,
    targets: &PassTargets,
    color: vk::RenderingAttachmentInfo,
) {
    let colors = [color];
    let depth = vk::RenderingAttachmentInfo::default()
        .image_view(targets.depth)
        .image_layout(vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL)
        .load_op(vk::AttachmentLoadOp::CLEAR)
        .store_op(vk::AttachmentStoreOp::DONT_CARE)
        .clear_value(vk::ClearValue { depth_stencil: vk::ClearDepthStencilValue { depth: 0.0, stencil: 0 } });
    let rendering = vk::RenderingInfo::default()
        .render_area(targets.area())
        .layer_count(1)
        .color_attachments(&colors)
        .depth_attachment(&depth);
    // SAFETY: the command buffer is recording; the views outlive the submission.
    unsafe { device.raw.cmd_begin_rendering(cmd, &rendering) };
}
