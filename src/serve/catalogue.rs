//! The scenes a server offers, made once at start: the practical's figures and every scene file of the
//! folders given with `--scenes`, each by its id (its file's stem). A request names a scene by id and only
//! by id: nothing a client sends is ever a path.

use std::collections::BTreeMap;
use std::path::PathBuf;

use anyhow::Context;
use vk_render::scene::figures::FIGURES;
use vk_render::{Override, Scene};

/// One scene of the catalogue.
pub struct Entry {
    pub id: String,
    /// The figure's label, or the file's name.
    pub title: String,
    /// The scene file's text, parsed again with each request's overrides.
    text: String,
    /// Where it was read from (mesh and material files are found beside it).
    path: PathBuf,
    /// The scene as its file says (no overrides).
    pub scene: Scene,
    /// Whether it is one of the practical's figures (a check without a scene is matched among those).
    pub figure: bool,
}

impl Entry {
    /// The scene with `overrides`, as `vk-render render --set` makes it.
    pub fn scene(&self, overrides: &[Override]) -> vk_render::Result<Scene> {
        Scene::parse(&self.text, &self.path, overrides)
    }

    /// The scene file's text (the explore page's download starts from it).
    pub fn text(&self) -> &str {
        &self.text
    }
}

/// Every scene offered, by id.
pub struct Catalogue {
    entries: BTreeMap<String, Entry>,
}

impl Catalogue {
    /// The practical's figures, then the `.toml` files of each folder (not their subfolders). Two scenes with
    /// one id, or a file that is not a valid scene, stop the server from starting, naming the files.
    pub fn new(folders: &[PathBuf]) -> anyhow::Result<Self> {
        let mut entries = BTreeMap::new();
        for figure in FIGURES {
            for image in figure.images {
                let id = image.file.trim_end_matches(".toml").to_string();
                let scene = image.scene(&[])?;
                let entry = Entry {
                    id: id.clone(),
                    title: format!("{}: {}", figure.title, image.label),
                    text: image.text().to_string(),
                    path: scene.source.clone(),
                    scene,
                    figure: true,
                };
                entries.insert(id, entry);
            }
        }
        for folder in folders {
            let listing = std::fs::read_dir(folder)
                .with_context(|| format!("--scenes {}: cannot read the folder", folder.display()))?;
            let mut files: Vec<PathBuf> = listing
                .filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|p| p.is_file() && p.extension().is_some_and(|e| e == "toml"))
                .collect();
            files.sort();
            for path in files {
                let id = path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
                if !is_id(&id) {
                    anyhow::bail!(
                        "{}: a scene's id is its file's stem, of letters, digits, '-', '_' and '.'",
                        path.display()
                    );
                }
                if let Some(other) = entries.get(&id) {
                    anyhow::bail!("{}: its id `{id}` is already {}'s", path.display(), other.path.display());
                }
                let text =
                    std::fs::read_to_string(&path).with_context(|| format!("{}: cannot read it", path.display()))?;
                let scene = Scene::parse(&text, &path, &[])?;
                let title = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
                entries.insert(id.clone(), Entry { id, title, text, path, scene, figure: false });
            }
        }
        Ok(Self { entries })
    }

    /// The scene `id`, if the catalogue has it.
    pub fn get(&self, id: &str) -> Option<&Entry> {
        self.entries.get(id)
    }

    /// Every scene, by id.
    pub fn entries(&self) -> impl Iterator<Item = &Entry> {
        self.entries.values()
    }
}

/// Whether `text` could be a scene's id (ids are file stems; anything else is no scene's).
pub fn is_id(text: &str) -> bool {
    !text.is_empty()
        && text.len() <= 128
        && !text.starts_with('.')
        && text.chars().all(|c| c.is_ascii_alphanumeric() || matches!(c, '-' | '_' | '.'))
}
