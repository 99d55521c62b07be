//! Bounds-checked accessor reading.
//!
//! The `gltf` crate's `Reader` trusts the file: a count of zero, a too-short buffer
//! view, a mismatched element type or a sparse index past the end panics there (debug
//! assertions and slice indexing). Scenes come from users, so this module reads
//! accessors itself with checked arithmetic and turns every inconsistency into an
//! error message. It also widens any component type to `f32` (honouring
//! `normalized`), which is all `KHR_mesh_quantization` needs.

use gltf::json;
use json::accessor::{ComponentType, Type};
use json::validation::Checked;

/// The document's buffers, for reading accessors and buffer views.
pub(crate) struct Data<'a> {
    pub root: &'a json::Root,
    pub buffers: &'a [Vec<u8>],
}

impl<'a> Data<'a> {
    /// The bytes of buffer view `view`, checked against its buffer.
    pub fn view_bytes(&self, view: usize) -> Result<&'a [u8], String> {
        let v = self.root.buffer_views.get(view).ok_or_else(|| format!("buffer view {view} does not exist"))?;
        let buffer = self
            .buffers
            .get(v.buffer.value())
            .ok_or_else(|| format!("buffer view {view}: buffer {} does not exist", v.buffer.value()))?;
        let start = v.byte_offset.map_or(0, |o| o.0);
        let end = start.checked_add(v.byte_length.0);
        end.and_then(|end| buffer.get(usize::try_from(start).ok()?..usize::try_from(end).ok()?)).ok_or_else(|| {
            format!(
                "buffer view {view} (bytes {start}..+{}) lies outside buffer {} ({} bytes)",
                v.byte_length.0,
                v.buffer.value(),
                buffer.len()
            )
        })
    }

    /// Reads accessor `index` as a flat list of `f32` components, requiring its
    /// type to be `expected`. Integer components are normalised when the
    /// accessor says so and converted as is otherwise.
    pub fn floats(&self, index: usize, expected: Type) -> Result<Vec<f32>, String> {
        let a = self.accessor(index)?;
        let (ty, ct) = types(a, index)?;
        if ty != expected {
            return Err(format!("accessor {index} is {ty:?}, expected {expected:?}"));
        }
        self.read(a, index, ct, dims(ty), a.normalized)
    }

    /// Reads accessor `index` as vertex indices (SCALAR of u8, u16 or u32).
    pub fn indices(&self, index: usize) -> Result<Vec<u32>, String> {
        let a = self.accessor(index)?;
        let (ty, ct) = types(a, index)?;
        if ty != Type::Scalar || !matches!(ct, ComponentType::U8 | ComponentType::U16 | ComponentType::U32) {
            return Err(format!("index accessor {index} is {ty:?} of {ct:?}, not SCALAR of unsigned integers"));
        }
        // u32 converts to f32 losslessly only below 2^24; read indices exactly.
        let mut out = Vec::new();
        self.visit(a, index, ct, 1, |bytes| out.push(raw_u32(ct, bytes)))?;
        Ok(out)
    }

    fn accessor(&self, index: usize) -> Result<&'a json::Accessor, String> {
        self.root.accessors.get(index).ok_or_else(|| format!("accessor {index} does not exist"))
    }

    fn read(
        &self,
        a: &json::Accessor,
        index: usize,
        ct: ComponentType,
        n: usize,
        normalized: bool,
    ) -> Result<Vec<f32>, String> {
        let mut out = Vec::new();
        self.visit(a, index, ct, n, |bytes| {
            let size = component_size(ct);
            out.extend(bytes.chunks_exact(size).map(|c| component(ct, c, normalized)));
        })?;
        Ok(out)
    }

    /// Calls `f(bytes)` for every element in order, after applying sparse
    /// substitution (the sparse values replace whole elements).
    fn visit(
        &self,
        a: &json::Accessor,
        index: usize,
        ct: ComponentType,
        n: usize,
        mut f: impl FnMut(&[u8]),
    ) -> Result<(), String> {
        let elem = component_size(ct) * n;
        let count = a.count.0;
        let zeros = vec![0u8; elem];
        // Dense part: the buffer view, or zeros when the accessor has none.
        let mut dense: Vec<&[u8]> = match a.buffer_view {
            Some(view) => {
                let bytes = self.view_bytes(view.value()).map_err(|e| format!("accessor {index}: {e}"))?;
                let stride = match self.root.buffer_views.get(view.value()).and_then(|v| v.byte_stride) {
                    Some(s) if s.0 < elem => {
                        let s = s.0;
                        return Err(format!("accessor {index}: byteStride {s} < element size {elem}"));
                    }
                    Some(s) => s.0,
                    None => elem,
                };
                let offset = a.byte_offset.map_or(0, |o| o.0);
                elements(bytes, offset, stride, elem, count).ok_or_else(|| {
                    let v = view.value();
                    format!("accessor {index}: {count} elements from byte {offset} overrun view {v}")
                })?
            }
            None => {
                // Implicit data is `count` zeros that no bytes in the file back, and
                // every consumer allocates per element: a tiny file could ask for
                // gigabytes. So it may not be larger than the file's buffers together
                // (a sparse accessor's few values live there, and an attribute is
                // as long as the buffer-backed ones beside it).
                let held: u64 = self.buffers.iter().map(|b| b.len() as u64).sum();
                if count.checked_mul(elem as u64).is_none_or(|bytes| bytes > held) {
                    let what = format!("{count} elements without a buffer view");
                    return Err(format!("accessor {index}: {what} exceed the {held} bytes of the file's buffers"));
                }
                vec![&zeros[..]; count as usize]
            }
        };
        if let Some(sparse) = &a.sparse {
            let k = sparse.count.0;
            let ict = match sparse.indices.component_type {
                Checked::Valid(c) => c.0,
                Checked::Invalid => return Err(format!("accessor {index}: invalid sparse index type")),
            };
            let isize_ = component_size(ict);
            let ibytes = self.view_bytes(sparse.indices.buffer_view.value())?;
            let ioff = sparse.indices.byte_offset.0;
            let idx = elements(ibytes, ioff, isize_, isize_, k)
                .ok_or_else(|| format!("accessor {index}: sparse indices overrun their buffer view"))?;
            let vbytes = self.view_bytes(sparse.values.buffer_view.value())?;
            let voff = sparse.values.byte_offset.0;
            let vals = elements(vbytes, voff, elem, elem, k)
                .ok_or_else(|| format!("accessor {index}: sparse values overrun their buffer view"))?;
            for (i, v) in idx.iter().zip(vals) {
                let target = raw_u32(ict, i) as usize;
                let slot = dense
                    .get_mut(target)
                    .ok_or_else(|| format!("accessor {index}: sparse index {target} >= count {count}"))?;
                *slot = v;
            }
        }
        for bytes in dense {
            f(bytes);
        }
        Ok(())
    }
}

/// Slices `count` elements of `elem` bytes, `stride` apart, from `offset` in
/// `bytes`; `None` if any falls outside.
fn elements(bytes: &[u8], offset: u64, stride: usize, elem: usize, count: u64) -> Option<Vec<&[u8]>> {
    if count == 0 {
        return Some(Vec::new());
    }
    let offset = usize::try_from(offset).ok()?;
    let count = usize::try_from(count).ok()?;
    let last_end = (count - 1).checked_mul(stride)?.checked_add(offset)?.checked_add(elem)?;
    if last_end > bytes.len() {
        return None;
    }
    Some((0..count).map(|i| &bytes[offset + i * stride..][..elem]).collect())
}

fn types(a: &json::Accessor, index: usize) -> Result<(Type, ComponentType), String> {
    match (&a.type_, &a.component_type) {
        (Checked::Valid(t), Checked::Valid(c)) => Ok((*t, c.0)),
        _ => Err(format!("accessor {index} has an invalid type")),
    }
}

fn dims(t: Type) -> usize {
    match t {
        Type::Scalar => 1,
        Type::Vec2 => 2,
        Type::Vec3 => 3,
        Type::Vec4 | Type::Mat2 => 4,
        Type::Mat3 => 9,
        Type::Mat4 => 16,
    }
}

fn component_size(c: ComponentType) -> usize {
    match c {
        ComponentType::I8 | ComponentType::U8 => 1,
        ComponentType::I16 | ComponentType::U16 => 2,
        ComponentType::U32 | ComponentType::F32 => 4,
    }
}

fn raw_u32(c: ComponentType, b: &[u8]) -> u32 {
    match c {
        ComponentType::U8 | ComponentType::I8 => u32::from(b[0]),
        ComponentType::U16 | ComponentType::I16 => u32::from(u16::from_le_bytes([b[0], b[1]])),
        ComponentType::U32 | ComponentType::F32 => u32::from_le_bytes([b[0], b[1], b[2], b[3]]),
    }
}

/// One component as `f32`, with glTF's normalisation rules (signed values clamp
/// at -1).
fn component(c: ComponentType, b: &[u8], normalized: bool) -> f32 {
    match c {
        ComponentType::F32 => f32::from_le_bytes([b[0], b[1], b[2], b[3]]),
        ComponentType::U8 if normalized => f32::from(b[0]) / 255.0,
        ComponentType::U8 => f32::from(b[0]),
        ComponentType::I8 if normalized => (f32::from(b[0] as i8) / 127.0).max(-1.0),
        ComponentType::I8 => f32::from(b[0] as i8),
        ComponentType::U16 if normalized => f32::from(u16::from_le_bytes([b[0], b[1]])) / 65535.0,
        ComponentType::U16 => f32::from(u16::from_le_bytes([b[0], b[1]])),
        ComponentType::I16 if normalized => (f32::from(i16::from_le_bytes([b[0], b[1]])) / 32767.0).max(-1.0),
        ComponentType::I16 => f32::from(i16::from_le_bytes([b[0], b[1]])),
        ComponentType::U32 if normalized => u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f32 / u32::MAX as f32,
        ComponentType::U32 => u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f32,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// One buffer: 3 VEC3 floats (36 bytes), then sparse indices (u16) and values.
    fn root(accessors: &str) -> json::Root {
        json::Root::from_str(&format!(
            r#"{{"asset": {{"version": "2.0"}},
                "buffers": [{{"byteLength": 64}}],
                "bufferViews": [{{"buffer": 0, "byteLength": 36}},
                                {{"buffer": 0, "byteOffset": 36, "byteLength": 4}},
                                {{"buffer": 0, "byteOffset": 40, "byteLength": 12}},
                                {{"buffer": 0, "byteOffset": 52, "byteLength": 12}}],
                "accessors": [{accessors}]}}"#
        ))
        .unwrap()
    }

    fn buffer() -> Vec<u8> {
        let mut b: Vec<u8> = (0..9).flat_map(|i| (i as f32).to_le_bytes()).collect();
        b.extend(1u16.to_le_bytes()); // sparse index: element 1
        b.extend(7u16.to_le_bytes()); // an index past the end, for the error case
        b.extend([9.0f32, 9.0, 9.0].iter().flat_map(|f| f.to_le_bytes()));
        b.extend([0u8, 128, 255, 0, 2, 0, 1, 0, 0, 0, 0, 0]); // u8 pairs, then u16 indices
        b
    }

    const SPARSE: &str = r#""sparse": {"count": 1, "indices": {"bufferView": 1, "componentType": 5123},
                                          "values": {"bufferView": 2}}"#;

    #[test]
    fn sparse_values_replace_elements() {
        let r = root(&format!(
            r#"{{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", {SPARSE}}},
               {{"componentType": 5126, "count": 2, "type": "VEC3", {SPARSE}}}"#
        ));
        let buffers = [buffer()];
        let d = Data { root: &r, buffers: &buffers };
        let dense = d.floats(0, Type::Vec3).unwrap();
        assert_eq!(dense, [0.0, 1.0, 2.0, 9.0, 9.0, 9.0, 6.0, 7.0, 8.0]);
        let implicit = d.floats(1, Type::Vec3).unwrap();
        assert_eq!(implicit, [0.0, 0.0, 0.0, 9.0, 9.0, 9.0]);
        assert!(d.floats(0, Type::Vec2).is_err(), "type mismatch is an error");
    }

    #[test]
    fn sparse_index_past_count_is_an_error() {
        let sparse = SPARSE.replace(r#""bufferView": 1, "#, r#""bufferView": 1, "byteOffset": 2, "#);
        let r = root(&format!(r#"{{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", {sparse}}}"#));
        let buffers = [buffer()];
        let d = Data { root: &r, buffers: &buffers };
        let e = d.floats(0, Type::Vec3).unwrap_err();
        assert!(e.contains("sparse index 7"), "{e}");
    }

    #[test]
    fn normalized_bytes_and_short_indices() {
        let r = root(
            r#"{"bufferView": 3, "componentType": 5121, "normalized": true, "count": 2, "type": "VEC2"},
               {"bufferView": 3, "byteOffset": 4, "componentType": 5123, "count": 4, "type": "SCALAR"},
               {"bufferView": 3, "componentType": 5126, "count": 4, "type": "SCALAR"}"#,
        );
        let buffers = [buffer()];
        let d = Data { root: &r, buffers: &buffers };
        let uv = d.floats(0, Type::Vec2).unwrap();
        assert_eq!(uv, [0.0, 128.0 / 255.0, 1.0, 0.0]);
        assert_eq!(d.indices(1).unwrap(), [2, 1, 0, 0]);
        assert!(d.indices(2).is_err(), "float indices are refused");
        assert!(d.indices(9).is_err(), "a missing accessor is an error");
    }
}
