//! The environment on the GPU, kept while a scene's environment is the same (per scene): its map, the
//! tables that importance-sample it (the exact mode) and its prefiltered layers (the fast mode, made on
//! first use); a black placeholder of each when a scene has none, so that the descriptor set is always
//! whole.

use std::sync::Arc;

use ash::vk;
use glam::Vec3;
use gpu_allocator::MemoryLocation;

use super::passes::barriers;
use crate::environment::prefilter::{prefiltered_layers, LAYERS, LAYER_WIDTH};
use crate::environment::sampling::SamplingTable;
use crate::environment::EnvironmentMap;
use crate::error::Result;
use crate::scene::EnvironmentSource;
use crate::vulkan::{layout_transition, Buffer, BufferDesc, Device, Image, ImageDesc};

/// The format of the maps: 32-bit float, read with linear filtering.
pub const MAP_FORMAT: vk::Format = vk::Format::R32G32B32A32_SFLOAT;

/// One environment's images and tables on the device.
pub struct EnvironmentTextures {
    /// What they were made from (`None`: the placeholders).
    pub source: Option<EnvironmentSource>,
    pub map: Image,
    /// The sampling table (`EnvironmentSampling` of `shaders/common/environment.glsl`): the sampling grid's
    /// size ((0, 0) for a constant environment, which is not importance-sampled), the samples a pass of the
    /// exact mode takes and a word of padding, then the marginal, each row's conditional, the cells'
    /// probabilities, the marginal's guide and each row's (`SamplingTable`).
    pub sampling: Buffer,
    /// The fast mode's layers, or a placeholder until a fast render needs them.
    pub prefiltered: Image,
    has_prefiltered: bool,
    /// The map, kept to prefilter it if the fast mode needs it (dropped once it is).
    kept_map: Option<EnvironmentMap>,
}

impl EnvironmentTextures {
    /// Black placeholders, for scenes without an environment.
    pub fn placeholder(device: &Arc<Device>) -> Result<Self> {
        let black = EnvironmentMap { width: 2, height: 1, texels: vec![Vec3::ZERO; 2] };
        let mut textures = Self::new(device, None, black)?;
        textures.kept_map = None;
        Ok(textures)
    }

    /// The map of `source` uploaded with its sampling table; its prefiltered layers wait for
    /// [`EnvironmentTextures::prefilter`].
    pub fn new(device: &Arc<Device>, source: Option<EnvironmentSource>, map: EnvironmentMap) -> Result<Self> {
        let table = SamplingTable::new(&map);
        let (width, height) = if map.is_constant() { (0, 0) } else { (table.width, table.height) };
        let words: Vec<u32> = [width, height, super::exact::SAMPLES_PER_PASS, 0]
            .into_iter()
            .chain(table.marginal.iter().chain(&table.conditional).chain(&table.probabilities).map(|v| v.to_bits()))
            .chain(table.marginal_guide.iter().chain(&table.conditional_guide).copied())
            .collect();
        let sampling =
            device.create_buffer_with_data(&words, vk::BufferUsageFlags::STORAGE_BUFFER, "environment sampling")?;
        let map_image = upload_layers(device, map.width, map.height, 1, &map.texels, "environment map")?;
        let prefiltered = upload_layers(device, 1, 1, LAYERS, &vec![Vec3::ZERO; LAYERS as usize], "no prefiltered")?;
        Ok(Self { source, map: map_image, sampling, prefiltered, has_prefiltered: false, kept_map: Some(map) })
    }

    /// Makes and uploads the prefiltered layers, once.
    pub fn prefilter(&mut self, device: &Arc<Device>) -> Result<()> {
        if self.has_prefiltered {
            return Ok(());
        }
        let Some(map) = self.kept_map.take() else { return Ok(()) };
        let layers = prefiltered_layers(&map);
        match upload_layers(device, LAYER_WIDTH, LAYER_WIDTH / 2, LAYERS, &layers, "environment prefiltered") {
            Ok(image) => {
                self.prefiltered = image;
                self.has_prefiltered = true;
                Ok(())
            }
            Err(e) => {
                self.kept_map = Some(map);
                Err(e)
            }
        }
    }
}

/// A sampled image of `layers` layers of `width` x `height` texels, filled from `texels` (RGB, layer after
/// layer) through a staging buffer, left in the layout shaders read.
fn upload_layers(
    device: &Arc<Device>,
    width: u32,
    height: u32,
    layers: u32,
    texels: &[Vec3],
    name: &str,
) -> Result<Image> {
    let rgba: Vec<[f32; 4]> = texels.iter().map(|t| t.extend(1.0).to_array()).collect();
    let mut staging = device.create_buffer(
        BufferDesc {
            size: std::mem::size_of_val(rgba.as_slice()) as vk::DeviceSize,
            usage: vk::BufferUsageFlags::TRANSFER_SRC,
            location: MemoryLocation::CpuToGpu,
        },
        name,
    )?;
    staging.write(&rgba)?;
    let desc = ImageDesc {
        width,
        height,
        layers,
        cube: false,
        format: MAP_FORMAT,
        samples: vk::SampleCountFlags::TYPE_1,
        usage: vk::ImageUsageFlags::SAMPLED | vk::ImageUsageFlags::TRANSFER_DST,
        aspect: vk::ImageAspectFlags::COLOR,
    };
    let image = device.create_image(desc, name)?;
    let range = image.full_range();
    let transition = |old, new, src, dst| layout_transition(image.raw, range, old, new, src, dst);
    let copy_write = (vk::PipelineStageFlags2::COPY, vk::AccessFlags2::TRANSFER_WRITE);
    let to_copy = transition(
        vk::ImageLayout::UNDEFINED,
        vk::ImageLayout::TRANSFER_DST_OPTIMAL,
        (vk::PipelineStageFlags2::NONE, vk::AccessFlags2::NONE),
        copy_write,
    );
    let to_shaders = transition(
        vk::ImageLayout::TRANSFER_DST_OPTIMAL,
        vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
        copy_write,
        (vk::PipelineStageFlags2::FRAGMENT_SHADER, vk::AccessFlags2::SHADER_SAMPLED_READ),
    );
    let region = vk::BufferImageCopy::default()
        .image_subresource(vk::ImageSubresourceLayers {
            aspect_mask: vk::ImageAspectFlags::COLOR,
            mip_level: 0,
            base_array_layer: 0,
            layer_count: layers,
        })
        .image_extent(vk::Extent3D { width, height, depth: 1 });
    device.submit_and_wait(|cmd| {
        barriers(device, cmd, &[to_copy]);
        // SAFETY: the command buffer is recording; the staging buffer and the image outlive the submission,
        // which submit_and_wait waits for.
        unsafe {
            device.raw.cmd_copy_buffer_to_image(
                cmd,
                staging.raw,
                image.raw,
                vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                &[region],
            );
        }
        barriers(device, cmd, &[to_shaders]);
        Ok(())
    })?;
    Ok(image)
}
