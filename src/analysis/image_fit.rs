//! Fitting a model to an image: the parameters of one object's material whose render best explains its
//! pixels in an 8-bit image of the scene, the scene's own geometry and lights known.
//!
//! At each pixel the CPU reference gives what the render shades at the pixel's centre: the normal, the view
//! direction, and each point light's direction, radiance times cosine and visibility. The radiance there is
//! then sum over visible lights of f_r(wi, wo) times that, linear in the model's colours: the fit is
//! [`super::fit`]'s solver (colours by least squares, the shape parameter searched) on the image's values
//! with the output transform inverted. Pixels are left out where the answer is not the shading of that
//! point alone: within a pixel of another object or of a shadow's edge (MSAA mixes them, and a shadow map
//! places its edges apart from a ray's), and where a channel is clipped (0 or 255 stands for a range), or
//! within [`CLIP_MARGIN`] pixels of a channel at [`CLIP_LEVEL`] or above (JPEG rings a clipped highlight down
//! to 250 or so, and such a level stands for far less than the highlight's radiance).

use image::RgbImage;

use super::fit::{fit_values, Fit, FitModel};
use crate::brdf::Brdf;
use crate::error::{Error, Result};
use crate::pictures::output::level;
use crate::reference::{surface_points, SurfacePoint};
use crate::render::{ProbeCase, Renderer};
use crate::scene::{Encoding, Scene, Tonemap, View};

/// The level from which a channel counts as clipped (with its neighbours, see the module's notes).
pub const CLIP_LEVEL: u8 = 250;
/// How far around a clipped pixel others are left out.
pub const CLIP_MARGIN: i64 = 2;

/// A model fitted to an image.
#[derive(Clone, Debug)]
pub struct ImageFit {
    /// The fitted model, its residual on the fit's own measure and its parameters' errors.
    pub fit: Fit,
    /// The pixels fitted.
    pub pixels: usize,
    /// The root mean square over those pixels and their channels of (the fitted model's render - the
    /// image), in 8-bit levels after the output transform (from the middle of the range a level stands for).
    pub residual_levels: f64,
    /// The same of the scene's own material.
    pub scene_levels: f64,
}

/// The pixels of an object that a fit reads, and what the image says of each.
struct Observed {
    points: Vec<SurfacePoint>,
    /// The image's linear radiance, the output transform inverted.
    wanted: Vec<[f64; 3]>,
    /// The image's levels.
    levels: Vec<[u8; 3]>,
}

/// An 8-bit image of a scene as rendered (radiance, point lights), ready to fit: checked against the scene,
/// with what the reference sees at each pixel's centre (traced once for every object and model fitted).
pub struct SceneImage<'a> {
    scene: &'a Scene,
    image: &'a RgbImage,
    path: &'a std::path::Path,
    points: Vec<Option<SurfacePoint>>,
}

impl<'a> SceneImage<'a> {
    /// `image`, read from `path` (named in errors), as an image of `scene`.
    ///
    /// # Errors
    /// `Error::Input` naming the image when it is not the scene's size; `Error::Scene` for a scene a fit cannot
    /// read (an environment's light, a term view); what the reference returns.
    pub fn new(scene: &'a Scene, image: &'a RgbImage, path: &'a std::path::Path) -> Result<Self> {
        let scene_error = |message: String| Error::Scene { file: scene.source.clone(), message };
        if scene.environment.is_some() {
            return Err(scene_error(
                "a fit to an image reads point lights alone; this scene has an [environment]".into(),
            ));
        }
        if scene.image.view != View::Radiance {
            return Err(scene_error(format!(
                "image.view = \"{}\": a fit to an image reads the radiance view",
                scene.image.view.name()
            )));
        }
        let size = (scene.image.width, scene.image.height);
        if image.dimensions() != size {
            return Err(Error::Input {
                path: path.to_path_buf(),
                message: format!(
                    "{} x {} pixels, and the scene renders {} x {}",
                    image.width(),
                    image.height(),
                    size.0,
                    size.1
                ),
            });
        }
        Ok(Self { scene, image, path, points: surface_points(scene)? })
    }

    /// Fits `model` to object `object`'s pixels; `progress` is told how many models the solver has evaluated.
    ///
    /// # Errors
    /// `Error::Scene` for an object the scene lacks; `Error::Input` naming the image when it leaves too few
    /// pixels of the object to fit; what the probe pass returns.
    pub fn fit(
        &self,
        renderer: &mut Renderer,
        object: usize,
        model: &FitModel,
        progress: impl FnMut(usize),
    ) -> Result<ImageFit> {
        let scene = self.scene;
        let target = object_of(scene, object)?;
        let observed = observe(scene, &self.points, self.image, object);
        if observed.points.len() < 16 {
            return Err(Error::Input {
                path: self.path.to_path_buf(),
                message: format!(
                    "only {} pixels of object {object} are unclipped and away from edges and shadows' edges: too \
                     few to fit",
                    observed.points.len()
                ),
            });
        }
        let weights = vec![1.0; observed.points.len()];
        let values = |brdfs: &[Brdf]| rendered_values(renderer, brdfs, &observed.points);
        let fit = fit_values(&target.brdf, model, &observed.wanted, &weights, values, progress)?;
        // The fitted model's render and the scene's own material's, in one probe.
        let mut renders =
            rendered_values(renderer, &[fit.brdf.clone(), target.brdf.clone()], &observed.points)?.into_iter();
        let (fitted, own) = (renders.next().unwrap_or_default(), renders.next().unwrap_or_default());
        let residual_levels = residual_levels(&fitted, &observed.levels, scene);
        let scene_levels = self::residual_levels(&own, &observed.levels, scene);
        Ok(ImageFit { pixels: observed.points.len(), residual_levels, scene_levels, fit })
    }
}

/// Object `object` of `scene`.
///
/// # Errors
/// `Error::Scene` naming the number when the scene has no such object.
pub fn object_of(scene: &Scene, object: usize) -> Result<&crate::scene::Object> {
    scene.objects.get(object).ok_or_else(|| Error::Scene {
        file: scene.source.clone(),
        message: format!("--object {object}: the scene has {} objects (numbered from 0)", scene.objects.len()),
    })
}

/// The object's pixels the fit reads (see the module's notes), with the image's values.
fn observe(scene: &Scene, points: &[Option<SurfacePoint>], image: &RgbImage, object: usize) -> Observed {
    let (w, h) = (scene.image.width as i64, scene.image.height as i64);
    let at = |x: i64, y: i64| points[(y * w + x) as usize].as_ref();
    // What the renders agree on at a pixel: its object, and which lights reach it.
    let signature =
        |p: Option<&SurfacePoint>| p.map(|p| (p.object, p.lights.iter().map(|l| l.visible).collect::<Vec<_>>()));
    let clipped = |x: i64, y: i64| image.get_pixel(x as u32, y as u32).0.iter().any(|&l| l >= CLIP_LEVEL);
    let near_clipped = |x: i64, y: i64| {
        (-CLIP_MARGIN..=CLIP_MARGIN).any(|dy| {
            (-CLIP_MARGIN..=CLIP_MARGIN).any(|dx| {
                let (nx, ny) = (x + dx, y + dy);
                (0..w).contains(&nx) && (0..h).contains(&ny) && clipped(nx, ny)
            })
        })
    };
    let mut observed = Observed { points: Vec::new(), wanted: Vec::new(), levels: Vec::new() };
    for y in 0..h {
        for x in 0..w {
            let Some(point) = at(x, y) else { continue };
            if point.object != object {
                continue;
            }
            let here = signature(Some(point));
            let inside = (-1..=1).all(|dy| {
                (-1..=1).all(|dx| {
                    let (nx, ny) = (x + dx, y + dy);
                    (0..w).contains(&nx) && (0..h).contains(&ny) && signature(at(nx, ny)) == here
                })
            });
            let levels = image.get_pixel(x as u32, y as u32).0;
            if !inside || levels.contains(&0) || near_clipped(x, y) {
                continue;
            }
            observed.wanted.push(levels.map(|l| linear_of(l, scene)));
            observed.levels.push(levels);
            observed.points.push(point.clone());
        }
    }
    observed
}

/// The linear radiance an 8-bit level stands for: the middle of its range, back through the encoding, the
/// tone curve and the exposure (each invertible below the clip).
fn linear_of(level: u8, scene: &Scene) -> f64 {
    let settings = &scene.image;
    let encoded = f64::from(level) / 255.0;
    let toned = match settings.encoding {
        // Truncated: the level stands for [l, l + 1) / 255.
        Encoding::Linear => encoded + 0.5 / 255.0,
        // Rounded: for [l - 1/2, l + 1/2] / 255 of the encoded value; IEC 61966-2-1 inverted.
        Encoding::Srgb => {
            if encoded <= 0.040_45 {
                encoded / 12.92
            } else {
                ((encoded + 0.055) / 1.055).powf(2.4)
            }
        }
    };
    let exposed = match settings.tonemap {
        Tonemap::Clamp => toned,
        Tonemap::Reinhard => toned / (1.0 - toned),
        Tonemap::Aces => {
            // y = x (2.51 x + 0.03) / (x (2.43 x + 0.59) + 0.14): the positive root of
            // (2.43 y - 2.51) x^2 + (0.59 y - 0.03) x + 0.14 y = 0.
            let (a, b, c) = (2.43 * toned - 2.51, 0.59 * toned - 0.03, 0.14 * toned);
            (-b - (b * b - 4.0 * a * c).max(0.0).sqrt()) / (2.0 * a)
        }
    };
    exposed / f64::from(settings.exposure)
}

/// Each brdf's render at the points: the sum over visible lights of f_r (from the probe pass) times the
/// light's radiance times cosine.
fn rendered_values(renderer: &mut Renderer, brdfs: &[Brdf], points: &[SurfacePoint]) -> Result<Vec<Vec<[f64; 3]>>> {
    let mut cases = Vec::new();
    let mut owners = Vec::new();
    for (b, brdf) in brdfs.iter().enumerate() {
        for (p, point) in points.iter().enumerate() {
            for light in point.lights.iter().filter(|l| l.visible) {
                cases.push(ProbeCase { brdf: brdf.clone(), n: point.n, wi: light.wi, wo: point.wo });
                owners.push((b, p, light.irradiance));
            }
        }
    }
    let f = renderer.probe_brdfs(&cases)?;
    let mut values = vec![vec![[0.0f64; 3]; points.len()]; brdfs.len()];
    for (f, (b, p, irradiance)) in f.into_iter().zip(owners) {
        let radiance = (f * irradiance).as_dvec3();
        for c in 0..3 {
            values[b][p][c] += radiance[c];
        }
    }
    Ok(values)
}

/// The root mean square of the fitted render's levels (unrounded) against the middle of the image's levels.
fn residual_levels(fitted: &[[f64; 3]], levels: &[[u8; 3]], scene: &Scene) -> f64 {
    let middle = match scene.image.encoding {
        Encoding::Linear => 0.5,
        Encoding::Srgb => 0.0,
    };
    let sum: f64 = fitted
        .iter()
        .zip(levels)
        .flat_map(|(f, l)| {
            (0..3).map(move |c| f64::from(level(f[c] as f32, &scene.image)) - (f64::from(l[c]) + middle))
        })
        .map(|d| d * d)
        .sum();
    (sum / (3 * fitted.len()) as f64).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn levels_invert_the_output_transform() {
        let mut scene = Scene::parse("", std::path::Path::new("t.toml"), &[]).unwrap();
        for (tonemap, encoding) in [
            (Tonemap::Clamp, Encoding::Linear),
            (Tonemap::Reinhard, Encoding::Srgb),
            (Tonemap::Aces, Encoding::Srgb),
            (Tonemap::Aces, Encoding::Linear),
        ] {
            scene.image.tonemap = tonemap;
            scene.image.encoding = encoding;
            scene.image.exposure = 1.5;
            for l in [1u8, 17, 128, 254] {
                let back = level(linear_of(l, &scene) as f32, &scene.image);
                let expected = f32::from(l) + if encoding == Encoding::Linear { 0.5 } else { 0.0 };
                assert!((back - expected).abs() < 1e-3, "{tonemap:?} {encoding:?} {l}: {back}");
            }
        }
    }
}
