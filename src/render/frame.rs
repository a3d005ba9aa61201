//! One image: what `Renderer::draw` decides (the kept targets, cubes and scene data brought up to date,
//! the shadow faces to draw, the background's writer) and the commands it records for it: the shadow cube
//! faces, the forward pass and the resolve into the read-back buffer.

use std::sync::Arc;

use ash::vk;
use glam::Mat4;

use super::forward::{self, Background, PipelineKey};
use super::gpu_types::MaterialData;
use super::gpu_types::{GpuFrame, GpuObject, GpuPointLight};
use super::occluders::{faces_with_occluders, occluders};
use super::passes::{barriers, draw_objects, image_barrier, MeshUploads, ObjectSets, PassTargets, PassView};
use super::resolve::{Readout, ResolveRecording};
use super::scene_data::{SceneData, SceneResources, SceneValues};
use super::shadow::{self, cube_face_views, faces_read_by, lookup_margin, FaceKey, ShadowCubes};
use super::targets::Targets;
use super::{Renderer, NEAR_PLANE};
use crate::error::{Error, Result};
use crate::mesh::PlacedMesh;
use crate::scene::Scene;
use crate::vulkan::{layer_range, layout_transition, Access, Device};

impl Renderer {
    /// Draws the scene into the kept targets and resolves it into their read-back buffer as `readout` says;
    /// an environment in the exact mode takes the samples from `first_sample` on.
    pub(super) fn draw(
        &mut self,
        scene: &Scene,
        placed: &[PlacedMesh],
        first_sample: u32,
        readout: Readout,
    ) -> Result<()> {
        let environment_albedo = self.prepare_environment(scene)?;
        let device = self.device.clone();
        let (width, height) = (scene.image.width, scene.image.height);
        let samples = vk::SampleCountFlags::from_raw(scene.image.samples);

        // Scene data. Each light that casts shadows on something gets the next cube of the shadow cube array,
        // holding its occluders on the faces the image reads where they fall (occluders.rs).
        let occluders: Vec<Vec<bool>> = scene
            .lights
            .iter()
            .map(|light| {
                if light.shadows {
                    occluders(light.position, scene.camera.position, placed)
                } else {
                    vec![false; placed.len()]
                }
            })
            .collect();
        let shadow_casters: Vec<usize> = (0..scene.lights.len()).filter(|&i| occluders[i].iter().any(|&o| o)).collect();
        let margin = lookup_margin(scene) as f32;
        let seen: Vec<[bool; 6]> = shadow_casters
            .iter()
            .map(|&i| {
                let light = scene.lights[i].position;
                let read = faces_read_by(scene, light);
                let occupied = faces_with_occluders(light, placed, &occluders[i], margin);
                std::array::from_fn(|face| read[face] && occupied[face])
            })
            .collect();
        let lights: Vec<GpuPointLight> = scene
            .lights
            .iter()
            .enumerate()
            .map(|(i, light)| {
                GpuPointLight::new(light, shadow_casters.iter().position(|&c| c == i).map(|cube| (cube, seen[cube])))
            })
            .collect();
        self.measured.hold(&device, scene.objects.iter().map(|o| &o.brdf))?;
        self.analytic.write(&device, scene.objects.iter().map(|o| &o.brdf), scene.objects.len())?;
        let data = MaterialData { measured: &self.measured, analytic: &self.analytic };
        let objects: Vec<GpuObject> =
            scene.objects.iter().zip(placed).map(|(object, p)| GpuObject::new(object, p.model, data)).collect();
        let report_offsets: Vec<u32> = (0..placed.len()).map(|i| self.analytic.report_offset(i)).collect();
        // Every face of every cube, in the order of the array's layers.
        let shadow_faces: Vec<PassView> = shadow_casters
            .iter()
            .flat_map(|&i| {
                let viewpoint = scene.lights[i].position;
                cube_face_views(viewpoint, NEAR_PLANE).map(|view_projection| PassView { viewpoint, view_projection })
            })
            .collect();
        let shadow_views: Vec<[[f32; 4]; 4]> =
            shadow_faces.iter().map(|face| face.view_projection.to_cols_array_2d()).collect();
        let mut frame = GpuFrame::new(&scene.camera, &scene.image, NEAR_PLANE);
        if let Some(environment) = &scene.environment {
            let (sin, cos) = environment.rotation.to_radians().sin_cos();
            frame.environment = [cos, sin, environment.intensity, 0.0];
            frame.environment_first_sample = first_sample;
        }
        let values = SceneValues {
            frame,
            lights: &lights,
            objects: &objects,
            shadow_views: &shadow_views,
            environment_albedo: &environment_albedo,
        };

        // What is kept from the last image where it still holds, made anew where not.
        self.meshes.update(&device, placed)?;
        let cube_size = scene.image.shadow_map_size;
        let mut cubes = ShadowCubes::for_lights(&device, self.shadow_cubes.take(), cube_size, shadow_casters.len())
            .map_err(|e| {
                // Distance and depth, 4 bytes a texel each: six faces a casting light, and one depth face.
                let bytes = u64::from(cube_size).pow(2) * 4 * (6 * shadow_casters.len() as u64 + 1);
                too_big(e, scene, format!("image.shadow_map_size = {cube_size}"), "shadow cubes", bytes)
            })?;
        let faces_to_draw = faces_to_draw(scene, placed, (&shadow_casters, &seen, &occluders), &shadow_faces, &cubes);
        let sampled_depth = self.background_counts.contains(samples);
        let targets = Targets::for_size(&device, self.targets.take(), (width, height), samples, sampled_depth)
            .map_err(|e| {
                // Colour (16 bytes) and depth (4) a sample, and the read-back buffer (16 a pixel).
                let bytes = u64::from(width) * u64::from(height) * (20 * u64::from(scene.image.samples) + 16);
                let setting = format!("image.width x height x samples = {width} x {height} x {}", scene.image.samples);
                too_big(e, scene, setting, "render targets", bytes)
            })?;
        let images = SceneResources {
            shadow_cubes: (cubes.maps.view, &self.shadow_sampler),
            environment: (&self.environment, &self.environment_sampler),
            measured: self.measured.buffer(),
            analytic: &self.analytic,
        };
        let scene_data = match self.scene_data.take() {
            Some(mut data) => {
                data.write(&device, &values, images)?;
                data
            }
            None => SceneData::new(&device, &self.layout, &values, images)?,
        };
        let background = background_of(scene, self.background_counts);
        let keys: Vec<PipelineKey> = std::iter::once(PipelineKey::background(scene))
            .chain(scene.objects.iter().zip(placed).map(|(object, p)| PipelineKey::for_object(scene, object, p)))
            .collect();
        let pipelines = self.forward.pipelines(&self.compiler, &keys)?;
        let (background_pipeline, forward_pipelines) = (pipelines[0], &pipelines[1..]);
        let shadow_pipelines: Vec<vk::Pipeline> = placed.iter().map(|p| self.shadow.pipeline(p)).collect();

        let frame = FrameRecording {
            device: &device,
            layout: self.layout.raw,
            sets: ObjectSets { set: scene_data.set, report_offsets: &report_offsets },
            placed,
            meshes: &self.meshes,
            shadow: ShadowDrawing { pipelines: &shadow_pipelines, faces: &faces_to_draw, lay_out: cubes.need_layout() },
            cubes: &cubes,
            forward: forward_pipelines,
            camera: PassView {
                viewpoint: scene.camera.position,
                view_projection: Mat4::from_cols_array_2d(&values.frame.view_projection),
            },
            targets: &targets,
            background: background_pipeline,
            resolve: self.resolve.prepare(
                &targets,
                readout,
                (background == Background::Resolved).then_some(values.frame.background),
            )?,
            background_mode: background,
        };
        let drawn = device.submit_and_wait(|cmd| {
            frame.record(cmd);
            self.analytic.record_host_read_barrier(cmd, vk::PipelineStageFlags2::FRAGMENT_SHADER);
            Ok(())
        });
        let drawn_faces: Vec<(u32, FaceKey)> = faces_to_draw.into_iter().map(|face| (face.layer, face.key)).collect();
        cubes.set_drawn(drawn.is_ok().then_some(&drawn_faces[..]));
        self.shadow_cubes = Some(cubes);
        self.targets = Some(targets);
        self.scene_data = Some(scene_data);
        drawn.map_err(|e| super::naming_models(e, scene.objects.iter().map(|o| &o.brdf)))?;
        self.note_invalid_values()
    }
}

/// What writes the background of `scene`: the resolve, at the sample counts where the device allows
/// (`background_counts`), when it is a constant colour; its triangle, which an environment's needs.
pub(super) fn background_of(scene: &Scene, background_counts: vk::SampleCountFlags) -> Background {
    let samples = vk::SampleCountFlags::from_raw(scene.image.samples);
    if background_counts.contains(samples) && scene.environment.is_none() {
        Background::Resolved
    } else {
        Background::Drawn
    }
}

/// An allocation that failed for what `setting` of `scene` asked, said as such with the bytes it needed;
/// any other error as it is.
fn too_big(error: Error, scene: &Scene, setting: String, what: &str, bytes: u64) -> Error {
    let why = match &error {
        Error::Allocation(e) => e.to_string(),
        // lavapipe on Mesa 25 refuses such an image when it is made.
        Error::Vulkan(e @ (vk::Result::ERROR_OUT_OF_DEVICE_MEMORY | vk::Result::ERROR_OUT_OF_HOST_MEMORY)) => {
            e.to_string()
        }
        _ => return error,
    };
    Error::Scene {
        file: scene.source.clone(),
        message: format!(
            "{setting}: the {what} need {:.1} GiB of device memory, more than the device could give ({why})",
            bytes as f64 / f64::from(1u32 << 30)
        ),
    }
}

/// One face of a shadow cube to draw.
struct FaceDrawing {
    /// The face's layer in the cube array.
    layer: u32,
    /// The light's index in the scene, and the face (0 to 5: +x, -x, +y, -y, +z, -z).
    light_face: (u32, u32),
    view: PassView,
    /// What it will hold; its `occluders` are the objects drawn into it.
    key: FaceKey,
}

/// The faces of the shadow cubes that this image reads (`seen`, per light of `casters`) and `cubes` do not
/// hold yet, each to be drawn with the objects that can shadow from its light (`occluders`, per light of the
/// scene).
fn faces_to_draw(
    scene: &Scene,
    placed: &[PlacedMesh],
    (casters, seen, occluders): (&[usize], &[[bool; 6]], &[Vec<bool>]),
    views: &[PassView],
    cubes: &ShadowCubes,
) -> Vec<FaceDrawing> {
    let geometry: Arc<[PlacedMesh]> = placed.into();
    let mut faces = Vec::new();
    for (cube, (&light, seen)) in casters.iter().zip(seen).enumerate() {
        let size = scene.image.shadow_map_size;
        let key = FaceKey::new(size, scene.lights[light].position, geometry.clone(), occluders[light].clone());
        for face in (0..6).filter(|&face| seen[face]) {
            let layer = (6 * cube + face) as u32;
            if !cubes.holds(layer, &key) {
                let light_face = (light as u32, face as u32);
                faces.push(FaceDrawing { layer, light_face, view: views[layer as usize], key: key.clone() });
            }
        }
    }
    faces
}

/// One image's commands: the shadow cube faces it needs drawn, the forward pass, the resolve into the
/// read-back buffer.
struct FrameRecording<'a> {
    device: &'a Device,
    layout: vk::PipelineLayout,
    sets: ObjectSets<'a>,
    placed: &'a [PlacedMesh],
    meshes: &'a MeshUploads,
    shadow: ShadowDrawing<'a>,
    cubes: &'a ShadowCubes,
    /// The forward pass's pipeline for each object.
    forward: &'a [vk::Pipeline],
    camera: PassView,
    targets: &'a Targets,
    /// The background's pipeline, and whether it is drawn.
    background: vk::Pipeline,
    background_mode: Background,
    resolve: ResolveRecording,
}

/// The shadow cube faces to draw.
struct ShadowDrawing<'a> {
    /// The shadow pass's pipeline for each object.
    pipelines: &'a [vk::Pipeline],
    faces: &'a [FaceDrawing],
    /// Whether the cubes' layers still need their first transition to the layout the forward pass reads.
    lay_out: bool,
}

impl FrameRecording<'_> {
    fn record(&self, cmd: vk::CommandBuffer) {
        let device = self.device;
        // SAFETY: every handle recorded here lives until submit_and_wait has waited for the work.
        unsafe {
            // The background's draw reads no object's report: the first's window will do.
            let offset = [self.sets.report_offsets.first().copied().unwrap_or(0)];
            device.raw.cmd_bind_descriptor_sets(
                cmd,
                vk::PipelineBindPoint::GRAPHICS,
                self.layout,
                0,
                &[self.sets.set],
                &offset,
            );
        }
        let mut to_targets = self.record_shadow_faces(cmd);

        // The forward pass.
        let targets = self.targets;
        to_targets.push(image_barrier(&targets.color, vk::ImageLayout::UNDEFINED, COLOR_TARGET, NOTHING, COLOR_WRITE));
        if self.background_mode == Background::Resolved {
            clear_depth(device, cmd, &targets.depth, forward::UNCOVERED_DEPTH);
            to_targets.push(image_barrier(&targets.depth, CLEAR_TARGET, DEPTH_TARGET, CLEAR_WRITE, DEPTH_TESTS));
        } else {
            to_targets.push(image_barrier(
                &targets.depth,
                vk::ImageLayout::UNDEFINED,
                DEPTH_TARGET,
                NOTHING,
                DEPTH_TESTS,
            ));
        }
        barriers(device, cmd, &to_targets);
        let pass = targets.pass_targets();
        forward::begin(device, cmd, &pass, self.background_mode);
        if self.background_mode == Background::Drawn {
            forward::draw_background(device, cmd, self.background, &pass);
        }
        let layout = (self.layout, self.sets);
        draw_objects(device, cmd, layout, self.forward, self.camera, &pass, self.placed, self.meshes, None);
        // SAFETY: as above.
        unsafe { device.raw.cmd_end_rendering(cmd) };

        // The resolve pass reads every sample (and depth, where it writes the background) and writes the
        // read-back buffer.
        let mut to_resolve = vec![image_barrier(&targets.color, COLOR_TARGET, READ_ONLY, COLOR_WRITE, RESOLVE_READ)];
        if self.background_mode == Background::Resolved {
            to_resolve.push(image_barrier(&targets.depth, DEPTH_TARGET, READ_ONLY, DEPTH_TESTS, RESOLVE_READ));
        }
        barriers(device, cmd, &to_resolve);
        self.resolve.record(device, cmd, targets);
    }

    /// Draws the shadow cube faces to draw, and returns the barriers that make them (and, on the first image,
    /// every layer) readable by the forward pass, to be recorded with the forward pass's own.
    fn record_shadow_faces(&self, cmd: vk::CommandBuffer) -> Vec<vk::ImageMemoryBarrier2<'static>> {
        let (device, cubes, shadow) = (self.device, self.cubes, &self.shadow);
        let layer = |layer: u32, old, new, src, dst| {
            layout_transition(cubes.maps.raw, layer_range(vk::ImageAspectFlags::COLOR, layer, 1), old, new, src, dst)
        };
        let drawn = |l: u32| shadow.faces.iter().any(|face| face.layer == l);
        // Faces to draw go to the colour target layout, their contents discarded; on the first image every
        // other layer goes to the layout the set names, never to be written (no visible point reads it).
        let to_targets: Vec<_> = shadow
            .faces
            .iter()
            .map(|f| layer(f.layer, vk::ImageLayout::UNDEFINED, COLOR_TARGET, NOTHING, COLOR_WRITE))
            .collect();
        let mut to_read: Vec<_> = Vec::new();
        if shadow.lay_out {
            let unused = (0..cubes.maps.desc.layers).filter(|&l| !drawn(l));
            to_read.extend(unused.map(|l| layer(l, vk::ImageLayout::UNDEFINED, READ_ONLY, NOTHING, SAMPLED)));
        }
        if to_targets.is_empty() {
            return to_read;
        }
        barriers(device, cmd, &to_targets);
        let size = cubes.depth.desc.width;
        for face in shadow.faces {
            // The depth image is cleared for each face: the previous face's tests must be over first.
            barriers(
                device,
                cmd,
                &[image_barrier(&cubes.depth, vk::ImageLayout::UNDEFINED, DEPTH_TARGET, DEPTH_TESTS, DEPTH_TESTS)],
            );
            let face_view = &cubes.face_views[face.layer as usize];
            let targets = PassTargets { color: face_view.raw, depth: cubes.depth.view, width: size, height: size };
            shadow::begin(device, cmd, &targets);
            draw_objects(
                device,
                cmd,
                (self.layout, self.sets),
                shadow.pipelines,
                face.view,
                &targets,
                self.placed,
                self.meshes,
                Some((face.light_face, &face.key.occluders)),
            );
            // SAFETY: the command buffer is recording; every handle outlives the submission.
            unsafe { device.raw.cmd_end_rendering(cmd) };
        }
        to_read.extend(shadow.faces.iter().map(|f| layer(f.layer, COLOR_TARGET, READ_ONLY, COLOR_WRITE, SAMPLED)));
        to_read
    }
}

const COLOR_TARGET: vk::ImageLayout = vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL;
const DEPTH_TARGET: vk::ImageLayout = vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL;
const READ_ONLY: vk::ImageLayout = vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL;
const NOTHING: Access = (vk::PipelineStageFlags2::NONE, vk::AccessFlags2::NONE);
const COLOR_WRITE: Access =
    (vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT, vk::AccessFlags2::COLOR_ATTACHMENT_WRITE);
const DEPTH_TESTS: Access = (
    vk::PipelineStageFlags2::from_raw(
        vk::PipelineStageFlags2::EARLY_FRAGMENT_TESTS.as_raw() | vk::PipelineStageFlags2::LATE_FRAGMENT_TESTS.as_raw(),
    ),
    vk::AccessFlags2::from_raw(
        vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_READ.as_raw()
            | vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_WRITE.as_raw(),
    ),
);
const SAMPLED: Access = (vk::PipelineStageFlags2::FRAGMENT_SHADER, vk::AccessFlags2::SHADER_SAMPLED_READ);
const RESOLVE_READ: Access = (vk::PipelineStageFlags2::COMPUTE_SHADER, vk::AccessFlags2::SHADER_SAMPLED_READ);
const CLEAR_TARGET: vk::ImageLayout = vk::ImageLayout::TRANSFER_DST_OPTIMAL;
const CLEAR_WRITE: Access = (vk::PipelineStageFlags2::CLEAR, vk::AccessFlags2::TRANSFER_WRITE);

/// Clears every sample of a depth image to `depth`, leaving it in the clear's layout.
fn clear_depth(device: &Device, cmd: vk::CommandBuffer, image: &crate::vulkan::Image, depth: f32) {
    barriers(device, cmd, &[image_barrier(image, vk::ImageLayout::UNDEFINED, CLEAR_TARGET, NOTHING, CLEAR_WRITE)]);
    let value = vk::ClearDepthStencilValue { depth, stencil: 0 };
    // SAFETY: the command buffer is recording; the image outlives the submission.
    unsafe { device.raw.cmd_clear_depth_stencil_image(cmd, image.raw, CLEAR_TARGET, &value, &[image.full_range()]) };
}
