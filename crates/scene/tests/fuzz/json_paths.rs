//! JSON mutation, part one: paths into a document and the values the mutators put there.

use serde_json::{json, Value};

use crate::rng::Rng;

#[derive(Clone, Debug)]
pub(crate) enum Seg {
    Key(String),
    Index(usize),
}

/// Every value's path in `v` (the root included), depth-first.
pub(crate) fn paths(v: &Value) -> Vec<Vec<Seg>> {
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

pub(crate) fn get<'a>(v: &'a Value, path: &[Seg]) -> Option<&'a Value> {
    path.iter().try_fold(v, |v, s| match s {
        Seg::Key(k) => v.get(k.as_str()),
        Seg::Index(i) => v.get(*i),
    })
}

pub(crate) fn get_mut<'a>(v: &'a mut Value, path: &[Seg]) -> Option<&'a mut Value> {
    path.iter().try_fold(v, |v, s| match s {
        Seg::Key(k) => v.get_mut(k.as_str()),
        Seg::Index(i) => v.get_mut(*i),
    })
}

/// The object key a value sits under (an array element: its array's key).
pub(crate) fn key_of(path: &[Seg]) -> &str {
    path.iter()
        .rev()
        .find_map(|s| match s {
            Seg::Key(k) => Some(k.as_str()),
            Seg::Index(_) => None,
        })
        .unwrap_or("")
}

pub(crate) fn show(path: &[Seg]) -> String {
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
pub(crate) const INDEX_KEYS: &[&str] = &[
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

pub(crate) fn extreme_number(rng: &mut Rng, orig: Option<&Value>) -> Value {
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
pub(crate) fn enum_values(key: &str, current: &Value) -> Option<Vec<Value>> {
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

pub(crate) const ATTRIBUTES: &[&str] = &[
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
pub(crate) const URIS: &[&str] = &[
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
pub(crate) const NAMES: &[&str] = &["line\nbreak", "cr\rreturn", "nul\u{0}", "\u{1b}[31mred", "é∂ü", "", "tab\there"];
