//! `vk-render check`'s diagnosis: every mistake of the catalogue, rendered on a scene of the practical where it
//! shows and saved as JPEG at quality 75 and 95, is diagnosed as that mistake (or as a tie that names it, when
//! mistakes look alike there); the correct render matches, as JPEG and as the course's own PNG.

mod common;

use std::collections::BTreeMap;

use image::RgbImage;
use vk_render::check::catalogue::{Mistake, CATALOGUE};
use vk_render::check::{diagnose, render_candidates, Candidate, Verdict};
use vk_render::scene::figures::practical_image;
use vk_render::Scene;

/// A practical's scene, small (the tests render every mistake on it), with the entry's overrides.
fn scene(name: &str, overrides: &[&str]) -> Scene {
    let mut all: Vec<vk_render::Override> =
        ["image.width=300", "image.height=210"].iter().map(|o| o.parse().unwrap()).collect();
    all.extend(overrides.iter().map(|o| o.parse().unwrap()));
    practical_image(name).expect("a practical's scene").scene(&all).expect("valid")
}

/// The image saved as JPEG at `quality` and read back, as a student's would be.
fn as_jpeg(image: &RgbImage, quality: u8) -> RgbImage {
    let mut bytes = Vec::new();
    image::codecs::jpeg::JpegEncoder::new_with_quality(&mut bytes, quality).encode_image(image).unwrap();
    image::load_from_memory(&bytes).unwrap().to_rgb8()
}

/// Every entry's scene, with the candidates rendered once for all the entries that show there.
fn candidates_by_scene() -> BTreeMap<(&'static str, Vec<&'static str>), Vec<Candidate>> {
    let everything: Vec<&'static Mistake> = CATALOGUE.iter().collect();
    let mut by_scene = BTreeMap::new();
    for mistake in CATALOGUE {
        let key = (mistake.shows_on.0, mistake.shows_on.1.to_vec());
        if by_scene.contains_key(&key) {
            continue;
        }
        let scene = scene(key.0, &key.1);
        let candidates = render_candidates(&mut common::renderer(), &scene, &everything, |_, _| {}).expect("renders");
        by_scene.insert(key, candidates);
    }
    by_scene
}

#[test]
fn every_mistake_is_diagnosed_from_its_jpeg_and_the_correct_image_matches() {
    let by_scene = candidates_by_scene();
    let mut failures = Vec::new();
    for ((name, overrides), candidates) in &by_scene {
        for quality in [75, 95] {
            let correct = diagnose(&as_jpeg(&candidates[0].image, quality), candidates);
            if correct.verdict != Verdict::Matches {
                failures.push(format!(
                    "{name} {overrides:?}: the correct render at quality {quality}: {:?} ({:?})",
                    correct.verdict, correct.against_exact
                ));
            }
        }
        let exact = diagnose(&candidates[0].image, candidates);
        assert_eq!(exact.verdict, Verdict::Matches, "{name}: the exact image");
        for candidate in &candidates[1..] {
            let mistake = candidate.mistake.unwrap();
            if (mistake.shows_on.0, mistake.shows_on.1.to_vec()) != (*name, overrides.clone()) {
                continue;
            }
            for quality in [75, 95] {
                let diagnosis = diagnose(&as_jpeg(&candidate.image, quality), candidates);
                let named = match &diagnosis.verdict {
                    Verdict::Mistake(found) => *found == mistake.name,
                    Verdict::Tie(found) => found.contains(&mistake.name),
                    _ => false,
                };
                let top: Vec<String> = diagnosis
                    .ranking
                    .iter()
                    .take(3)
                    .map(|(m, d)| format!("{} {d:.2}", m.map_or("correct", |m| m.name)))
                    .collect();
                eprintln!("{} q{quality}: {:?} [{}]", mistake.name, diagnosis.verdict, top.join(", "));
                if !named {
                    failures.push(format!(
                        "{} at quality {quality} on {name}: {:?} [{}]",
                        mistake.name,
                        diagnosis.verdict,
                        top.join(", ")
                    ));
                }
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn the_exact_image_of_every_figure_matches_as_its_jpeg() {
    // Only the correct render is a candidate here: the verdict is the tolerance's alone.
    for image in vk_render::scene::figures::FIGURES.iter().flat_map(|figure| figure.images) {
        let scene = scene(image.file.trim_end_matches(".toml"), &[]);
        let exact = common::renderer().render_rgb8(&scene).expect("render");
        let candidates = [Candidate { mistake: None, image: exact.clone() }];
        for mine in [exact.clone(), as_jpeg(&exact, 75)] {
            let diagnosis = diagnose(&mine, &candidates);
            assert_eq!(diagnosis.verdict, Verdict::Matches, "{}: {:?}", image.file, diagnosis.against_exact);
        }
    }
}

#[test]
fn every_catalogue_edit_fits_the_shaders_once() {
    use vk_render::check::catalogue::Variant;
    for mistake in CATALOGUE {
        if let Variant::Shader(edits) = mistake.variant {
            let sources = edits
                .iter()
                .try_fold(vk_render::vulkan::ShaderSources::default(), |s, e| s.with_replaced(e.file, e.from, e.to));
            assert!(sources.is_ok(), "{}: {:?}", mistake.name, sources.err());
        }
    }
    let mut names: Vec<&str> = CATALOGUE.iter().map(|m| m.name).collect();
    names.sort_unstable();
    names.dedup();
    assert_eq!(names.len(), CATALOGUE.len(), "two mistakes share a name");
}

/// `vk-render check` as a student runs it: exit 0 for a match, 1 for a difference (with the report), 2 for
/// bad input (and no report).
#[test]
fn check_exits_0_1_or_2_and_writes_its_report() {
    let folder = common::temp_dir();
    let path = |name: &str| folder.path().join(name);
    let fig1 = practical_image("fig1-lambert")
        .unwrap()
        .scene(&["image.width=160".parse().unwrap(), "image.height=120".parse().unwrap()])
        .unwrap();
    let exact = common::renderer().render_rgb8(&fig1).unwrap();
    as_jpeg(&exact, 75).save(path("mine.jpg")).unwrap();
    let check = |mine: &str, scene: &str, report: &str| {
        common::vk_render(&[
            "check",
            path(mine).to_str().unwrap(),
            "--scene",
            scene,
            "-o",
            path(report).to_str().unwrap(),
        ])
    };
    let output = check("mine.jpg", "fig1-lambert", "ok.png");
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert_eq!(output.status.code(), Some(0), "{stdout}{}", String::from_utf8_lossy(&output.stderr));
    assert!(
        stdout.contains(": matches") && stdout.contains("a match is a root mean square within 2 levels"),
        "{stdout}"
    );
    // Twice as bright: the Lambert without its 1/pi would be pi times, the radiance twice more; not a
    // known mistake, but a difference.
    let brighter =
        image::RgbImage::from_fn(160, 120, |x, y| image::Rgb(exact.get_pixel(x, y).0.map(|c| c.saturating_mul(2))));
    brighter.save(path("bright.png")).unwrap();
    let output = check("bright.png", "fig1-lambert", "report.png");
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert_eq!(output.status.code(), Some(1), "{stdout}");
    assert!(stdout.contains(": differs") && stdout.contains("sphere (object 0, material grey) lit body"), "{stdout}");
    assert!(image::open(path("report.png")).unwrap().width() > 3 * 160);
    // Bad input: exit 2, one line, no report.
    image::GrayImage::new(160, 120).save(path("grey.png")).unwrap();
    image::ImageBuffer::<image::Rgb<u16>, Vec<u16>>::new(160, 120).save(path("deep.png")).unwrap();
    std::fs::write(path("broken.jpg"), b"not a jpeg").unwrap();
    for (mine, scene, needle) in [
        ("grey.png", "fig1-lambert", "grey.png: a L8 image"),
        ("deep.png", "fig1-lambert", "deep.png: a Rgb16 image"),
        ("broken.jpg", "fig1-lambert", "broken.jpg: not a PNG or JPEG image"),
        ("missing.png", "fig1-lambert", "missing.png"),
        ("mine.jpg", "fig9-unknown", "--scene fig9-unknown: neither a scene file"),
    ] {
        let output = check(mine, scene, "bad.png");
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(2), "{mine} {scene}: {stderr}");
        assert!(stderr.lines().count() == 1 && stderr.contains(needle), "{mine} {scene}: {stderr}");
        assert!(!path("bad.png").exists(), "a report was written for bad input");
    }
    let list = common::vk_render(&["check", "--list"]);
    let stdout = String::from_utf8_lossy(&list.stdout);
    assert!(
        list.status.success()
            && stdout.contains("fig2-oren-nayar-sigma-0.6")
            && stdout.contains("gold-comma-operator:"),
        "{stdout}"
    );
}

#[test]
fn a_tie_names_every_mistake_and_a_scene_that_tells_them_apart() {
    use vk_render::check::scene_that_tells_apart;
    let named = |name: &str| CATALOGUE.iter().find(|m| m.name == name).unwrap();
    let (without_pi, no_falloff) = (named("lambert-without-pi"), named("no-distance-falloff"));
    // Two mistakes that render alike (here made so: one image for both) tie, and are named together.
    let fig1 = scene("fig1-lambert", &[]);
    let exact = common::renderer().render_rgb8(&fig1).unwrap();
    let mistaken = render_candidates(&mut common::renderer(), &fig1, &[without_pi], |_, _| {}).unwrap().remove(1).image;
    let candidates = [
        Candidate { mistake: None, image: exact },
        Candidate { mistake: Some(without_pi), image: mistaken.clone() },
        Candidate { mistake: Some(no_falloff), image: mistaken.clone() },
    ];
    let diagnosis = diagnose(&as_jpeg(&mistaken, 90), &candidates);
    match &diagnosis.verdict {
        Verdict::Tie(names) => {
            assert!(names.len() == 2 && names.contains(&without_pi.name) && names.contains(&no_falloff.name))
        }
        other => panic!("{other:?}: {:?}", diagnosis.ranking),
    }
    // Figure 1 itself tells them apart: pi against 60 / d^2 times brighter.
    let (scene, distance) = scene_that_tells_apart(&mut common::renderer(), &[without_pi, no_falloff], (300, 210))
        .unwrap()
        .expect("a scene");
    assert_eq!(scene.0, "fig1-lambert");
    assert!(distance > 20.0, "{distance}");
}

/// A model's image depends on its file of shaders/brdf/ (`Brdf::shader_file`) and on what that file
/// includes, and on no other file there, so the check renders no mistake of another model's file (it takes
/// the correct image for it): each file broken in turn (every value it returns doubled), a sphere of each
/// model changes where the file is the model's own, and keeps every byte where the model's file does not
/// include it.
#[test]
fn each_models_image_depends_on_its_shader_file_and_what_it_includes_alone() {
    let models = [
        "brdf = \"lambert\"\nkd = [0.5, 0.5, 0.5]",
        "brdf = \"oren-nayar\"\nkd = [0.5, 0.5, 0.5]\nsigma = 0.6",
        "brdf = \"phong\"\nkd = [0.35, 0.35, 0.35]\nks = [0.15, 0.15, 0.15]\nshininess = 16.0",
        "brdf = \"blinn-phong\"\nkd = [0.35, 0.35, 0.35]\nks = [0.15, 0.15, 0.15]\nshininess = 64.0",
        "brdf = \"cook-torrance\"\nkd = [1.0, 0.85, 0.57]\nf0 = [1.0, 0.85, 0.57]\nroughness = 0.3\nmetalness = 0.5\ndiffuse = \"lambert\"",
    ];
    let scenes: Vec<Scene> = models
        .iter()
        .map(|material| {
            let text = format!(
                "[image]\nwidth = 48\nheight = 32\nsamples = 1\n[camera]\nposition = [0, 0, 0]\nlook_at = [0, 0, 1]\n\
                 up = [0, 1, 0]\nfov_y = 60\n[[light]]\ntype = \"point\"\nposition = [1, 1, -1]\ncolor = [1, 1, 1]\n\
                 power = 60\n[material.m]\n{material}\n[[object]]\nshape = \"sphere\"\ncenter = [0, 0, 3]\nradius = 1\n\
                 material = \"m\"\n"
            );
            Scene::parse(&text, &common::root().join("tests/model.toml"), &[]).expect("a valid scene")
        })
        .collect();
    let mut renderer = common::renderer();
    let correct: Vec<RgbImage> = scenes.iter().map(|s| renderer.render_rgb8(s).unwrap()).collect();
    let defaults = vk_render::vulkan::ShaderSources::default();
    let own: Vec<&str> = scenes.iter().map(|s| s.materials["m"].shader_file().unwrap()).collect();
    let files: Vec<String> = defaults.paths().filter(|p| own.contains(p)).map(str::to_string).collect();
    assert_eq!(files.len(), 5, "{files:?}");
    let mut wrong = Vec::new();
    for file in &files {
        let text = defaults.text(file).unwrap();
        let broken = text.replace("return ", "return 2.0 * ");
        renderer.set_shaders(defaults.clone().with_file(file, broken)).unwrap();
        for (k, scene) in scenes.iter().enumerate() {
            let changed = renderer.render_rgb8(scene).unwrap() != correct[k];
            let included = defaults.included_by(own[k]).contains(file);
            if (own[k] == file && !changed) || (!included && changed) {
                wrong.push(format!("{file} broken: {} changed {changed}, includes it {included}", own[k]));
            }
        }
    }
    renderer.set_shaders(defaults).unwrap();
    assert!(wrong.is_empty(), "{wrong:#?}");
}
