//! `vk-render serve` in a real browser (Debian's headless Chromium over WebDriver): the explore page's still
//! frame after a control moves is, pixel for pixel, `vk-render render` with that override; a student's image
//! dropped on the check page gives the verdict and the mistake names of `vk-render check`; the browser's
//! console stays clean. With VK_RENDER_SCREENSHOTS=DIR the pages' screenshots are written there (the
//! pictures of docs/serve.md).

mod common;

use std::path::Path;
use std::time::Duration;

use serde_json::{json, Value};

use common::server::Server;
use common::webdriver::{base64, base64_encoded, Browser};
use vk_render::check::catalogue::CATALOGUE;
use vk_render::check::render_candidates;
use vk_render::figures::practical_image;

fn save_screenshot(browser: &Browser, name: &str) {
    let png = browser.screenshot();
    assert!(image::load_from_memory(&png).is_ok(), "a screenshot decodes");
    if let Some(folder) = std::env::var_os("VK_RENDER_SCREENSHOTS") {
        std::fs::write(Path::new(&folder).join(name), png).expect("write the screenshot");
    }
}

fn assert_console_clean(browser: &Browser, page: &str) {
    let messages = browser.console();
    let errors: Vec<_> = messages.iter().filter(|(level, _)| level == "SEVERE" || level == "WARNING").collect();
    assert!(errors.is_empty(), "{page}: the browser's console: {errors:?}");
}

#[test]
fn the_explore_and_check_pages_work_in_a_browser() {
    assert!(Path::new(common::webdriver::CHROMIUM).exists(), "chromium is missing: run `make setup-test`");
    assert_eq!(base64(&base64_encoded(b"vk-render")), b"vk-render");
    let folder = common::temp_dir();
    let server = Server::local();
    let browser = Browser::start(1500, 1000);
    let base = format!("http://{}", server.loopback());

    // Explore: the first still frame, then a control moved and the still frame after it.
    browser.open(&format!("{base}/explore?scene=fig3-plastic-s-16"));
    let still = "const c = document.getElementById('frame'); return c.dataset.frame === 'still' && c.dataset.state === String(page.sent);";
    browser.wait_for("the first still frame", still, Duration::from_secs(60));
    let moved = browser.run(
        "const slider = document.querySelector('input[data-key=\"light.0.power\"]');
         slider.value = String(Number(slider.max) * 0.35);
         slider.dispatchEvent(new Event('input', {bubbles: true}));
         return document.querySelector('input[data-key=\"light.0.power\"]').nextElementSibling.textContent;",
        &[],
    );
    let power: f64 = moved.as_str().unwrap().parse().unwrap();
    browser.wait_for("the still frame after the change", still, Duration::from_secs(60));
    let frame = browser.run(
        "const c = document.getElementById('frame');
         return {width: c.width, height: c.height, png: c.toDataURL('image/png').split(',')[1], state: c.dataset.state};",
        &[],
    );
    let (width, height) = (frame["width"].as_u64().unwrap(), frame["height"].as_u64().unwrap());
    let shown = image::load_from_memory(&base64(frame["png"].as_str().unwrap())).unwrap().to_rgb8();
    let out = folder.path().join("cli.png");
    let scene = common::root().join("assets/scenes/fig3-plastic-s-16.toml");
    let set = format!("light.0.power={power}");
    let (w, h) = (width.to_string(), height.to_string());
    let output = common::vk_render(&[
        "render",
        scene.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--width",
        &w,
        "--height",
        &h,
        "--set",
        &set,
    ]);
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    let cli = image::open(&out).unwrap().to_rgb8();
    assert_eq!(shown.dimensions(), cli.dimensions());
    let differing = shown.pixels().zip(cli.pixels()).filter(|(a, b)| a != b).count();
    if differing > 0 {
        let _ = shown.save(std::env::temp_dir().join("vk-render-browser-shown.png"));
        let _ = cli.save(std::env::temp_dir().join("vk-render-browser-cli.png"));
        eprintln!("page state: {}", browser.run("const c = document.getElementById('frame'); return JSON.stringify(request()) + ' sent ' + page.sent + ' ' + JSON.stringify(c.dataset) + ' ' + document.getElementById('status').textContent;", &[]));
    }
    assert_eq!(differing, 0, "the page's still frame ({width} x {height}, power {power}) differs from vk-render render in {differing} pixels");
    browser.wait_for("the lobe and albedo", "return document.getElementById('lobe').complete && document.getElementById('albedo').complete && document.getElementById('albedo').naturalWidth > 0;", Duration::from_secs(60));
    save_screenshot(&browser, "serve-explore.png");
    assert_console_clean(&browser, "explore");

    // Check: a student's image (sigma in degrees) dropped on the page; the report names the mistake.
    let sized = ["image.width=320".parse().unwrap(), "image.height=240".parse().unwrap()];
    let figure = practical_image("fig2-oren-nayar-sigma-0.6").unwrap().scene(&sized).unwrap();
    let mistakes: Vec<_> = CATALOGUE.iter().filter(|m| m.name == "sigma-in-degrees").collect();
    let mistaken = render_candidates(&mut common::renderer(), &figure, &mistakes, |_, _| {}).unwrap().remove(1).image;
    let mut jpeg = Vec::new();
    image::codecs::jpeg::JpegEncoder::new_with_quality(&mut jpeg, 90).encode_image(&mistaken).unwrap();
    let student = folder.path().join("mine.jpg");
    std::fs::write(&student, &jpeg).unwrap();
    browser.open(&format!("{base}/check"));
    browser.wait_for(
        "the scenes",
        "return document.querySelectorAll('#scene option').length > 1;",
        Duration::from_secs(30),
    );
    browser.run(
        "const bytes = Uint8Array.from(atob(arguments[0]), (c) => c.charCodeAt(0));
         const file = new File([bytes], 'mine.jpg', {type: 'image/jpeg'});
         const transfer = new DataTransfer();
         transfer.items.add(file);
         document.getElementById('drop').dispatchEvent(new DragEvent('drop', {dataTransfer: transfer, bubbles: true, cancelable: true}));
         document.getElementById('scene').value = 'fig2-oren-nayar-sigma-0.6';
         document.getElementById('submit').click();",
        &[Value::String(base64_encoded(&jpeg))],
    );
    browser.wait_for("the report", "return document.getElementById('verdict') !== null;", Duration::from_secs(120));
    let report = browser.run(
        "return {verdict: document.getElementById('verdict').dataset.verdict,
                 line: document.getElementById('verdict').textContent,
                 mistakes: [...document.querySelectorAll('[data-mistake]')].map((m) => m.dataset.mistake),
                 address: location.pathname};",
        &[],
    );
    let output = common::vk_render(&["check", student.to_str().unwrap(), "--scene", "fig2-oren-nayar-sigma-0.6"]);
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert_eq!(output.status.code(), Some(1), "{stdout}");
    assert!(stdout.contains("diagnosis: sigma-in-degrees:"), "{stdout}");
    assert_eq!(
        (report["verdict"].clone(), report["mistakes"].clone()),
        (json!("mistake"), json!(["sigma-in-degrees"])),
        "{report}"
    );
    assert!(report["address"].as_str().unwrap().starts_with("/reports/"), "{report}");
    browser.wait_for(
        "the report's pictures",
        "return [...document.images].every((i) => i.complete && i.naturalWidth > 0);",
        Duration::from_secs(30),
    );
    save_screenshot(&browser, "serve-check-report.png");
    assert_console_clean(&browser, "the report");
    drop(browser);
    let (code, stderr, _) = server.terminate(Duration::from_secs(30));
    assert_eq!(code, Some(0), "{stderr}");
}
