//! AMD TressFX 4 `.tfx` files (the `TressFXTFXFileHeader` of AMD's TressFX 4 `TressFXFileFormat.h`, as loaded by
//! `TressFXAsset::LoadV4`; also read by The Forge and O3DE), read and write.
//!
//! Layout, little-endian: a 160-byte header — f32 version (4.0), u32 strand count, u32 vertices per strand (the
//! same for every strand), five u32 byte offsets from the start of the file (vertex positions, strand UVs, vertex
//! UVs, strand thickness, vertex colours; 0 = absent, except positions) and 32 reserved u32 — and the arrays at
//! those offsets: f32×4 positions (one per vertex, `w` is TressFX's simulation flag: 0 pins the vertex), f32×2
//! strand UVs (one per strand), f32×2 vertex UVs, f32 strand thickness (one per strand), f32×4 RGBA vertex
//! colours.
//!
//! Mapping to hairlab (whose world is right-handed and Y-up, in the file's own units — nothing is rescaled):
//! positions `xyz` are taken as they are (TressFX runtimes are Y-up; AMD's exporters convert to it), `w` is
//! dropped; each strand's thickness becomes the thickness of its every point; vertex colour `rgb` becomes the
//! colour and `a` the alpha. The UV arrays are bounds-checked and dropped (hairlab has no texture coordinates).
//!
//! Reading checks that every array the header names lies inside the file, after the header, before allocating
//! anything, then validates the contents (finite positions and UVs, thickness finite and not negative, colours
//! finite with alpha in [0, 1]). AMD's runtime also needs 4 to 64 vertices per strand (a power of two); hairlab
//! reads any positive count. TressFX 3 files (a different header) are refused by their version.

use std::path::{Path, PathBuf};

use glam::Vec4;
use thiserror::Error;

use super::Strands;

/// Size of the fixed header.
pub const HEADER_BYTES: usize = 160;
/// The only version read: AMD's loader takes this header only when the version is exactly 4.
pub const VERSION: f32 = 4.0;

/// Everything that can go wrong reading or writing a `.tfx` file. Each message is one line.
#[derive(Debug, Error)]
pub enum TfxError {
    #[error("{path}: {cause}")]
    Io { path: PathBuf, cause: std::io::Error },
    /// A decoding or validation error in a named file.
    #[error("{path}: {cause}")]
    InFile { path: PathBuf, cause: Box<TfxError> },
    #[error("truncated header: the file holds {len} bytes, a .tfx header alone needs 160")]
    TruncatedHeader { len: usize },
    #[error("TressFX version {version}: only version 4 files are read (TressFX 3 has a different header)")]
    Version { version: f32 },
    #[error("the header says {strands} strands of 0 vertices; a strand needs at least one vertex")]
    NoVertices { strands: u32 },
    #[error("the header has no vertex positions (offset 0)")]
    NoPositions,
    #[error(
        "{array} at byte {offset} ({entries} entries, {bytes} bytes) {problem}, in a file of {len} bytes"
    )]
    OutOfFile {
        array: &'static str,
        offset: u32,
        entries: u64,
        bytes: u64,
        problem: &'static str,
        len: usize,
    },
    #[error("{what} {index} is not finite: {value}")]
    NotFinite {
        what: &'static str,
        index: usize,
        value: String,
    },
    #[error("thickness of strand {index} is {value}; it must be finite and not negative")]
    BadThickness { index: usize, value: f32 },
    #[error("alpha of vertex {index} is {value}; it must lie in [0, 1]")]
    BadAlpha { index: usize, value: f32 },
    #[error("{array} has {len} entries, expected {expected}")]
    ArrayLength {
        array: &'static str,
        len: usize,
        expected: usize,
    },
    #[error("cannot write .tfx: {0}")]
    Unwritable(String),
}

/// A `.tfx` file: the header's counts and the arrays hairlab keeps.
#[derive(Clone, Debug, PartialEq)]
pub struct TfxFile {
    pub strand_count: u32,
    pub vertices_per_strand: u32,
    /// Vertex positions; `w` is TressFX's simulation flag (0 = pinned).
    pub positions: Vec<Vec4>,
    /// One thickness per strand.
    pub strand_thickness: Option<Vec<f32>>,
    /// RGBA per vertex.
    pub vertex_color: Option<Vec<Vec4>>,
    /// Whether the file has strand UVs (checked, not kept).
    pub strand_uvs: bool,
    /// Whether the file has vertex UVs (checked, not kept).
    pub vertex_uvs: bool,
}

impl TfxFile {
    /// Converts to [`Strands`] as the module documentation maps it.
    pub fn to_strands(&self) -> Strands {
        let per = self.vertices_per_strand as usize;
        Strands {
            points: self.positions.iter().map(|p| p.truncate()).collect(),
            counts: vec![self.vertices_per_strand; self.strand_count as usize],
            thickness: self
                .strand_thickness
                .as_ref()
                .map(|t| t.iter().flat_map(|&t| std::iter::repeat_n(t, per)).collect()),
            alpha: self
                .vertex_color
                .as_ref()
                .map(|c| c.iter().map(|c| c.w).collect()),
            color: self
                .vertex_color
                .as_ref()
                .map(|c| c.iter().map(|c| c.truncate()).collect()),
        }
    }

    /// Builds a file from strands: every strand must have the same number of points (at least one), thickness
    /// must be constant along each strand, and colour and alpha come together (a `.tfx` colour is RGBA). Positions
    /// get `w` = 1 (free to simulate) except each strand's first two points, which get 0 (pinned), as AMD's
    /// loader sets them for TressFX 3 files.
    pub fn from_strands(strands: &Strands) -> Result<TfxFile, TfxError> {
        let per = strands.counts.first().copied().unwrap_or(1);
        if let Some(i) = strands.counts.iter().position(|&c| c == 0) {
            return Err(TfxError::Unwritable(format!("strand {i} has no points")));
        }
        if let Some((i, &c)) = strands.counts.iter().enumerate().find(|(_, c)| **c != per) {
            return Err(TfxError::Unwritable(format!(
                "strand {i} has {c} points and strand 0 has {per}; every .tfx strand has the same number of points"
            )));
        }
        let strand_count = u32::try_from(strands.counts.len()).map_err(|_| {
            TfxError::Unwritable(format!("{} strands do not fit a u32", strands.counts.len()))
        })?;
        let per_usize = per as usize;
        let strand_thickness = match &strands.thickness {
            None => None,
            Some(t) => Some(
                t.chunks(per_usize)
                    .enumerate()
                    .map(|(i, s)| match s.first() {
                        Some(&first) if s.iter().all(|&v| v == first) => Ok(first),
                        _ => Err(TfxError::Unwritable(format!(
                            "the thickness of strand {i} varies along it; a .tfx thickness is one per strand"
                        ))),
                    })
                    .collect::<Result<Vec<f32>, TfxError>>()?,
            ),
        };
        let vertex_color = match (&strands.color, &strands.alpha) {
            (None, None) => None,
            (Some(c), Some(a)) => Some(c.iter().zip(a).map(|(c, &a)| c.extend(a)).collect()),
            _ => {
                return Err(TfxError::Unwritable(
                    "a .tfx vertex colour is RGBA: the strands need both colour and alpha, or neither".into(),
                ));
            }
        };
        let positions = strands
            .points
            .iter()
            .enumerate()
            .map(|(i, p)| p.extend(if i % per_usize < 2 { 0.0 } else { 1.0 }))
            .collect();
        let f = TfxFile {
            strand_count,
            vertices_per_strand: per,
            positions,
            strand_thickness,
            vertex_color,
            strand_uvs: false,
            vertex_uvs: false,
        };
        f.validate()?;
        Ok(f)
    }

    /// Checks array lengths against the counts, and the values.
    pub fn validate(&self) -> Result<(), TfxError> {
        let vertices = self.strand_count as usize * self.vertices_per_strand as usize;
        let len_error = |array, len, expected| TfxError::ArrayLength { array, len, expected };
        if self.positions.len() != vertices {
            return Err(len_error("positions", self.positions.len(), vertices));
        }
        if let Some(t) = &self.strand_thickness
            && t.len() != self.strand_count as usize
        {
            return Err(len_error("strand thickness", t.len(), self.strand_count as usize));
        }
        if let Some(c) = &self.vertex_color
            && c.len() != vertices
        {
            return Err(len_error("vertex colours", c.len(), vertices));
        }
        if let Some((index, p)) = self.positions.iter().enumerate().find(|(_, p)| !p.is_finite()) {
            return Err(TfxError::NotFinite {
                what: "position of vertex",
                index,
                value: p.to_string(),
            });
        }
        if let Some(t) = &self.strand_thickness
            && let Some((index, &value)) = t.iter().enumerate().find(|(_, t)| !(t.is_finite() && **t >= 0.0))
        {
            return Err(TfxError::BadThickness { index, value });
        }
        if let Some(c) = &self.vertex_color {
            if let Some((index, c)) = c.iter().enumerate().find(|(_, c)| !c.is_finite()) {
                return Err(TfxError::NotFinite {
                    what: "colour of vertex",
                    index,
                    value: c.to_string(),
                });
            }
            if let Some((index, c)) = c.iter().enumerate().find(|(_, c)| !(0.0..=1.0).contains(&c.w)) {
                return Err(TfxError::BadAlpha { index, value: c.w });
            }
        }
        Ok(())
    }
}

fn f32s(bytes: &[u8]) -> impl Iterator<Item = f32> + '_ {
    bytes.as_chunks::<4>().0.iter().map(|c| f32::from_le_bytes(*c))
}

fn vec4s(bytes: &[u8]) -> Vec<Vec4> {
    f32s(bytes)
        .collect::<Vec<f32>>()
        .as_chunks::<4>()
        .0
        .iter()
        .map(|c| Vec4::from_array(*c))
        .collect()
}

/// Decodes and validates a `.tfx` file held in memory.
pub fn read_tfx(bytes: &[u8]) -> Result<TfxFile, TfxError> {
    let header = bytes
        .first_chunk::<HEADER_BYTES>()
        .ok_or(TfxError::TruncatedHeader { len: bytes.len() })?;
    let mut words = [0u32; 8];
    for (w, c) in words.iter_mut().zip(header.as_chunks::<4>().0) {
        *w = u32::from_le_bytes(*c);
    }
    let version = f32::from_bits(words[0]);
    if version != VERSION {
        return Err(TfxError::Version { version });
    }
    let [
        _,
        strand_count,
        vertices_per_strand,
        positions_at,
        strand_uv_at,
        vertex_uv_at,
        thickness_at,
        color_at,
    ] = words;
    if vertices_per_strand == 0 {
        return Err(TfxError::NoVertices {
            strands: strand_count,
        });
    }
    if positions_at == 0 {
        return Err(TfxError::NoPositions);
    }
    let strands = u64::from(strand_count);
    let vertices = strands * u64::from(vertices_per_strand);
    // An array's size in bytes can pass u64 (16 × (2³² − 1)² ≈ 2⁶⁸), so it saturates: an impossible size reads as
    // "past the end".
    let array =
        |name: &'static str, offset: u32, entries: u64, size: u64| -> Result<Option<&[u8]>, TfxError> {
            if offset == 0 {
                return Ok(None);
            }
            let bytes_len = entries.saturating_mul(size);
            let out = |problem| TfxError::OutOfFile {
                array: name,
                offset,
                entries,
                bytes: bytes_len,
                problem,
                len: bytes.len(),
            };
            if (offset as usize) < HEADER_BYTES {
                return Err(out("starts inside the 160-byte header"));
            }
            let end = u64::from(offset).saturating_add(bytes_len);
            if end > bytes.len() as u64 {
                return Err(out("runs past the end of the file"));
            }
            // Both bounds lie in the file, so they fit a usize.
            bytes
                .get(offset as usize..end as usize)
                .map(Some)
                .ok_or_else(|| out("runs past the end of the file"))
        };
    // Every range is checked before any array is decoded, so a lying count fails before anything is allocated.
    let positions = array("vertex positions", positions_at, vertices, 16)?;
    let strand_uv = array("strand UVs", strand_uv_at, strands, 8)?;
    let vertex_uv = array("vertex UVs", vertex_uv_at, vertices, 8)?;
    let thickness = array("strand thickness", thickness_at, strands, 4)?;
    let color = array("vertex colours", color_at, vertices, 16)?;
    for (what, uv) in [
        ("strand UV of strand", strand_uv),
        ("vertex UV of vertex", vertex_uv),
    ] {
        let uv = uv.unwrap_or_default();
        if let Some((index, c)) = uv
            .as_chunks::<8>()
            .0
            .iter()
            .enumerate()
            .find(|(_, c)| !f32s(c.as_slice()).all(f32::is_finite))
        {
            let v: Vec<String> = f32s(c.as_slice()).map(|v| v.to_string()).collect();
            return Err(TfxError::NotFinite {
                what,
                index,
                value: format!("[{}]", v.join(", ")),
            });
        }
    }
    let f = TfxFile {
        strand_count,
        vertices_per_strand,
        positions: positions.map(vec4s).unwrap_or_default(),
        strand_thickness: thickness.map(|t| f32s(t).collect()),
        vertex_color: color.map(vec4s),
        strand_uvs: strand_uv.is_some(),
        vertex_uvs: vertex_uv.is_some(),
    };
    f.validate()?;
    Ok(f)
}

/// Reads and validates a `.tfx` file; every error names the file.
pub fn read_tfx_file(path: &Path) -> Result<TfxFile, TfxError> {
    read_tfx_file_with(path, &mut crate::progress::Quiet)
}

/// [`read_tfx_file`] telling `progress` how far the read got ([`super::progress::read_file`]).
pub(super) fn read_tfx_file_with(
    path: &Path,
    progress: &mut dyn crate::progress::Progress,
) -> Result<TfxFile, TfxError> {
    let bytes = super::progress::read_file(path, progress).map_err(|cause| TfxError::Io {
        path: path.to_owned(),
        cause,
    })?;
    read_tfx(&bytes).map_err(|e| TfxError::InFile {
        path: path.to_owned(),
        cause: Box::new(e),
    })
}

/// Encodes a file: the header, then positions, strand thickness and vertex colours in that order (each at an
/// 8-byte-aligned offset, as the format asks); no UV arrays.
pub fn write_tfx(f: &TfxFile) -> Vec<u8> {
    let positions_at = HEADER_BYTES;
    let thickness_at = positions_at + f.positions.len() * 16;
    let thickness_len = f.strand_thickness.as_ref().map_or(0, |t| t.len() * 4);
    let color_at = (thickness_at + thickness_len).next_multiple_of(8);
    let total = color_at + f.vertex_color.as_ref().map_or(0, |c| c.len() * 16);
    let mut out = Vec::with_capacity(total);
    out.extend_from_slice(&VERSION.to_le_bytes());
    let offset = |present: bool, at: usize| if present { at as u32 } else { 0 };
    for w in [
        f.strand_count,
        f.vertices_per_strand,
        positions_at as u32,
        0,
        0,
        offset(f.strand_thickness.is_some(), thickness_at),
        offset(f.vertex_color.is_some(), color_at),
    ] {
        out.extend_from_slice(&w.to_le_bytes());
    }
    out.resize(HEADER_BYTES, 0);
    let push = |v: f32, out: &mut Vec<u8>| out.extend_from_slice(&v.to_le_bytes());
    f.positions
        .iter()
        .flat_map(|p| p.to_array())
        .for_each(|v| push(v, &mut out));
    f.strand_thickness
        .iter()
        .flatten()
        .for_each(|&v| push(v, &mut out));
    out.resize(color_at, 0);
    f.vertex_color
        .iter()
        .flatten()
        .flat_map(|c| c.to_array())
        .for_each(|v| push(v, &mut out));
    out
}

/// Validates `f` and writes it to `path` atomically ([`crate::io::write_atomic_io`]).
pub fn write_tfx_file(path: &Path, f: &TfxFile) -> Result<(), TfxError> {
    f.validate().map_err(|e| TfxError::InFile {
        path: path.to_owned(),
        cause: Box::new(e),
    })?;
    crate::io::write_atomic_io(path, &write_tfx(f)).map_err(|cause| TfxError::Io {
        path: path.to_owned(),
        cause,
    })
}
