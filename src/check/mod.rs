//! Diagnosing a student's image against the exact one (`vk-render check`): the correct render and the render
//! of every mistake of the [`catalogue`] on the same scene, each compared with the student's image in a way
//! JPEG cannot fool, and ranked by how well they explain it. A layer above render, like the analysis.

pub mod catalogue;
pub mod report;
pub mod summary;

use image::RgbImage;

use crate::error::{Error, Result};
use crate::pictures::output::tonemap;
use crate::render::Renderer;
use crate::scene::Scene;
use crate::scene::View;
use crate::vulkan::ShaderSources;
use catalogue::{Mistake, ShaderEdit, ShowsOn, Variant};
pub use check_rules::{
    blurred, blurred_differences, differences, judged_pixels, regions, Region, Stats, EDGE_MARGIN, GRAZING_BAND,
    MATCH_P99, MATCH_RMS,
};

/// One candidate explanation: the correct render (no mistake) or a mistake's.
pub struct Candidate {
    /// The mistake rendered, `None` for the correct render.
    pub mistake: Option<&'static Mistake>,
    /// Its render, after the scene's output transform.
    pub image: RgbImage,
}

/// Renders the correct image of `scene` and each of `mistakes`' on `renderer`, telling `progress` how many
/// of how many are done. The renderer's shaders are the embedded ones again at the end.
///
/// # Errors
/// What rendering returns; `Error::Shader` naming a mistake whose edit no longer fits the shaders.
pub fn render_candidates(
    renderer: &mut Renderer,
    scene: &Scene,
    mistakes: &[&'static Mistake],
    mut progress: impl FnMut(usize, usize),
) -> Result<Vec<Candidate>> {
    let exact = renderer.render_rgb8(scene)?;
    let mut images: Vec<Option<RgbImage>> = vec![None; mistakes.len()];
    let mut done = 0;
    // The mistakes of the scene and of the output first, on the embedded shaders; then those of the shaders,
    // each on its variant, the embedded shaders put back once at the end (a failed render too).
    for (image, mistake) in images.iter_mut().zip(mistakes) {
        crate::interrupt::check()?;
        let made = match mistake.variant {
            Variant::Shader(_) => continue,
            Variant::Scene(change) => {
                let mut changed = scene.clone();
                change(&mut changed);
                renderer.render_rgb8(&changed)?
            }
            Variant::Rounding => rounded(&renderer.render(scene)?, scene),
        };
        *image = Some(made);
        done += 1;
        progress(done, mistakes.len());
    }
    let reached = files_reached(scene);
    let mut shader_variants = || -> Result<()> {
        for (image, mistake) in images.iter_mut().zip(mistakes) {
            let Variant::Shader(edits) = mistake.variant else { continue };
            crate::interrupt::check()?;
            let sources = edits
                .iter()
                .try_fold(ShaderSources::default(), |sources, e| sources.with_replaced(e.file, e.from, e.to))
                .map_err(|log| Error::Shader { path: mistake.name.to_string(), log })?;
            *image = Some(if reaches(reached.as_ref(), edits) {
                renderer.set_shaders(sources)?;
                renderer.render_rgb8(scene)?
            } else {
                exact.clone()
            });
            done += 1;
            progress(done, mistakes.len());
        }
        Ok(())
    };
    let rendered = shader_variants();
    if mistakes.iter().any(|m| matches!(m.variant, Variant::Shader(_))) {
        renderer.set_shaders(ShaderSources::default())?;
    }
    rendered?;
    let mut candidates = vec![Candidate { mistake: None, image: exact }];
    candidates.extend(
        mistakes
            .iter()
            .zip(images)
            .filter_map(|(&mistake, image)| image.map(|image| Candidate { mistake: Some(mistake), image })),
    );
    Ok(candidates)
}

/// The shader files whose edits can change `scene`'s image, or `None` for every file. An edit of a model's
/// file (`brdf/X.glsl`) reaches only the materials whose model's file includes it ([`Brdf::shader_file`] and
/// what it includes), and renders the very bytes of the correct image where none does (`tests/check.rs`
/// breaks each file and holds every model to it): a check of a Lambert figure then renders none of the
/// mistakes of Phong, Blinn-Phong, Oren-Nayar and Cook-Torrance. A measured or analytic material, a term
/// view or an environment (whose samplers and albedo tables are not told apart here) may be reached by any.
///
/// [`Brdf::shader_file`]: crate::brdf::Brdf::shader_file
fn files_reached(scene: &Scene) -> Option<std::collections::BTreeSet<String>> {
    if scene.image.view != View::Radiance || scene.environment.is_some() {
        return None;
    }
    let sources = ShaderSources::default();
    let mut reached = std::collections::BTreeSet::new();
    for brdf in scene.materials.values() {
        reached.extend(sources.included_by(brdf.shader_file()?));
    }
    Some(reached)
}

/// Whether shader edits `edits` can change an image whose reached files are `reached` ([`files_reached`]):
/// an edit outside the models' files (`brdf/`) always can.
fn reaches(reached: Option<&std::collections::BTreeSet<String>>, edits: &[ShaderEdit]) -> bool {
    reached.is_none_or(|files| edits.iter().any(|edit| !edit.file.starts_with("brdf/") || files.contains(edit.file)))
}

/// The course's output transform with the levels rounded instead of truncated.
fn rounded(hdr: &crate::HdrImage, scene: &Scene) -> RgbImage {
    let settings = &scene.image;
    let level = |c: f32| {
        let c = tonemap(c * settings.exposure, settings.tonemap);
        if c.is_nan() {
            0
        } else {
            (c.clamp(0.0, 1.0) * 255.0).round() as u8
        }
    };
    let bytes = hdr.pixels.iter().flat_map(|p| p.to_array()).map(level).collect();
    RgbImage::from_raw(hdr.width, hdr.height, bytes).unwrap_or_default()
}

/// What the candidates say of an image.
pub struct Diagnosis {
    /// The image against the correct render.
    pub against_exact: Stats,
    /// Every candidate's distance from the image ([`Stats::distance`]: the root mean square with the bias
    /// weighed in), best first (the correct render among them).
    pub ranking: Vec<(Option<&'static Mistake>, f64)>,
    /// The verdict.
    pub verdict: Verdict,
}

/// What the diagnosis concludes, the mistakes named by their names in the catalogue.
pub type Verdict = check_rules::Verdict<&'static str>;

/// Ranks the candidates (the first the correct render) by how well they explain `mine`, by the rules of
/// crates/check-rules ([`check_rules::rank`]), which the browser's check page runs too.
pub fn diagnose(mine: &RgbImage, candidates: &[Candidate]) -> Diagnosis {
    let labelled: Vec<(Option<&'static Mistake>, &RgbImage)> =
        candidates.iter().map(|c| (c.mistake, &c.image)).collect();
    let ranked = check_rules::rank(mine, &labelled);
    let verdict = ranked.verdict().map(|mistake| mistake.name);
    Diagnosis { against_exact: ranked.against_exact, ranking: ranked.ranking, verdict }
}

/// The scene of the practical that tells `mistakes` apart best, among those where each shows (the
/// catalogue's), at `size`: where the two closest of their renders are farthest apart, and how far (the
/// distance of [`Stats::distance`], in levels). None when no scene separates every pair by more than twice
/// the match tolerance.
///
/// # Errors
/// What rendering returns.
pub fn scene_that_tells_apart(
    renderer: &mut Renderer,
    mistakes: &[&'static Mistake],
    (width, height): (u32, u32),
) -> Result<Option<(ShowsOn, f64)>> {
    let mut best: Option<(ShowsOn, f64)> = None;
    let mut tried: Vec<(&str, &[&str])> = Vec::new();
    for mistake in mistakes {
        let (name, overrides) = mistake.shows_on;
        if tried.contains(&(name, overrides)) {
            continue;
        }
        tried.push((name, overrides));
        let Some(image) = crate::scene::figures::practical_image(name) else { continue };
        let mut all: Vec<crate::Override> = vec![
            crate::Override::new("image.width", i64::from(width)),
            crate::Override::new("image.height", i64::from(height)),
        ];
        for text in overrides {
            all.push(text.parse().map_err(|message: String| Error::Scene { file: name.into(), message })?);
        }
        let scene = image.scene(&all)?;
        let candidates = render_candidates(renderer, &scene, mistakes, |_, _| {})?;
        let judged = judged_pixels(&candidates[0].image);
        let renders: Vec<Vec<[f32; 3]>> = candidates[1..].iter().map(|c| blurred(&c.image)).collect();
        let mut closest = f64::INFINITY;
        for (i, a) in renders.iter().enumerate() {
            for b in &renders[i + 1..] {
                closest = closest.min(Stats::of(blurred_differences(a, b, &judged).iter()).distance());
            }
        }
        if closest > 2.0 * MATCH_RMS && best.is_none_or(|(_, d)| closest > d) {
            best = Some(((name, overrides), closest));
        }
    }
    Ok(best)
}
