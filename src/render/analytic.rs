//! Analytic models on the GPU: the buffer of every analytic material's values (`AnalyticParameters` of
//! `shaders/common/analytic.glsl`), written for each piece of work, with the report the shaders make of the
//! values no BRDF may give; and the key by which a model's compiled shaders and pipelines are kept.

use std::fmt;
use std::sync::Arc;

use ash::vk;
use glam::Vec3;
use gpu_allocator::MemoryLocation;

use crate::brdf::{Analytic, AnalyticModel, Brdf};
use crate::error::Result;
use crate::vulkan::{Buffer, BufferDesc, Device};

/// A model as pipelines are kept by: equal when the models compile to the same shaders.
#[derive(Clone, Debug)]
pub struct AnalyticShader(pub Arc<AnalyticModel>);

impl PartialEq for AnalyticShader {
    fn eq(&self, other: &Self) -> bool {
        self.0.key() == other.0.key()
    }
}

impl Eq for AnalyticShader {}

impl std::hash::Hash for AnalyticShader {
    fn hash<H: std::hash::Hasher>(&self, state: &mut H) {
        self.0.key().hash(state);
    }
}

impl PartialOrd for AnalyticShader {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for AnalyticShader {
    fn cmp(&self, other: &Self) -> std::cmp::Ordering {
        self.0.key().cmp(&other.0.key())
    }
}

/// The model a material's shaders are compiled with, for an analytic material.
pub fn analytic_shader(brdf: &Brdf) -> Option<AnalyticShader> {
    match brdf {
        Brdf::Analytic(material) => Some(AnalyticShader(material.model().clone())),
        _ => None,
    }
}

/// The bytes of one `AnalyticReport` of `shaders/common/analytic.glsl` (std430): four uints (the count, the
/// material's first value, two of padding), then three vec4 (wi, wo, the value), read by
/// [`AnalyticValues::report`] at those offsets.
pub const REPORT_BYTES: u64 = 64;

/// Where a model gave values no BRDF may: how many evaluations did, and the first one recorded.
#[derive(Clone, Debug, PartialEq)]
pub struct InvalidValues {
    /// The file of the material of the first one recorded.
    pub file: std::path::PathBuf,
    /// How many evaluations gave NaN, an infinity or a negative value in some channel.
    pub count: u64,
    /// The first one's directions in the surface's frame (X, Y, N) and its value.
    pub wi: Vec3,
    /// Its direction to the viewer, in the same frame.
    pub wo: Vec3,
    /// The value it gave, RGB.
    pub value: Vec3,
}

impl InvalidValues {
    /// `later` counted after these: its evaluations added, the first case kept.
    pub fn merged(earlier: Option<Self>, later: Option<Self>) -> Option<Self> {
        match (earlier, later) {
            (Some(mut first), Some(then)) => {
                first.count += then.count;
                Some(first)
            }
            (first, then) => first.or(then),
        }
    }
}

impl fmt::Display for InvalidValues {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let angles = |w: Vec3| {
            let theta = w.z.clamp(-1.0, 1.0).acos().to_degrees();
            let phi = w.y.atan2(w.x).to_degrees();
            format!("(theta {theta:.2}, phi {phi:.2} degrees)")
        };
        write!(
            f,
            "{}: its BRDF gave NaN, an infinity or a negative value {} time(s), e.g. f = [{}, {}, {}] at L {} and V \
             {} (in the frame X, Y, N); such values count as 0 in images",
            self.file.display(),
            self.count,
            self.value.x,
            self.value.y,
            self.value.z,
            angles(self.wi),
            angles(self.wo)
        )
    }
}

/// The values' buffer and which material's values are where, and the reports' buffer: one report a slot
/// (an object of the forward pass, a dispatch of the probe), each `report_stride` bytes from the last.
pub struct AnalyticValues {
    values: Buffer,
    reports: Buffer,
    report_stride: u64,
    slots: usize,
    /// Each material written, and the index of its first value in `analytic_parameters`.
    held: Vec<(Analytic, u32)>,
}

impl AnalyticValues {
    /// Buffers of no values and one report.
    ///
    /// # Errors
    /// `Error::Vulkan` or `Error::Allocation`.
    pub fn new(device: &Arc<Device>) -> Result<Self> {
        // A dynamic offset is a multiple of the device's alignment for storage buffers.
        let alignment = device.limits.min_storage_buffer_offset_alignment.max(1);
        let report_stride = REPORT_BYTES.div_ceil(alignment) * alignment;
        Ok(Self {
            values: host_buffer(device, 4, "analytic values")?,
            reports: host_buffer(device, report_stride, "analytic reports")?,
            report_stride,
            slots: 1,
            held: Vec::new(),
        })
    }

    /// Writes the values of every analytic material among `brdfs` (each distinct material once) and clears
    /// `slots` reports. No submitted work may still use the buffers (the passes wait for theirs).
    ///
    /// # Errors
    /// `Error::Vulkan` or `Error::Allocation`.
    pub fn write<'a>(
        &mut self,
        device: &Arc<Device>,
        brdfs: impl IntoIterator<Item = &'a Brdf>,
        slots: usize,
    ) -> Result<()> {
        self.held.clear();
        let mut values: Vec<f32> = Vec::new();
        for brdf in brdfs {
            if let Brdf::Analytic(material) = brdf {
                if !self.held.iter().any(|(held, _)| held == material) {
                    self.held.push((material.clone(), values.len() as u32));
                    values.extend(material.floats());
                }
            }
        }
        if values.is_empty() {
            values.push(0.0);
        }
        let needed = 4 * values.len() as u64;
        if self.values.desc.size < needed {
            self.values = host_buffer(device, 2 * needed, "analytic values")?;
        }
        self.values.write(&values)?;
        self.slots = slots.max(1);
        let report_bytes = self.report_stride * self.slots as u64;
        if self.reports.desc.size < report_bytes {
            self.reports = host_buffer(device, 2 * report_bytes, "analytic reports")?;
        }
        self.reports.bytes_mut()?[..report_bytes as usize].fill(0);
        Ok(())
    }

    /// Where `material`'s values begin (0 for one not written: [`AnalyticValues::write`] first).
    pub fn first(&self, material: &Analytic) -> u32 {
        self.held.iter().find(|(held, _)| held == material).map_or(0, |(_, first)| *first)
    }

    /// The values' buffer to bind.
    pub fn values(&self) -> &Buffer {
        &self.values
    }

    /// The reports' buffer to bind (whole, or one report's window moved by [`AnalyticValues::report_offset`]).
    pub fn reports(&self) -> &Buffer {
        &self.reports
    }

    /// Where slot `slot`'s report is in the reports' buffer.
    pub fn report_offset(&self, slot: usize) -> u32 {
        (self.report_stride * slot as u64) as u32
    }

    /// Makes the shaders' reports visible to the host once the submission's fence has signalled, for work
    /// whose shaders at `stage` may have written them; record it last.
    pub fn record_host_read_barrier(&self, cmd: vk::CommandBuffer, stage: vk::PipelineStageFlags2) {
        if !self.held.is_empty() {
            let access = vk::AccessFlags2::SHADER_STORAGE_WRITE | vk::AccessFlags2::SHADER_STORAGE_READ;
            self.reports.record_host_read_barrier(cmd, stage, access);
        }
    }

    /// What the reports of the work done since they were last taken say, if a model gave an invalid value:
    /// the count over every slot, and the first slot's first case; the reports are cleared. No submitted
    /// work may still write them.
    ///
    /// # Errors
    /// `Error::Vulkan` if the buffer cannot be read.
    pub fn take_report(&mut self) -> Result<Option<InvalidValues>> {
        if self.held.is_empty() {
            return Ok(None);
        }
        let report_bytes = (self.report_stride * self.slots as u64) as usize;
        let bytes = &mut self.reports.bytes_mut()?[..report_bytes];
        let mut found: Option<InvalidValues> = None;
        for slot in 0..self.slots {
            let at = (self.report_stride * slot as u64) as usize;
            let word = |i: usize| {
                let b = &bytes[at + 4 * i..at + 4 * i + 4];
                u32::from_ne_bytes([b[0], b[1], b[2], b[3]])
            };
            let vector =
                |i: usize| Vec3::new(f32::from_bits(word(i)), f32::from_bits(word(i + 1)), f32::from_bits(word(i + 2)));
            let count = u64::from(word(0));
            if count == 0 {
                continue;
            }
            match &mut found {
                Some(first) => first.count += count,
                None => {
                    let material = word(1);
                    let file = self
                        .held
                        .iter()
                        .find(|(_, first)| *first == material)
                        .map(|(held, _)| held.model().path.clone())
                        .unwrap_or_default();
                    found = Some(InvalidValues { file, count, wi: vector(4), wo: vector(8), value: vector(12) });
                }
            }
        }
        bytes.fill(0);
        Ok(found)
    }
}

fn host_buffer(device: &Arc<Device>, size: u64, name: &str) -> Result<Buffer> {
    let usage = vk::BufferUsageFlags::STORAGE_BUFFER;
    device.create_buffer(BufferDesc { size, usage, location: MemoryLocation::CpuToGpu }, name)
}
