//! Binary mutation: the byte strings inside a document and the edits on them.

use serde_json::{json, Value};

use crate::corpus::Doc;
use crate::encoding::{crc32, split_data_uri};
use crate::rng::Rng;

/// A byte string inside a document.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Blob {
    /// The GLB BIN chunk.
    Bin,
    /// `doc.files[i]`.
    File(usize),
    /// The data URI of `buffers[i]` / `images[i]`.
    Uri(&'static str, usize),
}

pub(crate) fn blobs(doc: &Doc) -> Vec<Blob> {
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

pub(crate) fn blob_get(doc: &Doc, b: Blob) -> Option<Vec<u8>> {
    match b {
        Blob::Bin => doc.bin.clone(),
        Blob::File(i) => Some(doc.files.get(i)?.1.clone()),
        Blob::Uri(key, i) => Some(split_data_uri(doc.json.get(key)?.get(i)?.get("uri")?.as_str()?)?.1),
    }
}

pub(crate) fn blob_set(doc: &mut Doc, b: Blob, bytes: Vec<u8>) -> Option<()> {
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
pub(crate) fn mutate_bytes(b: &mut Vec<u8>, rng: &mut Rng, other: &[u8]) -> String {
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
