//! The analysis commands as a user runs them: `plot lobe`, `plot albedo` and `furnace` write the file `-o`
//! names (.png, .svg, .csv) in the shape scripts rely on, and every bad input is one clear line, a non-zero
//! exit status and no file.

mod common;

use std::path::Path;

use common::{root, temp_dir, vk_render};

fn fig2() -> String {
    root().join("assets/scenes/fig2-oren-nayar-sigma-0.6.toml").to_str().unwrap().to_string()
}

/// Runs the command, which must succeed, and returns its standard output.
fn succeeds(args: &[&str]) -> String {
    let output = vk_render(args);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "{args:?}: {stderr}");
    // Standard error is no terminal here: the progress bars draw nothing.
    assert!(stderr.is_empty(), "{args:?} wrote to standard error: {stderr}");
    String::from_utf8_lossy(&output.stdout).to_string()
}

/// A CSV's header and its rows of numbers.
fn read_csv(path: &Path) -> (Vec<String>, Vec<Vec<f64>>) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header = lines.next().unwrap().split(',').map(str::to_string).collect();
    let rows = lines.map(|l| l.split(',').map(|v| v.parse().unwrap()).collect()).collect();
    (header, rows)
}

#[test]
fn plot_lobe_writes_its_csv_png_and_svg() {
    let folder = temp_dir();
    let csv = folder.path().join("lobe.csv");
    let fig2 = fig2();
    succeeds(&["plot", "lobe", &fig2, "--theta-i", "30,60", "-o", csv.to_str().unwrap()]);
    let (header, rows) = read_csv(&csv);
    assert_eq!(header, ["theta_o", "matte_r", "matte_g", "matte_b", "red_r", "red_g", "red_b"]);
    assert_eq!(rows.len(), 361, "theta_o from -90 to 90 every half degree");
    assert_eq!((rows[0][0], rows[180][0], rows[360][0]), (-90.0, 0.0, 90.0));
    // The red plane is Lambert: f_r cos(theta_o) = cos(theta_o) / pi in red, 0 in green.
    let at_60 = &rows[300];
    assert_eq!(at_60[0], 60.0);
    assert!((at_60[4] - 0.5 / std::f64::consts::PI).abs() < 1e-6 && at_60[5] == 0.0, "{at_60:?}");
    // Every row equals the Rust mirror's f_r cos(theta_o) at wi = 30 degrees in the plane of incidence.
    let matte = vk_render::brdf::Brdf::OrenNayar { kd: glam::Vec3::splat(0.5), sigma: 0.6 };
    let wi = glam::Vec3::new(30f32.to_radians().sin(), 0.0, 30f32.to_radians().cos());
    for row in &rows {
        let theta = (row[0] as f32).to_radians();
        let wo = glam::Vec3::new(-theta.sin(), 0.0, theta.cos());
        let rust = f64::from(matte.eval(glam::Vec3::Z, wi, wo).x * wo.z.max(0.0));
        assert!((row[1] - rust).abs() <= 1e-4 * rust.max(0.01), "theta_o {}: {} vs {rust}", row[0], row[1]);
    }
    for picture in ["lobe-picture.png", "lobe-picture.svg"] {
        let path = folder.path().join(picture);
        succeeds(&[
            "plot",
            "lobe",
            &fig2,
            "--theta-i",
            "30,60",
            "--log",
            "--channel",
            "r",
            "-o",
            path.to_str().unwrap(),
        ]);
        if picture.ends_with(".png") {
            let image = image::open(&path).unwrap().to_rgb8();
            assert_eq!(image.dimensions(), (1100, 980));
            let coloured = image.pixels().filter(|p| p.0.iter().max() != p.0.iter().min()).count();
            assert!(coloured > 5000, "only {coloured} coloured pixels: no curves drawn?");
        } else {
            let svg = std::fs::read_to_string(&path).unwrap();
            assert!(svg.starts_with("<svg") && svg.contains("matte: oren-nayar kd 0.5, sigma 0.6"), "{}", &svg[..200]);
        }
        // Its numbers beside it, as the CSV output would hold them.
        assert_eq!(read_csv(&path.with_extension("csv")), (header.clone(), rows.clone()), "{picture}'s CSV");
    }
}

#[test]
fn plot_albedo_states_its_accuracy_and_writes_one_row_a_degree() {
    let folder = temp_dir();
    let csv = folder.path().join("albedo.csv");
    let stdout = succeeds(&["plot", "albedo", &fig2(), "--material", "red", "-o", csv.to_str().unwrap()]);
    assert!(stdout.contains("each within") && stdout.contains("asked: 1e-5"), "{stdout}");
    let (header, rows) = read_csv(&csv);
    assert_eq!(header, ["theta_o", "red_r", "red_g", "red_b"]);
    assert_eq!(rows.len(), 91);
    assert!(rows.iter().all(|r| (r[1] - 1.0).abs() < 1e-5 && r[2] == 0.0), "Lambert's albedo is kd");
    let png = folder.path().join("albedo.png");
    succeeds(&["plot", "albedo", &fig2(), "-o", png.to_str().unwrap()]);
    assert_eq!(image::open(&png).unwrap().to_rgb8().dimensions(), (1100, 620));
}

#[test]
fn furnace_writes_its_table() {
    let folder = temp_dir();
    let csv = folder.path().join("furnace.csv");
    let stdout = succeeds(&["furnace", &fig2(), "--material", "matte", "-o", csv.to_str().unwrap()]);
    let text = std::fs::read_to_string(&csv).unwrap();
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some("material,model and parameters,max albedo,error bound,theta_o,verdict"));
    let rows: Vec<&str> = lines.collect();
    assert_eq!(rows.len(), 1 + 9, "the material, then Oren-Nayar's white grid over sigma");
    assert!(rows[0].starts_with("matte,\"oren-nayar kd 0.5, sigma 0.6\",0.459"), "{}", rows[0]);
    assert!(rows
        .iter()
        .any(|r| r.starts_with("white,\"oren-nayar kd 1, sigma 0.2\",1.015") && r.contains("creates energy")));
    assert!(stdout.lines().count() == 10 && stdout.contains("creates energy"), "{stdout}");
    let png = folder.path().join("furnace.png");
    succeeds(&["furnace", &fig2(), "--material", "matte", "-o", png.to_str().unwrap()]);
    assert!(image::open(&png).is_ok());
}

/// The command must fail with exit status `code`, one line holding every needle, and no file in `folder`.
fn fails(folder: &Path, args: &[&str], code: i32, needles: &[&str]) {
    let output = vk_render(args);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(code), "{args:?}: {stderr}");
    assert_eq!(stderr.lines().count(), 1, "{args:?}: {stderr}");
    for needle in needles {
        assert!(stderr.contains(needle), "{args:?}: stderr lacks {needle:?}: {stderr}");
    }
    assert_eq!(std::fs::read_dir(folder).unwrap().count(), 0, "{args:?} left a file");
}

#[test]
fn bad_analysis_inputs_are_one_line_and_leave_nothing() {
    let folder = temp_dir();
    let out = |name: &str| folder.path().join(name).to_str().unwrap().to_string();
    let fig2 = fig2();
    fails(
        folder.path(),
        &["plot", "albedo", &fig2, "--material", "velvet", "-o", &out("a.csv")],
        1,
        &["fig2-oren-nayar-sigma-0.6.toml", "--material velvet: no such material", "matte, red"],
    );
    for (angle, shown) in [("90", "90"), ("-5", "-5"), ("nan", "NaN")] {
        fails(
            folder.path(),
            &["plot", "lobe", &fig2, "--theta-i", &format!("30,{angle}"), "-o", &out("l.png")],
            1,
            &[&format!("--theta-i {shown}"), "from 0 to below 90 degrees"],
        );
    }
    fails(
        folder.path(),
        &["plot", "lobe", &fig2, "--theta-i", "30", "-o", &out("l.txt")],
        1,
        &["l.txt", ".png, .svg or .csv"],
    );
    fails(
        folder.path(),
        &["plot", "lobe", &fig2, "--theta-i", "30", "--channel", "alpha", "-o", &out("l.png")],
        2,
        &["alpha"],
    );
    fails(
        folder.path(),
        &["furnace", &fig2, "--set", "material.matte.sigma=-1", "-o", &out("f.csv")],
        1,
        &["material.matte.sigma"],
    );
    let empty = folder.path().join("empty.toml");
    std::fs::write(&empty, "# no materials\n").unwrap();
    let result = vk_render(&["furnace", empty.to_str().unwrap(), "-o", &out("f.csv")]);
    std::fs::remove_file(&empty).unwrap();
    assert_eq!(result.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&result.stderr).contains("defines no [material.NAME]"));
    assert_eq!(std::fs::read_dir(folder.path()).unwrap().count(), 0);
}

#[test]
fn plot_slice_writes_a_cell_a_degree_in_csv_and_a_picture() {
    let folder = temp_dir();
    let csv = folder.path().join("slice.csv");
    succeeds(&["plot", "slice", &fig2(), "--phi-d", "45", "-o", csv.to_str().unwrap()]);
    let (header, rows) = read_csv(&csv);
    assert_eq!(header, ["theta_h", "theta_d", "matte_r", "matte_g", "matte_b", "red_r", "red_g", "red_b"]);
    assert_eq!(rows.len(), 90 * 90);
    assert_eq!((rows[0][0], rows[0][1], rows[91][0], rows[91][1]), (0.5, 0.5, 1.5, 1.5));
    let png = folder.path().join("slice.png");
    succeeds(&["plot", "slice", &fig2(), "--log", "-o", png.to_str().unwrap()]);
    assert_eq!(image::open(&png).unwrap().to_rgb8().dimensions(), (2 * 460 + 150, 520));
}

#[test]
fn compare_prints_the_differences_and_writes_the_report() {
    let folder = temp_dir();
    let scene = |name: &str| root().join("assets/scenes").join(name).to_str().unwrap().to_string();
    let report = folder.path().join("cmp.png");
    let small = ["--width", "120", "--height", "80"];
    // Oren-Nayar with sigma 0 is Lambert exactly: Figure 2's first image is Figure 1 byte for byte.
    let mut args = vec!["compare", "--set", "material.matte.sigma=0"];
    let (fig1, fig2) = (scene("fig1-lambert.toml"), scene("fig2-oren-nayar-sigma-0.6.toml"));
    args.extend([fig2.as_str(), fig1.as_str(), "-o", report.to_str().unwrap()]);
    args.extend(small);
    let output = vk_render(&args);
    // fig1 has no material named matte: --set applies to both scenes, so this is refused, naming fig1.
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("fig1-lambert.toml") && stderr.contains("material.matte"), "{stderr}");
    let zero = scene("fig2-oren-nayar-sigma-0.0.toml");
    let mut args = vec!["compare", zero.as_str(), fig1.as_str(), "-o", report.to_str().unwrap()];
    args.extend(small);
    let stdout = succeeds(&args);
    assert!(
        stdout.starts_with("mean 0.000 levels, p99 0, max 0") && stdout.contains(" 0.00% of the pixels differ"),
        "{stdout}"
    );
    let mut args = vec!["compare", fig2.as_str(), fig1.as_str(), "-o", report.to_str().unwrap()];
    args.extend(small);
    let stdout = succeeds(&args);
    assert!(!stdout.starts_with("mean 0.000") && !stdout.contains(" 0.00% of the pixels differ"), "{stdout}");
    let picture = image::open(&report).unwrap().to_rgb8();
    assert!(picture.width() > 3 * 120 && picture.height() > 80, "{:?}", picture.dimensions());
    // Two sizes are refused, and nothing is written.
    std::fs::remove_file(&report).unwrap();
    let output = vk_render(&["compare", &fig1, &fig2, "--set", "image.width=64", "-o", report.to_str().unwrap()]);
    assert_eq!(output.status.code(), Some(0), "--set applies to both: one size");
    std::fs::remove_file(&report).unwrap();
    let narrow = folder.path().join("narrow.toml");
    std::fs::write(&narrow, std::fs::read_to_string(&fig1).unwrap().replace("width = 600", "width = 64")).unwrap();
    let output = vk_render(&["compare", narrow.to_str().unwrap(), &fig2, "-o", report.to_str().unwrap()]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("is 64 x 400") && stderr.contains("is 600 x 400"), "{stderr}");
    assert!(!report.exists());
}

#[test]
fn fit_prints_name_value_lines_and_draws_the_lobes() {
    let folder = temp_dir();
    let materials = root().join("assets/analysis/course-materials.toml");
    let plot = folder.path().join("fit.svg");
    let stdout = succeeds(&[
        "fit",
        materials.to_str().unwrap(),
        "--material",
        "blinn-phong",
        "--to",
        "blinn-phong",
        "--theta-i",
        "20,50",
        "-o",
        plot.to_str().unwrap(),
    ]);
    let lines: Vec<&str> = stdout.lines().collect();
    assert!(lines[0].contains("over theta_i = 20, 50 degrees"), "{stdout}");
    // `name = value ± error`: the material is a Blinn-Phong one, so the fit is exact and so sure of it.
    let zeros = "[0.000000, 0.000000, 0.000000]";
    assert_eq!(lines[1], format!("kd = [0.350000, 0.350000, 0.350000] ± {zeros}"), "{stdout}");
    assert_eq!(lines[2], format!("ks = [0.150000, 0.150000, 0.150000] ± {zeros}"), "{stdout}");
    let (shininess, error) = lines[3].strip_prefix("shininess = ").unwrap().split_once(" ± ").unwrap();
    assert!((shininess.parse::<f32>().unwrap() - 16.0).abs() < 0.01, "{stdout}");
    assert!(error.parse::<f32>().unwrap() < 1e-3, "{stdout}");
    assert!(lines[4].starts_with("residual = 0.000000"), "{stdout}");
    assert!(std::fs::read_to_string(&plot).unwrap().contains("blinn-phong (fit), θi 50°"));
    for (args, needle) in [
        (vec!["--material", "velvet", "--to", "phong"], "--material velvet: no such material"),
        (vec!["--material", "gold", "--to", "ward"], "--to ward: not a model"),
        (vec!["--material", "gold", "--to", "phong", "--theta-i", "95"], "--theta-i 95"),
        (vec!["--material", "gold", "--to", "phong", "-o", "fit.csv"], "drawn as .png or .svg"),
        (vec!["--material", "gold", "--to", "nosuch.brdf"], "--to: cannot read the BRDF file nosuch.brdf"),
        (vec!["--material", "gold", "--to", "phong", "--hold", "ks"], "--hold ks: none of the models fitted (phong)"),
    ] {
        let mut full = vec!["fit", materials.to_str().unwrap()];
        full.extend(args);
        let output = vk_render(&full);
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert!(
            !output.status.success() && stderr.lines().count() == 1 && stderr.contains(needle),
            "{full:?}: {stderr}"
        );
    }
}

/// A `.brdf` file fitted: each parameter with its error, those held as the file has them; with a built-in
/// model beside it, the two ranked by their residuals.
#[test]
fn fit_to_a_brdf_file_holds_what_it_is_told_and_ranks_it_beside_the_built_in_models() {
    let materials = root().join("assets/analysis/course-materials.toml");
    let file = root().join("assets/brdfs/blinn_phong.brdf");
    let fit = |to: &str, hold: &[&str]| {
        let mut args = vec!["fit", materials.to_str().unwrap(), "--material", "blinn-phong", "--to", to];
        args.extend(hold);
        succeeds(&args)
    };
    // The file's Blinn-Phong is the material's model: exact, every parameter found.
    let stdout = fit(file.to_str().unwrap(), &[]);
    let lines: Vec<&str> = stdout.lines().collect();
    assert!(lines[0].contains("fitted with blinn_phong.brdf"), "{stdout}");
    assert!(lines[1].starts_with("kd = [0.350000, 0.350000, 0.350000] ± ["), "{stdout}");
    assert!(lines[2].starts_with("ks = [0.150000, 0.150000, 0.150000] ± ["), "{stdout}");
    assert!(lines[3].starts_with("shininess = 16.0000 ± "), "{stdout}");
    assert!(lines[4].starts_with("residual = 0.000000"), "{stdout}");
    // ks held at the file's 0.3: the others make up for it as they can, and the residual says so.
    let stdout = fit(file.to_str().unwrap(), &["--hold", "ks"]);
    assert!(stdout.contains("\nks = [0.3, 0.3, 0.3] (held)\n"), "{stdout}");
    let shininess: f32 = stdout.split("shininess = ").nth(1).unwrap().split(' ').next().unwrap().parse().unwrap();
    assert!(shininess > 20.0, "{stdout}");
    assert!(!stdout.contains("residual = 0.000000"), "{stdout}");
    // Beside the built-in Blinn-Phong, Ward's file comes second.
    let ward = root().join("assets/brdfs/ward.brdf");
    let stdout = fit(&format!("{},blinn-phong", ward.display()), &[]);
    let lines: Vec<&str> = stdout.lines().collect();
    assert!(lines[0].contains("fitted with 2 models") && lines[0].ends_with("best first:"), "{stdout}");
    assert!(lines[1].starts_with("1. blinn-phong") && lines[2].starts_with("2. ward.brdf"), "{stdout}");
}

#[test]
fn plot_lobe3d_renders_a_panel_per_material() {
    let folder = temp_dir();
    let png = folder.path().join("lobe3d.png");
    let fig2 = fig2();
    succeeds(&[
        "plot",
        "lobe3d",
        &fig2,
        "--theta-i",
        "45",
        "--size",
        "200,150",
        "--from",
        "30,-20",
        "-o",
        png.to_str().unwrap(),
    ]);
    let picture = image::open(&png).unwrap().to_rgb8();
    assert!(picture.width() > 2 * 200 && picture.height() > 150, "{:?}", picture.dimensions());
    std::fs::remove_file(&png).unwrap();
    let svg = folder.path().join("lobe3d.svg");
    fails(folder.path(), &["plot", "lobe3d", &fig2, "-o", svg.to_str().unwrap()], 1, &["rendered, to a .png"]);
    fails(
        folder.path(),
        &["plot", "lobe3d", &fig2, "--from", "95,0", "-o", png.to_str().unwrap()],
        1,
        &["--from 95,0"],
    );
}

#[test]
fn a_term_view_the_scene_cannot_show_is_one_line_and_no_file() {
    let folder = temp_dir();
    let out = folder.path().join("d.png");
    let fig1 = root().join("assets/scenes/fig1-lambert.toml");
    fails(
        folder.path(),
        &["render", fig1.to_str().unwrap(), "--view", "d", "-o", out.to_str().unwrap()],
        1,
        &["fig1-lambert.toml", "image.view = \"d\": no object is Cook-Torrance"],
    );
    fails(
        folder.path(),
        &["render", fig1.to_str().unwrap(), "--view", "depth", "-o", out.to_str().unwrap()],
        2,
        &["'depth'"],
    );
    let gold = root().join("assets/scenes/fig4-gold-metalness-0.5.toml");
    let output = vk_render(&[
        "render",
        gold.to_str().unwrap(),
        "--view",
        "d",
        "--width",
        "60",
        "--height",
        "40",
        "-o",
        out.to_str().unwrap(),
    ]);
    let (stdout, stderr) = (String::from_utf8_lossy(&output.stdout), String::from_utf8_lossy(&output.stderr));
    assert!(output.status.success(), "{stderr}");
    assert!(stdout.starts_with("view d: PNG level = 255 x value / "), "the scale is stated: {stdout}");
    assert!(stderr.contains("object.1 (lambert) not Cook-Torrance: black in this view"), "{stderr}");
}
