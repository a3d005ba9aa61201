//! Golden images: every figure (at 300 x 200) and every scene of tests/scenes/, compared with the PNGs of
//! tests/golden/ to catch regressions. On the device that made them the comparison is tight: at most one
//! level on 99.9% of the pixels. On another device the images are held to the reference's tolerance
//! instead (mean <= 1 level, p99 <= 4, <= 1% over 3), and the test says so.
//!
//! `make bless` (VK_RENDER_BLESS=1) rewrites the golden images and tests/golden/DEVICE on purpose.

mod common;

use std::path::PathBuf;

use common::*;
use vk_render::compare::{compare, write_failure_images};
use vk_render::figures::FIGURES;
use vk_render::Scene;

fn golden_dir() -> PathBuf {
    root().join("tests/golden")
}

/// Every golden image's name and scene.
fn cases() -> Vec<(String, Scene)> {
    let small: Vec<vk_render::Override> =
        ["image.width=300", "image.height=200"].iter().map(|o| o.parse().unwrap()).collect();
    let mut cases: Vec<(String, Scene)> =
        FIGURES.iter().flat_map(|f| f.images).map(|image| (image.png_name(), image.scene(&small).unwrap())).collect();
    for entry in std::fs::read_dir(root().join("tests/scenes")).unwrap() {
        let name = entry.unwrap().file_name().to_string_lossy().into_owned();
        cases.push((name.replace(".toml", ".png"), test_scene(&name)));
    }
    cases.sort_by(|a, b| a.0.cmp(&b.0));
    cases
}

#[test]
fn images_match_the_golden_images() {
    let device = renderer().device_info().name.clone();
    let folder = golden_dir();
    if std::env::var_os("VK_RENDER_BLESS").is_some() {
        std::fs::create_dir_all(&folder).unwrap();
        for (name, scene) in cases() {
            render(&scene).to_rgb8(&scene.image).save(folder.join(&name)).unwrap();
            eprintln!("blessed tests/golden/{name}");
        }
        std::fs::write(folder.join("DEVICE"), format!("{device}\n")).unwrap();
        return;
    }
    let blessed_on = std::fs::read_to_string(folder.join("DEVICE")).expect("tests/golden/DEVICE (run `make bless`)");
    let same_device = blessed_on.trim() == device;
    if !same_device {
        eprintln!(
            "golden images were made on {:?}, this is {device:?}: holding them to the reference's tolerance",
            blessed_on.trim()
        );
    }
    let mut failures = Vec::new();
    for (name, scene) in cases() {
        let image = render(&scene).to_rgb8(&scene.image);
        let golden = image::open(folder.join(&name))
            .unwrap_or_else(|e| panic!("tests/golden/{name}: {e} (run `make bless` to make it)"))
            .into_rgb8();
        assert_eq!(image.dimensions(), golden.dimensions(), "{name}: size changed");
        let everything = vec![false; (image.width() * image.height()) as usize];
        let c = compare(&image, &golden, &everything);
        let within_one =
            image.pixels().zip(golden.pixels()).filter(|(a, b)| (0..3).all(|i| a.0[i].abs_diff(b.0[i]) <= 1)).count();
        let fraction_within_one = within_one as f64 / c.compared as f64;
        let passed = if same_device { fraction_within_one >= 0.999 } else { acceptable(&c) };
        if !passed {
            let paths = write_failure_images(
                &root().join("target/test-output"),
                &format!("golden-{name}"),
                &image,
                &golden,
                &everything,
            )
            .unwrap();
            failures.push(format!(
                "{name}: {c}, {:.3}% within one level; see {}",
                100.0 * fraction_within_one,
                paths.iter().map(|p| p.display().to_string()).collect::<Vec<_>>().join(", ")
            ));
        }
    }
    assert!(failures.is_empty(), "images differ from tests/golden/:\n{}", failures.join("\n"));
}

#[test]
fn every_golden_image_has_a_scene() {
    let names: Vec<String> = cases().into_iter().map(|(name, _)| name).collect();
    for entry in std::fs::read_dir(golden_dir()).unwrap() {
        let name = entry.unwrap().file_name().to_string_lossy().into_owned();
        assert!(
            name == "DEVICE" || names.contains(&name),
            "tests/golden/{name} has no scene: remove it or `make bless`"
        );
    }
}
