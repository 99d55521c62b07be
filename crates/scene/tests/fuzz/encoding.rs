//! Encodings: base64, data URIs and CRC-32.

/// Lenient decoding (the mutators only decode what they encoded, or corrupted): bits past the
/// last whole byte are ignored.
fn base64_decode(s: &str) -> Option<Vec<u8>> {
    base64::decode_config(s, base64::STANDARD.decode_allow_trailing_bits(true)).ok()
}

pub(crate) fn data_uri(mime: &str, data: &[u8]) -> String {
    format!("data:{mime};base64,{}", base64::encode(data))
}

/// Splits a base64 data URI into (head up to and including the comma, bytes).
pub(crate) fn split_data_uri(uri: &str) -> Option<(String, Vec<u8>)> {
    let at = uri.find(";base64,")? + ";base64,".len();
    Some((uri[..at].to_string(), base64_decode(&uri[at..])?))
}

pub(crate) fn crc32(bytes: &[u8]) -> u32 {
    crc32fast::hash(bytes)
}
