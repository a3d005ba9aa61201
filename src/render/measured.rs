//! The measured materials' tables on the GPU: one storage buffer holding every table the work at hand uses,
//! one after the other, each followed by its sampler (`MeasuredTables` of `shaders/brdf/measured.glsl`),
//! kept while the next work uses the same tables.

use std::sync::Arc;

use ash::vk;

use crate::brdf::measured::ENTRIES;
use crate::brdf::measured_sampler::SAMPLER_FLOATS;
use crate::brdf::{Brdf, Measured};
use crate::error::{Error, Result};
use crate::vulkan::{Buffer, Device};

/// The floats of a table's place in the buffer: its entries, then its sampler (`MEASURED_TABLE_FLOATS`).
const TABLE_FLOATS: usize = 3 * ENTRIES + SAMPLER_FLOATS;

/// The buffer, and which table is at which place in it.
pub struct MeasuredTables {
    buffer: Buffer,
    held: Vec<Measured>,
}

impl MeasuredTables {
    /// An empty set: a buffer of one entry, which no material reads (a binding may not be empty).
    ///
    /// # Errors
    /// `Error::Vulkan` or `Error::Allocation`.
    pub fn new(device: &Arc<Device>) -> Result<Self> {
        let buffer =
            device.create_buffer_with_data(&[0.0f32; 3], vk::BufferUsageFlags::STORAGE_BUFFER, "no measured tables")?;
        Ok(Self { buffer, held: Vec::new() })
    }

    /// Makes sure that every measured table among `brdfs` is in the buffer: the buffer is kept when it
    /// holds them all already, and made anew with exactly these otherwise. No submitted work may still read
    /// the buffer (the passes wait for theirs).
    ///
    /// # Errors
    /// `Error::Device` when the tables are more than one storage buffer may hold (`maxStorageBufferRange`: 7
    /// tables on lavapipe's 128 MiB), `Error::Vulkan` or `Error::Allocation`.
    pub fn hold<'a>(&mut self, device: &Arc<Device>, brdfs: impl IntoIterator<Item = &'a Brdf>) -> Result<()> {
        let mut wanted: Vec<&Measured> = Vec::new();
        for brdf in brdfs {
            if let Brdf::Measured(table) = brdf {
                if !wanted.iter().any(|w| w.same_table(table)) {
                    wanted.push(table);
                }
            }
        }
        if wanted.iter().all(|w| self.held.iter().any(|h| h.same_table(w))) {
            return Ok(());
        }
        let bytes = (wanted.len() * TABLE_FLOATS * std::mem::size_of::<f32>()) as u64;
        let range = u64::from(device.limits.max_storage_buffer_range);
        if bytes > range {
            return Err(Error::Device(format!(
                "{} measured materials at once need {} MiB of tables, over this device's storage buffer range of {} \
                 MiB ({} tables)",
                wanted.len(),
                bytes >> 20,
                range >> 20,
                range / (bytes / wanted.len() as u64)
            )));
        }
        let mut values = Vec::with_capacity(wanted.len() * TABLE_FLOATS);
        for table in &wanted {
            values.extend_from_slice(&table.table().rgb);
            values.extend_from_slice(table.table().sampler());
        }
        self.buffer =
            device.create_buffer_with_data(&values, vk::BufferUsageFlags::STORAGE_BUFFER, "measured tables")?;
        self.held = wanted.into_iter().cloned().collect();
        Ok(())
    }

    /// The place of `table` in the buffer (0 for a table it does not hold: [`MeasuredTables::hold`] first).
    pub fn slot(&self, table: &Measured) -> u32 {
        self.held.iter().position(|h| h.same_table(table)).unwrap_or(0) as u32
    }

    /// The buffer to bind.
    pub fn buffer(&self) -> &Buffer {
        &self.buffer
    }
}
