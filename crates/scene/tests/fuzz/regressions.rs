//! Helpers of the regression tests (the tests are in main.rs, to keep their names).

use leakless_scene::{Scene, SceneError};
use serde_json::Value;

use crate::budget::{METER, OVER_CAP_NOTE};
use crate::cases::write_case;
use crate::corpus::Doc;

/// Writes `files` (the scene first) to a fresh directory and loads the scene with
/// the allocation meter armed; returns the result and the peak bytes held.
fn load_files(test: &str, files: &[(&str, Vec<u8>)]) -> (Result<Scene, SceneError>, usize) {
    let dir = std::env::temp_dir().join(format!("leakless-fuzz-{}-{test}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    for (name, bytes) in files {
        std::fs::write(dir.join(name), bytes).unwrap();
    }
    *OVER_CAP_NOTE.lock().unwrap() = format!("Regression test {test}, input in {}.", dir.display());
    let path = dir.join(files[0].0);
    METER.with(|m| {
        m.live.set(0);
        m.peak.set(0);
        m.refused.set(0);
        m.armed.set(true);
    });
    let r = Scene::load(&path);
    let (peak, refused) = METER.with(|m| {
        m.armed.set(false);
        (m.peak.get(), m.refused.get())
    });
    assert_eq!(refused, 0, "{test}: asked for {refused} bytes over the cap");
    let _ = std::fs::remove_dir_all(&dir);
    (r, peak)
}

/// A hand-built seed, edited, written as `scene.gltf` (or `.glb`) with its files.
pub(crate) fn load_seed(test: &str, mut doc: Doc, edit: impl FnOnce(&mut Value)) -> (Result<Scene, SceneError>, usize) {
    edit(&mut doc.json);
    let case = write_case(&doc, None, &mut Vec::new(), 0);
    let files: Vec<(&str, Vec<u8>)> = case.files.iter().map(|(n, b)| (n.as_str(), b.clone())).collect();
    load_files(test, &files)
}

pub(crate) fn one_line_error(r: Result<Scene, SceneError>) -> String {
    let e = r.expect_err("an error");
    let s = e.to_string();
    assert!(!s.is_empty() && !s.contains(['\n', '\r']), "{s:?}");
    s
}
