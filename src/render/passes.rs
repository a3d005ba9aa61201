//! What the shadow and forward passes share: the vertex layout, the attachments of a pass, the drawing of
//! every object, and layout transitions.

use std::collections::HashMap;
use std::sync::Arc;

use ash::vk;
use glam::{Mat4, Vec3};

use crate::error::{Error, Result};
use crate::mesh::{Mesh, PlacedMesh, Vertex};
use crate::vulkan::{
    layout_transition, Access, Buffer, Device, GraphicsPipelineDesc, Image, Pipeline, PipelineLayout, ShaderCompiler,
};

/// The depth format of every pass that tests depth (shadow, forward, the resolve's copy of it).
pub const DEPTH_FORMAT: vk::Format = vk::Format::D32_SFLOAT;

/// The vertex buffer layout: a homogeneous position, a normal and a tangent.
pub fn vertex_input() -> ([vk::VertexInputBindingDescription; 1], [vk::VertexInputAttributeDescription; 3]) {
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
        vk::VertexInputAttributeDescription {
            location: 2,
            binding: 0,
            format: vk::Format::R32G32B32_SFLOAT,
            offset: std::mem::offset_of!(Vertex, tangent) as u32,
        },
    ];
    (bindings, attributes)
}

/// A pass's pipeline from compiled SPIR-V: the vertex layout of [`vertex_input`], one colour target of
/// `color_format` with `samples`, the fragment shader's specialization constants, and reverse-Z depth (nearer is greater; equal passes, so that the plane's horizon, at
/// depth 0, is drawn).
///
/// # Errors
/// `Error::Vulkan` if the driver refuses a module or the pipeline.
pub fn build_pipeline(
    device: &Arc<Device>,
    layout: &Arc<PipelineLayout>,
    (vertex, fragment): (&CompiledShader, &CompiledShader),
    (color_format, samples): (vk::Format, vk::SampleCountFlags),
    fragment_constants: &[u32],
) -> Result<Pipeline> {
    let vertex_module = device.create_shader_module(&vertex.spirv, &vertex.name)?;
    let fragment_module = device.create_shader_module(&fragment.spirv, &fragment.name)?;
    let (bindings, attributes) = vertex_input();
    let desc = GraphicsPipelineDesc {
        vertex: &vertex_module,
        fragment: &fragment_module,
        vertex_bindings: &bindings,
        vertex_attributes: &attributes,
        color_formats: &[color_format],
        depth_format: DEPTH_FORMAT,
        depth_compare: vk::CompareOp::GREATER_OR_EQUAL,
        samples,
        layout,
        fragment_constants,
    };
    device.create_graphics_pipeline(&desc, &format!("{} x{} {fragment_constants:?}", fragment.name, samples.as_raw()))
}

/// One shader's SPIR-V and its file's name.
pub struct CompiledShader {
    pub name: String,
    pub spirv: Vec<u32>,
}

impl CompiledShader {
    /// Compiles `name` of shaders/.
    ///
    /// # Errors
    /// `Error::Shader` naming the file and line.
    pub fn new(compiler: &ShaderCompiler, name: impl Into<String>) -> Result<Self> {
        let name = name.into();
        Ok(Self { spirv: compiler.compile(&name)?, name })
    }
}

/// The attachments of one pass.
pub struct PassTargets {
    pub color: vk::ImageView,
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

/// A mesh's vertex and index buffers on the device, and what decides whether its back faces are culled.
struct GpuMesh {
    vertices: Buffer,
    indices: Buffer,
    index_count: u32,
    /// See [`Mesh::is_closed_outward`].
    closed_outward: bool,
    /// The mesh's bounding box, in its own space.
    bounds: (Vec3, Vec3),
}

impl GpuMesh {
    /// Whether the back faces of this mesh placed by `model` can be culled as seen from `viewpoint`: the
    /// mesh is closed and wound outwards, the placement keeps the winding, and the viewpoint is outside its
    /// bounding box, hence outside the mesh, so that every back face lies behind a front face. Back faces
    /// cost a CPU rasterizer as much as front faces: culling them took the bunny's frame from 64 to 37 ms.
    fn hides_back_faces(&self, model: Mat4, viewpoint: Vec3) -> bool {
        let local = model.inverse().transform_point3(viewpoint);
        let (min, max) = self.bounds;
        let inside = local.cmpge(min).all() && local.cmple(max).all();
        self.closed_outward && model.determinant() > 0.0 && !inside
    }
}

/// Kept per scene geometry: each distinct mesh uploaded once and kept while renders draw it. Each entry
/// holds its mesh, so the address that keys it cannot be reused by another mesh while it is kept.
#[derive(Default)]
pub struct MeshUploads {
    meshes: HashMap<usize, (Arc<Mesh>, GpuMesh)>,
}

/// Meshes are shared between objects (every sphere uses the one bounding sphere): key them by address.
fn mesh_key(mesh: &Arc<Mesh>) -> usize {
    Arc::as_ptr(mesh) as usize
}

impl MeshUploads {
    /// Uploads the meshes of `placed` not yet on the device and lets go of those no longer placed.
    ///
    /// # Errors
    /// `Error::Vulkan` or `Error::Allocation`.
    pub fn update(&mut self, device: &Arc<Device>, placed: &[PlacedMesh]) -> Result<()> {
        self.meshes.retain(|key, _| placed.iter().any(|p| mesh_key(&p.mesh) == *key));
        for p in placed {
            if self.meshes.contains_key(&mesh_key(&p.mesh)) {
                continue;
            }
            let mesh = &p.mesh;
            let vertices =
                device.create_buffer_with_data(&mesh.vertices, vk::BufferUsageFlags::VERTEX_BUFFER, "vertices")?;
            let indices =
                device.create_buffer_with_data(&mesh.indices, vk::BufferUsageFlags::INDEX_BUFFER, "indices")?;
            let index_count =
                u32::try_from(mesh.indices.len()).map_err(|_| Error::Vulkan(vk::Result::ERROR_OUT_OF_DEVICE_MEMORY))?;
            let gpu_mesh = GpuMesh {
                vertices,
                indices,
                index_count,
                closed_outward: mesh.is_closed_outward(),
                bounds: mesh.bounds(),
            };
            self.meshes.insert(mesh_key(mesh), (mesh.clone(), gpu_mesh));
        }
        Ok(())
    }

    fn get(&self, mesh: &Arc<Mesh>) -> &GpuMesh {
        &self.meshes[&mesh_key(mesh)].1
    }
}

/// Where a pass looks from: its viewpoint (the camera, or a light) and view-projection.
#[derive(Clone, Copy)]
pub struct PassView {
    pub viewpoint: Vec3,
    pub view_projection: Mat4,
}

impl PassView {
    /// The winding, in this pass's framebuffer, of a triangle that faces the viewpoint: the front face that
    /// makes back faces those turned away from it. Found by projecting such a triangle and taking the sign
    /// of its area as Vulkan's rasterizer does (a = -1/2 sum of x_i y_i+1 - x_i+1 y_i, positive for
    /// counter-clockwise), so that a projection that flips y (the camera's) or not (the shadow cubes') gets
    /// the right one.
    pub fn front_face(&self) -> vk::FrontFace {
        // A point straight ahead: the middle of the image at depth 0.5 (twice the near distance).
        let ahead = self.view_projection.inverse().project_point3(Vec3::new(0.0, 0.0, 0.5));
        let towards_viewer = (self.viewpoint - ahead).normalize();
        let (t1, t2) = towards_viewer.any_orthonormal_pair();
        let size = 0.1 * (self.viewpoint - ahead).length();
        // Counter-clockwise seen from the viewpoint: (b - a) x (c - a) points at it.
        let (a, mut b, mut c) = (ahead, ahead + size * t1, ahead + size * t2);
        if (b - a).cross(c - a).dot(towards_viewer) < 0.0 {
            std::mem::swap(&mut b, &mut c);
        }
        let [a, b, c] = [a, b, c].map(|p| self.view_projection.project_point3(p));
        let area = -0.5 * ((a.x * b.y - b.x * a.y) + (b.x * c.y - c.x * b.y) + (c.x * a.y - a.x * c.y));
        if area > 0.0 {
            vk::FrontFace::COUNTER_CLOCKWISE
        } else {
            vk::FrontFace::CLOCKWISE
        }
    }
}

/// The scene's descriptor set, and for each object the dynamic offset of its analytic report (binding 11 of
/// the scene layout: each draw writes its own, so that no two draws write the same memory).
#[derive(Clone, Copy)]
pub struct ObjectSets<'a> {
    pub set: vk::DescriptorSet,
    pub report_offsets: &'a [u32],
}

/// Sets the viewport and scissor to the target and draws every object with its pipeline (`pipelines[i]` for
/// object i) and its descriptors (`sets`), culling the back faces of closed meshes the viewpoint is outside
/// of, and telling the shaders which object each draw is and, for the shadow pass, which light and cube face
/// (`shadow_face`, with which objects can shadow from that light: that pass leaves out the others).
#[allow(clippy::too_many_arguments)] // one pass's whole state, recorded in one go
pub fn draw_objects(
    device: &Device,
    cmd: vk::CommandBuffer,
    (layout, sets): (vk::PipelineLayout, ObjectSets),
    pipelines: &[vk::Pipeline],
    view: PassView,
    targets: &PassTargets,
    placed: &[PlacedMesh],
    meshes: &MeshUploads,
    shadow_face: Option<((u32, u32), &[bool])>,
) {
    // SAFETY: the command buffer is recording inside a render pass; the buffers outlive the submission.
    unsafe {
        set_viewport_and_scissor(device, cmd, targets);
        device.raw.cmd_set_front_face(cmd, view.front_face());
        let mut bound = None;
        for (index, (p, &pipeline)) in placed.iter().zip(pipelines).enumerate() {
            if shadow_face.is_some_and(|(_, occluders)| !occluders[index]) {
                continue;
            }
            if bound != Some(pipeline) {
                device.raw.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, pipeline);
                bound = Some(pipeline);
            }
            let offset = [sets.report_offsets[index]];
            device.raw.cmd_bind_descriptor_sets(cmd, vk::PipelineBindPoint::GRAPHICS, layout, 0, &[sets.set], &offset);
            let mesh = meshes.get(&p.mesh);
            let cull = if mesh.hides_back_faces(p.model, view.viewpoint) {
                vk::CullModeFlags::BACK
            } else {
                vk::CullModeFlags::NONE
            };
            device.raw.cmd_set_cull_mode(cmd, cull);
            device.raw.cmd_bind_vertex_buffers(cmd, 0, &[mesh.vertices.raw], &[0]);
            device.raw.cmd_bind_index_buffer(cmd, mesh.indices.raw, 0, vk::IndexType::UINT32);
            let (light, face) = shadow_face.map_or((0, 0), |(light_face, _)| light_face);
            let push = [index as u32, light, face];
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

/// Sets the viewport and scissor to the whole target.
pub fn set_viewport_and_scissor(device: &Device, cmd: vk::CommandBuffer, targets: &PassTargets) {
    let viewport = vk::Viewport {
        x: 0.0,
        y: 0.0,
        width: targets.width as f32,
        height: targets.height as f32,
        min_depth: 0.0,
        max_depth: 1.0,
    };
    // SAFETY: the command buffer is recording.
    unsafe {
        device.raw.cmd_set_viewport(cmd, 0, &[viewport]);
        device.raw.cmd_set_scissor(cmd, 0, &[targets.area()]);
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

/// How a pass starts its depth target.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum DepthStart {
    /// Cleared to this depth as the pass begins (0 is the far end in reverse-Z).
    Cleared(f32),
    /// As it is (cleared before the pass began).
    Loaded,
    /// Neither loaded nor cleared: the pass's first draw writes every sample.
    Written,
}

/// Begins dynamic rendering into `color` and the targets' depth image, started as `depth` says and stored
/// only when `keep_depth` (for a later pass to read).
pub fn begin_rendering(
    device: &Device,
    cmd: vk::CommandBuffer,
    targets: &PassTargets,
    color: vk::RenderingAttachmentInfo,
    depth: DepthStart,
    keep_depth: bool,
) {
    let colors = [color];
    let (load, clear) = match depth {
        DepthStart::Cleared(value) => (vk::AttachmentLoadOp::CLEAR, value),
        DepthStart::Loaded => (vk::AttachmentLoadOp::LOAD, 0.0),
        DepthStart::Written => (vk::AttachmentLoadOp::DONT_CARE, 0.0),
    };
    let depth = vk::RenderingAttachmentInfo::default()
        .image_view(targets.depth)
        .image_layout(vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL)
        .load_op(load)
        .store_op(if keep_depth { vk::AttachmentStoreOp::STORE } else { vk::AttachmentStoreOp::DONT_CARE })
        .clear_value(vk::ClearValue { depth_stencil: vk::ClearDepthStencilValue { depth: clear, stencil: 0 } });
    let rendering = vk::RenderingInfo::default()
        .render_area(targets.area())
        .layer_count(1)
        .color_attachments(&colors)
        .depth_attachment(&depth);
    // SAFETY: the command buffer is recording; the views outlive the submission.
    unsafe { device.raw.cmd_begin_rendering(cmd, &rendering) };
}
