//! What hairlab checks before it hands a glTF file to the `gltf` crate, so that the crate never over-allocates or
//! panics on our input: the file is read bounded (`io::read_regular_file`); a `.glb`'s header
//! and chunk lengths must agree with the file's size; buffer URIs are data URIs or relative paths to regular files
//! inside the file's folder; and every buffer view and accessor a primitive reads lies inside its buffer, with a
//! stride no smaller than its element and the component types the loader reads. Each failure is one
//! [`GltfCheckError`] saying what is wrong and where (the loader prefixes the file).

use std::path::{Component, Path};

use gltf::accessor::{DataType, Dimensions};
use gltf::buffer::Source;
use gltf::mesh::Semantic;

/// What a check found wrong in a glTF file, and where in it.
#[derive(Debug, thiserror::Error, PartialEq, Eq)]
pub enum GltfCheckError {
    /// A `.glb`'s 12-byte header.
    #[error("glb header: {0}")]
    GlbHeader(String),
    /// A `.glb` chunk's header or length.
    #[error("glb chunk {chunk} at byte {at}: {problem}")]
    GlbChunk {
        chunk: usize,
        at: usize,
        problem: String,
    },
    /// The `.glb`'s chunk sequence.
    #[error("glb: {0}")]
    Glb(&'static str),
    /// A buffer's URI.
    #[error("buffer {buffer} ('{uri}'): {problem}")]
    BufferUri {
        buffer: usize,
        uri: String,
        problem: String,
    },
    /// An accessor a primitive reads (`at` names the mesh, primitive, attribute and accessor).
    #[error("{at}: {problem}")]
    Accessor { at: String, problem: String },
    /// An index that names nothing.
    #[error("{what} names {of} {index}, and there are {len}")]
    MissingIndex {
        what: String,
        of: &'static str,
        index: usize,
        len: usize,
    },
}

const GLB_MAGIC: &[u8; 4] = b"glTF";
const CHUNK_JSON: u32 = 0x4E4F_534A;
const CHUNK_BIN: u32 = 0x004E_4942;

fn u32_at(bytes: &[u8], at: usize) -> Option<u32> {
    bytes
        .get(at..at + 4)
        .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
}

/// Checks a binary glTF's 12-byte header and its chunks against the file's `bytes` (a text glTF passes).
pub fn check_glb(bytes: &[u8]) -> Result<(), GltfCheckError> {
    if bytes.get(..4) != Some(GLB_MAGIC) {
        return Ok(());
    }
    let (Some(version), Some(length)) = (u32_at(bytes, 4), u32_at(bytes, 8)) else {
        return Err(GltfCheckError::GlbHeader(format!(
            "{} bytes, 12 needed",
            bytes.len()
        )));
    };
    if version != 2 {
        return Err(GltfCheckError::GlbHeader(format!(
            "version {version}, only 2 is supported"
        )));
    }
    if length as usize != bytes.len() {
        return Err(GltfCheckError::GlbHeader(format!(
            "declares {length} bytes, the file holds {}",
            bytes.len()
        )));
    }
    let mut at = 12;
    let mut chunk = 0;
    while at < bytes.len() {
        let (Some(len), Some(kind)) = (u32_at(bytes, at), u32_at(bytes, at + 4)) else {
            return Err(GltfCheckError::GlbChunk {
                chunk,
                at,
                problem: "its 8-byte header is cut off".to_owned(),
            });
        };
        let end = (at + 8).checked_add(len as usize).filter(|&e| e <= bytes.len());
        let Some(end) = end else {
            return Err(GltfCheckError::GlbChunk {
                chunk,
                at,
                problem: format!("declares {len} bytes, {} remain", bytes.len() - at - 8),
            });
        };
        match (chunk, kind) {
            (0, CHUNK_JSON) | (1, CHUNK_BIN) => {}
            (0, _) => return Err(GltfCheckError::Glb("the first chunk is not JSON")),
            (1, _) => {}
            _ => {}
        }
        at = end;
        chunk += 1;
    }
    if chunk == 0 {
        return Err(GltfCheckError::Glb("no JSON chunk"));
    }
    Ok(())
}

/// Checks every buffer's URI: a data URI, or a relative path without `..` naming a regular file of at most
/// `io::MAX_INPUT_BYTES` inside `dir`.
pub fn check_buffer_uris(document: &gltf::Document, dir: &Path) -> Result<(), GltfCheckError> {
    for buffer in document.buffers() {
        let Source::Uri(uri) = buffer.source() else {
            continue;
        };
        if uri.starts_with("data:") {
            continue;
        }
        let problem = |problem: String| GltfCheckError::BufferUri {
            buffer: buffer.index(),
            uri: uri.to_owned(),
            problem,
        };
        if uri.contains("://") || uri.starts_with('/') || uri.starts_with('\\') {
            return Err(problem("only relative buffer paths are read".to_owned()));
        }
        let rel = Path::new(uri);
        if rel
            .components()
            .any(|c| !matches!(c, Component::Normal(_) | Component::CurDir))
        {
            return Err(problem("leaves the file's folder".to_owned()));
        }
        let path = dir.join(rel);
        let meta = std::fs::metadata(&path).map_err(|e| problem(format!("cannot read: {e}")))?;
        if !meta.is_file() {
            return Err(problem("not a regular file".to_owned()));
        }
        if meta.len() > crate::io::MAX_INPUT_BYTES {
            return Err(problem(format!(
                "{} bytes, more than the {} bytes hairlab reads",
                meta.len(),
                crate::io::MAX_INPUT_BYTES
            )));
        }
    }
    Ok(())
}

/// Bytes of one component of `t`.
fn component_bytes(t: DataType) -> usize {
    match t {
        DataType::I8 | DataType::U8 => 1,
        DataType::I16 | DataType::U16 => 2,
        DataType::U32 | DataType::F32 => 4,
    }
}

/// Checks every accessor a primitive reads against the loaded `buffers`: the buffer view inside its buffer, the
/// accessor inside its view (offset, stride and count), no sparse storage, and the types the loader reads
/// (positions and normals: float VEC3; colours: VEC3/VEC4 of float or normalised unsigned bytes/shorts; indices:
/// unsigned scalars).
pub fn check_accessors(
    document: &gltf::Document,
    buffers: &[gltf::buffer::Data],
) -> Result<(), GltfCheckError> {
    for mesh in document.meshes() {
        for prim in mesh.primitives() {
            let where_ = format!("mesh {} primitive {}", mesh.index(), prim.index());
            let mut read: Vec<(String, gltf::Accessor)> = prim
                .attributes()
                .filter(|(s, _)| matches!(s, Semantic::Positions | Semantic::Normals | Semantic::Colors(0)))
                .map(|(s, a)| (format!("{s:?}"), a))
                .collect();
            if let Some(a) = prim.indices() {
                read.push(("indices".to_owned(), a));
            }
            for (what, a) in read {
                let ok = match what.as_str() {
                    "Positions" | "Normals" => {
                        a.dimensions() == Dimensions::Vec3 && a.data_type() == DataType::F32
                    }
                    "indices" => {
                        a.dimensions() == Dimensions::Scalar
                            && matches!(a.data_type(), DataType::U8 | DataType::U16 | DataType::U32)
                    }
                    _ => {
                        matches!(a.dimensions(), Dimensions::Vec3 | Dimensions::Vec4)
                            && (a.data_type() == DataType::F32
                                || (a.normalized() && matches!(a.data_type(), DataType::U8 | DataType::U16)))
                    }
                };
                let at = format!("{where_}: {what} (accessor {})", a.index());
                if !ok {
                    return Err(GltfCheckError::Accessor {
                        at,
                        problem: format!(
                            "{:?} {:?} is not a type this attribute can have",
                            a.dimensions(),
                            a.data_type()
                        ),
                    });
                }
                check_accessor(&a, buffers, &at)?;
            }
        }
    }
    Ok(())
}

/// Checks, on the raw JSON before the crate validates it, that every index the loader follows names something
/// that exists (the crate's validation and wrappers index without checking): primitive attributes, indices and materials, accessor buffer views, view
/// buffers, node meshes and children, scene nodes.
pub fn check_indices(document: &gltf::Document) -> Result<(), GltfCheckError> {
    let j = document.as_json();
    let check = |what: String, index: usize, len: usize, of: &'static str| {
        if index < len {
            Ok(())
        } else {
            Err(GltfCheckError::MissingIndex { what, of, index, len })
        }
    };
    for (m, mesh) in j.meshes.iter().enumerate() {
        for (p, prim) in mesh.primitives.iter().enumerate() {
            let at = format!("mesh {m} primitive {p}");
            for a in prim.attributes.values() {
                check(
                    format!("{at}: an attribute"),
                    a.value(),
                    j.accessors.len(),
                    "accessor",
                )?;
            }
            if let Some(i) = &prim.indices {
                check(
                    format!("{at}: its indices"),
                    i.value(),
                    j.accessors.len(),
                    "accessor",
                )?;
            }
            if let Some(i) = &prim.material {
                check(
                    format!("{at}: its material"),
                    i.value(),
                    j.materials.len(),
                    "material",
                )?;
            }
        }
    }
    for (a, accessor) in j.accessors.iter().enumerate() {
        if let Some(v) = &accessor.buffer_view {
            check(
                format!("accessor {a}"),
                v.value(),
                j.buffer_views.len(),
                "buffer view",
            )?;
        }
    }
    for (v, view) in j.buffer_views.iter().enumerate() {
        check(
            format!("buffer view {v}"),
            view.buffer.value(),
            j.buffers.len(),
            "buffer",
        )?;
    }
    for (n, node) in j.nodes.iter().enumerate() {
        if let Some(m) = &node.mesh {
            check(format!("node {n}"), m.value(), j.meshes.len(), "mesh")?;
        }
        for c in node.children.iter().flatten() {
            check(format!("node {n}: a child"), c.value(), j.nodes.len(), "node")?;
        }
    }
    if let Some(s) = &j.scene {
        check("the default scene".to_owned(), s.value(), j.scenes.len(), "scene")?;
    }
    for (s, scene) in j.scenes.iter().enumerate() {
        for n in &scene.nodes {
            check(format!("scene {s}"), n.value(), j.nodes.len(), "node")?;
        }
    }
    Ok(())
}

/// Checks accessor `a` against `buffers`; an error names it as `at`.
fn check_accessor(
    a: &gltf::Accessor,
    buffers: &[gltf::buffer::Data],
    at: &str,
) -> Result<(), GltfCheckError> {
    let problem = |problem: String| GltfCheckError::Accessor {
        at: at.to_owned(),
        problem,
    };
    if a.sparse().is_some() {
        return Err(problem("sparse accessors are not supported".to_owned()));
    }
    let Some(view) = a.view() else {
        return Err(problem("has no buffer view".to_owned()));
    };
    let buffer = buffers
        .get(view.buffer().index())
        .ok_or_else(|| problem(format!("buffer view {} names a missing buffer", view.index())))?;
    let view_end = view.offset().checked_add(view.length());
    if view_end.is_none_or(|end| end > buffer.len()) {
        return Err(problem(format!(
            "buffer view {} (bytes {}..+{}) lies outside its buffer of {} bytes",
            view.index(),
            view.offset(),
            view.length(),
            buffer.len()
        )));
    }
    let element = component_bytes(a.data_type()) * a.dimensions().multiplicity();
    let stride = view.stride().unwrap_or(element);
    if stride < element {
        return Err(problem(format!(
            "byteStride {stride} is smaller than its {element}-byte element"
        )));
    }
    if a.count() == 0 {
        return Err(problem("has count 0 (glTF requires at least 1)".to_owned()));
    }
    let end = (a.count() - 1)
        .checked_mul(stride)
        .and_then(|s| s.checked_add(a.offset()))
        .and_then(|s| s.checked_add(element));
    if end.is_none_or(|end| end > view.length()) {
        return Err(problem(format!(
            "{} elements of {element} bytes every {stride} from byte {} do not fit its buffer view of {} bytes",
            a.count(),
            a.offset(),
            view.length()
        )));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn glb(length: u32, chunks: &[(u32, u32, usize)]) -> Vec<u8> {
        let mut b = Vec::new();
        b.extend_from_slice(GLB_MAGIC);
        b.extend_from_slice(&2u32.to_le_bytes());
        b.extend_from_slice(&length.to_le_bytes());
        for &(len, kind, actual) in chunks {
            b.extend_from_slice(&len.to_le_bytes());
            b.extend_from_slice(&kind.to_le_bytes());
            b.extend(std::iter::repeat_n(b' ', actual));
        }
        b
    }

    #[test]
    fn glb_headers_must_agree_with_the_file() {
        let ok = glb(12 + 8 + 4, &[(4, CHUNK_JSON, 4)]);
        check_glb(&ok).unwrap();
        check_glb(b"{\"asset\":{}}").unwrap();
        let e = check_glb(&glb(4_294_967_284, &[(4, CHUNK_JSON, 4)])).unwrap_err();
        assert_eq!(
            e.to_string(),
            "glb header: declares 4294967284 bytes, the file holds 24"
        );
        let e = check_glb(&glb(11, &[])).unwrap_err();
        assert_eq!(e.to_string(), "glb header: declares 11 bytes, the file holds 12");
        let e = check_glb(&glb(12 + 8 + 4, &[(4_000_000, CHUNK_JSON, 4)])).unwrap_err();
        assert_eq!(
            e.to_string(),
            "glb chunk 0 at byte 12: declares 4000000 bytes, 4 remain"
        );
        let e = check_glb(&glb(12 + 8 + 4, &[(4, CHUNK_BIN, 4)])).unwrap_err();
        assert_eq!(e.to_string(), "glb: the first chunk is not JSON");
        let e = check_glb(&glb(12, &[])).unwrap_err();
        assert_eq!(e.to_string(), "glb: no JSON chunk");
        let mut cut = glb(12 + 8 + 4 + 3, &[(4, CHUNK_JSON, 4)]);
        cut.extend_from_slice(&[1, 2, 3]);
        let e = check_glb(&cut).unwrap_err();
        assert_eq!(
            e.to_string(),
            "glb chunk 1 at byte 24: its 8-byte header is cut off"
        );
        let mut v1 = ok.clone();
        v1[4] = 1;
        assert_eq!(
            check_glb(&v1).unwrap_err().to_string(),
            "glb header: version 1, only 2 is supported"
        );
        assert!(
            check_glb(&ok[..7])
                .unwrap_err()
                .to_string()
                .starts_with("glb header: 7 bytes")
        );
    }
}
