//! The golden images of tests/golden/: every figure at 300 x 200 and every scene of tests/scenes/, each
//! with its file name. Shared by the golden tests and `make bless` (examples/bless.rs), which makes them.

use std::path::PathBuf;

use vk_render::figures::FIGURES;
use vk_render::{Override, Scene};

/// The folder of the golden PNGs.
pub fn folder() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/golden")
}

/// Every golden image's file name and scene, sorted by name.
pub fn cases() -> Vec<(String, Scene)> {
    let small: Vec<Override> = ["image.width=300", "image.height=200"].iter().map(|o| o.parse().unwrap()).collect();
    let mut cases: Vec<(String, Scene)> =
        FIGURES.iter().flat_map(|f| f.images).map(|image| (image.png_name(), image.scene(&small).unwrap())).collect();
    let scenes = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/scenes");
    for entry in std::fs::read_dir(&scenes).unwrap() {
        let path = entry.unwrap().path();
        let name = path.file_name().unwrap().to_string_lossy().replace(".toml", ".png");
        cases.push((name, Scene::load(&path, &[]).unwrap()));
    }
    cases.sort_by(|a, b| a.0.cmp(&b.0));
    cases
}
