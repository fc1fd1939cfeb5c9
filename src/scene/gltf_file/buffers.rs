//! The bytes of a glTF file's buffers: the GLB binary chunk, `data:` URIs
//! (base64) and files beside the glTF. Read by glint rather than the
//! `gltf` crate's importer, so each problem names the buffer and the file.

use std::path::{Path, PathBuf};

use base64::Engine as _;

/// Every buffer's bytes, indexed like `buffers` in the file, and the
/// external files read (for hot reload to watch).
pub(crate) struct Buffers {
    pub data: Vec<Vec<u8>>,
    pub files: Vec<PathBuf>,
}

/// Reads the buffers of `doc`; `blob` is the GLB binary chunk, `dir` the
/// folder relative URIs start from.
pub(crate) fn read(doc: &gltf::Document, blob: Option<Vec<u8>>, dir: &Path) -> Result<Buffers, String> {
    let mut blob = blob;
    let mut out = Buffers { data: Vec::new(), files: Vec::new() };
    for buffer in doc.buffers() {
        let at = format!("buffers[{}]", buffer.index());
        let bytes = match buffer.source() {
            gltf::buffer::Source::Bin => blob
                .take()
                .ok_or_else(|| format!("{at}: has no `uri`, and the file has no GLB binary chunk to take its bytes from (only a .glb file's first buffer may leave out `uri`)"))?,
            gltf::buffer::Source::Uri(uri) => match data_uri(uri) {
                Some(decoded) => decoded.map_err(|e| format!("{at}.uri: a data URI that is not valid base64: {e}"))?,
                None => {
                    let file = local_file(uri, dir).map_err(|e| format!("{at}.uri: {e}"))?;
                    let bytes = std::fs::read(&file).map_err(|e| format!("{at}.uri: cannot read \"{uri}\" (looked for {}): {e}", file.display()))?;
                    out.files.push(file);
                    bytes
                }
            },
        };
        if bytes.len() < buffer.length() {
            return Err(format!("{at}: holds {} bytes, but its byteLength says {}", bytes.len(), buffer.length()));
        }
        out.data.push(bytes);
    }
    Ok(out)
}

/// The decoded bytes of a `data:` URI, or None for any other URI.
pub(crate) fn data_uri(uri: &str) -> Option<Result<Vec<u8>, String>> {
    let rest = uri.strip_prefix("data:")?;
    let Some((header, payload)) = rest.split_once(',') else {
        return Some(Err("no ',' before the data".into()));
    };
    if !header.ends_with(";base64") {
        return Some(Err(format!("glint reads base64 data URIs; this one is \"data:{header},...\"")));
    }
    Some(base64::engine::general_purpose::STANDARD.decode(payload.trim()).map_err(|e| e.to_string()))
}

/// The file a relative URI names: percent-decoded, below `dir`. URIs with a
/// scheme (http:, file:) are refused: glint reads files beside the glTF.
pub(crate) fn local_file(uri: &str, dir: &Path) -> Result<PathBuf, String> {
    let scheme = uri.split_once(':').map(|(s, _)| s).filter(|s| s.len() > 1 && s.chars().all(|c| c.is_ascii_alphanumeric() || "+-.".contains(c)));
    if let Some(scheme) = scheme {
        return Err(format!("\"{uri}\" is a `{scheme}:` URI; glint reads files given by a relative path beside the glTF file"));
    }
    let decoded = percent_decode(uri).ok_or_else(|| format!("\"{uri}\" is not a valid percent-encoded path"))?;
    Ok(dir.join(decoded))
}

/// `%20` -> ' ' and so on; None for a bad escape or bytes that are not UTF-8.
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
    use super::*;

    #[test]
    fn data_uris_decode_and_bad_ones_say_why() {
        assert_eq!(data_uri("data:application/octet-stream;base64,AAEC"), Some(Ok(vec![0, 1, 2])));
        assert!(data_uri("file.bin").is_none());
        assert!(matches!(data_uri("data:application/octet-stream;base64,A!!"), Some(Err(_))));
        let Some(Err(e)) = data_uri("data:text/plain,abc") else { panic!("a non-base64 URI was read") };
        assert!(e.contains("base64"), "{e}");
    }

    #[test]
    fn relative_uris_are_percent_decoded_and_schemes_refused() {
        let dir = Path::new("assets");
        assert_eq!(local_file("my%20mesh.bin", dir), Ok(PathBuf::from("assets/my mesh.bin")));
        assert_eq!(local_file("sub/m.bin", dir), Ok(PathBuf::from("assets/sub/m.bin")));
        assert!(local_file("https://example.com/m.bin", dir).unwrap_err().contains("`https:`"));
        assert!(local_file("bad%2", dir).is_err());
        assert!(local_file("bad%zz", dir).is_err());
    }
}
