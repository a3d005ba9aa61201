//! The explore page's editor of a student's own `.brdf` (static/explore/editor.js), in the browser of the explore
//! test: the model typed into the page is read by the library's code as WebAssembly, compiled by the
//! browser's WebGL2 and drawn as `vk-render render` renders the downloaded file (within the explorer's
//! bound), its parameters moved by the page as `--set` moves them; its lobe, by the browser, is `vk-render
//! plot lobe`'s; a mistake is shown at its line of the
//! text; an endless loop, a 50 MB file, a file that is no text and a lost WebGL context end in a message, the
//! page still drawing; the text outlives a reload.

use std::path::Path;
use std::time::Duration;

use serde_json::{json, Value};

use super::common::webdriver::Browser;
use super::{assert_console_clean, cli_frame, compare, drawn_frame, within_bound};

/// A student's model: a colour, a float and a bool, a helper function and a loop (guarded in the browser,
/// never stopped: four steps).
pub const STUDENT_BRDF: &str = "analytic
# A student's model: Lambert layers and a GGX lobe.
::begin parameters
color base 0.6 0.25 0.1
float roughness 0.05 1 0.35
bool glossy 1
::end parameters

::begin shader
const float PI = 3.14159265358979;

float ggx(float NoH, float a)
{
    float a2 = a * a;
    float d = NoH * NoH * (a2 - 1.0) + 1.0;
    return a2 / (PI * d * d);
}

vec3 BRDF(vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y)
{
    vec3 H = normalize(L + V);
    float NoL = max(dot(N, L), 1e-4);
    float NoV = max(dot(N, V), 1e-4);
    float layers = 0.0;
    for (int i = 0; i < 4; i++) layers += 0.25;
    vec3 f = base / PI * layers;
    if (glossy) f += vec3(0.04 * ggx(max(dot(N, H), 0.0), roughness * roughness) / (4.0 * NoL * NoV));
    return f;
}
::end shader
";

/// The line of [`STUDENT_BRDF`] (from 1) that holds `text`.
fn line_of(text: &str) -> usize {
    STUDENT_BRDF.lines().position(|line| line.contains(text)).expect("the model has the line") + 1
}

/// Puts `text` in the editor and draws it: the editor's status and error lines once it has answered.
fn draw(browser: &Browser, text: &str) -> (String, String) {
    browser.run(
        "document.getElementById('editor-status').textContent = '';
         document.getElementById('editor-error').textContent = '';
         document.getElementById('editor-text').value = arguments[0];
         document.getElementById('editor-apply').click();",
        &[json!(text)],
    );
    browser.wait_for(
        "the editor's answer",
        "return document.getElementById('editor-status').textContent !== '' || document.getElementById('editor-error').textContent !== '';",
        Duration::from_secs(60),
    );
    let said = browser.run(
        "return [document.getElementById('editor-status').textContent, document.getElementById('editor-error').textContent];",
        &[],
    );
    (said[0].as_str().unwrap().to_string(), said[1].as_str().unwrap().to_string())
}

/// The student's model drawn on Figure 1's sphere against `vk-render render` of the downloaded file in the
/// figure's scene, as drawn and with its parameters moved, its lobe and albedo, its mistakes, hostile input,
/// the storage and a lost context. `page` is the explore page's address (the server's or a site's: the same
/// script, which draws in the browser alone).
pub fn the_students_own_brdf(browser: &Browser, page: &str, folder: &Path) {
    browser.open(&format!("{page}?scene=fig1-lambert"));
    browser.wait_for("the page's renderer", "return page.mode === 'browser';", Duration::from_secs(120));
    let (status, error) = draw(browser, STUDENT_BRDF);
    assert_eq!(error, "", "{status}");
    assert!(status.contains("compiled by your browser, drawn on object 0"), "{status}");
    let material = browser.run("return editor.model.name;", &[]);
    let material = material.as_str().unwrap().to_string();

    // The file the page downloads, in the figure's scene in place of the sphere's grey.
    let file = browser.run("return editorFile();", &[]);
    assert_eq!(file.as_str(), Some(STUDENT_BRDF));
    let scenes = folder.join("student");
    std::fs::create_dir_all(&scenes).unwrap();
    std::fs::write(scenes.join("student.brdf"), STUDENT_BRDF).unwrap();
    let figure = std::fs::read_to_string(super::common::root().join("assets/scenes/fig1-lambert.toml")).unwrap();
    let grey = "[material.grey]\nbrdf = \"lambert\"\nkd = [0.5, 0.5, 0.5]";
    assert!(figure.contains(grey));
    let scene = scenes.join("student.toml");
    std::fs::write(&scene, figure.replace(grey, "[material.grey]\nbrdf = \"analytic\"\nfile = \"student.brdf\""))
        .unwrap();

    let moved = [
        ("roughness", json!(0.8), "0.8"),
        ("glossy", json!(false), "false"),
        ("base", json!([0.2, 0.5, 0.9]), "[0.2,0.5,0.9]"),
    ];
    for state in [&moved[..0], &moved[..]] {
        let set: serde_json::Map<String, Value> = state
            .iter()
            .map(|(name, value, _)| (format!("material.{material}.params.{name}"), value.clone()))
            .collect();
        browser.run("Object.assign(page.set, arguments[0]); sendState(true);", &[Value::Object(set)]);
        let shown = drawn_frame(browser, "fig1-lambert");
        let (width, height) = shown.dimensions();
        let args: Vec<String> = state
            .iter()
            .flat_map(|(name, _, cli)| ["--set".to_string(), format!("material.grey.params.{name}={cli}")])
            .collect();
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let cli = cli_frame(folder, "student", &scene, width, height, &args);
        let single = cli_frame(folder, "student", &scene, width, height, &[&args[..], &["--samples", "1"]].concat());
        let edges: Vec<bool> = cli.pixels().zip(single.pixels()).map(|(a, b)| a != b).collect();
        let agreement = compare(&shown, &cli, &edges);
        eprintln!("the student's model {args:?} at {width} x {height}, the silhouettes aside: {agreement}");
        assert!(
            within_bound(&agreement),
            "the student's model {args:?}: the browser against vk-render render: {agreement}"
        );
    }

    // Its lobe, by the browser's probe pass, against `vk-render plot lobe` of the file, at its defaults.
    browser.run("page.set = {}; sendState(true); studentStudies();", &[]);
    let lobe = browser.run("return editor.lobe;", &[]);
    let worst = lobe_against_plot(&lobe, &scene, "grey", folder);
    eprintln!("the student's lobe against vk-render plot lobe: at most {worst:.2e} of its peak off");
    assert!(worst <= 1e-4, "the browser's lobe against vk-render plot lobe: {worst:.2e} of the peak");
    // Its albedo, by the library's cubature (WebAssembly) over the browser's albedo probe, against `vk-render
    // plot albedo` of the file: within the two bounds stated.
    browser.run("editor.albedo = null; studentStudies();", &[]);
    browser.wait_for("the student's albedo", "return Boolean(editor.albedo);", Duration::from_secs(120));
    let albedo = browser.run("return editor.albedo;", &[]);
    let (share, worst, _) = albedo_against_plot(&albedo, &scene, "grey", folder);
    eprintln!(
        "the student's albedo against vk-render plot albedo: at most {worst:.1e} off, {share:.2} of the bounds \
         stated (the browser's at most {:.1e})",
        albedo["bound"].as_array().unwrap().iter().map(|b| b.as_f64().unwrap()).fold(0.0, f64::max)
    );
    assert!(share <= 1.0, "the browser's albedo against vk-render plot albedo: {share:.2} of the bounds stated");
    let shown = browser.run("return document.getElementById('editor-albedo-status').textContent;", &[]);
    assert!(shown.as_str().unwrap().starts_with("its directional albedo at 19 angles"), "{shown}");
    assert_console_clean(browser, "the editor");
    // The picture (at the file's defaults, as the sliders show them) and the editor, for docs/serve.md.
    browser.resize(1400, 1400);
    browser.run("page.set = {}; sendState(true); window.scrollTo(0, 0);", &[]);
    drawn_frame(browser, "fig1-lambert");
    super::save_screenshot(browser, "explore-editor.png");
    browser.resize(1500, 1000);

    // Mistakes, at their lines of the text.
    let undeclared = STUDENT_BRDF.replace("NoH * NoH * (a2", "NoH * NoHH * (a2");
    let (_, error) = draw(browser, &undeclared);
    assert_eq!(error, format!("line {}: GLSL: 'NoHH' : undeclared identifier", line_of("NoH * NoH * (a2")));
    let integer = STUDENT_BRDF.replace("(4.0 * NoL", "(4 * NoL");
    let (_, error) = draw(browser, &integer);
    assert!(error.starts_with(&format!("line {}: GLSL: '*' : wrong operand types", line_of("(4.0 * NoL"))), "{error}");
    let parameter = STUDENT_BRDF.replace("float roughness 0.05 1 0.35", "float roughness 0.05 1");
    let (_, error) = draw(browser, &parameter);
    assert_eq!(error, "line 5: `float roughness 0.05 1`: a float parameter is `float NAME MIN MAX DEFAULT`");
    let no_brdf = STUDENT_BRDF.replace("vec3 BRDF(", "vec3 brdf(");
    let (_, error) = draw(browser, &no_brdf);
    assert!(error.starts_with("the shader section defines no function `vec3 BRDF("), "{error}");

    // A loop that never ends stops at its guard: the page draws, and goes on drawing.
    let endless = STUDENT_BRDF.replace("    return f;", "    while (true) { f *= 1.0001; }\n    return f;");
    let (status, _) = draw(browser, &endless);
    assert!(status.contains("compiled by your browser"), "{status}");
    drawn_frame(browser, "fig1-lambert");
    browser.wait_for(
        "the stopped loop said",
        "return document.getElementById('editor-error').textContent.startsWith('its loops ran past 4096 steps in one evaluation');",
        Duration::from_secs(30),
    );

    // A 50 MB file dropped, a file that is no text, and a text past the limit typed in.
    let big = browser.run(
        "const file = new File([new Uint8Array(50 * 1024 * 1024)], 'huge.brdf');
         const drop = new DataTransfer();
         drop.items.add(file);
         document.getElementById('editor-error').textContent = '';
         document.getElementById('editor-text').dispatchEvent(new DragEvent('drop', {dataTransfer: drop}));
         return document.getElementById('editor-error').textContent;",
        &[],
    );
    assert_eq!(big, json!("huge.brdf is 52428800 bytes: the editor takes a .brdf file of at most 262144"));
    let (_, error) = draw(browser, "\u{89}PNG\r\n\u{1a}\n\u{0}\u{0}");
    assert!(error.starts_with("line 1: the file starts with `\u{89}PNG`, not `analytic`"), "{error}");
    let (_, error) = draw(browser, &"x".repeat(300 * 1024));
    assert_eq!(error, "the text is 307200 bytes: the editor takes at most 262144");

    // One model at a time: drawn again, it replaces the one before, its shaders and programs.
    draw(browser, STUDENT_BRDF);
    let kept = browser.run(
        "const mine = (name) => name.includes('your-brdf-');
         return {shaders: Object.keys(page.browser.shaders).filter(mine).every((n) => n.endsWith(editor.model.name)),
                 programs: [...page.browser.programs.keys()].filter(mine).every((k) => k.split('|')[1].endsWith(editor.model.name)),
                 materials: Object.keys(page.scene.materials).filter(mine).length, serial: editor.serial};",
        &[],
    );
    assert_eq!(
        (&kept["shaders"], &kept["programs"], &kept["materials"]),
        (&json!(true), &json!(true), &json!(1)),
        "{kept}"
    );
    assert!(kept["serial"].as_u64().unwrap() >= 3, "{kept}");

    // The text outlives a reload; drawn again, the model survives a lost WebGL context.
    browser.open(&format!("{page}?scene=fig1-lambert"));
    browser.wait_for("the page's renderer", "return page.mode === 'browser';", Duration::from_secs(120));
    let kept = browser.run("return editorFile();", &[]);
    assert_eq!(kept.as_str(), Some(STUDENT_BRDF), "the browser's storage");
    draw(browser, STUDENT_BRDF);
    drawn_frame(browser, "fig1-lambert");
    browser.run(
        "window.lostContext = page.browser.gl.getExtension('WEBGL_lose_context'); lostContext.loseContext();",
        &[],
    );
    browser.wait_for("the lost context said", "return page.mode === 'none';", Duration::from_secs(30));
    let status = browser.run("return document.getElementById('status').textContent;", &[]);
    assert_eq!(
        status,
        json!("your browser cannot draw your model now: the browser's WebGL context was lost; vk-render render can (download your .brdf)")
    );
    browser.run("lostContext.restoreContext();", &[]);
    drawn_frame(browser, "fig1-lambert");
    let on = browser.run("return page.scene.objects[0].material;", &[]);
    assert!(on.as_str().unwrap().starts_with("your-brdf-"), "{on}");
    let said: Vec<_> = browser.console().into_iter().filter(|(_, m)| !m.contains("CONTEXT_LOST_WEBGL")).collect();
    assert!(said.iter().all(|(level, _)| level != "SEVERE"), "the editor's console: {said:?}");
}

/// How far the page's albedo (`{theta_o, albedo, bound}`: ρ per channel at each angle, and the bound the
/// browser's cubature reached) is from `vk-render plot albedo` of `material` in scene file `scene` at the same
/// angles, as a share of what the two stated bounds allow together: 1 is at the allowance. Also the largest
/// difference itself, and the largest over the albedo (of at least 1e-3).
pub fn albedo_against_plot(albedo: &Value, scene: &Path, material: &str, folder: &Path) -> (f64, f64, f64) {
    let (said, rows) = plot_csv("albedo", scene, material, &[], folder);
    // "... each within 8.8e-6 (asked: 1e-5; ...": the bound the command states.
    let stated: f64 =
        said.split("each within ").nth(1).and_then(|rest| rest.split(' ').next()).unwrap().parse().unwrap();
    let angles = albedo["theta_o"].as_array().unwrap();
    assert_eq!(angles.len(), 19, "every 5 degrees and 89");
    let (mut share, mut worst, mut relative) = (0.0f64, 0.0f64, 0.0f64);
    for (k, angle) in angles.iter().enumerate() {
        let row = rows.iter().find(|row| Some(row[0]) == angle.as_f64()).expect("an angle the plot has");
        let allowed = stated + albedo["bound"][k].as_f64().unwrap();
        for channel in 0..3 {
            let difference = (albedo["albedo"][k][channel].as_f64().unwrap() - row[1 + channel]).abs();
            worst = worst.max(difference);
            share = share.max(difference / allowed);
            relative = relative.max(difference / row[1 + channel].abs().max(1e-3));
        }
    }
    (share, worst, relative)
}

/// How far the page's lobe (`{theta_o, values}`: f_r cos θo per channel at θi 30°) is from `vk-render plot
/// lobe` of `material` in scene file `scene` at the same angles: the largest difference over its peak.
pub fn lobe_against_plot(lobe: &Value, scene: &Path, material: &str, folder: &Path) -> f64 {
    let (_, rows) = plot_csv("lobe", scene, material, &["--theta-i", "30"], folder);
    assert_eq!(rows.len(), 361);
    assert_eq!(lobe["theta_i"], json!(30));
    let peak = rows.iter().flat_map(|row| row[1..].iter().copied()).fold(0.0, f64::max);
    let mut worst = 0.0f64;
    for (k, row) in rows.iter().enumerate() {
        assert_eq!(lobe["theta_o"][k].as_f64(), Some(row[0]), "the lobe's angles");
        for channel in 0..3 {
            let shown = lobe["values"][k][channel].as_f64().unwrap();
            worst = worst.max((shown - row[1 + channel]).abs() / peak);
        }
    }
    worst
}

/// `vk-render plot KIND SCENE --material MATERIAL ARGS -o CSV`: what it said, and the CSV's rows of numbers.
fn plot_csv(kind: &str, scene: &Path, material: &str, args: &[&str], folder: &Path) -> (String, Vec<Vec<f64>>) {
    let csv = folder.join(format!("{material}-{kind}.csv"));
    let command =
        [&["plot", kind, scene.to_str().unwrap(), "--material", material][..], args, &["-o", csv.to_str().unwrap()]];
    let plotted = super::common::vk_render(&command.concat());
    assert!(plotted.status.success(), "{}", String::from_utf8_lossy(&plotted.stderr));
    let rows = std::fs::read_to_string(&csv)
        .unwrap()
        .lines()
        .skip(1)
        .map(|line| line.split(',').map(|v| v.parse().unwrap()).collect())
        .collect();
    (String::from_utf8_lossy(&plotted.stdout).into_owned(), rows)
}
