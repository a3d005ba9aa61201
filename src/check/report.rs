//! A whole check of one image, as data: what `vk-render check` prints and the Python package's `check`
//! returns are both read from a [`Checked`].

use std::path::Path;

use image::RgbImage;

pub use check_rules::decode_image;

use super::catalogue::{Mistake, ShowsOn, CATALOGUE};
use super::MATCH_RMS;
use super::{diagnose, regions, render_candidates, scene_that_tells_apart, Candidate, Diagnosis, Region, Verdict};
use crate::analysis::fit::{parameters, FitModel};
use crate::analysis::image_fit::{ImageFit, SceneImage};
use crate::error::{Error, Result};
use crate::render::Renderer;
use crate::scene::figures::practical_image;
use crate::scene::{Override, Scene};

/// The outcome of checking an image against a scene.
pub struct Checked {
    /// The exact render first, then each mistake's.
    pub candidates: Vec<Candidate>,
    /// The verdict and the ranking of the candidates.
    pub diagnosis: Diagnosis,
    /// The differences per object and region (lit body, unlit part, highlight, grazing band, open part).
    pub regions: Vec<Region>,
    /// For a tie: the practical's scene that tells the tied mistakes apart, and by how many levels their
    /// renders differ there at least (`None` when no scene does, or there is no tie).
    pub tells_apart: Option<(ShowsOn, f64)>,
    /// When no mistake explains the image: the objects whose own model, its parameters fitted to the image,
    /// explains their pixels where the scene's parameters do not.
    pub wrong_parameters: Vec<WrongParameters>,
}

/// An object whose pixels the scene's own model explains with other parameters.
pub struct WrongParameters {
    /// The object's index in the scene.
    pub object: usize,
    /// The fit of the object's model to the image.
    pub fitted: ImageFit,
    /// The parameters that differ from the scene's: name, the fitted components, the scene's.
    pub differing: Vec<(String, Vec<f32>, Vec<f32>)>,
}

/// A fit explains an object's pixels when its residual is within the match tolerance and at most this share
/// of the scene's own material's on the same pixels.
const EXPLAINS: f64 = 0.5;

/// Each object whose own model, fitted to `mine`, explains its pixels where the scene's parameters do not
/// (see [`WrongParameters`]); a parameter differs beyond three standard errors, 2% of the scene's value and
/// 0.01. Objects a fit cannot read (a measured material, an environment's light, too few pixels) are passed.
///
/// # Errors
/// What rendering and the reference return, but a fit's refusal of the scene or the image.
fn wrong_parameters(renderer: &mut Renderer, mine: &RgbImage, scene: &Scene) -> Result<Vec<WrongParameters>> {
    let mut found = Vec::new();
    let image = match SceneImage::new(scene, mine, Path::new("image")) {
        Ok(image) => image,
        Err(Error::Scene { .. } | Error::Input { .. }) => return Ok(found),
        Err(other) => return Err(other),
    };
    for (object, target) in scene.objects.iter().enumerate() {
        let Some(model) = FitModel::of(&target.brdf) else { continue };
        let fitted = match image.fit(renderer, object, &model, |_| {}) {
            Ok(fitted) => fitted,
            Err(Error::Scene { .. } | Error::Input { .. }) => continue,
            Err(other) => return Err(other),
        };
        if fitted.residual_levels > MATCH_RMS || fitted.residual_levels > EXPLAINS * fitted.scene_levels {
            continue;
        }
        let given = parameters(&target.brdf);
        let differing: Vec<_> = fitted
            .fit
            .parameters
            .iter()
            .filter_map(|p| given.iter().find(|(name, _)| *name == p.name).map(|(_, given)| (p, given)))
            .filter(|(p, given)| {
                p.values.iter().zip(*given).zip(&p.errors).any(|((&value, &given), error)| {
                    let tolerance = (3.0 * error.unwrap_or(0.0)).max(0.02 * f64::from(given.abs())).max(0.01);
                    f64::from((value - given).abs()) > tolerance
                })
            })
            .map(|(p, given)| (p.name.clone(), p.values.clone(), given.clone()))
            .collect();
        if !differing.is_empty() {
            found.push(WrongParameters { object, fitted, differing });
        }
    }
    Ok(found)
}

impl Checked {
    /// The exact image, at the checked image's size.
    pub fn exact(&self) -> &RgbImage {
        &self.candidates[0].image
    }

    /// Whether the image matches: within the tolerance and explained by no mistake.
    pub fn matches(&self) -> bool {
        self.diagnosis.against_exact.matches() && self.diagnosis.verdict == Verdict::Matches
    }

    /// The mistakes the diagnosis names: one, the tied ones, or none.
    pub fn mistakes(&self) -> Vec<&'static Mistake> {
        self.diagnosis.verdict.mistakes().iter().filter_map(|name| CATALOGUE.iter().find(|m| m.name == *name)).collect()
    }
}

/// Checks `mine` against `scene` rendered at its size (the caller sized the scene): every mistake of the
/// catalogue rendered, the diagnosis, the regions from the CPU reference's object ids, and for a tie the
/// scene that tells the tied mistakes apart. `progress` hears how many renders of how many are done.
///
/// # Errors
/// What rendering returns; `Error::Interrupted` when a stop was requested between renders.
pub fn check_image(
    renderer: &mut Renderer,
    mine: &RgbImage,
    scene: &Scene,
    progress: impl FnMut(usize, usize),
) -> Result<Checked> {
    let mistakes: Vec<&'static Mistake> = CATALOGUE.iter().collect();
    let candidates = render_candidates(renderer, scene, &mistakes, progress)?;
    let diagnosis = diagnose(mine, &candidates);
    let traced = crate::reference::render(scene)?;
    let regions = regions(mine, &candidates[0].image, &traced.object_ids);
    let mut checked = Checked { candidates, diagnosis, regions, tells_apart: None, wrong_parameters: Vec::new() };
    if matches!(checked.diagnosis.verdict, Verdict::Tie(_)) {
        checked.tells_apart = scene_that_tells_apart(renderer, &checked.mistakes(), mine.dimensions())?;
    }
    if checked.diagnosis.verdict == Verdict::Unexplained {
        checked.wrong_parameters = wrong_parameters(renderer, mine, scene)?;
    }
    Ok(checked)
}

/// The scene to check against: one of the practical's images by name, else a scene file (.toml).
///
/// # Errors
/// `Error::Scene` for a name that is neither, and what loading the scene returns.
pub fn scene_named(name: &str, overrides: &[Override]) -> Result<Scene> {
    if let Some(image) = practical_image(name) {
        return image.scene(overrides);
    }
    let path = Path::new(name);
    if path.extension().is_none_or(|e| e != "toml") {
        return Err(Error::Scene {
            file: path.to_path_buf(),
            message: format!(
                "--scene {name}: neither a scene file (.toml) nor one of the practical's images (vk-render check --list)"
            ),
        });
    }
    Scene::load(path, overrides)
}

/// An image to check: PNG or JPEG, 8-bit RGB (alpha, if any, left out); grey-scale and 16-bit images are
/// refused.
///
/// # Errors
/// `Error::Input` naming the file.
pub fn read_image(path: &Path) -> Result<RgbImage> {
    let error = |message: String| Error::Input { path: path.to_path_buf(), message };
    let bytes = crate::files::read_regular(path, "image", crate::files::MAX_IMAGE_BYTES).map_err(error)?;
    decode_image(&bytes, image::Limits::default()).map_err(error)
}
