//! Files the targets write their inputs to, for the readers that take paths:
//! one folder per process, so that runs side by side do not collide.

use std::path::PathBuf;

fn folder() -> PathBuf {
    std::env::temp_dir().join(format!("bvol-fuzz-{}", std::process::id()))
}

/// Writes `bytes` to the scratch file `name` and returns its path.
pub fn file(name: &str, bytes: &[u8]) -> PathBuf {
    let dir = folder();
    std::fs::create_dir_all(&dir).expect("create the scratch folder");
    let path = dir.join(name);
    std::fs::write(&path, bytes).expect("write a scratch file");
    path
}

/// Removes this process's scratch files.
pub fn remove_scratch() {
    let _ = std::fs::remove_dir_all(folder());
}
