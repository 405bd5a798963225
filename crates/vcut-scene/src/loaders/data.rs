//! The bytes a glTF names: its buffers and its images, from the GLB blob, a buffer view, base64
//! `data:` URIs or files beside it. Our own rather than gltf's importers, which unwrap on URIs that
//! percent-decode to invalid UTF-8 (found by the fuzzer).

use std::path::Path;

/// Loads every buffer: the GLB blob, `data:` URIs (base64) or files relative to `base`.
pub(super) fn import_buffers(
    doc: &gltf::Document,
    base: Option<&Path>,
    mut blob: Option<Vec<u8>>,
) -> Result<Vec<Vec<u8>>, String> {
    let mut out = Vec::new();
    for buffer in doc.buffers() {
        let what = format!("buffer {}", buffer.index());
        let mut data = match buffer.source() {
            gltf::buffer::Source::Bin => {
                blob.take().ok_or_else(|| format!("{what} refers to a missing GLB BIN chunk"))?
            }
            gltf::buffer::Source::Uri(uri) => uri_bytes(uri, base, &what)?,
        };
        if data.len() < buffer.length() {
            return Err(format!("{what} declares {} bytes but holds {}", buffer.length(), data.len()));
        }
        while data.len() % 4 != 0 {
            data.push(0);
        }
        out.push(data);
    }
    Ok(out)
}

/// The encoded bytes of `image`: a buffer view, a base64 data URI or a file relative to `base`.
pub(super) fn image_bytes(
    image: &gltf::Image<'_>,
    buffers: &[Vec<u8>],
    base: Option<&Path>,
) -> Result<Vec<u8>, String> {
    let what = format!("image {}", image.index());
    match image.source() {
        gltf::image::Source::View { view, .. } => {
            let buffer = buffers.get(view.buffer().index()).map(Vec::as_slice).unwrap_or_default();
            let range = view.offset()..view.offset().saturating_add(view.length());
            Ok(buffer.get(range).ok_or_else(|| format!("{what}: its view runs past its buffer"))?.to_vec())
        }
        gltf::image::Source::Uri { uri, .. } => uri_bytes(uri, base, &what),
    }
}

/// A base64 `data:` URI decoded, or a file relative to `base` read (`None`: refused).
fn uri_bytes(uri: &str, base: Option<&Path>, what: &str) -> Result<Vec<u8>, String> {
    use base64::Engine as _;
    if uri.starts_with("data:") {
        let (_, payload) =
            uri.split_once(";base64,").ok_or_else(|| format!("{what}: only base64 data URIs are supported"))?;
        return base64::engine::general_purpose::STANDARD
            .decode(payload)
            .map_err(|e| format!("{what}: bad base64 data: {e}"));
    }
    let base = base.ok_or_else(|| format!("{what} refers to external file '{uri}'"))?;
    let rel = percent_decode(uri).ok_or_else(|| format!("{what}: malformed URI '{uri}'"))?;
    let path = base.join(&rel);
    std::fs::read(&path).map_err(|e| format!("{what}: cannot read {}: {e}", path.display()))
}

/// `%XX` decoding of a relative URI; `None` for bad escapes or invalid UTF-8.
fn percent_decode(uri: &str) -> Option<String> {
    let b = uri.as_bytes();
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
