//! Reading the files a user names: regular files only, and of bounded size, so that a FIFO, a device, a
//! folder or a huge file gives one clear line instead of a hang or exhausted memory.

use std::io::Read;
use std::path::Path;

/// The most a scene file may hold: 16 MiB (the figures' are under 2 KiB).
pub const MAX_SCENE_BYTES: u64 = 16 << 20;
/// The most an OBJ file may hold: 4 GiB (glmark2's bunny is 3 MiB).
pub const MAX_MESH_BYTES: u64 = 4 << 30;
/// The most an image a user names may hold (an environment map, `check`'s image): 1 GiB.
pub const MAX_IMAGE_BYTES: u64 = 1 << 30;
/// The most a shader source may hold: 1 MiB.
pub const MAX_SHADER_BYTES: u64 = 1 << 20;

/// At most the first 40 characters of `text`, for messages that quote what the user gave (the `.brdf` reader's,
/// which the browser runs too).
pub use brdf_file::shortened;

/// The bytes of `path`, `what` it is (named in errors: "scene file", "OBJ file"), which must be a regular
/// file of at most `limit` bytes. The kind is checked before the file is opened (opening a FIFO waits
/// for a writer), and reading stops past the limit should the file grow meanwhile.
///
/// # Errors
/// One line naming the path and what is wrong with it.
pub fn read_regular(path: &Path, what: &str, limit: u64) -> Result<Vec<u8>, String> {
    let shown = path.display();
    let metadata = std::fs::metadata(path).map_err(|e| format!("cannot read the {what} {shown}: {e}"))?;
    if !metadata.is_file() {
        return Err(format!("the {what} {shown} is {}, not a regular file", kind_of(&metadata.file_type())));
    }
    let too_big = |size: u64| {
        format!("the {what} {shown} holds {}: over the {} a {what} may hold", size_text(size), size_text(limit))
    };
    if metadata.len() > limit {
        return Err(too_big(metadata.len()));
    }
    let file = std::fs::File::open(path).map_err(|e| format!("cannot read the {what} {shown}: {e}"))?;
    let mut bytes = Vec::with_capacity(metadata.len() as usize);
    file.take(limit + 1).read_to_end(&mut bytes).map_err(|e| format!("cannot read the {what} {shown}: {e}"))?;
    if bytes.len() as u64 > limit {
        return Err(too_big(bytes.len() as u64));
    }
    Ok(bytes)
}

/// As [`read_regular`], the bytes then read as UTF-8 text.
///
/// # Errors
/// As [`read_regular`], or a line saying the file is not UTF-8 text.
pub fn read_regular_text(path: &Path, what: &str, limit: u64) -> Result<String, String> {
    String::from_utf8(read_regular(path, what, limit)?)
        .map_err(|e| format!("the {what} {} is not UTF-8 text (byte {})", path.display(), e.utf8_error().valid_up_to()))
}

/// What a file that is not a regular file is, in words.
fn kind_of(kind: &std::fs::FileType) -> &'static str {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if kind.is_fifo() {
            return "a FIFO (named pipe)";
        }
        if kind.is_char_device() || kind.is_block_device() {
            return "a device";
        }
        if kind.is_socket() {
            return "a socket";
        }
    }
    if kind.is_dir() {
        "a folder"
    } else {
        "not a file"
    }
}

/// A size in bytes as people read it: "16 MiB", "1.5 GiB", "300 bytes".
fn size_text(bytes: u64) -> String {
    const UNITS: [(&str, u64); 3] = [("GiB", 1 << 30), ("MiB", 1 << 20), ("KiB", 1 << 10)];
    match UNITS.iter().find(|(_, size)| bytes >= *size) {
        Some((unit, size)) if bytes.is_multiple_of(*size) => format!("{} {unit}", bytes / size),
        Some((unit, size)) => format!("{:.1} {unit}", bytes as f64 / *size as f64),
        None => format!("{bytes} bytes"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_read_as_people_say_them() {
        assert_eq!(size_text(MAX_SCENE_BYTES), "16 MiB");
        assert_eq!(size_text(MAX_MESH_BYTES), "4 GiB");
        assert_eq!(size_text(3 << 19), "1.5 MiB");
        assert_eq!(size_text(300), "300 bytes");
    }

    #[test]
    fn devices_folders_and_big_files_are_refused_by_name() {
        let message = read_regular(Path::new("/dev/zero"), "scene file", MAX_SCENE_BYTES).unwrap_err();
        assert!(message.contains("/dev/zero is a device, not a regular file"), "{message}");
        let folder = std::env::temp_dir();
        let message = read_regular(&folder, "OBJ file", MAX_MESH_BYTES).unwrap_err();
        assert!(message.contains("is a folder, not a regular file"), "{message}");
        let path = folder.join(format!("vk-render-big-{}", std::process::id()));
        std::fs::write(&path, vec![b'#'; 2048]).unwrap();
        let message = read_regular(&path, "scene file", 1024).unwrap_err();
        std::fs::remove_file(&path).unwrap();
        assert!(message.contains("holds 2 KiB: over the 1 KiB a scene file may hold"), "{message}");
    }
}
