//! A `vk-render site` folder's check page, in the browser with no vk-render running: the test suite's
//! students' images (each mistake of the catalogue rendered on the figure it shows on, and each figure's
//! exact image, as JPEG at quality 75) get the verdict, the mistakes and the statistics that
//! `vk-render check` gives (the library's `check_image` and its summary, which the CLI, the server and the
//! Python package print); hostile files end in a message, the page still working.

use std::path::Path;
use std::time::Duration;

use image::RgbImage;
use serde_json::{json, Value};

use super::common;
use super::common::webdriver::{base64_encoded, Browser};
use vk_render::check::catalogue::{Mistake, CATALOGUE};
use vk_render::check::report::check_image;
use vk_render::check::summary::Summary;
use vk_render::check::{diagnose, render_candidates};
use vk_render::scene::figures::practical_image;

/// The figures the catalogue's mistakes show on: those whose students' images `make test` checks in the
/// page (the course's three families of models: Lambert, Phong, Cook-Torrance), and the others
/// (`make test-long`).
pub const FIGURES_CHECKED: [&str; 3] = ["fig1-lambert", "fig3-plastic-s-16", "fig4-gold-metalness-1.0"];
pub const OTHER_FIGURES: [&str; 3] = ["fig2-oren-nayar-sigma-0.6", "fig5-golden-bunny", "fig6-blinn-phong"];

fn jpeg(image: &RgbImage, quality: u8) -> Vec<u8> {
    let mut bytes = Vec::new();
    image::codecs::jpeg::JpegEncoder::new_with_quality(&mut bytes, quality).encode_image(image).unwrap();
    bytes
}

/// Drops `bytes` as the file `name` on the page, checks it against `figure`, and waits for the report or
/// the error: `{"report", "seconds"}` or `{"error"}`.
fn check_in_page(browser: &Browser, name: &str, bytes: &[u8], figure: &str) -> Value {
    browser.run(
        "const bytes = Uint8Array.from(atob(arguments[0]), (c) => c.charCodeAt(0));
         const transfer = new DataTransfer();
         transfer.items.add(new File([bytes], arguments[1]));
         document.getElementById('error').textContent = '';
         document.getElementById('drop').dispatchEvent(new DragEvent('drop', {dataTransfer: transfer, bubbles: true, cancelable: true}));
         document.getElementById('scene').value = arguments[2];
         document.getElementById('submit').click();",
        &[Value::String(base64_encoded(bytes)), json!(name), json!(figure)],
    );
    answer(browser)
}

fn answer(browser: &Browser) -> Value {
    let done = "return checkPage.last !== null || document.getElementById('error').textContent !== '';";
    browser.wait_for("the check in the page", done, Duration::from_secs(60));
    browser.run(
        "return checkPage.last ? {report: checkPage.last.report, seconds: checkPage.last.seconds,
                             needs: [...document.querySelectorAll('[data-needs-renderer]')].map((p) => p.dataset.needsRenderer),
                             pictures: [...document.querySelectorAll('#site-report img')].map((i) => i.dataset.picture)}
                          : {error: document.getElementById('error').textContent};",
        &[],
    )
}

/// The page's report against the library's summary: the verdict, the mistakes by name, the statistics to
/// within float rounding, the regions where `library` has them.
fn assert_same(what: &str, page: &Value, library: &Value) {
    let report = &page["report"];
    assert_eq!(report["verdict"], library["verdict"], "{what}: {report}\nvk-render check: {library}");
    assert_eq!(report["matches"], library["matches"], "{what}");
    let names = |v: &Value| v["mistakes"].as_array().unwrap().iter().map(|m| m["name"].clone()).collect::<Vec<_>>();
    assert_eq!(names(report), names(library), "{what}");
    let close = |a: &Value, b: &Value| (a.as_f64().unwrap() - b.as_f64().unwrap()).abs() <= 1e-9;
    for key in ["rms", "mean", "p99", "over"] {
        assert!(close(&report["statistics"][key], &library["statistics"][key]), "{what}: {key}: {report} {library}");
    }
    if let Some(regions) = library["regions"].as_array() {
        let shown = report["regions"].as_array().unwrap();
        assert_eq!(shown.len(), regions.len(), "{what}: the regions");
        for (a, b) in shown.iter().zip(regions) {
            assert_eq!((&a["object"], &a["part"]), (&b["object"], &b["part"]), "{what}");
            assert!(close(&a["rms"], &b["rms"]) && close(&a["p99"], &b["p99"]), "{what}: {a} against {b}");
        }
    }
    let needs = if matches!(library["verdict"].as_str(), Some("tie" | "unexplained")) { 1 } else { 0 };
    assert_eq!(page["needs"].as_array().unwrap().len(), needs, "{what}: the page names vk-render check where it stops");
}

/// The check page of the site at `url` against the library on the students' images of `FIGURES_CHECKED`,
/// and its refusals.
pub fn the_check_in_the_browser(browser: &Browser, url: &str, folder: &Path) {
    open_check_page(browser, url);
    students_images_as_the_library_checks_them(browser, &FIGURES_CHECKED);
    let everything: Vec<&'static Mistake> = CATALOGUE.iter().collect();
    // An image of another figure: no mistake explains it, and the page says where the check goes on.
    let fig1 = practical_image("fig1-lambert").unwrap().scene(&[]).unwrap();
    let lambert = common::renderer().render_rgb8(&fig1).unwrap();
    let page = check_in_page(browser, "fig1.png", &jpeg(&lambert, 90), "fig4-gold-metalness-1.0");
    assert_eq!(page["report"]["verdict"], "unexplained", "{page}");
    assert_eq!(page["needs"], json!(["unexplained"]), "{page}");
    // The command line's own words on a mistake's image, as the page's.
    let nopi = folder.join("lambert-without-pi.jpg");
    let candidates = render_candidates(&mut common::renderer(), &fig1, &everything[..1], |_, _| {}).unwrap();
    std::fs::write(&nopi, jpeg(&candidates[1].image, 75)).unwrap();
    let output = common::vk_render(&["check", nopi.to_str().unwrap(), "--scene", "fig1-lambert"]);
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(stdout.contains("diagnosis: lambert-without-pi:"), "{stdout}");
    let page = check_in_page(browser, "lambert-without-pi.jpg", &std::fs::read(&nopi).unwrap(), "fig1-lambert");
    assert_eq!(page["report"]["mistakes"][0]["name"], "lambert-without-pi", "{page}");
    assert_eq!(page["pictures"], json!(["yours", "exact", "difference", "mistake"]), "{page}");
    browser.wait_for(
        "the report's pictures",
        "return [...document.images].every((i) => i.complete && i.naturalWidth > 0);",
        Duration::from_secs(30),
    );
    browser.run("document.getElementById('verdict').scrollIntoView();", &[]);
    super::save_screenshot(browser, "site-check.png");
    // Hostile files: too large (refused before it is read), a text named .png, another size.
    let refused = browser.run(
        "const transfer = new DataTransfer();
         transfer.items.add(new File([new Uint8Array(50 << 20)], 'huge.png', {type: 'image/png'}));
         document.getElementById('drop').dispatchEvent(new DragEvent('drop', {dataTransfer: transfer, bubbles: true, cancelable: true}));
         checkPage.last = null;
         document.getElementById('submit').click();",
        &[],
    );
    assert!(refused.is_null());
    let huge = answer(browser);
    assert!(
        huge["error"].as_str().unwrap().contains("huge.png is 50.0 MB: this page takes images up to 16 MB"),
        "{huge}"
    );
    let text = check_in_page(browser, "notes.png", b"these are my notes, not an image", "fig1-lambert");
    assert_eq!(text["error"], "your image: not a PNG or JPEG image vk-render can read", "{text}");
    let small = image::imageops::resize(&lambert, 300, 200, image::imageops::FilterType::Triangle);
    let other = check_in_page(browser, "small.jpg", &jpeg(&small, 90), "fig1-lambert");
    let said = other["error"].as_str().unwrap();
    assert!(
        said.starts_with("Your image is 300 x 200; this page checks the figures at their own size, 600 x 400.")
            && said.contains("vk-render check small.jpg --scene fig1-lambert"),
        "{said}"
    );
    // The page still works after them.
    let page = check_in_page(browser, "fig1.jpg", &jpeg(&lambert, 75), "fig1-lambert");
    assert_eq!(page["report"]["verdict"], "matches", "{page}");
    super::assert_console_clean(browser, "the site's check page");
}

/// The site's check page at `url`, once its figures are listed.
pub fn open_check_page(browser: &Browser, url: &str) {
    browser.open(url);
    browser.wait_for(
        "the figures",
        "return document.querySelectorAll('#scene option').length === 15;",
        Duration::from_secs(30),
    );
}

/// Each figure's exact image and each mistake shown on it (JPEG at quality 75), checked in the page: the
/// verdict, the mistakes and the statistics the library gives.
pub fn students_images_as_the_library_checks_them(browser: &Browser, figures: &[&str]) {
    let everything: Vec<&'static Mistake> = CATALOGUE.iter().collect();
    let mut verdicts = std::collections::BTreeMap::new();
    let mut seconds = Vec::new();
    for &figure in figures {
        let scene = practical_image(figure).unwrap().scene(&[]).unwrap();
        let candidates = render_candidates(&mut common::renderer(), &scene, &everything, |_, _| {}).unwrap();
        let mut students: Vec<(String, Vec<u8>)> =
            vec![(format!("{figure}-exact.jpg"), jpeg(&candidates[0].image, 75))];
        for candidate in &candidates[1..] {
            let mistake = candidate.mistake.unwrap();
            if mistake.shows_on.0 == figure {
                students.push((format!("{}.jpg", mistake.name), jpeg(&candidate.image, 75)));
            }
        }
        for (k, (name, bytes)) in students.iter().enumerate() {
            let page = check_in_page(browser, name, bytes, figure);
            assert!(page["error"].is_null(), "{name} on {figure}: {page}");
            let mine = image::load_from_memory(bytes).unwrap().to_rgb8();
            // The first image the whole check (its regions need the CPU reference), the others its diagnosis.
            let library = if k == 0 {
                let checked = check_image(&mut common::renderer(), &mine, &scene, |_, _| {}).unwrap();
                serde_json::to_value(Summary::of(&checked, &scene)).unwrap()
            } else {
                let diagnosis = diagnose(&mine, &candidates);
                let named: Vec<Value> = diagnosis.verdict.mistakes().iter().map(|n| json!({ "name": n })).collect();
                let s = &diagnosis.against_exact;
                json!({
                    "verdict": diagnosis.verdict.word(),
                    "matches": s.matches() && diagnosis.verdict == vk_render::check::Verdict::Matches,
                    "mistakes": named,
                    "statistics": { "rms": s.rms, "mean": s.mean, "p99": s.p99, "over": s.over },
                })
            };
            assert_same(&format!("{name} on {figure}"), &page, &library);
            *verdicts.entry(library["verdict"].as_str().unwrap().to_string()).or_insert(0) += 1;
            seconds.push(page["seconds"].as_f64().unwrap());
        }
    }
    seconds.sort_by(f64::total_cmp);
    eprintln!(
        "the site's check page: {} students' images, as vk-render check decides ({verdicts:?}); median {:.2} s a check",
        seconds.len(),
        seconds[seconds.len() / 2]
    );
}
