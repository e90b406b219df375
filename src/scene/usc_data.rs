//! USC-HairSalon `.data` files (Hu et al., "Single-View Hair Modeling Using A Hairstyle Database", SIGGRAPH 2015;
//! the format also of Hair20k and of the SIGGRAPH 2008 Hair Photobooth data), read and write.
//!
//! Layout, little-endian, no header beyond the count: i32 strand count, then per strand an i32 vertex count and
//! that many f32×3 positions. Nothing else: no thickness, transparency or colour.
//!
//! Mapping to hairlab (whose world is right-handed and Y-up, in the file's own units — nothing is rescaled):
//! positions are taken as they are (the database's hairstyles are Y-up, aligned to its head model). Strands of 0
//! vertices hold no hair and are dropped (counted in [`DataFile::empty_strands`], which `hairlab info` prints). A
//! strand of one vertex is a root with no hair — the database marks bare scalp that way — so it is kept apart from
//! the strands drawn, in [`DataFile::bare_roots`] (`hairlab info` counts them, `hairlab convert` keeps them where
//! the target format holds a one-point strand).
//!
//! Reading is bounded by the file's size: the strand count is checked against the bytes its vertex counts alone
//! need, and each strand's vertex count against the bytes left, before anything is allocated for it. Negative
//! counts and non-finite positions are refused; bytes after the last strand are ignored with a `log::warn!`.

use std::path::{Path, PathBuf};

use glam::Vec3;
use thiserror::Error;

use super::Strands;

/// Everything that can go wrong reading or writing a `.data` file. Each message is one line.
#[derive(Debug, Error)]
pub enum DataError {
    #[error("{path}: {cause}")]
    Io { path: PathBuf, cause: std::io::Error },
    /// A decoding or validation error in a named file.
    #[error("{path}: {cause}")]
    InFile { path: PathBuf, cause: Box<DataError> },
    #[error("truncated: the file holds {len} bytes, the strand count alone needs 4")]
    NoCount { len: usize },
    #[error("the strand count is {count}; it must not be negative")]
    NegativeStrands { count: i32 },
    #[error(
        "the header says {count} strands, whose vertex counts alone need {needed} bytes, but only {available} \
         follow it"
    )]
    TooManyStrands {
        count: i32,
        needed: u64,
        available: usize,
    },
    #[error("truncated: strand {strand} of {count} has no vertex count (the file ends at byte {len})")]
    MissingVertexCount { strand: usize, count: i32, len: usize },
    #[error("strand {strand} has {vertices} vertices; a count must not be negative")]
    NegativeVertices { strand: usize, vertices: i32 },
    #[error(
        "truncated: strand {strand} says {vertices} vertices ({needed} bytes) at byte {at}, but only {available} \
         bytes are left"
    )]
    Truncated {
        strand: usize,
        vertices: i32,
        needed: u64,
        at: usize,
        available: usize,
    },
    #[error("point {index} (strand {strand}) is not finite: {point}")]
    NonFinitePoint {
        index: usize,
        strand: usize,
        point: Vec3,
    },
    #[error("cannot write .data: {0}")]
    Unwritable(String),
}

/// A `.data` file as hairlab keeps it.
#[derive(Clone, Debug, PartialEq)]
pub struct DataFile {
    /// The strands of at least two vertices (the hair drawn), positions only.
    pub strands: Strands,
    /// The strands of one vertex: roots with no hair (bare scalp), in file order.
    pub bare_roots: Vec<Vec3>,
    /// Strands of 0 vertices in the file, dropped.
    pub empty_strands: usize,
}

/// Decodes and validates a `.data` file held in memory.
pub fn read_data(bytes: &[u8]) -> Result<DataFile, DataError> {
    read_data_from(bytes, ".data file", &mut crate::progress::Quiet)
}

/// Parses `bytes` (from `source`), telling `progress` every [`super::progress::BATCH`] strands; once it answers
/// `false` the parse stops and gives the strands parsed so far.
fn read_data_from(
    bytes: &[u8],
    source: &str,
    progress: &mut dyn crate::progress::Progress,
) -> Result<DataFile, DataError> {
    let (head, mut rest) = bytes
        .split_first_chunk::<4>()
        .ok_or(DataError::NoCount { len: bytes.len() })?;
    let count = i32::from_le_bytes(*head);
    let strands = usize::try_from(count).map_err(|_| DataError::NegativeStrands { count })?;
    // Every strand has at least its 4-byte vertex count, so the count is bounded by the file before `counts` is
    // allocated.
    let needed = strands as u64 * 4;
    if needed > rest.len() as u64 {
        return Err(DataError::TooManyStrands {
            count,
            needed,
            available: rest.len(),
        });
    }
    let mut out = Strands {
        counts: Vec::with_capacity(strands),
        ..Strands::default()
    };
    let mut empty_strands = 0;
    let mut bare_roots = Vec::new();
    for strand in 0..strands {
        if !super::progress::parsed(strand, strands, progress) {
            return Ok(DataFile {
                strands: out,
                bare_roots,
                empty_strands,
            });
        }
        let at = bytes.len() - rest.len();
        let (head, tail) = rest
            .split_first_chunk::<4>()
            .ok_or(DataError::MissingVertexCount {
                strand,
                count,
                len: bytes.len(),
            })?;
        let vertices = i32::from_le_bytes(*head);
        let n = usize::try_from(vertices).map_err(|_| DataError::NegativeVertices { strand, vertices })?;
        let needed = n as u64 * 12;
        let (body, tail) = usize::try_from(needed)
            .ok()
            .and_then(|k| tail.split_at_checked(k))
            .ok_or(DataError::Truncated {
                strand,
                vertices,
                needed,
                at: at + 4,
                available: tail.len(),
            })?;
        let first = out.points.len();
        out.points.extend(body.as_chunks::<12>().0.iter().map(|c| {
            let (v, _) = c.as_chunks::<4>();
            Vec3::new(
                f32::from_le_bytes(v[0]),
                f32::from_le_bytes(v[1]),
                f32::from_le_bytes(v[2]),
            )
        }));
        if let Some((i, &point)) = out
            .points
            .iter()
            .enumerate()
            .skip(first)
            .find(|(_, p)| !p.is_finite())
        {
            return Err(DataError::NonFinitePoint {
                index: i,
                strand,
                point,
            });
        }
        if n == 0 {
            empty_strands += 1;
        } else if n == 1 {
            bare_roots.extend(out.points.pop());
        } else {
            // n ≤ file size / 12 < 2³², so it fits the u32 count.
            out.counts.push(n as u32);
        }
        rest = tail;
    }
    if !rest.is_empty() {
        log::warn!(
            "{source}: {} bytes after the last strand; ignoring them",
            rest.len()
        );
    }
    if empty_strands > 0 {
        log::warn!("{source}: {empty_strands} strands of 0 vertices dropped");
    }
    Ok(DataFile {
        strands: out,
        bare_roots,
        empty_strands,
    })
}

impl DataFile {
    /// The strands followed by each bare root as a strand of one point (positions only), for a format that holds
    /// one-point strands (`.data`, `.hair`).
    pub fn strands_with_roots(&self) -> Strands {
        let mut s = self.strands.clone();
        s.points.extend_from_slice(&self.bare_roots);
        s.counts.extend(std::iter::repeat_n(1, self.bare_roots.len()));
        s
    }
}

/// Reads and validates a `.data` file; every error names the file.
pub fn read_data_file(path: &Path) -> Result<DataFile, DataError> {
    read_data_file_with(path, &mut crate::progress::Quiet)
}

/// [`read_data_file`] telling `progress` how far the read and the parse got ([`super::progress`]).
pub(super) fn read_data_file_with(
    path: &Path,
    progress: &mut dyn crate::progress::Progress,
) -> Result<DataFile, DataError> {
    let bytes = super::progress::read_file(path, &mut *progress).map_err(|cause| DataError::Io {
        path: path.to_owned(),
        cause,
    })?;
    read_data_from(&bytes, &path.display().to_string(), progress).map_err(|e| DataError::InFile {
        path: path.to_owned(),
        cause: Box::new(e),
    })
}

/// Encodes strands as a `.data` file (positions only: thickness, alpha and colour have no place in it). Errors
/// when a count does not fit an i32 or the points do not add up to the counts.
pub fn write_data(strands: &Strands) -> Result<Vec<u8>, DataError> {
    let total: u64 = strands.counts.iter().map(|&c| u64::from(c)).sum();
    if total != strands.points.len() as u64 {
        return Err(DataError::Unwritable(format!(
            "the strand counts add up to {total} points but there are {}",
            strands.points.len()
        )));
    }
    let i32_of = |v: usize, what: &str| {
        i32::try_from(v).map_err(|_| DataError::Unwritable(format!("{v} {what} do not fit an i32 count")))
    };
    let mut out = Vec::with_capacity(4 + strands.counts.len() * 4 + strands.points.len() * 12);
    out.extend_from_slice(&i32_of(strands.counts.len(), "strands")?.to_le_bytes());
    for (first, n) in strands.ranges() {
        out.extend_from_slice(&i32_of(n, "vertices")?.to_le_bytes());
        for p in strands.points.get(first..first + n).unwrap_or_default() {
            p.to_array()
                .iter()
                .for_each(|v| out.extend_from_slice(&v.to_le_bytes()));
        }
    }
    Ok(out)
}

/// [`write_data`] to `path`, atomically ([`crate::io::write_atomic_io`]); errors name the file.
pub fn write_data_file(path: &Path, strands: &Strands) -> Result<(), DataError> {
    let bytes = write_data(strands).map_err(|e| DataError::InFile {
        path: path.to_owned(),
        cause: Box::new(e),
    })?;
    crate::io::write_atomic_io(path, &bytes).map_err(|cause| DataError::Io {
        path: path.to_owned(),
        cause,
    })
}
