//! Writing a file aside and renaming it into place, so a failure never leaves a half-written
//! file at the target path and never clobbers a good existing one.

use std::path::Path;

/// Writes `bytes` to `.NAME.tmp-PID` beside `path`, then renames it over `path`; the temporary
/// file is removed when either step fails.
pub fn write_file_atomically(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let file_name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let tmp = path.with_file_name(format!(".{file_name}.tmp-{}", std::process::id()));
    let result = std::fs::write(&tmp, bytes).and_then(|()| std::fs::rename(&tmp, path));
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result
}
