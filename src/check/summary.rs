//! A check as plain data: what `vk-render check` prints, the Python package's `vk_render.check` returns as a
//! dict (converted from its JSON) and the server's `POST /api/check` answers as JSON, made in one place so
//! that none can say something different.

use serde::Serialize;

use super::report::Checked;
use crate::scene::Scene;
pub use check_rules::{RegionStatistics, Statistics};

/// The outcome of a check, in the words of `vk-render check`.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Summary {
    /// Within the tolerance and explained by no mistake.
    pub matches: bool,
    /// "matches", "mistake", "tie" or "unexplained".
    pub verdict: &'static str,
    /// The mistakes the diagnosis names: one, the tied ones, or none.
    pub mistakes: Vec<NamedMistake>,
    /// The differences against the exact image, over the judged pixels.
    pub statistics: Statistics,
    /// The same per object and region.
    pub regions: Vec<RegionStatistics>,
    /// For a tie: the practical's scene that tells the tied mistakes apart, as `NAME --set 'KEY=VALUE' ...`.
    pub tells_apart: Option<String>,
    /// How far apart the tied mistakes' renders are on that scene, in 8-bit levels: the least distance
    /// between two of them.
    pub tells_apart_levels: Option<f64>,
    /// When no mistake explains the image: the objects whose own model explains it with other parameters.
    pub wrong_parameters: Vec<WrongParameter>,
}

/// A mistake of the catalogue.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct NamedMistake {
    /// Its name in the catalogue, e.g. `"lambert-without-pi"`.
    pub name: &'static str,
    /// What went wrong, in one sentence.
    pub explanation: &'static str,
    /// The formula as it should be.
    pub should_be: &'static str,
    /// The formula as the image suggests it is.
    pub looks_like: &'static str,
}

/// An object's parameters fitted to the image where they differ from the scene's.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct WrongParameter {
    /// The object's index in the scene.
    pub object: usize,
    /// The `[material.NAME]` it uses.
    pub material: String,
    /// Its model's name in scene files, e.g. `"cook-torrance"`.
    pub model: &'static str,
    /// Each differing parameter's fitted components, and the scene's (in JSON, objects by name).
    #[serde(serialize_with = "by_name")]
    pub fitted: Vec<(String, Vec<f32>)>,
    /// The scene's values of the same parameters, in the same order.
    #[serde(serialize_with = "by_name")]
    pub scene: Vec<(String, Vec<f32>)>,
    /// The fitted model's root mean square difference from the image over the object's pixels, in 8-bit levels.
    pub residual_levels: f64,
    /// The same of the scene's own material.
    pub scene_levels: f64,
}

/// Named values as an object, in their order.
fn by_name<S: serde::Serializer>(values: &[(String, Vec<f32>)], serializer: S) -> Result<S::Ok, S::Error> {
    serializer.collect_map(values.iter().map(|(name, v)| (name, v)))
}

impl Summary {
    /// The summary of `checked`, a check of an image against `scene`.
    pub fn of(checked: &Checked, scene: &Scene) -> Self {
        let mistakes = checked
            .mistakes()
            .into_iter()
            .map(|m| NamedMistake {
                name: m.name,
                explanation: m.explanation,
                should_be: m.should_be,
                looks_like: m.looks_like,
            })
            .collect();
        let regions = checked.regions.iter().map(RegionStatistics::from).collect();
        let wrong_parameters = checked
            .wrong_parameters
            .iter()
            .map(|wrong| {
                let object = &scene.objects[wrong.object];
                WrongParameter {
                    object: wrong.object,
                    material: object.material.clone(),
                    model: object.brdf.name(),
                    fitted: wrong.differing.iter().map(|(name, fitted, _)| (name.clone(), fitted.clone())).collect(),
                    scene: wrong.differing.iter().map(|(name, _, given)| (name.clone(), given.clone())).collect(),
                    residual_levels: wrong.fitted.residual_levels,
                    scene_levels: wrong.fitted.scene_levels,
                }
            })
            .collect();
        Self {
            matches: checked.matches(),
            verdict: checked.diagnosis.verdict.word(),
            mistakes,
            statistics: (&checked.diagnosis.against_exact).into(),
            regions,
            tells_apart: checked.tells_apart.map(|(shows_on, _)| scene_words(shows_on)),
            tells_apart_levels: checked.tells_apart.map(|(_, levels)| levels),
            wrong_parameters,
        }
    }
}

impl Summary {
    /// The summary as JSON, as the server answers it and the Python package reads it into a dict.
    ///
    /// # Errors
    /// serde_json's (none for these types, whose keys are all strings).
    pub fn to_json(&self) -> serde_json::Result<String> {
        serde_json::to_string(self)
    }
}

/// A scene of the practical and its overrides as a command line's words: `NAME --set 'KEY=VALUE' ...`.
pub fn scene_words((name, overrides): (&str, &[&str])) -> String {
    let sets: Vec<String> = overrides.iter().map(|o| format!("--set '{o}'")).collect();
    format!("{name} {}", sets.join(" ")).trim_end().to_string()
}
