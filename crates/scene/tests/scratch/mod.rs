//! A fresh directory per test (tests run in parallel threads of one process), removed when the
//! test is done with it, so that runs of the suite leave nothing in the temporary directory.

use std::ops::Deref;
use std::path::{Path, PathBuf};

pub struct Scratch(PathBuf);

/// `leakless-scene-{kind}{pid}-{test}` under the temporary directory, empty.
pub fn scratch(kind: &str, test: &str) -> Scratch {
    let dir = std::env::temp_dir().join(format!("leakless-scene-{kind}{}-{test}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    Scratch(dir)
}

impl Deref for Scratch {
    type Target = Path;
    fn deref(&self) -> &Path {
        &self.0
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}
