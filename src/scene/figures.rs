//! The practical's figures: which scene files make each one and how their tiles are labelled.
//!
//! The scene files of assets/scenes/ are embedded, so `vk-render figures` works from any folder.

use std::path::Path;

use crate::error::Result;
use crate::scene::{Override, Scene};

/// One image of a figure: its scene file (under assets/scenes/) and its label on the contact sheet.
pub struct FigureImage {
    /// The scene file's name under assets/scenes/, e.g. `fig1-lambert.toml`.
    pub file: &'static str,
    /// Its tile's label on the contact sheet.
    pub label: &'static str,
    text: &'static str,
}

impl FigureImage {
    /// The image's scene with `overrides`, parsed as if read from assets/scenes/.
    ///
    /// # Errors
    /// `Error::Scene` if an override does not fit (the tests make sure the embedded files are valid).
    pub fn scene(&self, overrides: &[Override]) -> Result<Scene> {
        Scene::parse(self.text, &Path::new("assets/scenes").join(self.file), overrides)
    }

    /// The scene file's text.
    pub fn text(&self) -> &'static str {
        self.text
    }

    /// The file name of the rendered image: the scene's name with .png.
    pub fn png_name(&self) -> String {
        format!("{}.png", self.file.trim_end_matches(".toml"))
    }
}

/// The practical's image whose scene file is `name` (with or without .toml), e.g. "fig2-oren-nayar-sigma-0.6".
pub fn practical_image(name: &str) -> Option<&'static FigureImage> {
    let file = format!("{}.toml", name.trim_end_matches(".toml"));
    FIGURES.iter().flat_map(|figure| figure.images).find(|image| image.file == file)
}

/// A figure of the practical and the images it is made of.
pub struct Figure {
    /// The contact sheet's file stem, e.g. "figure-2-oren-nayar".
    pub name: &'static str,
    /// The sheet's title.
    pub title: &'static str,
    /// Its images, in the order of the sheet.
    pub images: &'static [FigureImage],
}

macro_rules! image {
    ($file:literal, $label:literal) => {
        FigureImage { file: $file, label: $label, text: include_str!(concat!("../../assets/scenes/", $file)) }
    };
}

/// Every figure of the practical that vk-render reproduces.
pub const FIGURES: &[Figure] = &[
    Figure { name: "figure-1-lambert", title: "Figure 1 - Lambert", images: &[image!("fig1-lambert.toml", "lambert")] },
    Figure {
        name: "figure-2-oren-nayar",
        title: "Figure 2 - Oren-Nayar",
        images: &[
            image!("fig2-oren-nayar-sigma-0.0.toml", "sigma = 0"),
            image!("fig2-oren-nayar-sigma-0.2.toml", "sigma = 0.2"),
            image!("fig2-oren-nayar-sigma-0.4.toml", "sigma = 0.4"),
            image!("fig2-oren-nayar-sigma-0.6.toml", "sigma = 0.6"),
        ],
    },
    Figure {
        name: "figure-3-plastic",
        title: "Figure 3 - Plastic (Lambert + Phong)",
        images: &[
            image!("fig3-plastic-s-8.toml", "s = 8"),
            image!("fig3-plastic-s-16.toml", "s = 16"),
            image!("fig3-plastic-s-32.toml", "s = 32"),
            image!("fig3-plastic-s-64.toml", "s = 64"),
        ],
    },
    Figure {
        name: "figure-4-gold",
        title: "Figure 4 - Cook-Torrance gold, roughness 0.3",
        images: &[
            image!("fig4-gold-metalness-0.0.toml", "metalness = 0"),
            image!("fig4-gold-metalness-0.5.toml", "metalness = 0.5"),
            image!("fig4-gold-metalness-1.0.toml", "metalness = 1"),
        ],
    },
    Figure {
        name: "figure-5-golden-bunny",
        title: "Figure 5 - Golden bunny",
        images: &[image!("fig5-golden-bunny.toml", "cook-torrance gold, metalness 1")],
    },
    Figure {
        name: "figure-6-phong-blinn-phong",
        title: "Figure 6 - Phong and Blinn-Phong at a grazing angle",
        images: &[image!("fig6-phong.toml", "phong"), image!("fig6-blinn-phong.toml", "blinn-phong")],
    },
];

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_figure_scene_is_valid_and_every_scene_file_is_in_a_figure() {
        let mut files: Vec<&str> = Vec::new();
        for figure in FIGURES {
            for image in figure.images {
                image.scene(&[]).unwrap_or_else(|e| panic!("{e}"));
                files.push(image.file);
            }
        }
        let folder = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scenes");
        for entry in std::fs::read_dir(folder).unwrap() {
            let name = entry.unwrap().file_name().to_string_lossy().into_owned();
            assert!(files.contains(&name.as_str()), "assets/scenes/{name} belongs to no figure");
        }
    }
}
