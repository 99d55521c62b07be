//! Buffer and image sources: the GLB `BIN` chunk, `data:` URIs and files beside the
//! scene.
//!
//! Done here rather than with `gltf::import_buffers` because that path panics on a
//! percent-encoded URI that is not UTF-8 and its errors do not say which file was
//! missing; a user moving a `.gltf` without its `.bin` deserves the file name.

use std::path::{Path, PathBuf};

use gltf::json;

/// Where a source's bytes could not be had.
pub(crate) enum SourceError {
    /// An external file (named) could not be read.
    Io(PathBuf, std::io::Error),
    /// Anything else (bad data URI, unsupported scheme, ...).
    Other(String),
}

/// Loads every buffer of the document. `blob` is the GLB `BIN` chunk.
pub(crate) fn load_buffers(
    root: &json::Root,
    mut blob: Option<Vec<u8>>,
    base: &Path,
) -> Result<Vec<Vec<u8>>, (usize, SourceError)> {
    let mut out = Vec::with_capacity(root.buffers.len());
    for (i, buffer) in root.buffers.iter().enumerate() {
        let data = match &buffer.uri {
            Some(uri) => read_uri(uri, base).map_err(|e| (i, e))?,
            None => blob
                .take()
                .ok_or_else(|| (i, SourceError::Other("has no uri and the file has no GLB BIN chunk".into())))?,
        };
        let need = buffer.byte_length.0;
        if (data.len() as u64) < need {
            return Err((i, SourceError::Other(format!("declares {need} bytes but has only {}", data.len()))));
        }
        out.push(data);
    }
    Ok(out)
}

/// Reads a `data:` URI or a file relative to `base`.
pub(crate) fn read_uri(uri: &str, base: &Path) -> Result<Vec<u8>, SourceError> {
    if let Some(rest) = uri.strip_prefix("data:") {
        let payload = rest
            .split_once(";base64,")
            .map(|(_, p)| p)
            .ok_or_else(|| SourceError::Other("data URI is not base64".into()))?;
        return base64(payload).ok_or_else(|| SourceError::Other("invalid base64 in data URI".into()));
    }
    let relative = if let Some(rest) = uri.strip_prefix("file://").or_else(|| uri.strip_prefix("file:")) {
        rest
    } else if uri.contains(':') {
        return Err(SourceError::Other(format!("unsupported URI scheme in '{uri}'")));
    } else {
        uri
    };
    let decoded = percent_decode(relative)
        .ok_or_else(|| SourceError::Other(format!("invalid percent-encoding in URI '{uri}'")))?;
    let file = base.join(decoded);
    read_regular(&file).map_err(|e| SourceError::Io(file, e))
}

/// Reads a regular file, at most the size it had when opened. A URI may name a
/// device (`/dev/zero` reads until memory runs out) or a FIFO (opening it blocks),
/// so anything else is refused before it is opened.
fn read_regular(path: &Path) -> std::io::Result<Vec<u8>> {
    use std::io::Read;
    if !std::fs::metadata(path)?.is_file() {
        return Err(std::io::Error::new(std::io::ErrorKind::InvalidInput, "not a regular file"));
    }
    let file = std::fs::File::open(path)?;
    let len = file.metadata()?.len();
    let mut out = Vec::new();
    file.take(len).read_to_end(&mut out)?;
    Ok(out)
}

impl std::fmt::Display for SourceError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            SourceError::Io(path, e) => write!(f, "cannot read {}: {e}", path.display()),
            SourceError::Other(m) => f.write_str(m),
        }
    }
}

/// Standard base64 (RFC 4648 alphabet, `=` padding optional).
fn base64(s: &str) -> Option<Vec<u8>> {
    base64::decode(s).ok()
}

/// RFC 3986 percent-decoding to a UTF-8 path; `None` for malformed escapes or bytes
/// that are not UTF-8.
fn percent_decode(s: &str) -> Option<String> {
    let b = s.as_bytes();
    let mut out = Vec::with_capacity(b.len());
    let mut i = 0;
    while i < b.len() {
        if b[i] == b'%' {
            let hex = std::str::from_utf8(b.get(i + 1..i + 3)?).ok()?;
            out.push(u8::from_str_radix(hex, 16).ok()?);
            i += 3;
        } else {
            out.push(b[i]);
            i += 1;
        }
    }
    String::from_utf8(out).ok()
}

#[cfg(test)]
mod tests {
    #[test]
    fn base64_round_trips_known_vectors() {
        assert_eq!(super::base64("").unwrap(), b"");
        assert_eq!(super::base64("Zg==").unwrap(), b"f");
        assert_eq!(super::base64("Zg").unwrap(), b"f");
        assert_eq!(super::base64("Zm8=").unwrap(), b"fo");
        assert_eq!(super::base64("Zm9v").unwrap(), b"foo");
        assert_eq!(super::base64("Zm9vYmFy").unwrap(), b"foobar");
        assert!(super::base64("Z").is_none());
        assert!(super::base64("Zm9*").is_none());
    }

    #[test]
    fn percent_decoding_rejects_non_utf8() {
        assert_eq!(super::percent_decode("a%20b.bin").unwrap(), "a b.bin");
        assert!(super::percent_decode("%FF").is_none());
        assert!(super::percent_decode("%4").is_none());
    }
}
