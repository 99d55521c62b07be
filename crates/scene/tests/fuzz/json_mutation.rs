//! JSON mutation, part two: the mutations themselves.

use serde_json::{json, Value};

use crate::corpus::Doc;
use crate::json_paths::{
    enum_values, extreme_number, get, get_mut, key_of, paths, show, Seg, ATTRIBUTES, INDEX_KEYS, NAMES, URIS,
};
use crate::rng::Rng;

/// A (JSON) mutation of the document; returns a description, or `None` when it
/// found nothing to act on.
pub(crate) fn mutate_json(doc: &mut Doc, corpus: &[Doc], rng: &mut Rng) -> Option<String> {
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
