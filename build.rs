//! Embeds the GLSL sources of shaders/ in the binary, and links shaderc against Debian's static glslang and SPIRV-Tools archives.
//!
//! Debian's `libshaderc.so` does not declare its glslang and spvtools dependencies, so the shaderc crate's
//! default dynamic link fails with undefined symbols. With the crate's `prefer-static-linking` feature it
//! links `libshaderc_combined.a`-style; the eight archives below supply the rest (all are needed).

const STATIC_LIBS: [&str; 8] = [
    "glslang",
    "MachineIndependent",
    "GenericCodeGen",
    "OSDependent",
    "OGLCompiler",
    "SPIRV",
    "SPIRV-Tools-opt",
    "SPIRV-Tools",
];

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    embed_shaders();
    println!("cargo:rustc-link-search=native=/usr/lib/x86_64-linux-gnu");
    for lib in STATIC_LIBS {
        println!("cargo:rustc-link-lib=static:-bundle={lib}");
    }
}

/// Writes `$OUT_DIR/shaders.rs`: a table of every file under shaders/ (path relative to it, text), so the
/// binary compiles its shaders at run time from wherever it is installed, with no files beside it.
fn embed_shaders() {
    println!("cargo:rerun-if-changed=shaders");
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("shaders");
    let mut files = Vec::new();
    collect(&root, &mut files);
    files.sort();
    let mut table = String::from("&[\n");
    for file in &files {
        let relative = file.strip_prefix(&root).expect("under shaders/").to_string_lossy().replace('\\', "/");
        println!("cargo:rerun-if-changed={}", file.display());
        table.push_str(&format!("    ({relative:?}, include_str!({:?})),\n", file.display().to_string()));
    }
    table.push_str("]\n");
    let out = std::path::Path::new(&std::env::var("OUT_DIR").expect("cargo sets OUT_DIR")).join("shaders.rs");
    std::fs::write(out, table).expect("OUT_DIR is writable");
}

fn collect(dir: &std::path::Path, files: &mut Vec<std::path::PathBuf>) {
    for entry in std::fs::read_dir(dir).expect("shaders/ is readable").flatten() {
        let path = entry.path();
        if path.is_dir() {
            collect(&path, files);
        } else {
            files.push(path);
        }
    }
}
