//! The golden images of tests/golden/: every figure at 300 x 200, every scene of tests/scenes/ and a measured
//! material, each with its file name. Shared by the golden tests and `make bless` (examples/bless.rs), which
//! makes them.

use std::path::PathBuf;

use vk_render::scene::figures::FIGURES;
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
    cases.push(("measured-copper.png".into(), measured_copper()));
    cases.sort_by(|a, b| a.0.cmp(&b.0));
    cases
}

/// A measured sphere on a plane, two lights with shadows. Its MERL file (35 MB, not kept in the repository)
/// is a Cook-Torrance copy tabulated from the Rust mirror, the same bytes each time, written into the
/// temporary folder under a name of this call's and renamed into place.
fn measured_copper() -> Scene {
    use vk_render::brdf::{Brdf, DiffuseModel, MeasuredTable};
    let folder = std::env::temp_dir().join("vk-render-golden");
    std::fs::create_dir_all(&folder).unwrap();
    let path = folder.join("copper.binary");
    let copper = Brdf::CookTorrance {
        kd: glam::Vec3::new(0.5, 0.35, 0.3),
        f0: glam::Vec3::new(0.95, 0.64, 0.54),
        roughness: 0.35,
        metalness: 0.6,
        diffuse: DiffuseModel::OrenNayar,
    };
    let table = MeasuredTable::tabulate(path.clone(), |wi, wo| copper.eval(glam::Vec3::Z, wi, wo));
    static WRITES: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    let write = WRITES.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let partial = folder.join(format!("copper.binary.{}-{write}", std::process::id()));
    std::fs::write(&partial, table.to_bytes()).unwrap();
    std::fs::rename(&partial, &path).unwrap();
    let text = "[image]\nwidth = 300\nheight = 200\nsamples = 4\n\
                [camera]\nposition = [0, 2.5, -4]\nlook_at = [0, 0.6, 1]\n\
                [[light]]\nposition = [3, 3, 0]\npower = 40\n\
                [[light]]\nposition = [-3, 2, -1]\npower = 15\ncolor = [0.6, 0.7, 1.0]\n\
                [material.copper]\nbrdf = \"measured\"\nfile = \"copper.binary\"\n\
                [material.floor]\nbrdf = \"lambert\"\nkd = 0.6\n\
                [[object]]\nshape = \"plane\"\npoint = [0, 0, 0]\nnormal = [0, 1, 0]\nmaterial = \"floor\"\n\
                [[object]]\nshape = \"sphere\"\ncenter = [0, 0.8, 1]\nradius = 0.8\nmaterial = \"copper\"\n";
    Scene::parse(text, &folder.join("measured-copper.toml"), &[]).unwrap()
}
