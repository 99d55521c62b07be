//! Hand-built seeds: small valid documents for what the repository's scenes lack.

use serde_json::{json, Value};

use crate::corpus::Doc;
use crate::encoding::data_uri;

pub(crate) fn f32s(xs: &[f32]) -> Vec<u8> {
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
pub(crate) struct Bin {
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
    pub(crate) fn packed(&mut self, bytes: &[u8], component: u32, count: usize, ty: &str) -> usize {
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
pub(crate) enum Embed {
    DataUri,
    Glb,
    File(&'static str),
}

/// Completes `root` with `bin`'s buffer, views and accessors.
pub(crate) fn seed(label: &str, mut root: Value, bin: Bin, embed: Embed, files: Vec<(String, Vec<u8>)>) -> Doc {
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
pub(crate) fn lights(kinds: Value) -> Value {
    json!({"KHR_lights_punctual": {"lights": kinds}})
}

pub(crate) fn light_node(light: usize, translation: [f32; 3]) -> Value {
    json!({"extensions": {"KHR_lights_punctual": {"light": light}}, "translation": translation})
}

fn png(w: u32, h: u32) -> Vec<u8> {
    let img = image::RgbaImage::from_fn(w, h, |x, y| image::Rgba([(x * 60) as u8, (y * 60) as u8, 128, 255]));
    let mut out = std::io::Cursor::new(Vec::new());
    img.write_to(&mut out, image::ImageFormat::Png).unwrap();
    out.into_inner()
}

pub(crate) fn jpeg(w: u32, h: u32) -> Vec<u8> {
    let img = image::RgbImage::from_fn(w, h, |x, y| image::Rgb([(x * 30) as u8, (y * 30) as u8, 200]));
    let mut out = std::io::Cursor::new(Vec::new());
    img.write_to(&mut out, image::ImageFormat::Jpeg).unwrap();
    out.into_inner()
}

/// Accessors of every kind the loader reads: interleaved and strided attributes,
/// indices of u8/u16/u32, strips and fans, `KHR_mesh_quantization` (normalized and
/// integer attributes), sparse accessors with each index type, over a view and
/// without one.
pub(crate) fn seed_accessors() -> Doc {
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

pub(crate) fn seed_textured() -> Doc {
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

pub(crate) fn hand_seeds() -> Vec<Doc> {
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
