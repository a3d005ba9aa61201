//! Writing a site's folder, file by file.

use std::path::Path;

use anyhow::Context;

/// Writes `bytes` as the file `name` (a path relative to `folder`, its folders made as needed).
pub fn put(folder: &Path, name: &str, bytes: &[u8]) -> anyhow::Result<()> {
    let path = folder.join(name);
    if let Some(parent) = path.parent() {
        std::fs::create_dir_all(parent).with_context(|| format!("{}: cannot make the folder", parent.display()))?;
    }
    std::fs::write(&path, bytes).with_context(|| format!("{}: cannot write it", path.display()))
}
