//! `vk-render site`: the explorer as a static folder, served by any static file server with no vk-render
//! process behind it. The folder holds the server's own pages and scripts (src/serve/pages/, the same
//! files), its own `static/site.js` (what tells the scripts that they read files, not the API), the
//! translated shaders, and in `data/` what the API would answer for each catalogue scene, written once: the
//! scene list, each object's mesh, each measured table, each `.brdf` model's shaders, each environment and
//! each material's albedo table at the scene's own values (src/serve/pages/common.js's `dataUrl` names them),
//! and in `data/check/` the renders the check page decides with (src/serve/site/check.rs).
//! Every link is relative, so the folder works from any sub-path.

use std::collections::hash_map::{Entry as Slot, HashMap};
use std::path::{Path, PathBuf};

use anyhow::Context;
use clap::Args;
use serde_json::{json, Value as Json};

use vk_render::brdf::Brdf;
use vk_render::mesh::motion::motion_mesh;
use vk_render::{Renderer, RendererOptions};

use super::catalogue::{Catalogue, Entry};
use super::error::ApiError;
use super::{api, browser, description, pages};

mod check;
mod folder;

use folder::put;

#[derive(Args)]
pub struct SiteArgs {
    /// The folder to write: made anew (an empty folder or one that `vk-render site` wrote before is
    /// replaced; any other existing path is refused).
    #[arg(short, long, value_name = "DIR")]
    output: PathBuf,

    /// Also publish every scene file (.toml) of this folder, by its file's stem (repeat for more folders).
    #[arg(long, value_name = "DIR")]
    scenes: Vec<PathBuf>,
}

/// What the folder's `static/site.js` says (the server's says `null`).
const SITE_SCRIPT: &str = "// Written by vk-render site: the pages read the files of data/ in the API's place \
                           (src/serve/pages/site.js).\nexport const SITE = { data: \"data/\" };\n";

/// Writes the folder and prints what it holds.
pub fn run(args: SiteArgs, options: RendererOptions) -> anyhow::Result<()> {
    let catalogue = Catalogue::new(&args.scenes)?;
    let output = &args.output;
    let empty_folder = std::fs::read_dir(output).is_ok_and(|mut listing| listing.next().is_none());
    if output.exists() && !empty_folder && !output.join("static/site.js").is_file() {
        anyhow::bail!(
            "-o {}: it exists and is not an empty folder or one that vk-render site wrote; name a new folder",
            output.display()
        );
    }
    // Written beside it, then put in its place: a failure leaves no half-written folder.
    let name = output.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_else(|| "site".into());
    let partial = output.with_file_name(format!(".{name}.partial-{}", std::process::id()));
    let written = write(&partial, &catalogue, options);
    if let Err(error) = written {
        // Best effort: the error says what failed; a leftover partial folder is named as such.
        let _ = std::fs::remove_dir_all(&partial);
        return Err(error);
    }
    if output.exists() {
        std::fs::remove_dir_all(output).with_context(|| format!("-o {}: cannot replace it", output.display()))?;
    }
    std::fs::rename(&partial, output).with_context(|| format!("-o {}: cannot write it", output.display()))?;
    let (files, bytes) = size(output)?;
    let (_, check_bytes) = size(&output.join("data/check"))?;
    println!(
        "site: {} ({} scenes, {files} files, {:.1} MB, the check page's renders {:.1} MB of it): serve it as it is, \
         e.g. python3 -m http.server -d {}",
        output.display(),
        catalogue.entries().count(),
        bytes as f64 / 1e6,
        check_bytes as f64 / 1e6,
        output.display()
    );
    Ok(())
}

/// The folder's files and their bytes.
fn size(folder: &Path) -> anyhow::Result<(usize, u64)> {
    let mut total = (0, 0);
    for entry in std::fs::read_dir(folder)? {
        let entry = entry?;
        if entry.file_type()?.is_dir() {
            let (files, bytes) = size(&entry.path())?;
            total = (total.0 + files, total.1 + bytes);
        } else {
            total = (total.0 + 1, total.1 + entry.metadata()?.len());
        }
    }
    Ok(total)
}

fn failed(entry: &Entry, error: ApiError) -> anyhow::Error {
    anyhow::anyhow!("scene {}: {}", entry.id, error.message)
}

/// Every file of the folder, into `folder`.
fn write(folder: &Path, catalogue: &Catalogue, options: RendererOptions) -> anyhow::Result<()> {
    for (name, bytes) in pages::site_files() {
        put(folder, &name, bytes)?;
    }
    put(folder, "static/site.js", SITE_SCRIPT.as_bytes())?;
    put(folder, "static/shaders.json", browser::shaders_file().as_bytes())?;
    put(folder, "static/brdf-templates.json", browser::templates_file().as_bytes())?;
    let mut scenes = serde_json::to_value(description::describe(catalogue))?;
    let mut renderer = None;
    // Each `.brdf` model translated once, whichever scenes and materials name it (a second of work each).
    let mut translated: HashMap<u64, Vec<u8>> = HashMap::new();
    for (entry, described) in catalogue.entries().zip(scenes.as_array_mut().into_iter().flatten()) {
        // A material's files are named by its place among the scene's materials (names are any TOML key).
        let numbers: serde_json::Map<String, Json> =
            entry.scene.materials.keys().enumerate().map(|(k, name)| (name.clone(), json!(k))).collect();
        described["site"] = json!({ "materials": numbers });
        let data = format!("data/{}/", entry.id);
        // The objects placed once (an OBJ read once), each mesh and its lighter one where it has one.
        let placed =
            vk_render::mesh::place_objects(&entry.scene).map_err(|e| failed(entry, ApiError::from_library(&e)))?;
        for (object, placed) in placed.iter().enumerate() {
            put(folder, &format!("{data}mesh-{object}.bin"), &browser::mesh_bytes(&placed.mesh))?;
            if let Some(light) = motion_mesh(&placed.mesh) {
                put(folder, &format!("{data}mesh-{object}-motion.bin"), &browser::mesh_bytes(&light))?;
            }
        }
        for (k, brdf) in entry.scene.materials.values().enumerate() {
            match brdf {
                Brdf::Measured(table) => {
                    put(folder, &format!("{data}measured-{k}.bin"), &browser::measured_file(table))?
                }
                Brdf::Analytic(material) => {
                    let model = material.model();
                    let shaders = match translated.entry(model.key()) {
                        Slot::Occupied(known) => known.into_mut(),
                        Slot::Vacant(new) => new.insert(browser::analytic_file(model).map_err(|e| failed(entry, e))?),
                    };
                    put(folder, &format!("{data}analytic-{k}.json"), shaders)?;
                }
                _ => {}
            }
        }
        if let Some(environment) = &entry.scene.environment {
            let file = browser::environment_file(&entry.scene, environment).map_err(|e| failed(entry, e))?;
            put(folder, &format!("{data}environment.bin"), &file)?;
            let renderer = match &mut renderer {
                Some(renderer) => renderer,
                None => renderer.insert(Renderer::new(options.clone())?),
            };
            for (k, brdf) in entry.scene.materials.values().enumerate() {
                put(folder, &format!("{data}albedo-{k}.json"), api::albedo_file(renderer, brdf)?.as_bytes())?;
            }
        }
    }
    put(folder, "data/scenes.json", serde_json::to_string(&scenes)?.as_bytes())?;
    let renderer = match &mut renderer {
        Some(renderer) => renderer,
        None => renderer.insert(Renderer::new(options)?),
    };
    check::write(folder, catalogue, renderer)
}
