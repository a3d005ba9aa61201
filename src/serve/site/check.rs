//! What a `vk-render site` folder's check page decides with (`data/check/`): for each of the practical's
//! figures, at its own size (the practical's 600 x 400), the exact image and every mistake of the catalogue
//! rendered as `vk-render check` renders them, each distinct picture written once, and the objects' ids from
//! the CPU reference, from which the page's WebAssembly (crates/check-rules) tells a region's differences.
//! `data/check/index.json` lists it all, with the catalogue's words for each mistake.

use std::collections::HashMap;
use std::path::Path;

use serde_json::{json, Value as Json};

use vk_render::check::catalogue::{Mistake, CATALOGUE};
use vk_render::check::render_candidates;
use vk_render::pictures::output::png_bytes;
use vk_render::Renderer;

use super::folder::put;
use crate::serve::catalogue::Catalogue;

/// Writes `data/check/` into `folder`.
pub fn write(folder: &Path, catalogue: &Catalogue, renderer: &mut Renderer) -> anyhow::Result<()> {
    let everything: Vec<&'static Mistake> = CATALOGUE.iter().collect();
    let mut figures = Vec::new();
    for entry in catalogue.entries().filter(|e| e.figure) {
        let scene = &entry.scene;
        let (width, height) = (scene.image.width, scene.image.height);
        let data = format!("data/check/{}/", entry.id);
        let candidates = render_candidates(renderer, scene, &everything, |_, _| {})?;
        // Each distinct picture once: most mistakes leave most figures as they are.
        let mut pictures: Vec<String> = Vec::new();
        let mut known: HashMap<Vec<u8>, usize> = HashMap::new();
        let mut listed = Vec::new();
        for candidate in &candidates {
            let bytes = png_bytes(&candidate.image)?;
            let picture = match known.get(&bytes) {
                Some(&k) => k,
                None => {
                    let k = pictures.len();
                    let name = format!("{data}{k}.png");
                    put(folder, &name, &bytes)?;
                    pictures.push(name);
                    known.insert(bytes, k);
                    k
                }
            };
            listed.push((candidate.mistake, picture));
        }
        let traced = vk_render::reference::render(scene)?;
        let objects = object_picture(&traced.object_ids, width, height)
            .ok_or_else(|| anyhow::anyhow!("scene {}: more objects than a check page tells apart", entry.id))?;
        put(folder, &format!("{data}objects.png"), &png_bytes(&objects)?)?;
        figures.push(json!({
            "id": entry.id,
            "title": entry.title,
            "width": width,
            "height": height,
            "pictures": pictures,
            "candidates": listed.iter().map(|(m, k)| json!([m.map(|m| m.name), k])).collect::<Vec<_>>(),
            "objects": format!("{data}objects.png"),
        }));
    }
    let mistakes: serde_json::Map<String, Json> = CATALOGUE
        .iter()
        .map(|m| {
            let words = json!({ "explanation": m.explanation, "should_be": m.should_be, "looks_like": m.looks_like });
            (m.name.to_string(), words)
        })
        .collect();
    let index = json!({ "figures": figures, "mistakes": mistakes });
    put(folder, "data/check/index.json", serde_json::to_string(&index)?.as_bytes())
}

/// The objects' ids as a picture: grey level 0 the background, k + 1 object k (every channel alike, so that
/// the page reads it as the colour PNG it reads every picture as); None past 254 objects.
fn object_picture(object_ids: &[Option<usize>], width: u32, height: u32) -> Option<image::RgbImage> {
    let levels: Option<Vec<u8>> =
        object_ids.iter().map(|id| id.map_or(Some(0), |k| u8::try_from(k + 1).ok())).collect();
    let bytes = levels?.into_iter().flat_map(|level| [level; 3]).collect();
    image::RgbImage::from_raw(width, height, bytes)
}
