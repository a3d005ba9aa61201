//! `vk-render sweep` over several parameters, in shards and resumed after a kill, and `vk-render sheet`: the
//! tiles are the renders of their values, the sheets the same bytes however the sweep was split or stopped.

mod common;

use std::collections::BTreeSet;
use std::path::Path;
use std::process::{Command, Output};

use common::{root, temp_dir, vk_render};
use image::RgbImage;
use vk_render::pictures::sheet::{assemble, SheetLayout};

/// Small, fast tiles.
const SMALL: [&str; 6] = ["--width", "48", "--height", "32", "--samples", "1"];

/// `vk-render COMMAND` (sweep or sheet) of Figure 1 over `params` (KEY, V1,V2,...), its sheet at `sheet`, then
/// `extra` arguments; with the validation layer on.
fn grid_command(command: &str, params: &[(&str, &str)], sheet: &Path, extra: &[&str]) -> Output {
    vk_render(&grid_args(command, params, sheet, extra).iter().map(String::as_str).collect::<Vec<_>>())
}

fn grid_args(command: &str, params: &[(&str, &str)], sheet: &Path, extra: &[&str]) -> Vec<String> {
    let fig1 = root().join("assets/scenes/fig1-lambert.toml");
    let mut args = vec![command.to_string(), fig1.to_str().unwrap().to_string()];
    for (key, values) in params {
        args.extend(["--param", key, "--values", values].map(String::from));
    }
    args.extend(["-o", sheet.to_str().unwrap()].map(String::from));
    args.extend(SMALL.iter().chain(extra).map(|arg| arg.to_string()));
    args
}

fn succeeded(output: &Output) -> String {
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    String::from_utf8_lossy(&output.stdout).into_owned()
}

/// The names of the files in `folder`, sorted.
fn names(folder: &Path) -> BTreeSet<String> {
    std::fs::read_dir(folder).unwrap().flatten().map(|e| e.file_name().to_string_lossy().into_owned()).collect()
}

fn read(path: &Path) -> RgbImage {
    image::open(path).unwrap_or_else(|e| panic!("{}: {e}", path.display())).into_rgb8()
}

/// Runs a command that must fail with `code`, one line on stderr holding every needle, and leave `folder`
/// as it was.
fn fails(output: Output, code: i32, folder: &Path, before: &BTreeSet<String>, needles: &[&str]) {
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(code), "{stderr}");
    assert_eq!(stderr.trim_end().lines().count(), 1, "not one line: {stderr}");
    for needle in needles {
        assert!(stderr.contains(needle), "stderr lacks {needle:?}: {stderr}");
    }
    assert_eq!(&names(folder), before, "files written or removed; {stderr}");
}

const KD: (&str, &str) = ("material.grey.kd", "0.2,0.6");
const POWER: (&str, &str) = ("light.0.power", "30,60,90");
const RED: (&str, &str) = ("material.red.kd", "0.5,1");

#[test]
fn two_parameters_make_a_grid_of_the_renders_of_their_values() {
    let folder = temp_dir();
    let sheet = folder.path().join("grid.png");
    succeeded(&grid_command("sweep", &[KD, POWER], &sheet, &[]));
    let mut expected = BTreeSet::from(["grid.png".to_string()]);
    let mut tiles = Vec::new();
    for kd in ["0.2", "0.6"] {
        for power in ["30", "60", "90"] {
            let name = format!("grid-kd={kd}-power={power}.png");
            let tile = folder.path().join(&name);
            // The tile is the very file `render` writes with the same values.
            let alone = folder.path().join("alone").with_extension("png");
            let fig1 = root().join("assets/scenes/fig1-lambert.toml");
            let kd_set = format!("material.grey.kd={kd}");
            let power_set = format!("light.0.power={power}");
            let mut args = vec!["render", fig1.to_str().unwrap(), "-o", alone.to_str().unwrap()];
            args.extend(["--set", &kd_set, "--set", &power_set]);
            args.extend(SMALL);
            succeeded(&vk_render(&args));
            assert!(std::fs::read(&tile).unwrap() == std::fs::read(&alone).unwrap(), "{name} is not its render");
            std::fs::remove_file(&alone).unwrap();
            tiles.push((String::new(), read(&tile)));
            expected.insert(name);
        }
    }
    assert_eq!(names(folder.path()), expected);
    // Rows of kd, columns of power, labelled at the left and on top: the sheet drawn again from the tiles.
    let layout = SheetLayout::grid(
        Some("material.grey.kd x light.0.power"),
        vec!["kd = 0.2".into(), "kd = 0.6".into()],
        vec!["power = 30".into(), "power = 60".into(), "power = 90".into()],
        (48, 32),
    );
    let made = read(&sheet);
    assert_eq!(made.dimensions(), layout.size());
    assert!(made.width() > 8 + 3 * (48 + 8) && made.height() > 8 + 2 * (32 + 8), "no room for the labels");
    assert!(made == assemble(&layout, &tiles), "the sheet is not the grid of the tiles");
}

#[test]
fn three_parameters_make_a_labelled_tile_per_combination() {
    let folder = temp_dir();
    let sheet = folder.path().join("three.png");
    succeeded(&grid_command("sweep", &[KD, POWER, RED], &sheet, &["--columns", "6"]));
    let mut tiles = Vec::new();
    for kd in ["0.2", "0.6"] {
        for power in ["30", "60", "90"] {
            for red in ["0.5", "1"] {
                let tile = read(
                    &folder.path().join(format!("three-material.grey.kd={kd}-power={power}-material.red.kd={red}.png")),
                );
                let label = format!("material.grey.kd = {kd}, power = {power}, material.red.kd = {red}");
                tiles.push((label, tile));
            }
        }
    }
    assert_eq!(names(folder.path()).len(), 2 * 3 * 2 + 1, "a tile per combination and the sheet");
    let layout = SheetLayout::new(Some("material.grey.kd x light.0.power x material.red.kd"), 12, (48, 32), 6)
        .with_fitted_labels();
    let made = read(&sheet);
    assert_eq!(made.dimensions(), (8 + 6 * (48 + 8), layout.size().1));
    assert!(made == assemble(&layout, &tiles), "the sheet is not the labelled tiles");
}

#[test]
fn shards_then_sheet_make_the_bytes_of_one_sweep() {
    let whole = temp_dir();
    let whole_sheet = whole.path().join("s.png");
    succeeded(&grid_command("sweep", &[POWER, KD], &whole_sheet, &[]));
    let split = temp_dir();
    let sheet = split.path().join("s.png");
    let mut shares: Vec<BTreeSet<String>> = Vec::new();
    for k in 1..=3 {
        let before = names(split.path());
        let stdout = succeeded(&grid_command("sweep", &[POWER, KD], &sheet, &["--shard", &format!("{k}/3")]));
        // No sheet yet, and one line saying how to make it.
        assert!(!sheet.exists(), "shard {k}/3 wrote the sheet");
        assert!(stdout.contains(&format!("shard {k}/3: 2 tile(s) written")), "{stdout}");
        assert!(stdout.contains(" sheet ") && !stdout.contains("--shard"), "{stdout}");
        shares.push(names(split.path()).difference(&before).cloned().collect());
    }
    let mut tiles = names(whole.path());
    tiles.remove("s.png");
    assert_eq!(tiles.len(), 6);
    for (k, share) in shares.iter().enumerate() {
        assert_eq!(share.len(), 2, "shard {}/3: {share:?}", k + 1);
    }
    assert_eq!(shares.iter().flatten().cloned().collect::<BTreeSet<_>>(), tiles, "the shards cover the sweep");
    assert_eq!(names(split.path()), tiles, "the shards overlap or wrote other files");
    // `sheet` renders nothing: it must not need a device (no Vulkan driver at all here).
    let args = grid_args("sheet", &[POWER, KD], &sheet, &[]);
    let output = Command::new(env!("CARGO_BIN_EXE_vk-render"))
        .args(&args)
        .env("VK_ICD_FILENAMES", split.path().join("none.json"))
        .env("VK_DRIVER_FILES", split.path().join("none.json"))
        .output()
        .unwrap();
    succeeded(&output);
    for name in tiles.iter().chain(["s.png".to_string()].iter()) {
        let same = std::fs::read(split.path().join(name)).unwrap() == std::fs::read(whole.path().join(name)).unwrap();
        assert!(same, "{name} differs from the one-process sweep's");
    }
    // Shard 1/1 is the whole sweep, sheet and all.
    let one = temp_dir();
    succeeded(&grid_command("sweep", &[POWER, KD], &one.path().join("s.png"), &["--shard", "1/1"]));
    assert!(std::fs::read(one.path().join("s.png")).unwrap() == std::fs::read(&whole_sheet).unwrap());
}

#[test]
fn a_killed_sweep_resumes_to_the_bytes_of_an_uninterrupted_one() {
    let values = ("material.grey.kd", "0.1,0.2,0.3,0.4,0.5,0.6");
    let whole = temp_dir();
    succeeded(&grid_command("sweep", &[values], &whole.path().join("kd.png"), &[]));
    let folder = temp_dir();
    let sheet = folder.path().join("kd.png");
    // Every write held 400 ms before its rename: killed once the first tile is whole, the sweep is far
    // from done.
    let mut child = Command::new(env!("CARGO_BIN_EXE_vk-render"))
        .args(grid_args("sweep", &[values], &sheet, &[]))
        .env("VK_RENDER_TEST_WRITE_PAUSE_MS", "400")
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let deadline = std::time::Instant::now() + std::time::Duration::from_secs(60);
    while !names(folder.path()).iter().any(|name| name.ends_with(".png")) {
        assert!(std::time::Instant::now() < deadline, "no tile appeared");
        assert!(child.try_wait().unwrap().is_none(), "the sweep ended before it was killed");
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
    child.kill().unwrap(); // SIGKILL: nothing is cleaned up
    child.wait().unwrap();
    let left = names(folder.path());
    let whole_tiles = left.iter().filter(|name| name.ends_with(".png")).count();
    assert!((1..6).contains(&whole_tiles) && !sheet.exists(), "killed too late: {left:?}");
    let stdout = succeeded(&grid_command("sweep", &[values], &sheet, &["--resume"]));
    assert!(stdout.contains(&format!("--resume: skipped {whole_tiles} of 6 tile(s)")), "{stdout}");
    // Every tile and the sheet the same bytes, and no partial file left.
    assert_eq!(names(folder.path()), names(whole.path()));
    for name in names(whole.path()) {
        let same =
            std::fs::read(folder.path().join(&name)).unwrap() == std::fs::read(whole.path().join(&name)).unwrap();
        assert!(same, "{name} differs from the uninterrupted sweep's");
    }
    // Resumed again with everything on disk: nothing rendered, the same sheet.
    let stdout = succeeded(&grid_command("sweep", &[values], &sheet, &["--resume"]));
    assert!(stdout.contains("--resume: skipped 6 of 6 tile(s)"), "{stdout}");
    assert!(std::fs::read(&sheet).unwrap() == std::fs::read(whole.path().join("kd.png")).unwrap());
}

#[test]
fn resume_renders_again_a_tile_that_is_not_whole_and_keeps_tiles_on_a_failure() {
    let folder = temp_dir();
    let sheet = folder.path().join("kd.png");
    let values = ("material.grey.kd", "0.1,0.2,0.3");
    succeeded(&grid_command("sweep", &[values], &sheet, &[]));
    let good = std::fs::read(folder.path().join("kd-0.2.png")).unwrap();
    // A tile cut short and a tile of another size are rendered again.
    std::fs::write(folder.path().join("kd-0.2.png"), &good[..good.len() / 2]).unwrap();
    RgbImage::new(10, 10).save(folder.path().join("kd-0.3.png")).unwrap();
    let stdout = succeeded(&grid_command("sweep", &[values], &sheet, &["--resume"]));
    assert!(stdout.contains("--resume: skipped 1 of 3 tile(s)"), "{stdout}");
    assert!(std::fs::read(folder.path().join("kd-0.2.png")).unwrap() == good);
    // A failure (the sheet's path taken by a folder) removes what this run wrote, not the kept tiles.
    std::fs::remove_file(folder.path().join("kd-0.3.png")).unwrap();
    std::fs::remove_file(&sheet).unwrap();
    std::fs::create_dir(&sheet).unwrap();
    let output = grid_command("sweep", &[values], &sheet, &["--resume"]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("1 file(s) written before it were removed"), "{stderr}");
    assert_eq!(names(folder.path()), BTreeSet::from(["kd-0.1.png", "kd-0.2.png", "kd.png"].map(String::from)));
}

#[test]
fn bad_grids_shards_and_missing_tiles_are_one_line_and_write_nothing() {
    let folder = temp_dir();
    let dir = folder.path();
    let sheet = dir.join("g.png");
    let none = BTreeSet::new();
    let fig1 = root().join("assets/scenes/fig1-lambert.toml");
    let mut args = vec!["sweep", fig1.to_str().unwrap(), "--param", "material.grey.kd", "--values", "0.1"];
    args.extend(["--param", "light.0.power", "-o", sheet.to_str().unwrap()]);
    fails(vk_render(&args), 1, dir, &none, &["--param is given 2 time(s) and --values 1"]);
    // The second parameter's bad value is found before anything is rendered.
    let bad = ("light.0.power", "30,-5");
    fails(grid_command("sweep", &[KD, bad], &sheet, &[]), 1, dir, &none, &["light.0.power = -5"]);
    let twice = ("material.grey.kd", "0.3");
    fails(grid_command("sweep", &[KD, twice], &sheet, &[]), 1, dir, &none, &["material.grey.kd is given twice"]);
    fails(grid_command("sweep", &[KD, POWER], &sheet, &["--columns", "2"]), 1, dir, &none, &["--columns 2", "grid"]);
    for (shard, needle) in [("0/2", "K is 1 to 2"), ("3/2", "K is 1 to 2"), ("x", "is not K/N"), ("1/0", "N is")] {
        fails(grid_command("sweep", &[KD], &sheet, &["--shard", shard]), 2, dir, &none, &["--shard", needle]);
    }
    // `sheet` with a tile missing names how many and the first, and writes nothing.
    succeeded(&grid_command("sweep", &[KD, POWER], &sheet, &["--shard", "1/2"]));
    let before = names(dir);
    assert_eq!(before.len(), 3);
    fails(
        grid_command("sheet", &[KD, POWER], &sheet, &[]),
        1,
        dir,
        &before,
        &["3 of 6 tile(s) are missing or not whole", "g-kd=0.2-power=60.png (no such file)"],
    );
    // A tile of another size is not whole either.
    fails(
        grid_command("sheet", &[KD, POWER], &sheet, &["--set", "image.width=40"]),
        1,
        dir,
        &before,
        &["6 of 6 tile(s)", "g-kd=0.2-power=30.png (a 48 x 32 image, not the tile's 40 x 32)"],
    );
}
