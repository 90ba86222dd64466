//! Resolving the URIs of buffers and images: base64 `data:` URIs, or relative paths
//! that must stay inside the scene file's folder. Any other scheme, absolute paths
//! and `..` that climbs out of the folder are refused, so a scene file cannot make
//! the importer read arbitrary files.

use super::limits::ImportLimits;
use std::path::{Path, PathBuf};

/// Where a URI points.
#[derive(Debug)]
pub(super) enum Resolved {
    /// The decoded bytes of a `data:` URI.
    Data(Vec<u8>),
    /// A file inside the scene's folder.
    File(PathBuf),
}

/// Resolves `uri` relative to `folder` (the folder of the scene file). The error
/// says why the URI is refused.
pub(super) fn resolve(uri: &str, folder: &Path, limits: &ImportLimits) -> Result<Resolved, String> {
    if uri
        .get(..5)
        .is_some_and(|p| p.eq_ignore_ascii_case("data:"))
    {
        return decode_data_uri(uri, limits).map(Resolved::Data);
    }
    let first_segment = uri.split(['/', '\\']).next().unwrap_or("");
    if let Some(colon) = first_segment.find(':') {
        return Err(format!(
            "URI scheme '{}' is not allowed (only relative paths and data: URIs)",
            &first_segment[..colon]
        ));
    }
    let decoded = percent_decode(uri)?;
    if decoded.starts_with('/') || decoded.starts_with('\\') {
        return Err(format!(
            "'{decoded}' is an absolute path (only relative paths are allowed)"
        ));
    }
    let mut parts: Vec<&str> = Vec::new();
    for part in decoded.split(['/', '\\']) {
        match part {
            "" | "." => {}
            ".." => {
                if parts.pop().is_none() {
                    return Err(format!("'{decoded}' leads out of the scene file's folder"));
                }
            }
            p => parts.push(p),
        }
    }
    if parts.is_empty() {
        return Err(format!("'{decoded}' does not name a file"));
    }
    let mut target = folder.to_path_buf();
    target.extend(&parts);
    // A symbolic link inside the folder could still point outside it. A
    // scene named without a folder has the folder "", which names no file
    // to canonicalise: the current folder is meant.
    let here = if folder.as_os_str().is_empty() {
        Path::new(".")
    } else {
        folder
    };
    if let (Ok(real_folder), Ok(real_target)) = (here.canonicalize(), target.canonicalize()) {
        if !real_target.starts_with(&real_folder) {
            return Err(format!(
                "'{decoded}' leads out of the scene file's folder (through a symbolic link)"
            ));
        }
    }
    Ok(Resolved::File(target))
}

/// Decodes `data:[<media type>];base64,<data>`.
fn decode_data_uri(uri: &str, limits: &ImportLimits) -> Result<Vec<u8>, String> {
    let Some(comma) = uri.find(',') else {
        return Err("data: URI without a ',' before its data".to_string());
    };
    let header = &uri[5..comma];
    if !header.to_ascii_lowercase().ends_with(";base64") {
        return Err(
            "data: URI is not base64-encoded (only base64 data URIs are supported)".to_string(),
        );
    }
    let payload = uri[comma + 1..].trim_end();
    let decoded_len = (payload.len() as u64 / 4) * 3;
    if decoded_len > limits.max_file_bytes {
        return Err(format!(
            "data: URI holds about {decoded_len} bytes, more than the limit of {}",
            limits.max_file_bytes
        ));
    }
    base64::decode(payload).map_err(|e| format!("data: URI is not valid base64: {e}"))
}

/// Undoes `%XX` escapes; the result must be UTF-8.
fn percent_decode(uri: &str) -> Result<String, String> {
    let bytes = uri.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] == b'%' {
            let hex = bytes
                .get(i + 1..i + 3)
                .and_then(|h| std::str::from_utf8(h).ok())
                .and_then(|h| u8::from_str_radix(h, 16).ok())
                .ok_or_else(|| format!("'{uri}' has a malformed %-escape"))?;
            out.push(hex);
            i += 3;
        } else {
            out.push(bytes[i]);
            i += 1;
        }
    }
    String::from_utf8(out).map_err(|_| format!("'{uri}' is not UTF-8 after %-decoding"))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn refused(uri: &str) -> String {
        resolve(uri, Path::new("scene_dir"), &ImportLimits::default()).unwrap_err()
    }

    #[test]
    fn escaping_and_foreign_uris_are_refused() {
        assert!(refused("../secret.bin").contains("out of the scene"));
        assert!(refused("a/../../secret.bin").contains("out of the scene"));
        assert!(refused("%2E%2E/secret.bin").contains("out of the scene"));
        assert!(refused("/etc/passwd").contains("absolute"));
        assert!(refused("%2Fetc/passwd").contains("absolute"));
        assert!(refused("\\\\server\\share").contains("absolute"));
        assert!(refused("file:///etc/passwd").contains("scheme 'file'"));
        assert!(refused("https://example.com/a.bin").contains("scheme 'https'"));
        assert!(refused("C:\\x.bin").contains("scheme 'C'"));
        assert!(refused("data:application/octet-stream,abc").contains("base64"));
    }

    #[test]
    fn relative_paths_and_data_uris_resolve() {
        let limits = ImportLimits::default();
        match resolve("sub/../my%20mesh.bin", Path::new("d"), &limits).unwrap() {
            Resolved::File(p) => assert_eq!(p, Path::new("d").join("my mesh.bin")),
            Resolved::Data(_) => panic!("not a data URI"),
        }
        match resolve(
            "data:application/octet-stream;base64,AQID",
            Path::new("d"),
            &limits,
        )
        .unwrap()
        {
            Resolved::Data(b) => assert_eq!(b, vec![1, 2, 3]),
            Resolved::File(_) => panic!("a data URI"),
        }
    }
}
