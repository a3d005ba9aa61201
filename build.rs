//! Embeds the GLSL sources of shaders/ in the binary with their SPIR-V, compiled here by glslc, and links
//! shaderc (the run-time compiler of `--shaders` and hot reloading) against the system's static glslang and
//! SPIRV-Tools archives.
//!
//! Debian's `libshaderc.so` does not declare its glslang and spvtools dependencies, so the shaderc crate's
//! default dynamic link fails with undefined symbols. With the crate's `prefer-static-linking` feature it
//! links `libshaderc_combined.a`-style, and the archives below supply the rest. Which of them exist depends
//! on the glslang release (glslang 15, Debian 13, has no OGLCompiler; later ones fold more into glslang), and
//! where they are on the architecture: they are looked for, not assumed.

use std::path::{Path, PathBuf};
use std::process::Command;

#[path = "build/webgl.rs"]
mod webgl;

/// The archives shaderc needs, in link order (each before those it uses), and whether every glslang has it.
const ARCHIVES: [(&str, bool); 8] = [
    ("glslang", true),
    ("MachineIndependent", false),
    ("GenericCodeGen", false),
    ("OSDependent", false),
    ("OGLCompiler", false),
    ("SPIRV", false),
    ("SPIRV-Tools-opt", true),
    ("SPIRV-Tools", true),
];

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    embed_shaders();
    compile_shaders();
    translate_for_webgl();
    if std::env::var_os("CARGO_FEATURE_SERVE").is_some() {
        build_web_assembly();
    }
    link_glslang_and_spirv_tools();
}

/// Builds the crate crates/web/ (the library's code the pages run: a student's `.brdf` read and wrapped for WebGL2,
/// the albedo's cubature, the check's rules) for wasm32-unknown-unknown into `$OUT_DIR/vk-render.wasm`, which the server and `vk-render site` hand out
/// as `static/vk-render.wasm`. A cargo of its own, with its own target folder under OUT_DIR (this build's
/// holds its lock), offline and locked: the crates it uses are this build's.
fn build_web_assembly() {
    // crates/web/ and the device-free crates it is built from, beside it.
    println!("cargo:rerun-if-changed=crates");
    let out = PathBuf::from(std::env::var("OUT_DIR").expect("cargo sets OUT_DIR"));
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let manifest = Path::new(env!("CARGO_MANIFEST_DIR")).join("crates/web/Cargo.toml");
    let target = "wasm32-unknown-unknown";
    let mut command = Command::new(&cargo);
    command
        .args(["build", "--release", "--offline", "--locked", "--target", target, "--manifest-path"])
        .arg(&manifest)
        .arg("--target-dir")
        .arg(out.join("wasm-target"))
        // This build's flags are for this machine's code, not the WebAssembly's.
        .env_remove("RUSTFLAGS")
        .env_remove("CARGO_ENCODED_RUSTFLAGS")
        .env_remove("CARGO_BUILD_TARGET")
        .env("CARGO_PROFILE_RELEASE_STRIP", "true");
    let output = command.output().unwrap_or_else(|e| panic!("cannot run {cargo} to build crates/web/ ({e})"));
    if !output.status.success() {
        let said = String::from_utf8_lossy(&output.stderr);
        let hint =
            if said.contains(target) && said.contains("not installed") || said.contains("can't find crate for `std`") {
                format!("\nthe Rust target {target} is missing: `rustup target add {target}` (`make setup` does)")
            } else {
                String::new()
            };
        panic!("the WebAssembly of crates/web/ did not build:\n{said}{hint}");
    }
    let built = out.join(format!("wasm-target/{target}/release/vk_render_web.wasm"));
    std::fs::copy(&built, out.join("vk-render.wasm")).unwrap_or_else(|e| panic!("{}: {e}", built.display()));
}

/// Finds each archive of [`ARCHIVES`] in the library folders that pkg-config and the C compiler name, and
/// links those found; stops the build with the folders searched when a required one is missing.
fn link_glslang_and_spirv_tools() {
    let folders = library_folders();
    let mut linked_from = Vec::<PathBuf>::new();
    let mut missing = Vec::new();
    for (name, required) in ARCHIVES {
        let file = format!("lib{name}.a");
        match folders.iter().find(|folder| folder.join(&file).is_file()) {
            Some(folder) => {
                if !linked_from.contains(folder) {
                    println!("cargo:rustc-link-search=native={}", folder.display());
                    linked_from.push(folder.clone());
                }
                println!("cargo:rustc-link-lib=static:-bundle={name}");
            }
            None if required => missing.push(file),
            None => {}
        }
    }
    if !missing.is_empty() {
        let searched: Vec<_> = folders.iter().map(|f| f.display().to_string()).collect();
        panic!(
            "shaderc needs the static archives {} (Debian/Ubuntu packages glslang-dev and spirv-tools: run \
             `make setup`); searched {}",
            missing.join(", "),
            searched.join(", ")
        );
    }
}

/// Where static libraries may be: the folders pkg-config gives for glslang and SPIRV-Tools, then the C
/// compiler's library search path (which holds the multiarch folder of whatever architecture this is).
fn library_folders() -> Vec<PathBuf> {
    println!("cargo:rerun-if-env-changed=PKG_CONFIG_PATH");
    println!("cargo:rerun-if-env-changed=CC");
    let mut folders = Vec::new();
    for package in ["glslang", "SPIRV-Tools"] {
        if let Some(libdir) = output_of(Command::new("pkg-config").args(["--variable=libdir", package])) {
            folders.push(PathBuf::from(libdir.trim()));
        }
    }
    let compiler = std::env::var("CC").unwrap_or_else(|_| "cc".into());
    if let Some(dirs) = output_of(Command::new(compiler).arg("-print-search-dirs")) {
        let libraries = dirs.lines().find_map(|line| line.strip_prefix("libraries: =")).unwrap_or_default();
        folders.extend(libraries.split(':').filter(|d| !d.is_empty()).map(PathBuf::from));
    }
    let mut unique: Vec<PathBuf> = Vec::new();
    for folder in folders {
        let folder = folder.canonicalize().unwrap_or(folder);
        if folder.is_dir() && !unique.contains(&folder) {
            unique.push(folder);
        }
    }
    unique
}

/// The standard output of a command that ran and succeeded.
fn output_of(command: &mut Command) -> Option<String> {
    let output = command.output().ok().filter(|o| o.status.success())?;
    String::from_utf8(output.stdout).ok()
}

/// Writes `$OUT_DIR/shaders.rs`: a table of every file under shaders/ (path relative to it, text), so the
/// binary compiles its shaders at run time from wherever it is installed, with no files beside it.
fn embed_shaders() {
    println!("cargo:rerun-if-changed=shaders");
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("shaders");
    let mut files = Vec::new();
    webgl::collect(&root, &mut files);
    files.sort();
    let mut table = String::from("&[\n");
    for file in &files {
        let relative = file.strip_prefix(&root).expect("under shaders/").to_string_lossy().replace('\\', "/");
        println!("cargo:rerun-if-changed={}", file.display());
        table.push_str(&format!("    ({relative:?}, include_str!({:?})),\n", file.display().to_string()));
    }
    table.push_str("]\n");
    let out = Path::new(&std::env::var("OUT_DIR").expect("cargo sets OUT_DIR")).join("shaders.rs");
    std::fs::write(out, table).expect("OUT_DIR is writable");
}

/// Writes `$OUT_DIR/spirv.rs`: a table of every entry file under shaders/ (.vert, .frag, .comp) with its
/// SPIR-V, so that a process starts without compiling GLSL (the first compile of each stage builds glslang's
/// built-in tables: 80 ms of a 250 ms `vk-render render` on lavapipe). glslc is shaderc's own command, of
/// the same Debian source as the library the run-time compiler links; it runs in shaders/ with the run-time
/// compiler's options (ShaderCompiler::compile: Vulkan 1.3, SPIR-V 1.5, no debug info; includes beside the
/// including file, then from shaders/, then `double/FILE` as FILE made double: [`write_double_shaders`]),
/// and a test checks that both give the same words.
fn compile_shaders() {
    println!("cargo:rerun-if-env-changed=GLSLC");
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("shaders");
    let out = PathBuf::from(std::env::var("OUT_DIR").expect("cargo sets OUT_DIR")).join("spirv");
    let mut files = Vec::new();
    webgl::collect(&root, &mut files);
    files.sort();
    let glslc = std::env::var("GLSLC").unwrap_or_else(|_| "glslc".into());
    let doubles = write_double_shaders(&root, &files, &out);
    let mut table = String::from("&[\n");
    for file in &files {
        let relative = file.strip_prefix(&root).expect("under shaders/").to_string_lossy().replace('\\', "/");
        // shaders/web/ holds the browser's own entries (translate_for_webgl), which the renderer never runs.
        if !webgl::is_entry(&relative) || relative.starts_with("web/") {
            continue;
        }
        // An entry file may name variants, each compiled again with its macros defined: `// variant: A+B`
        // gives the entry `FILE+A+B` (shaders/forward.frag: its environment's light and its term views apart,
        // so that the radiance of scenes without an environment does not make lavapipe read their code).
        let text = std::fs::read_to_string(file).expect("shaders/ is readable");
        for variant in std::iter::once(None).chain(webgl::variants(&text).map(Some)) {
            let entry = match variant {
                Some(name) => format!("{relative}+{name}"),
                None => relative.clone(),
            };
            let spirv = out.join(format!("{entry}.spv"));
            std::fs::create_dir_all(spirv.parent().expect("a file has a folder")).expect("OUT_DIR is writable");
            let mut command = Command::new(&glslc);
            command.current_dir(&root).args(webgl::GLSLC_OPTIONS).arg("-I").arg(&doubles);
            for name in variant.iter().flat_map(|names| names.split('+')) {
                command.arg(format!("-D{name}"));
            }
            let status = command.arg("-o").arg(&spirv).arg(&relative).status().unwrap_or_else(|e| {
                panic!("cannot run {glslc} to compile shaders/{relative} ({e}): install the Debian package glslc (`make setup`)")
            });
            assert!(status.success(), "glslc could not compile shaders/{entry} (its errors are above)");
            table.push_str(&format!("    ({entry:?}, include_bytes!({:?})),\n", spirv.display().to_string()));
        }
    }
    table.push_str("]\n");
    std::fs::write(out.with_extension("rs"), table).expect("OUT_DIR is writable");
}

/// Writes every `.glsl` file of `files` (under `root`) made double (brdf_file::shader_in_double) under
/// `out`/double-includes/double/, as the run-time compiler offers `double/FILE`; returns the folder to give
/// glslc with -I.
fn write_double_shaders(root: &Path, files: &[PathBuf], out: &Path) -> PathBuf {
    let includes = out.join("double-includes");
    for file in files.iter().filter(|f| f.extension().is_some_and(|e| e == "glsl")) {
        let relative = file.strip_prefix(root).expect("under shaders/");
        let double = includes.join(brdf_file::DOUBLE_FOLDER).join(relative);
        std::fs::create_dir_all(double.parent().expect("a file has a folder")).expect("OUT_DIR is writable");
        let text = std::fs::read_to_string(file).expect("shaders/ is readable");
        std::fs::write(&double, brdf_file::shader_in_double(&text)).expect("OUT_DIR is writable");
    }
    includes
}

/// Writes `$OUT_DIR/webgl.rs`: the browser's shaders (build/webgl.rs translates them), a table of each entry
/// file's name and its GLSL ES 3.00, and `$OUT_DIR/webgl_templates.rs`: the analytic templates of the browser's
/// editor of `.brdf` models, likewise; a shader the translation cannot take stops the build here, with the
/// tool's errors above, never in a visitor's browser.
fn translate_for_webgl() {
    println!("cargo:rerun-if-changed=build/webgl.rs");
    println!("cargo:rerun-if-env-changed=SPIRV_CROSS");
    println!("cargo:rerun-if-env-changed=GLSLANG_VALIDATOR");
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("shaders");
    let out = PathBuf::from(std::env::var("OUT_DIR").expect("cargo sets OUT_DIR")).join("webgl");
    let translated = webgl::translate(&root, &out, true).unwrap_or_else(|e| panic!("{e}"));
    std::fs::write(out.with_extension("rs"), text_table(&translated)).expect("OUT_DIR is writable");
    let templates = webgl::translate_templates(&root, &out, true).unwrap_or_else(|e| panic!("{e}"));
    std::fs::write(out.with_file_name("webgl_templates.rs"), text_table(&templates)).expect("OUT_DIR is writable");
}

/// The source of a table of names and the texts of their files.
fn text_table(files: &[(String, PathBuf)]) -> String {
    let mut table = String::from("&[\n");
    for (name, file) in files {
        table.push_str(&format!("    ({name:?}, include_str!({:?})),\n", file.display().to_string()));
    }
    table.push_str("]\n");
    table
}
