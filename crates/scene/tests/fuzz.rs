//! Structure-aware mutation fuzzing of `Scene::load`, on stable Rust.
//!
//! `cargo fuzz` needs nightly, so this is a plain test: a seeded generator mutates
//! valid glTF documents (the repository's scenes and fixtures, plus documents built
//! here to reach accessors, textures, cameras, lights and animations) at the JSON,
//! buffer, data-URI, PNG and GLB-container levels, writes each case to its own
//! directory and loads it. Every case must end in a scene whose data is finite and
//! consistent, or in one `SceneError` whose message is one line; it must not panic,
//! take longer than a few seconds or make the loader hold more than 1 GiB (a
//! counting allocator in this test binary refuses more: the case fails, and when
//! the refusal aborts the process a message names the input, left on disk).
//!
//! ```text
//! cargo test -p leakless-scene --test fuzz -- --nocapture       # the bounded CI run
//! tools/fuzz-scenes 600 [SEED]                                  # 10 minutes, release
//! LEAKLESS_FUZZ_REPLAY=target/fuzz-failures/<case> cargo test -p leakless-scene --test fuzz -- --nocapture
//! ```
//!
//! `LEAKLESS_FUZZ_SECONDS` is the budget of the whole test, seeds included. The
//! default, 40 s, is what the CI job can spare: `tools/test` runs the workspace with
//! two test threads and this test holds one of them for its budget while the GPU
//! tests share the other core, so the suite's wall time grows by at most that much,
//! and the issue asks for at most 60 s. `LEAKLESS_FUZZ_SEED` (default 1) makes a run
//! reproducible; the cases follow from it (and the corpus) in order, so a longer
//! budget only appends cases. Failing inputs are copied to `target/fuzz-failures/`.

// The seed documents spell quaternions as glTF files do (0.7071068), not as Rust constants.
#![allow(clippy::approx_constant)]

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::{mpsc, Mutex};
use std::time::{Duration, Instant};

use leakless_scene::{Scene, SceneError};
use serde_json::{json, Value};

// ---------------------------------------------------------------------------------
// Allocation cap.

/// What one case may hold live at once. The inputs are at most a few hundred KiB,
/// so a loader that needs more is amplifying a count from the file.
const ALLOC_CAP: usize = 1 << 30;

struct Meter {
    armed: Cell<bool>,
    live: Cell<usize>,
    peak: Cell<usize>,
    /// Size of a refused request (0: none).
    refused: Cell<usize>,
}

thread_local! {
    static METER: Meter = const {
        Meter { armed: Cell::new(false), live: Cell::new(0), peak: Cell::new(0), refused: Cell::new(0) }
    };
}

/// Printed when a case goes over the cap, just before the allocation fails (which
/// aborts the process): names the case and where its input is.
static OVER_CAP_NOTE: Mutex<String> = Mutex::new(String::new());

/// Counts the bytes the armed thread (the one running a case) holds; refuses a
/// request that would take it over [`ALLOC_CAP`].
struct Capped;

#[global_allocator]
static ALLOCATOR: Capped = Capped;

/// Books `n` more bytes for the current thread; `false` refuses them.
fn charge(n: usize) -> bool {
    METER
        .try_with(|m| {
            if !m.armed.get() {
                return true;
            }
            let live = m.live.get().saturating_add(n);
            if live > ALLOC_CAP {
                // Disarmed first: the report below allocates.
                m.armed.set(false);
                m.refused.set(n);
                if let Ok(note) = OVER_CAP_NOTE.try_lock() {
                    eprintln!(
                        "\nfuzz: a case asked for {n} more bytes with {} live, over the 1 GiB cap. {note}",
                        m.live.get()
                    );
                }
                return false;
            }
            m.live.set(live);
            m.peak.set(m.peak.get().max(live));
            true
        })
        .unwrap_or(true)
}

fn credit(n: usize) {
    let _ = METER.try_with(|m| {
        if m.armed.get() {
            m.live.set(m.live.get().saturating_sub(n));
        }
    });
}

unsafe impl GlobalAlloc for Capped {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        if !charge(layout.size()) {
            return std::ptr::null_mut();
        }
        unsafe { System.alloc(layout) }
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        if !charge(layout.size()) {
            return std::ptr::null_mut();
        }
        unsafe { System.alloc_zeroed(layout) }
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        credit(layout.size());
        unsafe { System.dealloc(ptr, layout) }
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        let old = layout.size();
        if new_size > old && !charge(new_size - old) {
            return std::ptr::null_mut();
        }
        let p = unsafe { System.realloc(ptr, layout, new_size) };
        if !p.is_null() && new_size < old {
            credit(old - new_size);
        }
        p
    }
}

// ---------------------------------------------------------------------------------
// Random numbers (SplitMix64: tiny, seedable, good enough to pick mutations).

struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    fn below(&mut self, n: usize) -> usize {
        if n == 0 {
            0
        } else {
            (self.next() % n as u64) as usize
        }
    }

    fn one_in(&mut self, n: usize) -> bool {
        self.below(n) == 0
    }

    fn pick<'a, T>(&mut self, xs: &'a [T]) -> &'a T {
        &xs[self.below(xs.len())]
    }

    fn pick_some<'a, T>(&mut self, xs: &'a [T]) -> Option<&'a T> {
        (!xs.is_empty()).then(|| self.pick(xs))
    }

    /// An index into `weights`, chosen with probability proportional to its entry.
    fn weighted(&mut self, weights: &[usize]) -> usize {
        let mut r = self.below(weights.iter().sum());
        for (i, &w) in weights.iter().enumerate() {
            if r < w {
                return i;
            }
            r -= w;
        }
        weights.len() - 1
    }
}

// ---------------------------------------------------------------------------------
// Documents.

/// A glTF document as the mutators see it.
#[derive(Clone)]
struct Doc {
    /// Corpus name, then the mutations applied (for failure reports).
    label: String,
    /// Written as `.glb` (with `bin` as its BIN chunk) rather than `.gltf`.
    glb: bool,
    json: Value,
    bin: Option<Vec<u8>>,
    /// Files beside the scene (external buffers and images), by relative name.
    files: Vec<(String, Vec<u8>)>,
    /// Bytes that are not a parseable document (broken fixtures): only byte
    /// mutations apply, and they are written as they are.
    raw: Option<Vec<u8>>,
}

/// One input on disk: the scene file (always first, `scene.gltf` or `scene.glb`)
/// and the files beside it.
struct Case {
    id: u64,
    files: Vec<(String, Vec<u8>)>,
    recipe: String,
}

fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// `target/fuzz-failures` (beside `target/tmp`, which Cargo gives integration tests).
fn failures_dir() -> PathBuf {
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
fn file_corpus() -> Vec<Doc> {
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

// ---------------------------------------------------------------------------------
// Hand-built seeds: small valid documents for what the repository's scenes lack.

fn f32s(xs: &[f32]) -> Vec<u8> {
    xs.iter().flat_map(|x| x.to_le_bytes()).collect()
}
fn u16s(xs: &[u16]) -> Vec<u8> {
    xs.iter().flat_map(|x| x.to_le_bytes()).collect()
}
fn u32s(xs: &[u32]) -> Vec<u8> {
    xs.iter().flat_map(|x| x.to_le_bytes()).collect()
}
fn i16s(xs: &[i16]) -> Vec<u8> {
    xs.iter().flat_map(|x| x.to_le_bytes()).collect()
}

/// A buffer being assembled, with its views and accessors.
#[derive(Default)]
struct Bin {
    data: Vec<u8>,
    views: Vec<Value>,
    accessors: Vec<Value>,
}

impl Bin {
    /// A buffer view over `bytes` (4-byte aligned), returning its index.
    fn view(&mut self, bytes: &[u8], stride: Option<usize>) -> usize {
        while self.data.len() % 4 != 0 {
            self.data.push(0);
        }
        let mut v = json!({"buffer": 0, "byteOffset": self.data.len(), "byteLength": bytes.len()});
        if let Some(s) = stride {
            v["byteStride"] = json!(s);
        }
        self.data.extend_from_slice(bytes);
        self.views.push(v);
        self.views.len() - 1
    }

    fn accessor(&mut self, a: Value) -> usize {
        self.accessors.push(a);
        self.accessors.len() - 1
    }

    /// A tightly packed accessor over its own new view.
    fn packed(&mut self, bytes: &[u8], component: u32, count: usize, ty: &str) -> usize {
        let view = self.view(bytes, None);
        self.accessor(json!({"bufferView": view, "componentType": component, "count": count, "type": ty}))
    }

    /// A unit quad in the XY plane: (POSITION, NORMAL, TEXCOORD_0) accessors, the
    /// first two interleaved with a 24-byte stride, UVs normalized u16.
    fn quad(&mut self) -> (usize, usize, usize) {
        let p = [[0.0f32, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]];
        let interleaved: Vec<f32> = p.iter().flat_map(|v| v.iter().copied().chain([0.0, 0.0, 1.0])).collect();
        let view = self.view(&f32s(&interleaved), Some(24));
        let pos = self.accessor(json!({"bufferView": view, "componentType": 5126, "count": 4, "type": "VEC3",
                                        "min": [0, 0, 0], "max": [1, 1, 0]}));
        let nrm = self
            .accessor(json!({"bufferView": view, "byteOffset": 12, "componentType": 5126, "count": 4, "type": "VEC3"}));
        let uv_view = self.view(&u16s(&[0, 65535, 65535, 65535, 65535, 0, 0, 0]), None);
        let uv = self.accessor(
            json!({"bufferView": uv_view, "componentType": 5123, "normalized": true, "count": 4, "type": "VEC2"}),
        );
        (pos, nrm, uv)
    }
}

/// Where a seed's buffer goes.
enum Embed {
    DataUri,
    Glb,
    File(&'static str),
}

/// Completes `root` with `bin`'s buffer, views and accessors.
fn seed(label: &str, mut root: Value, bin: Bin, embed: Embed, files: Vec<(String, Vec<u8>)>) -> Doc {
    let mut buffer = json!({"byteLength": bin.data.len()});
    let (mut glb, mut blob, mut files) = (false, None, files);
    match embed {
        Embed::DataUri => buffer["uri"] = json!(data_uri("application/octet-stream", &bin.data)),
        Embed::Glb => (glb, blob) = (true, Some(bin.data)),
        Embed::File(name) => {
            buffer["uri"] = json!(name.replace(' ', "%20"));
            files.push((name.to_string(), bin.data));
        }
    }
    root["asset"] = json!({"version": "2.0", "generator": "leakless tests/fuzz.rs"});
    root["buffers"] = json!([buffer]);
    root["bufferViews"] = Value::Array(bin.views);
    root["accessors"] = Value::Array(bin.accessors);
    Doc { label: format!("seed:{label}"), glb, json: root, bin: blob, files, raw: None }
}

/// The light every seed needs to load: root extension plus a node using it.
fn lights(kinds: Value) -> Value {
    json!({"KHR_lights_punctual": {"lights": kinds}})
}

fn light_node(light: usize, translation: [f32; 3]) -> Value {
    json!({"extensions": {"KHR_lights_punctual": {"light": light}}, "translation": translation})
}

fn png(w: u32, h: u32) -> Vec<u8> {
    let img = image::RgbaImage::from_fn(w, h, |x, y| image::Rgba([(x * 60) as u8, (y * 60) as u8, 128, 255]));
    let mut out = std::io::Cursor::new(Vec::new());
    img.write_to(&mut out, image::ImageFormat::Png).unwrap();
    out.into_inner()
}

fn jpeg(w: u32, h: u32) -> Vec<u8> {
    let img = image::RgbImage::from_fn(w, h, |x, y| image::Rgb([(x * 30) as u8, (y * 30) as u8, 200]));
    let mut out = std::io::Cursor::new(Vec::new());
    img.write_to(&mut out, image::ImageFormat::Jpeg).unwrap();
    out.into_inner()
}

/// Accessors of every kind the loader reads: interleaved and strided attributes,
/// indices of u8/u16/u32, strips and fans, `KHR_mesh_quantization` (normalized and
/// integer attributes), sparse accessors with each index type, over a view and
/// without one.
fn seed_accessors() -> Doc {
    let mut b = Bin::default();
    let (pos, nrm, uv) = b.quad();
    let i8_ = b.packed(&[0, 1, 2, 0, 2, 3], 5121, 6, "SCALAR");
    let i16_ = b.packed(&u16s(&[0, 1, 2, 0, 2, 3]), 5123, 6, "SCALAR");
    let strip = b.packed(&u32s(&[0, 1, 3, 2]), 5125, 4, "SCALAR");
    let fan = b.packed(&u16s(&[0, 1, 2, 3]), 5123, 4, "SCALAR");
    // Quantized: i16 normalized positions (stride 8), i8 normalized normals
    // (stride 4), u8 normalized UVs (stride 4), i16 integer positions.
    let qp = b.view(&i16s(&[0, 0, 0, 0, 32767, 0, 0, 0, 32767, 32767, 0, 0, 0, 32767, 0, 0]), Some(8));
    let qpos =
        b.accessor(json!({"bufferView": qp, "componentType": 5122, "normalized": true, "count": 4, "type": "VEC3"}));
    let qn = b.view(&[0, 0, 127, 0, 0, 0, 127, 0, 0, 0, 127, 0, 0, 0, 127, 0], Some(4));
    let qnrm =
        b.accessor(json!({"bufferView": qn, "componentType": 5120, "normalized": true, "count": 4, "type": "VEC3"}));
    let qu = b.view(&[0, 255, 0, 0, 255, 255, 0, 0, 255, 0, 0, 0, 0, 0, 0, 0], Some(4));
    let quv =
        b.accessor(json!({"bufferView": qu, "componentType": 5121, "normalized": true, "count": 4, "type": "VEC2"}));
    let ipos = b.accessor(json!({"bufferView": qp, "componentType": 5122, "count": 4, "type": "VEC3"}));
    // Sparse over the quad's positions, indices u8, u16 and u32.
    let values = b.view(&f32s(&[2.0, 0.0, 0.0, 2.0, 2.0, 0.0]), None);
    let sparse = |b: &mut Bin, indices: Vec<u8>, ct: u32| {
        let iv = b.view(&indices, None);
        b.accessor(json!({"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
            "sparse": {"count": 2, "indices": {"bufferView": iv, "componentType": ct}, "values": {"bufferView": values}}}))
    };
    let s8 = sparse(&mut b, vec![1, 2], 5121);
    let s16 = sparse(&mut b, u16s(&[1, 2]), 5123);
    let s32 = sparse(&mut b, u32s(&[1, 2]), 5125);
    // A triangle from zeros plus sparse values, no buffer view.
    let tri = b.view(&f32s(&[1.0, 0.0, 0.0, 0.0, 1.0, 0.0]), None);
    let ti = b.view(&u16s(&[1, 2]), None);
    let implicit = b.accessor(json!({"componentType": 5126, "count": 3, "type": "VEC3",
        "sparse": {"count": 2, "indices": {"bufferView": ti, "componentType": 5123}, "values": {"bufferView": tri}}}));
    let prim = |p: usize, idx: Option<usize>, mode: u32| {
        let mut v = json!({"attributes": {"POSITION": p, "NORMAL": nrm, "TEXCOORD_0": uv}, "mode": mode});
        if let Some(i) = idx {
            v["indices"] = json!(i);
        }
        v
    };
    let root = json!({
        "extensionsUsed": ["KHR_lights_punctual", "KHR_mesh_quantization"],
        "extensionsRequired": ["KHR_mesh_quantization"],
        "extensions": lights(json!([{"type": "point", "intensity": 5}])),
        "scene": 0,
        "scenes": [{"nodes": [0, 1, 2, 3, 4, 5]}],
        "nodes": [
            {"mesh": 0},
            {"mesh": 1, "scale": [0.5, 0.5, 0.5], "translation": [2, 0, 0]},
            {"mesh": 2, "translation": [0, 2, 0]},
            {"mesh": 3, "translation": [4, 0, 0], "scale": [0.001, 0.001, 0.001]},
            light_node(0, [0.5, 0.5, 2.0]),
            {"mesh": 4, "translation": [-2, 0, 0]},
        ],
        "meshes": [
            {"name": "indexed", "primitives": [prim(pos, Some(i8_), 4), prim(pos, Some(i16_), 4), prim(pos, Some(strip), 5),
                                                prim(pos, Some(fan), 6), prim(pos, None, 6)]},
            {"name": "quantized", "primitives": [{"attributes": {"POSITION": qpos, "NORMAL": qnrm, "TEXCOORD_0": quv}, "indices": i8_}]},
            {"name": "sparse", "primitives": [prim(s8, Some(i8_), 4), prim(s16, Some(i16_), 4), prim(s32, Some(i8_), 4)]},
            {"name": "integer", "primitives": [{"attributes": {"POSITION": ipos}, "indices": i16_}]},
            {"name": "implicit", "primitives": [{"attributes": {"POSITION": implicit}}]},
        ],
    });
    seed("accessors", root, b, Embed::DataUri, Vec::new())
}

/// Base colour textures: a data-URI PNG, a JPEG from a buffer view, one image
/// shared by two materials, MASK and BLEND, a sampler, texcoord set 1.
fn textured_root(b: &mut Bin, images: Value) -> Value {
    let (pos, nrm, uv) = b.quad();
    let idx = b.packed(&u16s(&[0, 1, 2, 0, 2, 3]), 5123, 6, "SCALAR");
    let prim = |m: usize| json!({"attributes": {"POSITION": pos, "NORMAL": nrm, "TEXCOORD_0": uv, "TEXCOORD_1": uv}, "indices": idx, "material": m});
    json!({
        "extensionsUsed": ["KHR_lights_punctual", "KHR_texture_transform"],
        "extensions": lights(json!([{"type": "directional", "intensity": 3, "color": [1, 0.9, 0.8]}])),
        "scene": 0,
        "scenes": [{"nodes": [0, 1]}],
        "nodes": [{"mesh": 0}, light_node(0, [0.0, 0.0, 3.0])],
        "meshes": [{"primitives": [prim(0), prim(1), prim(2), prim(3), prim(4)]}],
        "materials": [
            {"name": "png", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}, "metallicFactor": 0}},
            {"name": "jpeg", "pbrMetallicRoughness": {"baseColorTexture": {"index": 1}, "baseColorFactor": [0.5, 0.5, 0.5, 1]}},
            {"name": "mask", "alphaMode": "MASK", "alphaCutoff": 0.25,
             "pbrMetallicRoughness": {"baseColorTexture": {"index": 2}, "metallicFactor": 0}},
            {"name": "blend", "alphaMode": "BLEND", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0, "texCoord": 1}}},
            {"name": "plain", "pbrMetallicRoughness": {"baseColorFactor": [0.2, 0.4, 0.6, 1.0]}, "emissiveFactor": [1, 0, 0]},
        ],
        "samplers": [{"magFilter": 9729, "minFilter": 9987, "wrapS": 33071, "wrapT": 33648}],
        "textures": [{"source": 0, "sampler": 0}, {"source": 1}, {"source": 0}],
        "images": images,
    })
}

fn seed_textured() -> Doc {
    let mut b = Bin::default();
    let jpg = b.view(&jpeg(8, 8), None);
    let images = json!([{"uri": data_uri("image/png", &png(4, 4))}, {"bufferView": jpg, "mimeType": "image/jpeg"}]);
    let root = textured_root(&mut b, images);
    seed("textured", root, b, Embed::DataUri, Vec::new())
}

/// The textured document as GLB, both images in buffer views.
fn seed_textured_glb() -> Doc {
    let mut b = Bin::default();
    let pngv = b.view(&png(3, 5), None);
    let jpg = b.view(&jpeg(8, 8), None);
    let images = json!([{"bufferView": pngv, "mimeType": "image/png"}, {"bufferView": jpg, "mimeType": "image/jpeg"}]);
    let root = textured_root(&mut b, images);
    seed("textured-glb", root, b, Embed::Glb, Vec::new())
}

/// External files: the buffer and a PNG beside the scene, the image's name
/// percent-encoded.
fn seed_external() -> Doc {
    let mut b = Bin::default();
    let jpg = b.view(&jpeg(8, 8), None);
    let images = json!([{"uri": "tex%20ture.png"}, {"bufferView": jpg, "mimeType": "image/jpeg"}]);
    let root = textured_root(&mut b, images);
    seed("external", root, b, Embed::File("scene data.bin"), vec![("tex ture.png".into(), png(2, 2))])
}

/// Node hierarchies and cameras: matrices, TRS, a mirroring scale, a deep chain,
/// several cameras (the first perspective one wins), two scenes.
fn seed_cameras() -> Doc {
    let mut b = Bin::default();
    let (pos, nrm, uv) = b.quad();
    let root = json!({
        "extensionsUsed": ["KHR_lights_punctual"],
        "extensions": lights(json!([{"type": "point", "intensity": 10, "range": 20}])),
        "scene": 1,
        "scenes": [{"nodes": [0]}, {"name": "main", "nodes": [1, 7], "extras": {"note": "hierarchy"}}],
        "nodes": [
            {"mesh": 0},
            {"name": "root", "matrix": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, -1, 1], "children": [2, 3]},
            {"name": "mirror", "mesh": 0, "scale": [-1, 1, 1], "children": [4]},
            {"name": "ortho", "camera": 1, "translation": [0, 0, 5]},
            {"name": "chain", "rotation": [0, 0.7071068, 0, 0.7071068], "translation": [1, 0, 0], "children": [5]},
            {"name": "eye", "camera": 0, "translation": [0, 1, 5], "scale": [2, 2, 2], "children": [6]},
            {"name": "second eye", "camera": 2, "mesh": 0},
            light_node(0, [0.0, 3.0, 0.0]),
        ],
        "cameras": [
            {"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.05, "zfar": 100, "aspectRatio": 1.5}},
            {"type": "orthographic", "orthographic": {"xmag": 2, "ymag": 2, "znear": 0.1, "zfar": 50}},
            {"name": "infinite", "type": "perspective", "perspective": {"yfov": 1.2, "znear": 0.1}},
        ],
        "meshes": [{"primitives": [{"attributes": {"POSITION": pos, "NORMAL": nrm, "TEXCOORD_0": uv}}]}],
    });
    seed("cameras", root, b, Embed::DataUri, Vec::new())
}

/// `KHR_lights_punctual`: point, spot and directional lights with every optional
/// field, on rotated and nested nodes.
fn seed_lights() -> Doc {
    let mut b = Bin::default();
    let (pos, nrm, _) = b.quad();
    let root = json!({
        "extensionsUsed": ["KHR_lights_punctual"],
        "extensions": lights(json!([
            {"name": "bulb", "type": "point", "color": [1, 0.5, 0.25], "intensity": 100, "range": 10},
            {"name": "cone", "type": "spot", "intensity": 50, "spot": {"innerConeAngle": 0.2, "outerConeAngle": 0.6}},
            {"name": "sun", "type": "directional", "intensity": 2},
            {"type": "spot", "spot": {}},
        ])),
        "scenes": [{"nodes": [0, 1, 2]}],
        "nodes": [
            {"mesh": 0},
            {"rotation": [-0.7071068, 0, 0, 0.7071068], "children": [3, 4], "extensions": {"KHR_lights_punctual": {"light": 2}}},
            light_node(0, [0.0, 1.0, 1.0]),
            light_node(1, [0.0, 0.0, 2.0]),
            {"matrix": [0, 1, 0, 0, -1, 0, 0, 0, 0, 0, 1, 0, 1, 1, 1, 1], "extensions": {"KHR_lights_punctual": {"light": 3}}},
        ],
        "meshes": [{"primitives": [{"attributes": {"POSITION": pos, "NORMAL": nrm}}]}],
    });
    seed("lights", root, b, Embed::DataUri, Vec::new())
}

/// Animations: LINEAR, STEP and CUBICSPLINE samplers on translation, rotation
/// (f32 and normalized i16 quaternions) and scale, a sparse output, a weights
/// channel on a morph-target mesh, two animations sharing an input.
fn seed_animation(embed: Embed) -> Doc {
    let mut b = Bin::default();
    let (pos, nrm, uv) = b.quad();
    let t = b.view(&f32s(&[0.0, 0.5, 1.0]), None);
    let times = b.accessor(
        json!({"bufferView": t, "componentType": 5126, "count": 3, "type": "SCALAR", "min": [0], "max": [1]}),
    );
    let translations = b.packed(&f32s(&[0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 1.0, 0.0]), 5126, 3, "VEC3");
    let q = [0.0f32, 0.0, 0.0, 1.0, 0.0, 0.7071068, 0.0, 0.7071068, 0.0, 1.0, 0.0, 0.0];
    let rotations = b.packed(&f32s(&q), 5126, 3, "VEC4");
    let qi: Vec<i16> = q.iter().map(|&x| (x * 32767.0) as i16).collect();
    let qv = b.view(&i16s(&qi), None);
    let rotations_i16 =
        b.accessor(json!({"bufferView": qv, "componentType": 5122, "normalized": true, "count": 3, "type": "VEC4"}));
    // CUBICSPLINE: (in-tangent, value, out-tangent) per key.
    let mut cubic_s = Vec::new();
    for k in 0..3 {
        cubic_s.extend([0.0, 0.0, 0.0, 1.0 + k as f32, 1.0, 1.0, 0.0, 0.0, 0.0]);
    }
    let scales = b.packed(&f32s(&cubic_s), 5126, 9, "VEC3");
    let mut cubic_r = Vec::new();
    for k in 0..3 {
        cubic_r.extend([0.0, 0.0, 0.0, 0.0]);
        cubic_r.extend(&q[4 * k..4 * k + 4]);
        cubic_r.extend([0.0, 0.0, 0.0, 0.0]);
    }
    let rotations_cubic = b.packed(&f32s(&cubic_r), 5126, 9, "VEC4");
    let sv = b.view(&f32s(&[0.0, 2.0, 0.0]), None);
    let si = b.view(&[2, 0, 0, 0], None);
    let sparse_out = b.accessor(json!({"componentType": 5126, "count": 3, "type": "VEC3",
        "sparse": {"count": 1, "indices": {"bufferView": si, "componentType": 5121}, "values": {"bufferView": sv}}}));
    let step_t = b.packed(&f32s(&[0.0, 0.25, 0.5, 2.0]), 5126, 4, "SCALAR");
    let step_s = b.packed(&f32s(&[1.0, 1.0, 1.0, 2.0, 2.0, 2.0, 1.0, 1.0, 1.0, 0.5, 0.5, 0.5]), 5126, 4, "VEC3");
    let displacement = b.packed(&f32s(&[0.0, 0.0, 1.0].repeat(4)), 5126, 4, "VEC3");
    let weights = b.packed(&f32s(&[0.0, 1.0, 0.5]), 5126, 3, "SCALAR");
    let sampler =
        |input: usize, output: usize, interp: &str| json!({"input": input, "output": output, "interpolation": interp});
    let channel = |s: usize, node: usize, path: &str| json!({"sampler": s, "target": {"node": node, "path": path}});
    let root = json!({
        "extensionsUsed": ["KHR_lights_punctual"],
        "extensions": lights(json!([{"type": "point", "intensity": 4}])),
        "scenes": [{"nodes": [0, 4]}],
        "nodes": [
            {"name": "spinner", "mesh": 0, "children": [1, 2]},
            {"name": "bouncer", "mesh": 0, "translation": [2, 0, 0]},
            {"name": "grower", "mesh": 0, "scale": [1, 1, 1], "children": [3]},
            {"name": "morph", "mesh": 1},
            light_node(0, [0.0, 0.0, 3.0]),
        ],
        "meshes": [
            {"primitives": [{"attributes": {"POSITION": pos, "NORMAL": nrm, "TEXCOORD_0": uv}}]},
            {"primitives": [{"attributes": {"POSITION": pos}, "targets": [{"POSITION": displacement}]}], "weights": [0.0]},
        ],
        "animations": [
            {"name": "all", "samplers": [
                sampler(times, translations, "LINEAR"), sampler(times, rotations, "STEP"),
                sampler(times, scales, "CUBICSPLINE"), sampler(times, rotations_cubic, "CUBICSPLINE"),
                sampler(times, rotations_i16, "LINEAR"), sampler(times, sparse_out, "STEP"),
                sampler(step_t, step_s, "STEP"), sampler(times, weights, "LINEAR")],
             "channels": [
                channel(0, 1, "translation"), channel(1, 0, "rotation"), channel(2, 2, "scale"), channel(3, 3, "rotation"),
                channel(4, 2, "rotation"), channel(5, 0, "translation"), channel(6, 1, "scale"), channel(7, 3, "weights")]},
            {"name": "shared input", "samplers": [{"input": times, "output": translations}],
             "channels": [{"sampler": 0, "target": {"node": 4, "path": "translation"}}]},
        ],
    });
    let label = match embed {
        Embed::Glb => "animation-glb",
        _ => "animation",
    };
    seed(label, root, b, embed, Vec::new())
}

fn hand_seeds() -> Vec<Doc> {
    vec![
        seed_accessors(),
        seed_textured(),
        seed_textured_glb(),
        seed_external(),
        seed_cameras(),
        seed_lights(),
        seed_animation(Embed::DataUri),
        seed_animation(Embed::Glb),
    ]
}

// ---------------------------------------------------------------------------------
// Encodings.

/// Lenient decoding (the mutators only decode what they encoded, or corrupted).
fn base64_decode(s: &str) -> Option<Vec<u8>> {
    let mut out = Vec::with_capacity(s.len() / 4 * 3);
    let (mut acc, mut bits) = (0u32, 0);
    for c in s.bytes().take_while(|&c| c != b'=') {
        let v = match c {
            b'A'..=b'Z' => c - b'A',
            b'a'..=b'z' => c - b'a' + 26,
            b'0'..=b'9' => c - b'0' + 52,
            b'+' => 62,
            b'/' => 63,
            _ => return None,
        };
        acc = (acc << 6) | u32::from(v);
        bits += 6;
        if bits >= 8 {
            bits -= 8;
            out.push((acc >> bits) as u8);
        }
    }
    Some(out)
}

fn data_uri(mime: &str, data: &[u8]) -> String {
    format!("data:{mime};base64,{}", base64::encode(data))
}

/// Splits a base64 data URI into (head up to and including the comma, bytes).
fn split_data_uri(uri: &str) -> Option<(String, Vec<u8>)> {
    let at = uri.find(";base64,")? + ";base64,".len();
    Some((uri[..at].to_string(), base64_decode(&uri[at..])?))
}

fn crc32(bytes: &[u8]) -> u32 {
    let mut c = !0u32;
    for &b in bytes {
        c ^= u32::from(b);
        for _ in 0..8 {
            c = if c & 1 != 0 { 0xEDB8_8320 ^ (c >> 1) } else { c >> 1 };
        }
    }
    !c
}

// ---------------------------------------------------------------------------------
// JSON mutation.

#[derive(Clone, Debug)]
enum Seg {
    Key(String),
    Index(usize),
}

/// Every value's path in `v` (the root included), depth-first.
fn paths(v: &Value) -> Vec<Vec<Seg>> {
    fn walk(v: &Value, at: &mut Vec<Seg>, out: &mut Vec<Vec<Seg>>) {
        out.push(at.clone());
        match v {
            Value::Array(a) => {
                for (i, x) in a.iter().enumerate() {
                    at.push(Seg::Index(i));
                    walk(x, at, out);
                    at.pop();
                }
            }
            Value::Object(o) => {
                for (k, x) in o {
                    at.push(Seg::Key(k.clone()));
                    walk(x, at, out);
                    at.pop();
                }
            }
            _ => {}
        }
    }
    let mut out = Vec::new();
    walk(v, &mut Vec::new(), &mut out);
    out
}

fn get<'a>(v: &'a Value, path: &[Seg]) -> Option<&'a Value> {
    path.iter().try_fold(v, |v, s| match s {
        Seg::Key(k) => v.get(k.as_str()),
        Seg::Index(i) => v.get(*i),
    })
}

fn get_mut<'a>(v: &'a mut Value, path: &[Seg]) -> Option<&'a mut Value> {
    path.iter().try_fold(v, |v, s| match s {
        Seg::Key(k) => v.get_mut(k.as_str()),
        Seg::Index(i) => v.get_mut(*i),
    })
}

/// The object key a value sits under (an array element: its array's key).
fn key_of(path: &[Seg]) -> &str {
    path.iter()
        .rev()
        .find_map(|s| match s {
            Seg::Key(k) => Some(k.as_str()),
            Seg::Index(_) => None,
        })
        .unwrap_or("")
}

fn show(path: &[Seg]) -> String {
    let mut s = String::new();
    for seg in path {
        match seg {
            Seg::Key(k) => s += &format!(".{k}"),
            Seg::Index(i) => s += &format!("[{i}]"),
        }
    }
    if s.is_empty() {
        "(root)".into()
    } else {
        s
    }
}

/// Keys whose numbers are indices, counts, offsets, lengths or enums: where a
/// wrong number reaches the loader's bounds checks rather than a float field.
const INDEX_KEYS: &[&str] = &[
    "bufferView",
    "buffer",
    "byteOffset",
    "byteLength",
    "byteStride",
    "count",
    "componentType",
    "mode",
    "material",
    "mesh",
    "camera",
    "light",
    "indices",
    "POSITION",
    "NORMAL",
    "TEXCOORD_0",
    "TEXCOORD_1",
    "input",
    "output",
    "sampler",
    "node",
    "index",
    "source",
    "texCoord",
    "scene",
    "nodes",
    "children",
    "skin",
    "target",
];

const EXTREME_INTS: &[i64] = &[
    0,
    1,
    2,
    3,
    4,
    5,
    7,
    8,
    12,
    16,
    24,
    252,
    253,
    255,
    256,
    4095,
    65535,
    65536,
    1 << 20,
    1 << 24,
    1 << 26,
    (1 << 26) + 1,
    1 << 28,
    (1 << 31) - 1,
    1 << 31,
    (1 << 32) - 1,
    1 << 32,
    1 << 40,
    1 << 53,
    i64::MAX,
    -1,
    -2,
    -(1 << 31),
];

const EXTREME_FLOATS: &[f64] =
    &[0.0, -0.0, 0.5, -1.0, 1e-45, 1e-38, 1e30, 1e38, -1e38, 3.4028235e38, 1e39, -1e39, 1e300, -1e300];

fn extreme_number(rng: &mut Rng, orig: Option<&Value>) -> Value {
    let o = orig.and_then(Value::as_i64).unwrap_or(0);
    match rng.below(10) {
        0..=3 => json!(*rng.pick(EXTREME_INTS)),
        4 => json!(u64::MAX),
        5 => json!(*rng.pick(EXTREME_FLOATS)),
        6 => json!(*rng.pick(&["NaN", "Infinity", "-Infinity", "1", ""])),
        7 => json!(o.wrapping_add(*rng.pick(&[1i64, -1, 2, -2, 3, 4, -4, 8, 12]))),
        8 => json!(o.wrapping_mul(*rng.pick(&[2i64, 3, 4, 1 << 16, 1 << 24]))),
        _ => json!(rng.below(10)),
    }
}

/// Replacement values for enum-like fields, by key.
fn enum_values(key: &str, current: &Value) -> Option<Vec<Value>> {
    let strs = |xs: &[&str]| Some(xs.iter().map(|s| json!(s)).collect());
    let nums = |xs: &[i64]| Some(xs.iter().map(|n| json!(n)).collect());
    match key {
        "componentType" => nums(&[5120, 5121, 5122, 5123, 5125, 5126, 5124, 5130, 0, 1]),
        "mode" => nums(&[0, 1, 2, 3, 4, 5, 6, 7, -1, 255]),
        "interpolation" => strs(&["LINEAR", "STEP", "CUBICSPLINE", "CUBIC", "linear", ""]),
        "path" => strs(&["translation", "rotation", "scale", "weights", "pointer", ""]),
        "alphaMode" => strs(&["OPAQUE", "MASK", "BLEND", "CLIP"]),
        "mimeType" => strs(&["image/png", "image/jpeg", "image/webp", "text/plain"]),
        "target" if current.is_number() => nums(&[34962, 34963, 0, 1]),
        "magFilter" | "minFilter" | "wrapS" | "wrapT" => nums(&[9728, 9729, 9984, 9987, 10497, 33071, 33648, 0]),
        "type" => match current.as_str() {
            Some("point" | "spot" | "directional") => strs(&["point", "spot", "directional", "area", "perspective"]),
            Some("perspective" | "orthographic") => strs(&["perspective", "orthographic", "fisheye", "point"]),
            _ => strs(&["SCALAR", "VEC2", "VEC3", "VEC4", "MAT2", "MAT3", "MAT4", "VEC5", "scalar", ""]),
        },
        _ => None,
    }
}

const ATTRIBUTES: &[&str] = &[
    "POSITION",
    "NORMAL",
    "TEXCOORD_0",
    "TEXCOORD_1",
    "TANGENT",
    "COLOR_0",
    "JOINTS_0",
    "WEIGHTS_0",
    "_CUSTOM",
    "position",
    "TEXCOORD_99999999999",
];

/// Strings for `uri` fields: missing and odd files, other schemes, broken escapes,
/// devices (a loader must not read `/dev/zero` until memory runs out).
const URIS: &[&str] = &[
    "missing.bin",
    "sub/dir/x.bin",
    "%FF.bin",
    "%zz",
    "%",
    "../missing.bin",
    "file:///dev/zero",
    "/dev/zero",
    "/dev/null",
    ".",
    "",
    "http://example.com/a.bin",
    "C:\\x.bin",
    "data:",
    "data:,",
    "data:application/octet-stream;base64,",
    "data:application/octet-stream;base64,=",
    "data:image/png;base64,iVBORw0KGgo=",
    "data:application/octet-stream,AAAA",
    "data:;base64,AAAA",
    "scene.gltf",
    "scene.glb",
];

/// Strings for names: what a one-line message must not let through.
const NAMES: &[&str] = &["line\nbreak", "cr\rreturn", "nul\u{0}", "\u{1b}[31mred", "é∂ü", "", "tab\there"];

/// A (JSON) mutation of the document; returns a description, or `None` when it
/// found nothing to act on.
fn mutate_json(doc: &mut Doc, corpus: &[Doc], rng: &mut Rng) -> Option<String> {
    let all = paths(&doc.json);
    let numbers: Vec<&Vec<Seg>> = all.iter().filter(|p| get(&doc.json, p).is_some_and(Value::is_number)).collect();
    match rng.weighted(&[22, 9, 7, 5, 6, 4, 6, 10, 5]) {
        // A number: extreme, off by one, scaled, or of the wrong kind.
        0 => {
            let indexy: Vec<&&Vec<Seg>> = numbers.iter().filter(|p| INDEX_KEYS.contains(&key_of(p))).collect();
            let path =
                if !indexy.is_empty() && !rng.one_in(3) { *rng.pick(&indexy) } else { *rng.pick_some(&numbers)? };
            let slot = get_mut(&mut doc.json, path)?;
            *slot = extreme_number(rng, Some(slot));
            Some(format!("{} = {slot}", show(path)))
        }
        // An enum-like value, or an attribute semantic.
        1 => {
            if rng.one_in(3) {
                let attrs: Vec<&Vec<Seg>> = all
                    .iter()
                    .filter(|p| key_of(p) == "attributes" && matches!(p.last(), Some(Seg::Key(k)) if k == "attributes"))
                    .collect();
                let path = (*rng.pick_some(&attrs)?).clone();
                let obj = get_mut(&mut doc.json, &path)?.as_object_mut()?;
                let from = obj.keys().nth(rng.below(obj.len()))?.clone();
                let to = rng.pick(ATTRIBUTES).to_string();
                let v = obj.remove(&from)?;
                obj.insert(to.clone(), v);
                return Some(format!("{}: {from} -> {to}", show(&path)));
            }
            let cands: Vec<(&Vec<Seg>, Vec<Value>)> = all
                .iter()
                .filter_map(|p| {
                    let v = get(&doc.json, p)?;
                    if v.is_object() || v.is_array() {
                        return None;
                    }
                    Some((p, enum_values(key_of(p), v)?))
                })
                .collect();
            let (path, values) = rng.pick_some(&cands)?;
            let value = rng.pick(values).clone();
            *get_mut(&mut doc.json, path)? = value.clone();
            Some(format!("{} = {value}", show(path)))
        }
        // Delete a key (often one the loader leans on).
        2 => {
            const VITAL: &[&str] = &[
                "bufferView",
                "byteStride",
                "sparse",
                "indices",
                "uri",
                "byteLength",
                "count",
                "type",
                "componentType",
                "perspective",
                "spot",
                "extensions",
                "scene",
                "scenes",
                "nodes",
                "children",
                "mesh",
                "sampler",
                "input",
                "output",
                "target",
                "path",
                "node",
                "buffers",
                "accessors",
                "POSITION",
                "values",
                "min",
            ];
            let keyed: Vec<&Vec<Seg>> = all.iter().filter(|p| matches!(p.last(), Some(Seg::Key(_)))).collect();
            let vital: Vec<&&Vec<Seg>> = keyed.iter().filter(|p| VITAL.contains(&key_of(p))).collect();
            let path = if !vital.is_empty() && rng.one_in(2) { **rng.pick(&vital) } else { *rng.pick_some(&keyed)? };
            let (Seg::Key(k), parent) = (path.last()?, &path[..path.len() - 1]) else { return None };
            get_mut(&mut doc.json, parent)?.as_object_mut()?.remove(k);
            Some(format!("delete {}", show(path)))
        }
        // Swap two index-like numbers, or two elements of an array.
        3 => {
            if rng.one_in(2) {
                let indexy: Vec<&&Vec<Seg>> = numbers.iter().filter(|p| INDEX_KEYS.contains(&key_of(p))).collect();
                if indexy.len() < 2 {
                    return None;
                }
                let (a, b) = (*rng.pick(&indexy), *rng.pick(&indexy));
                let (va, vb) = (get(&doc.json, a)?.clone(), get(&doc.json, b)?.clone());
                *get_mut(&mut doc.json, a)? = vb;
                *get_mut(&mut doc.json, b)? = va;
                return Some(format!("swap {} {}", show(a), show(b)));
            }
            let arrays: Vec<&Vec<Seg>> = all
                .iter()
                .filter(|p| get(&doc.json, p).and_then(Value::as_array).is_some_and(|a| a.len() > 1))
                .collect();
            let path = *rng.pick_some(&arrays)?;
            let a = get_mut(&mut doc.json, path)?.as_array_mut()?;
            let (i, j) = (rng.below(a.len()), rng.below(a.len()));
            a.swap(i, j);
            Some(format!("swap {}[{i}] [{j}]", show(path)))
        }
        // Grow, shrink, repeat or reverse an array.
        4 => {
            let arrays: Vec<&Vec<Seg>> =
                all.iter().filter(|p| get(&doc.json, p).is_some_and(Value::is_array)).collect();
            let path = *rng.pick_some(&arrays)?;
            let a = get_mut(&mut doc.json, path)?.as_array_mut()?;
            let what = match rng.below(5) {
                0 if !a.is_empty() && a.len() < 512 => {
                    let x = a[rng.below(a.len())].clone();
                    let at = rng.below(a.len() + 1);
                    a.insert(at, x);
                    "duplicate an element of"
                }
                1 if !a.is_empty() && a.len() < 128 => {
                    let copy = a.clone();
                    for _ in 0..1 + rng.below(3) {
                        a.extend(copy.iter().cloned());
                    }
                    "repeat"
                }
                2 => {
                    a.truncate(rng.below(a.len()));
                    "truncate"
                }
                3 => {
                    a.reverse();
                    "reverse"
                }
                _ => {
                    a.clear();
                    "empty"
                }
            };
            Some(format!("{what} {}", show(path)))
        }
        // Change a value's type.
        5 => {
            let path = rng.pick(&all[1.min(all.len() - 1)..]).clone();
            let slot = get_mut(&mut doc.json, &path)?;
            let old = slot.take();
            *slot = match rng.below(9) {
                0 => Value::Null,
                1 => json!(true),
                2 => json!("x"),
                3 => json!(0),
                4 => json!(-1),
                5 => json!([]),
                6 => json!({}),
                7 => json!([old]),
                _ => json!(old.to_string()),
            };
            Some(format!("{} = {slot:.40}", show(&path)))
        }
        // Strings: names with line breaks and control characters, URIs, data URIs.
        6 => {
            let strings: Vec<&Vec<Seg>> =
                all.iter().filter(|p| get(&doc.json, p).is_some_and(Value::is_string)).collect();
            let uris: Vec<&&Vec<Seg>> = strings.iter().filter(|p| key_of(p) == "uri").collect();
            let path = if !uris.is_empty() && !rng.one_in(3) { **rng.pick(&uris) } else { *rng.pick_some(&strings)? };
            let slot = get_mut(&mut doc.json, path)?;
            let s = slot.as_str()?.to_string();
            let new = if key_of(path) != "uri" {
                format!("{s}{}", rng.pick(NAMES))
            } else if let (Some(at), false) = (s.find(";base64,"), rng.one_in(3)) {
                let (head, payload) = (&s[..at], &s[at + 8..]);
                let cut = rng.below(payload.len() + 1);
                match rng.below(7) {
                    0 => format!("{head};base64,{}*{}", &payload[..cut], &payload[cut..]),
                    1 => format!("{head};base64,{}", &payload[..payload.len().saturating_sub(1 + rng.below(3))]),
                    2 => format!("{head};base64,{payload}==="),
                    3 => format!("{head};base64,{} {}", &payload[..cut], &payload[cut..]),
                    4 => format!(
                        "{}{}",
                        rng.pick(&[
                            "data:image/png",
                            "data:image/jpeg",
                            "data:text/plain",
                            "data:",
                            "data:application/gltf-buffer"
                        ]),
                        &s[at..]
                    ),
                    5 => format!("{head},{payload}"),
                    _ => format!("{head};base64,{}", &payload[..cut]),
                }
            } else if rng.one_in(4) && !doc.files.is_empty() {
                let f = &doc.files[rng.below(doc.files.len())].0;
                f.replace(' ', "%20")
            } else {
                rng.pick(URIS).to_string()
            };
            let label = format!("{} = {:.60?}", show(path), new);
            *slot = json!(new);
            Some(label)
        }
        // Insert a field the loader reads, with a plausible or hostile value.
        7 => insert_field(doc, rng),
        // Cross-over with another corpus document.
        _ => {
            let other = rng.pick(corpus);
            if other.raw.is_some() {
                return None;
            }
            let root = doc.json.as_object_mut()?;
            let oroot = other.json.as_object()?;
            let key = oroot.keys().nth(rng.below(oroot.len()))?.clone();
            let theirs = oroot[&key].clone();
            match (rng.below(3), root.get_mut(&key), theirs) {
                (0, Some(Value::Array(mine)), Value::Array(theirs)) if mine.len() + theirs.len() < 512 => {
                    mine.extend(theirs);
                    Some(format!("append {key} of {}", other.label))
                }
                (1, Some(Value::Array(mine)), Value::Array(theirs)) if !mine.is_empty() && !theirs.is_empty() => {
                    let i = rng.below(mine.len());
                    mine[i] = theirs[rng.below(theirs.len())].clone();
                    Some(format!("{key}[{i}] from {}", other.label))
                }
                (_, _, theirs) => {
                    root.insert(key.clone(), theirs);
                    if key == "buffers" {
                        doc.bin = other.bin.clone();
                        doc.files = other.files.clone();
                    }
                    Some(format!("{key} from {}", other.label))
                }
            }
        }
    }
}

/// Sets one field of one element of a top-level collection.
fn insert_field(doc: &mut Doc, rng: &mut Rng) -> Option<String> {
    let len = |k: &str| doc.json.get(k).and_then(Value::as_array).map_or(0, Vec::len);
    let (n_acc, n_view, n_node, n_mesh, n_mat) =
        (len("accessors"), len("bufferViews"), len("nodes"), len("meshes"), len("materials"));
    // A small index, usually in range, sometimes just past the end or absurd.
    let idx = |n: usize, rng: &mut Rng| -> Value {
        match rng.below(8) {
            0 => json!(n),
            1 => json!(*rng.pick(&[u32::MAX as u64, 1 << 31, 1 << 53])),
            _ => json!(rng.below(n.max(1))),
        }
    };
    let floats = |rng: &mut Rng, n: usize| -> Value {
        Value::Array((0..n).map(|_| json!(*rng.pick(&[0.0, 1.0, -1.0, 0.5, 1e38, -1e38, 1e39, 1e-40, 2.0]))).collect())
    };
    let (collection, field, value): (&str, &str, Value) = match rng.below(16) {
        0 => {
            let (ic, ivs) = (*rng.pick(&[5121, 5123, 5125, 5126]), idx(n_view, rng));
            let sparse = json!({"count": extreme_number(rng, Some(&json!(2))), "indices": {"bufferView": ivs, "componentType": ic,
                "byteOffset": *rng.pick(&[0, 1, 2, 4, 1 << 31])}, "values": {"bufferView": idx(n_view, rng), "byteOffset": *rng.pick(&[0, 4, 12])}});
            ("accessors", "sparse", sparse)
        }
        1 => ("accessors", "byteOffset", json!(*rng.pick(&[0u64, 1, 2, 3, 4, 12, 1 << 20, u32::MAX as u64, u64::MAX]))),
        2 => ("accessors", "normalized", json!(rng.one_in(2))),
        3 => ("bufferViews", "byteStride", json!(*rng.pick(&[0u64, 1, 3, 4, 6, 8, 12, 16, 24, 252, 256, 1 << 31]))),
        4 => ("nodes", "matrix", {
            let mut m = floats(rng, 16);
            if rng.one_in(2) {
                m = json!([1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]);
                m[rng.below(16)] = json!(*rng.pick(&[0.0, -1.0, 1e38, 1e39, 1e-30]));
            }
            m
        }),
        5 => ("nodes", "rotation", floats(rng, 4)),
        6 => ("nodes", "scale", floats(rng, 3)),
        7 => ("nodes", "children", Value::Array((0..1 + rng.below(3)).map(|_| idx(n_node, rng)).collect())),
        8 => ("nodes", *rng.pick(&["mesh", "camera", "skin"]), idx(n_mesh, rng)),
        9 => ("nodes", "extensions", json!({"KHR_lights_punctual": {"light": idx(3, rng)}})),
        10 => {
            let field = *rng.pick(&["indices", "material", "mode"]);
            let v = if field == "material" { idx(n_mat, rng) } else { idx(n_acc, rng) };
            let meshes = doc.json.get_mut("meshes")?.as_array_mut()?;
            let m = rng.below(meshes.len());
            let prims = meshes.get_mut(m)?.get_mut("primitives")?.as_array_mut()?;
            let p = rng.below(prims.len());
            let prim = prims.get_mut(p)?.as_object_mut()?;
            if rng.one_in(3) {
                let attr = *rng.pick(&["NORMAL", "TEXCOORD_0", "POSITION"]);
                let a = idx(n_acc, rng);
                prim.get_mut("attributes")?.as_object_mut()?.insert(attr.into(), a.clone());
                return Some(format!("meshes[{m}].primitives[{p}].attributes.{attr} = {a}"));
            }
            prim.insert(field.into(), v.clone());
            return Some(format!("meshes[{m}].primitives[{p}].{field} = {v}"));
        }
        11 => (
            "materials",
            "pbrMetallicRoughness",
            json!({"baseColorFactor": floats(rng, 4),
            "baseColorTexture": {"index": idx(len("textures"), rng), "texCoord": *rng.pick(&[0, 0, 1, 1 << 31])}}),
        ),
        12 => ("materials", "alphaCutoff", json!(*rng.pick(&[-1.0, 0.0, 2.0, 1e39, 1e-40]))),
        13 => (
            "cameras",
            "perspective",
            json!({"yfov": floats(rng, 1)[0], "znear": floats(rng, 1)[0], "zfar": floats(rng, 1)[0], "aspectRatio": floats(rng, 1)[0]}),
        ),
        14 => {
            let anim = json!({"samplers": [{"input": idx(n_acc, rng), "output": idx(n_acc, rng),
                "interpolation": *rng.pick(&["LINEAR", "STEP", "CUBICSPLINE"])}],
                "channels": [{"sampler": idx(1, rng), "target": {"node": idx(n_node, rng),
                "path": *rng.pick(&["translation", "rotation", "scale", "weights"])}}]});
            let anims = doc.json.as_object_mut()?.entry("animations").or_insert(json!([]));
            anims.as_array_mut()?.push(anim.clone());
            return Some(format!("animation {anim}"));
        }
        _ => (
            "",
            "extensionsRequired",
            json!([*rng.pick(&[
                "KHR_draco_mesh_compression",
                "KHR_mesh_quantization",
                "KHR_materials_unlit",
                "KHR_texture_transform",
                "KHR_lights_punctual",
                "EXT_meshopt_compression"
            ])]),
        ),
    };
    if collection.is_empty() {
        doc.json.as_object_mut()?.insert(field.into(), value.clone());
        return Some(format!("{field} = {value}"));
    }
    let items = doc.json.get_mut(collection)?.as_array_mut()?;
    let i = rng.below(items.len());
    let label = format!("{collection}[{i}].{field} = {value:.80}");
    items.get_mut(i)?.as_object_mut()?.insert(field.into(), value);
    Some(label)
}

// ---------------------------------------------------------------------------------
// Binary mutation.

/// A byte string inside a document.
#[derive(Clone, Copy, Debug)]
enum Blob {
    /// The GLB BIN chunk.
    Bin,
    /// `doc.files[i]`.
    File(usize),
    /// The data URI of `buffers[i]` / `images[i]`.
    Uri(&'static str, usize),
}

fn blobs(doc: &Doc) -> Vec<Blob> {
    let mut out = Vec::new();
    if doc.bin.is_some() {
        out.push(Blob::Bin);
    }
    out.extend((0..doc.files.len()).map(Blob::File));
    for key in ["buffers", "images"] {
        for (i, b) in doc.json.get(key).and_then(Value::as_array).into_iter().flatten().enumerate() {
            if b.get("uri").and_then(Value::as_str).is_some_and(|u| u.starts_with("data:") && u.contains(";base64,")) {
                out.push(Blob::Uri(key, i));
            }
        }
    }
    out
}

fn blob_get(doc: &Doc, b: Blob) -> Option<Vec<u8>> {
    match b {
        Blob::Bin => doc.bin.clone(),
        Blob::File(i) => Some(doc.files.get(i)?.1.clone()),
        Blob::Uri(key, i) => Some(split_data_uri(doc.json.get(key)?.get(i)?.get("uri")?.as_str()?)?.1),
    }
}

fn blob_set(doc: &mut Doc, b: Blob, bytes: Vec<u8>) -> Option<()> {
    match b {
        Blob::Bin => doc.bin = Some(bytes),
        Blob::File(i) => doc.files.get_mut(i)?.1 = bytes,
        Blob::Uri(key, i) => {
            let slot = doc.json.get_mut(key)?.get_mut(i)?.get_mut("uri")?;
            let (head, _) = split_data_uri(slot.as_str()?)?;
            *slot = json!(format!("{head}{}", base64::encode(&bytes)));
        }
    }
    Some(())
}

/// Mutates bytes: bit flips, special values at aligned offsets (floats for
/// attributes, integers for indices), truncation, extension, splicing, and PNG
/// header edits with the CRC fixed so the decoder gets past it.
fn mutate_bytes(b: &mut Vec<u8>, rng: &mut Rng, other: &[u8]) -> String {
    let aligned = |rng: &mut Rng, len: usize, w: usize| if len >= w { rng.below(len / w) * w } else { 0 };
    if b.starts_with(b"\x89PNG\r\n\x1a\n") && b.len() >= 33 && rng.one_in(3) {
        // IHDR data is bytes 16..29: width, height, depth, colour type, ...
        let what = match rng.below(4) {
            0 => {
                let v = *rng.pick(&[0u32, 1, 1 << 14, 1 << 15, 65535, 1 << 24, 0x7FFF_FFFF, u32::MAX]);
                let at = 16 + 4 * rng.below(2);
                b[at..at + 4].copy_from_slice(&v.to_be_bytes());
                format!("PNG {} = {v}", if at == 16 { "width" } else { "height" })
            }
            1 => {
                b[24] = *rng.pick(&[0u8, 1, 2, 3, 4, 8, 16, 32]);
                format!("PNG depth = {}", b[24])
            }
            2 => {
                b[25] = *rng.pick(&[0u8, 1, 2, 3, 4, 6, 7]);
                format!("PNG colour type = {}", b[25])
            }
            _ => {
                // A byte inside some later chunk (IDAT, usually), its CRC fixed.
                let at = 33 + rng.below(b.len().saturating_sub(33).max(1));
                if at < b.len() {
                    b[at] ^= 1 << rng.below(8);
                }
                "PNG chunk byte".to_string()
            }
        };
        // Re-CRC every chunk whose data changed (cheap: the images are tiny).
        let mut at = 8;
        while at + 12 <= b.len() {
            let len = u32::from_be_bytes(b[at..at + 4].try_into().unwrap()) as usize;
            let Some(end) = (at + 8).checked_add(len).filter(|&e| e + 4 <= b.len()) else { break };
            let crc = crc32(&b[at + 4..end]);
            b[end..end + 4].copy_from_slice(&crc.to_be_bytes());
            at = end + 4;
        }
        return what;
    }
    let len = b.len();
    match rng.below(10) {
        0 | 1 if len > 0 => {
            let n = 1 + rng.below(4);
            for _ in 0..n {
                let at = rng.below(len);
                b[at] ^= 1 << rng.below(8);
            }
            format!("flip {n} bits")
        }
        2 if len >= 4 => {
            let at = aligned(rng, len, 4);
            let f = *rng.pick(&[f32::NAN, f32::INFINITY, f32::NEG_INFINITY, 1e38, -1e38, -0.0, 1e-45, f32::MAX]);
            b[at..at + 4].copy_from_slice(&f.to_le_bytes());
            format!("f32 {f} at {at}")
        }
        3 if len >= 4 => {
            let at = aligned(rng, len, 4);
            let v = *rng.pick(&[u32::MAX, 0x8000_0000, 0xFFFF, 0x1_0000, 3, 255, 256]);
            b[at..at + 4].copy_from_slice(&v.to_le_bytes());
            format!("u32 {v} at {at}")
        }
        4 if len >= 2 => {
            let at = aligned(rng, len, 2);
            let v = *rng.pick(&[u16::MAX, 0x8000, 255, 256, 3, 7]);
            b[at..at + 2].copy_from_slice(&v.to_le_bytes());
            format!("u16 {v} at {at}")
        }
        5 => {
            let n = if rng.one_in(2) { 1 + rng.below(4) } else { rng.below(len + 1) };
            b.truncate(len.saturating_sub(n));
            format!("truncate by {n}")
        }
        6 => {
            let most = if rng.one_in(4) { 4096 } else { 16 };
            let n = 1 + rng.below(most);
            let fill = if rng.one_in(2) { 0 } else { rng.next() as u8 };
            b.extend(std::iter::repeat_n(fill, n));
            format!("extend by {n}")
        }
        7 if len > 0 => {
            let at = rng.below(len);
            let n = 1 + rng.below(8).min(len - at - 1);
            if rng.one_in(2) {
                b.drain(at..at + n);
                format!("delete {n} at {at}")
            } else {
                b.splice(at..at, (0..n).map(|_| rng.next() as u8));
                format!("insert {n} at {at}")
            }
        }
        8 if !other.is_empty() && len > 0 => {
            let from = rng.below(other.len());
            let n = (1 + rng.below(64)).min(other.len() - from).min(len);
            let at = rng.below(len - n + 1);
            b[at..at + n].copy_from_slice(&other[from..from + n]);
            format!("splice {n} bytes at {at}")
        }
        _ => {
            let at = rng.below(len.max(1));
            if at < len {
                b[at] = *rng.pick(&[0, 0xFF, 0x7F, 0x80, 0x01]);
            }
            format!("byte at {at}")
        }
    }
}

// ---------------------------------------------------------------------------------
// Writing cases.

/// A GLB container around `json` and `bin`; with `rng`, sometimes a broken one.
fn glb_bytes(json: &[u8], bin: Option<&[u8]>, rng: Option<&mut Rng>, recipe: &mut Vec<String>) -> Vec<u8> {
    let pad = |v: &mut Vec<u8>, with: u8| {
        while v.len() % 4 != 0 {
            v.push(with);
        }
    };
    let mut j = json.to_vec();
    pad(&mut j, b' ');
    let mut chunks: Vec<(u32, [u8; 4], Vec<u8>)> = vec![(j.len() as u32, *b"JSON", j)];
    if let Some(bin) = bin {
        let mut b = bin.to_vec();
        pad(&mut b, 0);
        chunks.push((b.len() as u32, *b"BIN\0", b));
    }
    let mut version = 2u32;
    let mut total: Option<u32> = None;
    let mut trailing = Vec::new();
    if let Some(rng) = rng.and_then(|r| r.one_in(5).then_some(r)) {
        let c = rng.below(chunks.len());
        let what = match rng.below(9) {
            0 => {
                version = *rng.pick(&[0, 1, 3, u32::MAX]);
                format!("GLB version {version}")
            }
            1 => {
                let t = *rng.pick(&[0u32, 11, 12, 13, 20, u32::MAX]);
                total = Some(t);
                format!("GLB length {t}")
            }
            2 => {
                let d = *rng.pick(&[1i64, -1, 3, -4, 4, 1 << 31]);
                chunks[c].0 = (chunks[c].0 as i64 + d) as u32;
                format!("chunk {c} length {d:+}")
            }
            3 => {
                chunks[c].0 = *rng.pick(&[0, u32::MAX, 0x7FFF_FFF8]);
                format!("chunk {c} length {}", chunks[c].0)
            }
            4 => {
                chunks[c].1 = *rng.pick(&[*b"JSON", *b"BIN\0", *b"XTRA", [0; 4]]);
                format!("chunk {c} type {:?}", String::from_utf8_lossy(&chunks[c].1))
            }
            5 => {
                chunks.reverse();
                "chunks swapped".into()
            }
            6 => {
                chunks.push((4, *b"XTRA", vec![1, 2, 3, 4]));
                let (last, other) = (chunks.len() - 1, rng.below(chunks.len()));
                chunks.swap(last, other);
                "extra chunk".into()
            }
            7 => {
                // Unpadded JSON: its declared length is not a multiple of 4.
                let n = chunks[0].2.len();
                let trimmed = n - chunks[0].2.iter().rev().take_while(|&&x| x == b' ').count();
                chunks[0].2.truncate(trimmed);
                chunks[0].0 = trimmed as u32;
                "unpadded JSON chunk".into()
            }
            _ => {
                trailing = vec![0xAB; 1 + rng.below(7)];
                "trailing bytes".into()
            }
        };
        recipe.push(what);
    }
    let body: usize = chunks.iter().map(|c| 8 + c.2.len()).sum();
    let total = total.unwrap_or((12 + body + trailing.len()) as u32);
    let mut out = Vec::with_capacity(12 + body);
    out.extend(b"glTF");
    out.extend(version.to_le_bytes());
    out.extend(total.to_le_bytes());
    for (len, ty, data) in chunks {
        out.extend(len.to_le_bytes());
        out.extend(ty);
        out.extend(data);
    }
    out.extend(trailing);
    out
}

/// Text-level edits that a JSON tree cannot express: numbers out of range, broken
/// syntax, deep nesting, invalid UTF-8.
fn mutate_text(text: &mut Vec<u8>, rng: &mut Rng) -> String {
    let digits: Vec<usize> = (0..text.len()).filter(|&i| text[i].is_ascii_digit()).collect();
    match rng.below(6) {
        0 if !digits.is_empty() => {
            let at = *rng.pick(&digits);
            let end = at + text[at..].iter().take_while(|c| c.is_ascii_digit() || b".eE+-".contains(c)).count();
            let start = at - text[..at].iter().rev().take_while(|c| c.is_ascii_digit() || b".-".contains(c)).count();
            let with = *rng.pick(&[
                "1e400",
                "-1e400",
                "18446744073709551616",
                "-9223372036854775809",
                "1E-400",
                "-0",
                "1.",
                "00",
                "+1",
                "0x10",
            ]);
            text.splice(start..end, with.bytes());
            format!("text number {with}")
        }
        1 => {
            let depth = *rng.pick(&[100, 127, 128, 129, 1000, 100_000]);
            let at = text.iter().position(|&c| c == b'{').map_or(0, |p| p + 1);
            let mut nest = b"\"extras\": ".to_vec();
            nest.extend(std::iter::repeat_n(b'[', depth));
            nest.extend(std::iter::repeat_n(b']', depth));
            nest.extend(b", ");
            text.splice(at..at, nest);
            format!("nesting {depth}")
        }
        2 => {
            let at = rng.below(text.len() + 1);
            text.truncate(at);
            format!("text cut at {at}")
        }
        3 => {
            let at = rng.below(text.len() + 1);
            let with: &[u8] = rng.pick::<&[u8]>(&[&b"\xFF"[..], b"\xEF\xBB\xBF", b"\0", b"\"", b"}", b"\\u0000"]);
            text.splice(at..at, with.iter().copied());
            format!("text insert {with:?} at {at}")
        }
        4 => {
            // A duplicated key (serde refuses) or an unknown one (ignored).
            let at = text.iter().position(|&c| c == b'{').map_or(0, |p| p + 1);
            let with =
                *rng.pick(&["\"scene\": 0, ", "\"unknown\": {\"a\": [1, 2]}, ", "\"asset\": {\"version\": \"1.0\"}, "]);
            text.splice(at..at, with.bytes());
            format!("text key {with}")
        }
        _ => {
            let at = rng.below(text.len().max(1));
            if at < text.len() {
                text[at] = rng.next() as u8;
            }
            format!("text byte at {at}")
        }
    }
}

/// Moves a `.gltf`'s first data-URI buffer into a GLB BIN chunk, or a GLB's BIN
/// chunk into a data URI.
fn convert(doc: &mut Doc) -> Option<String> {
    let buffer = doc.json.get_mut("buffers")?.get_mut(0)?.as_object_mut()?;
    if doc.glb {
        let bin = doc.bin.take()?;
        buffer.insert("uri".into(), json!(data_uri("application/octet-stream", &bin)));
        doc.glb = false;
        Some("GLB -> glTF".into())
    } else {
        let (_, bytes) = split_data_uri(buffer.get("uri")?.as_str()?)?;
        buffer.remove("uri");
        doc.bin = Some(bytes);
        doc.glb = true;
        Some("glTF -> GLB".into())
    }
}

/// Applies a few mutations to a copy of `base` and writes it out.
fn mutant(base: &Doc, corpus: &[Doc], rng: &mut Rng, id: u64) -> (Doc, Case) {
    let mut doc = base.clone();
    let mut recipe = vec![base.label.clone()];
    let most = if rng.one_in(4) { 8 } else { 3 };
    let n = if rng.one_in(2) { 1 } else { 1 + rng.below(most) };
    for _ in 0..n {
        if let Some(raw) = doc.raw.as_mut() {
            recipe.push(mutate_bytes(raw, rng, &[]));
            continue;
        }
        let what = match rng.weighted(&[70, 20, 3]) {
            0 => mutate_json(&mut doc, corpus, rng),
            1 => {
                let targets = blobs(&doc);
                if targets.is_empty() {
                    None
                } else {
                    let t = *rng.pick(&targets);
                    let donor = rng.pick(corpus);
                    let other = donor.bin.clone().or_else(|| blobs(donor).first().and_then(|&b| blob_get(donor, b)));
                    blob_get(&doc, t).and_then(|mut bytes| {
                        let what = mutate_bytes(&mut bytes, rng, other.as_deref().unwrap_or(&[]));
                        blob_set(&mut doc, t, bytes).map(|_| format!("{t:?}: {what}"))
                    })
                }
            }
            _ => convert(&mut doc),
        };
        recipe.extend(what);
    }
    let case = write_case(&doc, Some(rng), &mut recipe, id);
    doc.label = recipe.join(" | ");
    (doc, case)
}

/// The files of `doc`; with `rng`, sometimes with its text or GLB container broken.
fn write_case(doc: &Doc, mut rng: Option<&mut Rng>, recipe: &mut Vec<String>, id: u64) -> Case {
    let main = if doc.glb { "scene.glb" } else { "scene.gltf" };
    let bytes = match &doc.raw {
        Some(raw) => raw.clone(),
        None => {
            let mut text = serde_json::to_vec(&doc.json).expect("a Value serializes");
            if let Some(rng) = rng.as_deref_mut().and_then(|r| r.one_in(12).then_some(r)) {
                recipe.push(mutate_text(&mut text, rng));
            }
            if doc.glb {
                glb_bytes(&text, doc.bin.as_deref(), rng, recipe)
            } else {
                text
            }
        }
    };
    let mut files = vec![(main.to_string(), bytes)];
    files.extend(doc.files.iter().cloned());
    Case { id, files, recipe: recipe.join(" | ") }
}

// ---------------------------------------------------------------------------------
// Running and checking one case.

enum Verdict {
    /// Loaded, or refused with a proper error; the label names which (for the
    /// statistics).
    Clean(&'static str, String),
    Failed(String),
}

/// The promises of `Scene::load` about a loaded scene.
fn check_scene(s: &Scene) -> Result<(), String> {
    let finite = |xs: &[f32]| xs.iter().all(|x| x.is_finite());
    if s.vertices.is_empty() || s.vertices.len() % 3 != 0 {
        return Err(format!("{} vertices: not a non-empty triangle list", s.vertices.len()));
    }
    for (i, v) in s.vertices.iter().enumerate() {
        if !finite(&v.position) || !finite(&v.normal) || !finite(&v.uv) {
            return Err(format!("vertex {i} is not finite: {v:?}"));
        }
        let len = glam::Vec3::from(v.normal).length();
        if (len - 1.0).abs() > 1e-3 {
            return Err(format!("vertex {i} normal has length {len}"));
        }
    }
    if s.triangle_material.len() != s.triangle_count() {
        return Err(format!("{} triangle materials for {} triangles", s.triangle_material.len(), s.triangle_count()));
    }
    if s.materials.is_empty() {
        return Err("no materials".into());
    }
    if let Some(&m) = s.triangle_material.iter().find(|&&m| m as usize >= s.materials.len()) {
        return Err(format!("triangle material {m} out of {}", s.materials.len()));
    }
    for (i, m) in s.materials.iter().enumerate() {
        if !m.base_color.is_finite() {
            return Err(format!("material {i} has a non-finite base colour {}", m.base_color));
        }
        if m.alpha_cutoff.is_some_and(f32::is_nan) {
            return Err(format!("material {i} has a NaN alpha cutoff {:?}", m.alpha_cutoff));
        }
        if m.texture.is_some_and(|t| t as usize >= s.textures.len()) {
            return Err(format!("material {i} texture {:?} out of {}", m.texture, s.textures.len()));
        }
    }
    for (i, t) in s.textures.iter().enumerate() {
        if t.texels.len() as u64 != u64::from(t.width) * u64::from(t.height) || t.texels.is_empty() {
            return Err(format!("texture {i}: {} texels for {}x{}", t.texels.len(), t.width, t.height));
        }
    }
    if s.lights.is_empty() {
        return Err("no lights".into());
    }
    for l in &s.lights {
        let ok = l.position.is_finite()
            && l.direction.is_finite()
            && (l.direction.length() - 1.0).abs() < 1e-3
            && l.color.is_finite()
            && l.intensity.is_finite()
            && l.range.is_none_or(f32::is_finite);
        if !ok {
            return Err(format!("light is not finite: {l:?}"));
        }
    }
    if let Some(c) = &s.camera {
        if !(c.world_from_camera.is_finite()
            && c.yfov.is_finite()
            && c.yfov > 0.0
            && c.znear.is_finite()
            && c.znear > 0.0)
        {
            return Err(format!("camera is not usable: {c:?}"));
        }
    }
    for w in &s.warnings {
        if w.is_empty() || w.contains(['\n', '\r']) {
            return Err(format!("warning is not one line: {w:?}"));
        }
    }
    Ok(())
}

/// An animated scene posed at its start, middle and end, and at times outside its
/// range, keeps the same promises (the poses are what a renderer draws).
fn check_animation(s: &Scene) -> Result<(), String> {
    if !s.is_animated() {
        return Ok(());
    }
    let d = s.duration();
    if !(d.is_finite() && d >= 0.0) {
        return Err(format!("animation duration {d}"));
    }
    for t in [0.0, 0.5 * d, d, -1.0, d + 1.0, 1e30] {
        let posed = s.frozen_at(t);
        check_scene(&posed).map_err(|e| format!("posed at t = {t}: {e}"))?;
        if posed.triangle_count() != s.triangle_count() {
            return Err(format!(
                "posed at t = {t}: {} triangles, {} at load",
                posed.triangle_count(),
                s.triangle_count()
            ));
        }
    }
    Ok(())
}

fn verdict(r: std::thread::Result<Result<Scene, SceneError>>) -> Verdict {
    match r {
        Err(payload) => {
            let msg = payload
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| payload.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "(non-string payload)".into());
            Verdict::Failed(format!("panic: {msg}"))
        }
        Ok(Ok(scene)) => match check_scene(&scene).and_then(|()| check_animation(&scene)) {
            Ok(()) => Verdict::Clean("loaded", String::new()),
            Err(e) => Verdict::Failed(format!("loaded a bad scene: {e}")),
        },
        Ok(Err(e)) => {
            let s = e.to_string();
            if s.is_empty() || s.contains(['\n', '\r']) {
                return Verdict::Failed(format!("error is not one line: {s:?}"));
            }
            // The variant's name, for the statistics.
            let debug = format!("{e:?}");
            let name = debug.split([' ', '{', '(']).next().unwrap_or("");
            let kind = match name {
                "NotFound" => "NotFound",
                "Read" => "Read",
                "Malformed" => "Malformed",
                "Unsupported" => "Unsupported",
                "Buffer" => "Buffer",
                "Image" => "Image",
                "NoLight" => "NoLight",
                "NoTriangles" => "NoTriangles",
                "NonFinitePosition" => "NonFinitePosition",
                _ => "other error",
            };
            Verdict::Clean(kind, s)
        }
    }
}

struct Outcome {
    verdict: Verdict,
    elapsed: Duration,
    peak: usize,
}

/// Where a case runs: its own directory, in a per-process directory under
/// `target/fuzz-failures` so that a case that kills the process (an allocation
/// refused over the cap, a stack overflow) leaves its input where failures go.
struct Runner {
    work: PathBuf,
    seed: u64,
    limit: Duration,
}

/// A case that did not return in time: the thread is left running, so fuzzing
/// stops.
struct Hung;

impl Runner {
    fn case_dir(&self, id: u64) -> PathBuf {
        self.work.join(format!("case-{id}"))
    }

    fn run(&self, case: &Case) -> Result<Outcome, Hung> {
        let dir = self.case_dir(case.id);
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).expect("create case directory");
        for (name, bytes) in &case.files {
            std::fs::write(dir.join(name), bytes).expect("write case file");
        }
        *OVER_CAP_NOTE.lock().unwrap() =
            format!("Case {} (seed {}): {}. Its input is left in {}.", case.id, self.seed, case.recipe, dir.display());
        let path = dir.join(&case.files[0].0);
        let (tx, rx) = mpsc::channel();
        let start = Instant::now();
        std::thread::Builder::new()
            .name(format!("fuzz case {}", case.id))
            .spawn(move || {
                METER.with(|m| {
                    m.live.set(0);
                    m.peak.set(0);
                    m.refused.set(0);
                    m.armed.set(true);
                });
                let r = std::panic::catch_unwind(|| Scene::load(&path));
                let mut v = verdict(r);
                let (peak, refused) = METER.with(|m| {
                    m.armed.set(false);
                    (m.peak.get(), m.refused.get())
                });
                if refused > 0 {
                    v = Verdict::Failed(format!("asked for {refused} bytes over the {ALLOC_CAP}-byte cap"));
                }
                let _ = tx.send((v, peak));
            })
            .expect("spawn case thread");
        match rx.recv_timeout(self.limit) {
            Ok((verdict, peak)) => {
                let elapsed = start.elapsed();
                let verdict = match verdict {
                    Verdict::Clean(..) if elapsed > self.limit => Verdict::Failed(format!(
                        "took {:.2} s (limit {:.0} s)",
                        elapsed.as_secs_f64(),
                        self.limit.as_secs_f64()
                    )),
                    v => v,
                };
                let _ = std::fs::remove_dir_all(&dir);
                Ok(Outcome { verdict, elapsed, peak })
            }
            Err(_) => Err(Hung),
        }
    }

    /// Copies case `id`'s directory to `target/fuzz-failures/seed<S>-case<N>` with
    /// a note of what happened, and returns that path.
    fn save(&self, case: &Case, why: &str) -> PathBuf {
        let out = failures_dir().join(format!("seed{}-case{}", self.seed, case.id));
        let _ = std::fs::remove_dir_all(&out);
        let _ = std::fs::create_dir_all(&out);
        for (name, bytes) in &case.files {
            let _ = std::fs::write(out.join(name), bytes);
        }
        let note = format!(
            "{why}\ninput: {}\nrecipe: {}\nreplay: LEAKLESS_FUZZ_REPLAY={} cargo test -p leakless-scene --test fuzz -- --nocapture\n",
            case.files[0].0,
            case.recipe,
            out.display()
        );
        let _ = std::fs::write(out.join("WHY.txt"), note);
        out
    }
}

fn env_u64(name: &str) -> Option<u64> {
    let v = std::env::var(name).ok()?;
    Some(v.trim().parse().unwrap_or_else(|_| panic!("{name}={v:?} is not a non-negative integer")))
}

/// Per-case wall-time limit: a few milliseconds is typical; unoptimized builds
/// (the CI's `cargo test`) get more room.
fn case_limit() -> Duration {
    let default = if cfg!(debug_assertions) { 5 } else { 2 };
    Duration::from_secs(env_u64("LEAKLESS_FUZZ_CASE_SECONDS").unwrap_or(default))
}

/// The scene file of a saved failure (a directory) or the file itself.
fn replay_target(p: &Path) -> PathBuf {
    // `cargo test` runs in the crate's directory; a path may be relative to the
    // workspace instead.
    let joined = repo().join(p);
    let p = if p.exists() || !joined.exists() { p } else { joined.as_path() };
    if p.is_dir() {
        for name in ["scene.gltf", "scene.glb"] {
            if p.join(name).exists() {
                return p.join(name);
            }
        }
    }
    p.to_path_buf()
}

#[test]
fn fuzz_scene_load() {
    let start = Instant::now();
    let seed = env_u64("LEAKLESS_FUZZ_SEED").unwrap_or(1);
    let budget = Duration::from_secs(env_u64("LEAKLESS_FUZZ_SECONDS").unwrap_or(40));
    let work = failures_dir().join(format!("running-{}", std::process::id()));
    let runner = Runner { work: work.clone(), seed, limit: case_limit() };

    if let Ok(target) = std::env::var("LEAKLESS_FUZZ_REPLAY") {
        let path = replay_target(Path::new(&target));
        let mut files = vec![(path.file_name().unwrap().to_string_lossy().into_owned(), std::fs::read(&path).unwrap())];
        for e in std::fs::read_dir(path.parent().unwrap()).unwrap().flatten() {
            let name = e.file_name().to_string_lossy().into_owned();
            if e.path() != path && e.path().is_file() && name != "WHY.txt" {
                files.push((name, std::fs::read(e.path()).unwrap()));
            }
        }
        let case = Case { id: 0, files, recipe: format!("replay of {}", path.display()) };
        let outcome = runner.run(&case);
        let _ = std::fs::remove_dir_all(&work);
        match outcome {
            Ok(Outcome { verdict: Verdict::Clean(what, message), elapsed, peak }) => {
                println!(
                    "fuzz: replay of {} is clean ({what} {message:?}, {:.3} s, peak {} KiB)",
                    path.display(),
                    elapsed.as_secs_f64(),
                    peak >> 10
                )
            }
            Ok(Outcome { verdict: Verdict::Failed(why), .. }) => panic!("replay of {}: {why}", path.display()),
            Err(Hung) => panic!("replay of {}: no result within {:?}", path.display(), runner.limit),
        }
        return;
    }

    let mut corpus = file_corpus();
    assert!(corpus.len() >= 10, "the scene corpus is missing: {} files", corpus.len());
    let hand = hand_seeds();
    let hand_labels: Vec<String> = hand.iter().map(|d| d.label.clone()).collect();
    corpus.extend(hand);

    let mut rng = Rng(seed);
    let mut stats: BTreeMap<&'static str, u64> = BTreeMap::new();
    let mut failures: Vec<String> = Vec::new();
    let (mut cases, mut slowest, mut peak) = (0u64, (Duration::ZERO, String::new()), (0usize, String::new()));
    // Mutants that loaded, to mutate further (stacked mutations stay valid longer).
    let mut pool: Vec<Doc> = Vec::new();
    let mut pool_next = 0;
    let mut hung = false;

    // The seeds as they are, then mutants until the budget is spent.
    let seeds: Vec<Case> =
        corpus.iter().enumerate().map(|(i, d)| write_case(d, None, &mut vec![d.label.clone()], i as u64)).collect();
    let mut queue = seeds.into_iter();
    loop {
        let (case, doc) = match queue.next() {
            Some(c) => (c, None),
            None if start.elapsed() < budget => {
                let id = corpus.len() as u64 + cases;
                let base = if !pool.is_empty() && rng.one_in(3) {
                    &pool[rng.below(pool.len())]
                } else {
                    &corpus[rng.below(corpus.len())]
                };
                let (doc, case) = mutant(base, &corpus, &mut rng, id);
                (case, Some(doc))
            }
            None => break,
        };
        cases += 1;
        match runner.run(&case) {
            Ok(o) => {
                if o.peak > peak.0 {
                    peak = (o.peak, case.recipe.clone());
                }
                if o.elapsed > slowest.0 {
                    slowest = (o.elapsed, case.recipe.clone());
                }
                match o.verdict {
                    Verdict::Clean(what, message) => {
                        *stats.entry(what).or_default() += 1;
                        let is_seed = doc.is_none();
                        if is_seed && what != "loaded" {
                            println!("fuzz: seed {} does not load: {message}", case.recipe);
                        }
                        if is_seed && what != "loaded" && hand_labels.contains(&case.recipe) {
                            failures.push(format!("hand-built seed {} does not load: {message}", case.recipe));
                        }
                        if let (Some(doc), "loaded") = (doc, what) {
                            if case.files[0].1.len() < 1 << 20 {
                                if pool.len() < 64 {
                                    pool.push(doc);
                                } else {
                                    pool[pool_next % 64] = doc;
                                    pool_next += 1;
                                }
                            }
                        }
                    }
                    Verdict::Failed(why) => {
                        let saved = runner.save(&case, &why);
                        eprintln!(
                            "fuzz: FAILURE {why}\n      input saved to {}\n      recipe: {}",
                            saved.display(),
                            case.recipe
                        );
                        failures.push(format!("{why} ({})", saved.display()));
                        if failures.len() >= 20 {
                            break;
                        }
                    }
                }
            }
            Err(Hung) => {
                let why = format!("no result within {:?}: a hang", runner.limit);
                let saved = runner.save(&case, &why);
                eprintln!(
                    "fuzz: FAILURE {why}\n      input saved to {}\n      recipe: {}",
                    saved.display(),
                    case.recipe
                );
                failures.push(format!("{why} ({})", saved.display()));
                hung = true;
                break;
            }
        }
    }
    if !hung {
        let _ = std::fs::remove_dir_all(&work);
    }
    let secs = start.elapsed().as_secs_f64();
    let outcomes: Vec<String> = stats.iter().map(|(k, v)| format!("{k} {v}")).collect();
    println!(
        "fuzz: outcomes: {}\nfuzz: slowest case {:.3} s ({:.160})\nfuzz: largest allocation {} MiB ({:.160})",
        outcomes.join(", "),
        slowest.0.as_secs_f64(),
        slowest.1,
        peak.0 >> 20,
        peak.1
    );
    println!("fuzz: {cases} cases in {secs:.0} s, {} failures (seed {seed})", failures.len());
    assert!(failures.is_empty(), "{} fuzz failure(s):\n  {}", failures.len(), failures.join("\n  "));
}

// ---------------------------------------------------------------------------------
// Regressions: what the fuzzer found, each as the smallest input that shows it.

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
fn load_seed(test: &str, mut doc: Doc, edit: impl FnOnce(&mut Value)) -> (Result<Scene, SceneError>, usize) {
    edit(&mut doc.json);
    let case = write_case(&doc, None, &mut Vec::new(), 0);
    let files: Vec<(&str, Vec<u8>)> = case.files.iter().map(|(n, b)| (n.as_str(), b.clone())).collect();
    load_files(test, &files)
}

fn one_line_error(r: Result<Scene, SceneError>) -> String {
    let e = r.expect_err("an error");
    let s = e.to_string();
    assert!(!s.is_empty() && !s.contains(['\n', '\r']), "{s:?}");
    s
}

/// `/dev/zero` as a buffer was read until memory ran out (std's read gave up at
/// the 1 GiB cap here; without a cap, at the machine's end). Devices and FIFOs are
/// refused now, before they are opened.
#[test]
fn device_uri_is_refused() {
    for uri in ["/dev/zero", "file:///dev/zero"] {
        let (r, peak) = load_seed("dev-zero", seed_accessors(), |j| j["buffers"][0]["uri"] = json!(uri));
        let e = one_line_error(r);
        assert!(e.contains("not a regular file"), "{e}");
        assert!(peak < 1 << 20, "{peak} bytes");
    }
}

/// The JPEG decoder's message ends with a line break; names and extension names
/// from the file may hold any; messages and warnings stay one line each.
#[test]
fn messages_and_warnings_stay_one_line() {
    let mut doc = seed_textured();
    let mut bytes = jpeg(8, 8);
    bytes.truncate(bytes.len() / 2);
    doc.json["images"][1] = json!({"uri": data_uri("image/jpeg", &bytes)});
    let e = one_line_error(load_seed("jpeg", doc, |_| {}).0);
    assert!(e.contains("image 1"), "{e}");

    let (r, _) = load_seed("names", seed_accessors(), |j| {
        j["meshes"][0]["name"] = json!("two\nlines");
        j["accessors"][0]["count"] = json!(99);
    });
    let e = one_line_error(r);
    assert!(e.contains("two\\nlines"), "{e}");

    let (r, _) = load_seed("warnings", seed_textured(), |j| {
        j["extensionsUsed"] = json!(["KHR_lights_punctual", "EXT_two\nlines\r\n"]);
        j["materials"][3]["name"] = json!("blend\u{1b}[31m");
    });
    let s = r.unwrap();
    assert!(s.warnings.iter().all(|w| !w.contains(|c: char| c.is_control())), "{:?}", s.warnings);
    assert!(s.warnings[0].contains("EXT_two\\nlines"), "{:?}", s.warnings);
}

/// `baseColorFactor` past f32's range read as infinity, and negative factors went
/// through: both are clamped to glTF's [0, 1], with a warning.
#[test]
fn base_color_factor_is_clamped() {
    let (r, _) = load_seed("factor", seed_textured(), |j| {
        j["materials"][4]["pbrMetallicRoughness"]["baseColorFactor"] = json!([1e39, -1.0, 0.5, 2.0]);
    });
    let s = r.unwrap();
    let m = s.materials.iter().find(|m| m.name == "plain").unwrap();
    assert_eq!(m.base_color, glam::Vec4::new(1.0, 0.0, 0.5, 1.0));
    assert!(s.warnings.iter().any(|w| w == "baseColorFactor clamped to [0, 1]: material 'plain'"), "{:?}", s.warnings);
}

/// A normal whose squared length is subnormal normalized to a length of 0.77;
/// an infinite texture coordinate went through to the sampler.
#[test]
fn tiny_normals_are_unit_and_bad_uvs_are_zero() {
    let mut b = Bin::default();
    let pos = b.packed(&f32s(&[0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0]), 5126, 3, "VEC3");
    let nrm = b.packed(&f32s(&[1e-20, 0.0, 1e-21, 0.0, 3e-22, 0.0, 1e-40, 1e-40, 0.0]), 5126, 3, "VEC3");
    let uv = b.packed(&f32s(&[f32::NEG_INFINITY, 0.5, f32::NAN, 1.0, 0.25, f32::INFINITY]), 5126, 3, "VEC2");
    let root = json!({
        "extensions": lights(json!([{"type": "point"}])),
        "extensionsUsed": ["KHR_lights_punctual"],
        "nodes": [{"mesh": 0}, light_node(0, [0.0, 0.0, 1.0])],
        "meshes": [{"primitives": [{"attributes": {"POSITION": pos, "NORMAL": nrm, "TEXCOORD_0": uv}}]}],
    });
    let (r, _) = load_seed("tiny", seed("tiny", root, b, Embed::DataUri, Vec::new()), |_| {});
    let s = r.unwrap();
    check_scene(&s).unwrap();
    let uvs: Vec<[f32; 2]> = s.vertices.iter().map(|v| v.uv).collect();
    assert_eq!(uvs, [[0.0, 0.5], [0.0, 1.0], [0.25, 0.0]]);
}

/// An accessor without a buffer view is `count` zeros that no data backs: a
/// 3 KiB file with `count: 16777216` made the loader hold over 1 GiB (the old
/// bound was 2^26 elements). Now it may not exceed the file's buffers.
#[test]
fn implicit_accessor_count_is_bounded() {
    let held = |j: &Value| j["buffers"][0]["byteLength"].as_u64().unwrap();
    let implicit = |j: &Value| j["accessors"].as_array().unwrap().len() - 1;
    // As many zeros as the buffer has bytes still loads.
    let (r, _) = load_seed("implicit-fits", seed_accessors(), |j| {
        let (n, i) = (held(j) / 12, implicit(j));
        j["accessors"][i]["count"] = json!(n - n % 3);
    });
    r.unwrap();
    for count in [1u64 << 20, 1 << 24, 1 << 26, 1 << 40, u64::MAX] {
        let (r, peak) = load_seed("implicit", seed_accessors(), |j| {
            let i = implicit(j);
            j["accessors"][i]["count"] = json!(count);
        });
        let e = one_line_error(r);
        assert!(e.contains("without a buffer view"), "{e}");
        assert!(peak < 1 << 20, "count {count}: {peak} bytes");
    }
}
