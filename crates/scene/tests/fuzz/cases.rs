//! Writing cases: GLB containers, text mutation, a mutant of a document and its files on disk.

use serde_json::json;

use crate::byte_mutation::{blob_get, blob_set, blobs, mutate_bytes};
use crate::corpus::{Case, Doc};
use crate::encoding::{data_uri, split_data_uri};
use crate::json_mutation::mutate_json;
use crate::rng::Rng;

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
pub(crate) fn mutant(base: &Doc, corpus: &[Doc], rng: &mut Rng, id: u64) -> (Doc, Case) {
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
pub(crate) fn write_case(doc: &Doc, mut rng: Option<&mut Rng>, recipe: &mut Vec<String>, id: u64) -> Case {
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
