//! The sampler probe (`shaders/brdf_sample.comp`): a material's own sampler (`material_sample` of
//! `shaders/common/sampling.glsl`) run on the GPU for one view direction, and its density with
//! f_r cos(theta_i) at given directions, read back as float32, in the frame n = +z, X = +x.

use ash::vk;
use glam::{DVec3, Vec3, Vec4};

use super::analytic::analytic_shader;
use super::gpu_types::GpuMaterial;
use super::probe::EVALUATIONS_PER_DISPATCH;
use super::probe::{dispatch, per_buffer, push_constant, variant, GpuAlbedoJob, ProbeContext, ProbePass, Shader};
use super::Renderer;
use crate::brdf::Brdf;
use crate::error::{Error, Result};
use crate::vulkan::Buffer;

/// One draw of a material's sampler.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BrdfSample {
    /// The unit direction drawn towards the light; one below the surface (z <= 0) is no sample.
    pub wi: Vec3,
    /// The sampler's density at `wi` per solid angle (0 for no sample).
    pub pdf: f32,
    /// f_r(wi, wo) (0 for no sample).
    pub f: Vec3,
}

/// A material's sampler's density at one direction, with what it samples for.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SamplerDensity {
    /// The density per solid angle of drawing the direction (0 below the surface).
    pub pdf: f32,
    /// f_r(wi, wo) cos(theta_i) there (0 below the surface).
    pub f_cos: Vec3,
}

/// The draw mode's result of a sample: (wi, pdf) and (f, 0).
type GpuSample = [Vec4; 2];

impl ProbePass {
    /// Samples `range` (first index, count) of the random stream `seed` of `brdf`'s sampler seen from `wo`.
    fn draw_samples(
        &mut self,
        (brdf, wo): (&Brdf, Vec3),
        (first, count): (u64, usize),
        seed: u32,
        context: ProbeContext,
    ) -> Result<Vec<BrdfSample>> {
        let size = std::mem::size_of::<GpuSample>();
        let job = self.sampler_job(brdf, wo, context)?;
        // Draw mode reads no directions: a placeholder stands at their binding.
        let none = self.device.create_buffer_with_data(&[Vec4::ZERO], vk::BufferUsageFlags::STORAGE_BUFFER, "none")?;
        let per_dispatch = EVALUATIONS_PER_DISPATCH.min(per_buffer::<GpuSample>(&self.device));
        let pipeline = self.sampler.pipeline(&self.device, context.compiler, &variant(brdf))?;
        let mut samples = Vec::with_capacity(count);
        for start in (0..count).step_by(per_dispatch) {
            let n = per_dispatch.min(count - start);
            // The stream's index is 32 bits: a test draws far fewer.
            let index = push_constant((first + start as u64) as usize)?;
            let push = [push_constant(n)?, index, 1, seed];
            let bytes = dispatch(&self.device, pipeline, &[&job, &none], context.data, size, &push)?;
            samples.extend(floats(&bytes).chunks_exact(8).map(|v| BrdfSample {
                wi: Vec3::new(v[0], v[1], v[2]),
                pdf: v[3],
                f: Vec3::new(v[4], v[5], v[6]),
            }));
        }
        Ok(samples)
    }

    /// The density of `brdf`'s sampler seen from `wo`, and f_r cos(theta_i), at each of `directions`.
    fn sampler_densities(
        &mut self,
        (brdf, wo): (&Brdf, Vec3),
        directions: &[Vec3],
        context: ProbeContext,
    ) -> Result<Vec<SamplerDensity>> {
        let job = self.sampler_job(brdf, wo, context)?;
        let per_dispatch = EVALUATIONS_PER_DISPATCH.min(per_buffer::<Vec4>(&self.device));
        let pipeline = self.sampler.pipeline(&self.device, context.compiler, &variant(brdf))?;
        let mut densities = Vec::with_capacity(directions.len());
        for part in directions.chunks(per_dispatch) {
            let padded: Vec<Vec4> = part.iter().map(|d| d.extend(0.0)).collect();
            let input = self.device.create_buffer_with_data(
                &padded,
                vk::BufferUsageFlags::STORAGE_BUFFER,
                "sampler directions",
            )?;
            let push = [push_constant(part.len())?, 0, 0, 0];
            let bytes = dispatch(&self.device, pipeline, &[&job, &input], context.data, 16, &push)?;
            densities.extend(
                floats(&bytes)
                    .chunks_exact(4)
                    .map(|v| SamplerDensity { pdf: v[0], f_cos: Vec3::new(v[1], v[2], v[3]) }),
            );
        }
        Ok(densities)
    }

    /// The density of `brdf`'s sampler seen from `wo` (`material_pdf`'s; a `.brdf` file's: its pdfBRDF, else
    /// the cosine's) and f_r cos(theta_i), at each of `directions`, in double precision
    /// (`brdf_density64.comp`): `None` for a measured table, on a device without doubles, or for a file with
    /// no double form.
    fn sampler_densities_double(
        &mut self,
        (brdf, wo): (&Brdf, Vec3),
        directions: &[DVec3],
        context: ProbeContext,
    ) -> Result<Option<Vec<[f64; 4]>>> {
        let model = analytic_shader(brdf);
        let has_double_form = match (&model, brdf) {
            (Some(model), _) => !self.without_double.contains(model),
            (None, Brdf::Measured(_)) => false,
            (None, _) => true,
        };
        if !self.device.float64 || !has_double_form {
            return Ok(None);
        }
        let job = self.sampler_job(brdf, wo, context)?;
        let per_dispatch = EVALUATIONS_PER_DISPATCH.min(per_buffer::<[f64; 4]>(&self.device));
        if self.density64.is_none() {
            let shader = Shader::new(&self.device, context.compiler, ("brdf_density64.comp", 1), (6, 1))?;
            self.density64 = Some(shader.with_double_models());
        }
        let Some(shader) = self.density64.as_mut() else { return Ok(None) };
        // A .brdf file whose GLSL does not compile in double is integrated in float; the built-in models' must.
        let pipeline = match (shader.pipeline(&self.device, context.compiler, &variant(brdf)), model) {
            (Ok(pipeline), _) => pipeline,
            (Err(Error::Shader { log, .. }), Some(model)) => {
                log::info!("{}: no double-precision evaluation ({log})", model.0.name());
                self.without_double.insert(model);
                return Ok(None);
            }
            (Err(e), _) => return Err(e),
        };
        let mut values = Vec::with_capacity(directions.len());
        for part in directions.chunks(per_dispatch) {
            let padded: Vec<[f64; 4]> = part.iter().map(|d| [d.x, d.y, d.z, 0.0]).collect();
            let input =
                self.device.create_buffer_with_data(&padded, vk::BufferUsageFlags::STORAGE_BUFFER, "directions")?;
            let bytes =
                dispatch(&self.device, pipeline, &[&job, &input], context.data, 32, &[push_constant(part.len())?])?;
            values.extend(doubles(&bytes).chunks_exact(4).map(|v| [v[0], v[1], v[2], v[3]]));
        }
        Ok(Some(values))
    }

    /// The job buffer of `brdf_sample.comp`: the material and wo.
    fn sampler_job(&self, brdf: &Brdf, wo: Vec3, context: ProbeContext) -> Result<Buffer> {
        let job = GpuAlbedoJob { material: GpuMaterial::new(brdf, context.data), wo: wo.extend(0.0).into() };
        self.device.create_buffer_with_data(&[job], vk::BufferUsageFlags::STORAGE_BUFFER, "sampler job")
    }
}

/// The narrowest lobe (GGX's alpha, [`Brdf::lobe_width`]) whose integrals float32 evaluation holds within
/// the albedo's tolerance: at GGX's alpha 0.01 the course's Cook-Torrance albedo in float is within 1e-6 of
/// an independent integral at every view; at 0.0025 it is 1.7e-5 off at 85 degrees, and at 4e-4 up to 4e-5
/// (near the peak |n x h| is alpha while wi + wo cancels to 6e-8: tests/analysis.rs).
const FLOAT_LOBE_WIDTH: f32 = 0.01;

/// The f32 of a result buffer's bytes.
fn floats(bytes: &[u8]) -> Vec<f32> {
    bytes.chunks_exact(4).map(|b| f32::from_ne_bytes([b[0], b[1], b[2], b[3]])).collect()
}

/// The f64 of a result buffer's bytes.
fn doubles(bytes: &[u8]) -> Vec<f64> {
    bytes.chunks_exact(8).map(|b| f64::from_ne_bytes([b[0], b[1], b[2], b[3], b[4], b[5], b[6], b[7]])).collect()
}

impl Renderer {
    /// `count` draws of `brdf`'s own sampler (`material_sample`, the exact mode's lobes) seen from the unit
    /// direction `wo` (frame n = +z, X = +x), from index `first` of the random stream `seed`: independent
    /// uniform points of pcg2d, the same on every run.
    ///
    /// # Errors
    /// As [`Renderer::probe_brdfs`].
    pub fn draw_brdf_samples(
        &mut self,
        brdf: &Brdf,
        wo: Vec3,
        (first, count): (u64, usize),
        seed: u32,
    ) -> Result<Vec<BrdfSample>> {
        self.with_probe(std::iter::once(brdf), |probe, context| {
            probe.draw_samples((brdf, wo), (first, count), seed, context)
        })
    }

    /// The density of `brdf`'s sampler seen from `wo` (`material_pdf`) and f_r cos(theta_i), at each of
    /// `directions` (frame n = +z, X = +x).
    ///
    /// # Errors
    /// As [`Renderer::probe_brdfs`].
    pub fn brdf_sampler_densities(
        &mut self,
        brdf: &Brdf,
        wo: Vec3,
        directions: &[Vec3],
    ) -> Result<Vec<SamplerDensity>> {
        self.with_probe(std::iter::once(brdf), |probe, context| {
            probe.sampler_densities((brdf, wo), directions, context)
        })
    }

    /// Whether `brdf`'s integrals (its directional albedo, its sampler's density) are taken in double
    /// precision, [`Renderer::brdf_sampler_densities_double`]'s: a `.brdf` file's always (its float GLSL may
    /// round away what a sharp lobe is made of: GGX's `a^2 - 1`), a built-in model's when its lobe is
    /// narrower than GGX's alpha 0.01 (`FLOAT_LOBE_WIDTH`); where the device has doubles.
    ///
    /// # Errors
    /// As [`Renderer::probe_brdfs`].
    pub fn integrates_in_double(&mut self, brdf: &Brdf) -> Result<bool> {
        let sharp = brdf.lobe_width().is_none_or(|width| width < FLOAT_LOBE_WIDTH);
        Ok(sharp && self.brdf_sampler_densities_double(brdf, Vec3::Z, &[])?.is_some())
    }

    /// The density of `brdf`'s sampler seen from `wo` and f_r cos(theta_i) at each of `directions` (frame
    /// n = +z, X = +x), as [`Renderer::brdf_sampler_densities`] but in double precision, the model's GLSL
    /// compiled with doubles (a `.brdf` file's, or the built-in models' own): (density, f_r cos θi's RGB).
    /// `None` for a measured table (looked up in float), on a device without doubles (`shaderFloat64`), or
    /// for a file whose GLSL has no double form.
    ///
    /// # Errors
    /// As [`Renderer::probe_brdfs`].
    pub fn brdf_sampler_densities_double(
        &mut self,
        brdf: &Brdf,
        wo: Vec3,
        directions: &[DVec3],
    ) -> Result<Option<Vec<[f64; 4]>>> {
        self.with_probe(std::iter::once(brdf), |probe, context| {
            probe.sampler_densities_double((brdf, wo), directions, context)
        })
    }
}
