//! Documents: the mutators' view of a glTF document, a case on disk, and the corpus of the repository's files.

use std::path::{Path, PathBuf};

use serde_json::Value;

/// A glTF document as the mutators see it.
#[derive(Clone)]
pub(crate) struct Doc {
    /// Corpus name, then the mutations applied (for failure reports).
    pub(crate) label: String,
    /// Written as `.glb` (with `bin` as its BIN chunk) rather than `.gltf`.
    pub(crate) glb: bool,
    pub(crate) json: Value,
    pub(crate) bin: Option<Vec<u8>>,
    /// Files beside the scene (external buffers and images), by relative name.
    pub(crate) files: Vec<(String, Vec<u8>)>,
    /// Bytes that are not a parseable document (broken fixtures): only byte
    /// mutations apply, and they are written as they are.
    pub(crate) raw: Option<Vec<u8>>,
}

/// One input on disk: the scene file (always first, `scene.gltf` or `scene.glb`)
/// and the files beside it.
pub(crate) struct Case {
    pub(crate) id: u64,
    pub(crate) files: Vec<(String, Vec<u8>)>,
    pub(crate) recipe: String,
}

pub(crate) fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// `target/fuzz-failures` (beside `target/tmp`, which Cargo gives integration tests).
pub(crate) fn failures_dir() -> PathBuf {
    Path::new(env!("CARGO_TARGET_TMPDIR")).parent().unwrap_or(Path::new("target")).join("fuzz-failures")
}

/// Splits a GLB into its JSON and BIN chunks; `None` if it is not a well-formed one.
fn parse_glb(bytes: &[u8]) -> Option<(Value, Option<Vec<u8>>)> {
    if bytes.len() < 20 || &bytes[..4] != b"glTF" {
        return None;
    }
    let u32_at = |at: usize| Some(u32::from_le_bytes(bytes.get(at..at + 4)?.try_into().ok()?) as usize);
    let (mut at, mut json, mut bin) = (12, None, None);
    while at + 8 <= bytes.len() {
        let len = u32_at(at)?;
        let data = bytes.get(at + 8..at + 8 + len)?;
        match &bytes[at + 4..at + 8] {
            b"JSON" => json = Some(serde_json::from_slice(data).ok()?),
            b"BIN\0" => bin = Some(data.to_vec()),
            _ => {}
        }
        at += 8 + len;
    }
    Some((json?, bin))
}

/// Every `.gltf` / `.glb` under `scenes/` and `tests/scenes/` (recursively), sorted
/// by path, with the external files they reference by plain relative names.
pub(crate) fn file_corpus() -> Vec<Doc> {
    fn walk(dir: &Path, label: &str, out: &mut Vec<(String, PathBuf)>) {
        let Ok(entries) = std::fs::read_dir(dir) else { return };
        for e in entries.flatten() {
            let (p, name) = (e.path(), e.file_name().to_string_lossy().into_owned());
            if p.is_dir() {
                walk(&p, &format!("{label}/{name}"), out);
            } else if matches!(p.extension().and_then(|x| x.to_str()), Some("gltf" | "glb")) {
                out.push((format!("{label}/{name}"), p));
            }
        }
    }
    let mut paths = Vec::new();
    for dir in ["scenes", "tests/scenes"] {
        walk(&repo().join(dir), dir, &mut paths);
    }
    paths.sort();
    paths
        .into_iter()
        .map(|(label, p)| {
            let bytes = std::fs::read(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
            let glb = bytes.starts_with(b"glTF");
            let parsed = if glb { parse_glb(&bytes) } else { serde_json::from_slice(&bytes).ok().map(|j| (j, None)) };
            let Some((json, bin)) = parsed else {
                return Doc { label, glb, json: Value::Null, bin: None, files: Vec::new(), raw: Some(bytes) };
            };
            let mut files = Vec::new();
            for key in ["buffers", "images"] {
                for item in json.get(key).and_then(Value::as_array).into_iter().flatten() {
                    let Some(uri) = item.get("uri").and_then(Value::as_str) else { continue };
                    let beside = p.parent().unwrap_or(Path::new(".")).join(uri);
                    if !uri.contains([':', '%', '/', '\\']) && beside.is_file() {
                        files.push((uri.to_string(), std::fs::read(beside).unwrap()));
                    }
                }
            }
            Doc { label, glb, json, bin, files, raw: None }
        })
        .collect()
}
