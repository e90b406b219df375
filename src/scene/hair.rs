//! Cem Yuksel's `.hair` format (<http://www.cemyuksel.com/research/hairmodels/>), read and write.
//!
//! Layout, little-endian: a 128-byte header — `"HAIR"`, u32 strand count, u32 point count, u32 array flags,
//! u32 default segments per strand, f32 default thickness, f32 default transparency, f32×3 default colour and
//! an 88-byte NUL-padded info string — followed by the arrays the flags name, in this order: u16 segments per
//! strand, f32×3 points, f32 thickness, f32 transparency, f32×3 colours (all but the first one entry per
//! point).
//!
//! Reading checks the size the header implies against the file before allocating anything, then validates the
//! contents (segment counts against the point count, finite points, thickness and transparency ranges). Bytes
//! after the last array are ignored with a `log::warn!`: some exporters pad files, and the arrays themselves
//! are complete.

use std::path::{Path, PathBuf};

use glam::Vec3;
use thiserror::Error;

use super::Strands;

/// Size of the fixed header.
pub const HEADER_BYTES: usize = 128;
/// Size of the info string inside the header.
pub const INFO_BYTES: usize = 88;

const MAGIC: &[u8; 4] = b"HAIR";
const FLAG_SEGMENTS: u32 = 1;
const FLAG_POINTS: u32 = 2;
const FLAG_THICKNESS: u32 = 4;
const FLAG_TRANSPARENCY: u32 = 8;
const FLAG_COLORS: u32 = 16;
const KNOWN_FLAGS: u32 = FLAG_SEGMENTS | FLAG_POINTS | FLAG_THICKNESS | FLAG_TRANSPARENCY | FLAG_COLORS;

/// Everything that can go wrong reading or writing a `.hair` file. Each message is one line.
#[derive(Debug, Error)]
pub enum HairError {
    #[error("{path}: {cause}")]
    Io { path: PathBuf, cause: std::io::Error },
    /// A decoding or validation error in a named file.
    #[error("{path}: {cause}")]
    InFile { path: PathBuf, cause: Box<HairError> },
    #[error("not a .hair file: it starts with \"{}\" instead of \"HAIR\"", found.escape_ascii())]
    BadMagic { found: [u8; 4] },
    #[error("truncated header: the file holds {len} bytes, the header alone needs 128")]
    TruncatedHeader { len: usize },
    #[error(
        "truncated: header says {strands} strands and {points} points ({arrays}), which need {needed} bytes \
         after the header, but the file holds only {available} (needs {} more bytes)",
        needed - available
    )]
    Truncated {
        strands: u32,
        points: u32,
        arrays: String,
        needed: u64,
        available: u64,
    },
    #[error("the file has no points array, so there is no hair to show")]
    NoPoints,
    #[error(
        "segment counts add up to {expected} points ((segments + 1) over {strands} strands{}) but there are \
         {points} points",
        default_segments.map_or(String::new(), |d| format!(", using the default of {d} segments per strand"))
    )]
    SegmentMismatch {
        strands: u32,
        expected: u64,
        points: u64,
        default_segments: Option<u32>,
    },
    #[error("{array} array has {len} entries, expected {expected}")]
    ArrayLength {
        array: &'static str,
        len: usize,
        expected: usize,
    },
    #[error("point {index} is not finite: {point}")]
    NonFinitePoint { index: usize, point: Vec3 },
    #[error("thickness of point {index} is {value}; it must be finite and not negative")]
    BadThickness { index: usize, value: f32 },
    #[error("transparency of point {index} is {value}; it must lie in [0, 1]")]
    BadTransparency { index: usize, value: f32 },
    #[error("colour of point {index} is not finite: {color}")]
    NonFiniteColor { index: usize, color: Vec3 },
    #[error("strand {strand} has {points} points; a .hair strand has 1 to 65536 points")]
    StrandPoints { strand: usize, points: u32 },
    #[error("{count} {what} do not fit the 32-bit counts of a .hair header")]
    TooMany { what: &'static str, count: usize },
}

/// A `.hair` file: header defaults and info string, plus the arrays the file holds.
///
/// A value returned by [`read_hair`] or [`HairFile::from_strands`] passes [`HairFile::validate`]; values
/// edited by hand should be validated again (as [`write_hair_file`] and [`HairFile::to_strands`] do).
#[derive(Clone, Debug, PartialEq)]
pub struct HairFile {
    /// Number of strands; equals `segments.len()` when the segments array is present.
    pub strand_count: u32,
    pub default_segments: u32,
    pub default_thickness: f32,
    pub default_transparency: f32,
    pub default_color: Vec3,
    /// The info string, without NUL padding; [`write_hair`] keeps at most 87 bytes of it so a NUL terminator
    /// fits.
    pub info: String,
    /// Segments per strand (a strand has segments + 1 points).
    pub segments: Option<Vec<u16>>,
    pub points: Option<Vec<Vec3>>,
    pub thickness: Option<Vec<f32>>,
    /// Per-point transparency in [0, 1] (0 = opaque).
    pub transparency: Option<Vec<f32>>,
    pub color: Option<Vec<Vec3>>,
}

impl HairFile {
    /// Number of points the per-point arrays hold: the points array's length, or the first other per-point
    /// array's.
    pub fn point_count(&self) -> usize {
        self.points
            .as_ref()
            .map(Vec::len)
            .or_else(|| self.thickness.as_ref().map(Vec::len))
            .or_else(|| self.transparency.as_ref().map(Vec::len))
            .or_else(|| self.color.as_ref().map(Vec::len))
            .unwrap_or(0)
    }

    /// Checks that the arrays agree with each other and hold sane values.
    pub fn validate(&self) -> Result<(), HairError> {
        let points = self.points.as_ref().ok_or(HairError::NoPoints)?;
        let n = points.len();
        if let Some(seg) = &self.segments {
            check_len("segments", seg.len(), self.strand_count as usize)?;
        }
        if let Some(t) = &self.thickness {
            check_len("thickness", t.len(), n)?;
        }
        if let Some(t) = &self.transparency {
            check_len("transparency", t.len(), n)?;
        }
        if let Some(c) = &self.color {
            check_len("colour", c.len(), n)?;
        }
        let expected = match &self.segments {
            Some(seg) => seg.iter().map(|&s| u64::from(s) + 1).sum(),
            None => u64::from(self.strand_count) * (u64::from(self.default_segments) + 1),
        };
        if expected != n as u64 {
            return Err(HairError::SegmentMismatch {
                strands: self.strand_count,
                expected,
                points: n as u64,
                default_segments: self.segments.is_none().then_some(self.default_segments),
            });
        }
        if let Some((index, &point)) = points.iter().enumerate().find(|(_, p)| !p.is_finite()) {
            return Err(HairError::NonFinitePoint { index, point });
        }
        if let Some(t) = &self.thickness
            && let Some((index, &value)) = t.iter().enumerate().find(|(_, t)| !(t.is_finite() && **t >= 0.0))
        {
            return Err(HairError::BadThickness { index, value });
        }
        if let Some(t) = &self.transparency
            && let Some((index, &value)) = t.iter().enumerate().find(|(_, t)| !(0.0..=1.0).contains(*t))
        {
            return Err(HairError::BadTransparency { index, value });
        }
        if let Some(c) = &self.color
            && let Some((index, &color)) = c.iter().enumerate().find(|(_, c)| !c.is_finite())
        {
            return Err(HairError::NonFiniteColor { index, color });
        }
        Ok(())
    }

    /// Converts to [`Strands`]: transparency `t` becomes alpha `1 - t`; without a segments array every strand
    /// has `default_segments` segments. Arrays the file lacks stay `None` (the header defaults are not
    /// materialised, so the renderer's own thickness, alpha and colour apply); they remain available on
    /// `self`.
    pub fn to_strands(&self) -> Result<Strands, HairError> {
        self.validate()?;
        let points = self.points.clone().ok_or(HairError::NoPoints)?;
        let counts = match &self.segments {
            Some(seg) => seg.iter().map(|&s| u32::from(s) + 1).collect(),
            // Saturation needs 2³² points in one strand, which `validate` has ruled out for any real file.
            None => vec![self.default_segments.saturating_add(1); self.strand_count as usize],
        };
        Ok(Strands {
            points,
            counts,
            thickness: self.thickness.clone(),
            alpha: self
                .transparency
                .as_ref()
                .map(|t| t.iter().map(|t| 1.0 - t).collect()),
            color: self.color.clone(),
        })
    }

    /// Builds a file from strands: always a segments array and points, plus thickness, transparency (`1 -
    /// alpha`) and colour arrays where the strands have them. Header defaults: thickness 1, transparency 0,
    /// colour white, default segments 0 (unused, since the segments array is present).
    ///
    /// Alpha values below 0.5 may not survive `1 - (1 - alpha)` bit-exactly in `f32`; values from 0.5 to 1
    /// and multiples of 2⁻²⁴ do. Errors when a strand has 0 or more than 65536 points, or the contents fail
    /// [`HairFile::validate`].
    pub fn from_strands(strands: &Strands, info: &str) -> Result<HairFile, HairError> {
        let segments = strands
            .counts
            .iter()
            .enumerate()
            .map(|(strand, &points)| {
                points
                    .checked_sub(1)
                    .and_then(|s| u16::try_from(s).ok())
                    .ok_or(HairError::StrandPoints { strand, points })
            })
            .collect::<Result<Vec<u16>, HairError>>()?;
        let strand_count = u32::try_from(segments.len()).map_err(|_| HairError::TooMany {
            what: "strands",
            count: segments.len(),
        })?;
        if u32::try_from(strands.points.len()).is_err() {
            return Err(HairError::TooMany {
                what: "points",
                count: strands.points.len(),
            });
        }
        let h = HairFile {
            strand_count,
            default_segments: 0,
            default_thickness: 1.0,
            default_transparency: 0.0,
            default_color: Vec3::ONE,
            info: info.to_owned(),
            segments: Some(segments),
            points: Some(strands.points.clone()),
            thickness: strands.thickness.clone(),
            transparency: strands
                .alpha
                .as_ref()
                .map(|a| a.iter().map(|a| 1.0 - a).collect()),
            color: strands.color.clone(),
        };
        h.validate()?;
        Ok(h)
    }

    fn flags(&self) -> u32 {
        [
            (self.segments.is_some(), FLAG_SEGMENTS),
            (self.points.is_some(), FLAG_POINTS),
            (self.thickness.is_some(), FLAG_THICKNESS),
            (self.transparency.is_some(), FLAG_TRANSPARENCY),
            (self.color.is_some(), FLAG_COLORS),
        ]
        .iter()
        .filter(|(present, _)| *present)
        .fold(0, |f, (_, bit)| f | bit)
    }
}

fn check_len(array: &'static str, len: usize, expected: usize) -> Result<(), HairError> {
    if len == expected {
        Ok(())
    } else {
        Err(HairError::ArrayLength { array, len, expected })
    }
}

/// Reads fixed-size little-endian fields off the front of a byte slice.
struct Reader<'a> {
    rest: &'a [u8],
}

impl<'a> Reader<'a> {
    fn take<const N: usize>(&mut self) -> Option<[u8; N]> {
        let (head, rest) = self.rest.split_first_chunk::<N>()?;
        self.rest = rest;
        Some(*head)
    }
    fn u32(&mut self) -> Option<u32> {
        self.take().map(u32::from_le_bytes)
    }
    fn f32(&mut self) -> Option<f32> {
        self.take().map(f32::from_le_bytes)
    }
    fn vec3(&mut self) -> Option<Vec3> {
        Some(Vec3::new(self.f32()?, self.f32()?, self.f32()?))
    }
    /// Splits off the next `len` bytes.
    fn bytes(&mut self, len: u64) -> Option<&'a [u8]> {
        let (head, rest) = self.rest.split_at_checked(usize::try_from(len).ok()?)?;
        self.rest = rest;
        Some(head)
    }
}

fn f32s(bytes: &[u8]) -> Vec<f32> {
    bytes
        .as_chunks::<4>()
        .0
        .iter()
        .map(|c| f32::from_le_bytes(*c))
        .collect()
}

fn vec3s(bytes: &[u8]) -> Vec<Vec3> {
    f32s(bytes)
        .as_chunks::<3>()
        .0
        .iter()
        .map(|c| Vec3::from_array(*c))
        .collect()
}

/// Decodes and validates a `.hair` file held in memory.
pub fn read_hair(bytes: &[u8]) -> Result<HairFile, HairError> {
    read_hair_from(bytes, ".hair file")
}

/// [`read_hair`] with its warnings naming `source` (the file).
fn read_hair_from(bytes: &[u8], source: &str) -> Result<HairFile, HairError> {
    if let Some(found) = bytes.first_chunk::<4>()
        && found != MAGIC
    {
        return Err(HairError::BadMagic { found: *found });
    }
    let (header, body) = bytes
        .split_first_chunk::<HEADER_BYTES>()
        .ok_or(HairError::TruncatedHeader { len: bytes.len() })?;
    let truncated = || HairError::TruncatedHeader { len: bytes.len() };
    let mut r = Reader { rest: header };
    r.take::<4>().ok_or_else(truncated)?;
    let strand_count = r.u32().ok_or_else(truncated)?;
    let point_count = r.u32().ok_or_else(truncated)?;
    let flags = r.u32().ok_or_else(truncated)?;
    let default_segments = r.u32().ok_or_else(truncated)?;
    let default_thickness = r.f32().ok_or_else(truncated)?;
    let default_transparency = r.f32().ok_or_else(truncated)?;
    let default_color = r.vec3().ok_or_else(truncated)?;
    let info_bytes: [u8; INFO_BYTES] = r.take().ok_or_else(truncated)?;
    let info_len = info_bytes.iter().position(|&b| b == 0).unwrap_or(INFO_BYTES);
    let info = String::from_utf8_lossy(info_bytes.get(..info_len).unwrap_or_default()).into_owned();
    if flags & !KNOWN_FLAGS != 0 {
        log::warn!(
            "{source}: the header has unknown array flags {:#x}; ignoring them",
            flags & !KNOWN_FLAGS
        );
    }

    // Sizes in u64 from u32 counts: at most 32 × (2³² − 1) bytes, far from overflowing; saturating anyway so
    // that an impossible size reads as "does not fit" rather than wrapping.
    let has = |bit: u32| flags & bit != 0;
    let per_point = |bit: u32, size: u64| {
        if has(bit) {
            u64::from(point_count).saturating_mul(size)
        } else {
            0
        }
    };
    let seg_bytes = if has(FLAG_SEGMENTS) {
        u64::from(strand_count).saturating_mul(2)
    } else {
        0
    };
    let sizes = [
        (FLAG_SEGMENTS, "segments", seg_bytes),
        (FLAG_POINTS, "points", per_point(FLAG_POINTS, 12)),
        (FLAG_THICKNESS, "thickness", per_point(FLAG_THICKNESS, 4)),
        (FLAG_TRANSPARENCY, "transparency", per_point(FLAG_TRANSPARENCY, 4)),
        (FLAG_COLORS, "colours", per_point(FLAG_COLORS, 12)),
    ];
    let needed = sizes.iter().fold(0u64, |acc, (_, _, s)| acc.saturating_add(*s));
    let available = body.len() as u64;
    let truncated_arrays = || {
        let names: Vec<&str> = sizes
            .iter()
            .filter(|(bit, _, _)| has(*bit))
            .map(|(_, name, _)| *name)
            .collect();
        let arrays = if names.is_empty() {
            "no arrays".to_owned()
        } else {
            format!("arrays: {}", names.join(", "))
        };
        HairError::Truncated {
            strands: strand_count,
            points: point_count,
            arrays,
            needed,
            available,
        }
    };
    if needed > available {
        return Err(truncated_arrays());
    }
    if needed < available {
        log::warn!(
            "{source}: {} bytes after the last array; ignoring them",
            available - needed
        );
    }

    // Every array fits now, so the allocations below are bounded by the file's size.
    let mut r = Reader { rest: body };
    let mut array = |bit: u32, size: u64| -> Result<Option<&[u8]>, HairError> {
        if !has(bit) {
            return Ok(None);
        }
        let slice = r.bytes(size).ok_or_else(truncated_arrays)?;
        Ok(Some(slice))
    };
    let segments = array(FLAG_SEGMENTS, seg_bytes)?.map(|b| {
        b.as_chunks::<2>()
            .0
            .iter()
            .map(|c| u16::from_le_bytes(*c))
            .collect()
    });
    let points = array(FLAG_POINTS, per_point(FLAG_POINTS, 12))?.map(vec3s);
    let thickness = array(FLAG_THICKNESS, per_point(FLAG_THICKNESS, 4))?.map(f32s);
    let transparency = array(FLAG_TRANSPARENCY, per_point(FLAG_TRANSPARENCY, 4))?.map(f32s);
    let color = array(FLAG_COLORS, per_point(FLAG_COLORS, 12))?.map(vec3s);

    if points.is_none() {
        return Err(HairError::NoPoints);
    }
    let h = HairFile {
        strand_count,
        default_segments,
        default_thickness,
        default_transparency,
        default_color,
        info,
        segments,
        points,
        thickness,
        transparency,
        color,
    };
    h.validate()?;
    Ok(h)
}

/// Reads and validates a `.hair` file; every error names the file.
pub fn read_hair_file(path: &Path) -> Result<HairFile, HairError> {
    read_hair_file_with(path, &mut crate::progress::Quiet)
}

/// [`read_hair_file`] telling `progress` how far the read got ([`super::progress::read_file`]).
pub(super) fn read_hair_file_with(
    path: &Path,
    progress: &mut dyn crate::progress::Progress,
) -> Result<HairFile, HairError> {
    let bytes = super::progress::read_file(path, progress).map_err(|cause| HairError::Io {
        path: path.to_owned(),
        cause,
    })?;
    read_hair_from(&bytes, &path.display().to_string()).map_err(|e| HairError::InFile {
        path: path.to_owned(),
        cause: Box::new(e),
    })
}

/// Encodes a file. The header counts come from the arrays (strand count from the segments array when present,
/// point count from [`HairFile::point_count`]); the info string is cut to at most 87 bytes at a character
/// boundary. A value that fails [`HairFile::validate`] is written as given, and [`read_hair`] will reject it.
pub fn write_hair(h: &HairFile) -> Vec<u8> {
    let strand_count = h.segments.as_ref().map_or(h.strand_count, |s| s.len() as u32);
    let point_count = h.point_count();
    let arrays_len = h.segments.as_ref().map_or(0, |s| s.len() * 2)
        + [h.points.is_some(), h.color.is_some()]
            .iter()
            .filter(|&&p| p)
            .count()
            * point_count
            * 12
        + [h.thickness.is_some(), h.transparency.is_some()]
            .iter()
            .filter(|&&p| p)
            .count()
            * point_count
            * 4;
    let mut out = Vec::with_capacity(HEADER_BYTES + arrays_len);
    out.extend_from_slice(MAGIC);
    for v in [strand_count, point_count as u32, h.flags(), h.default_segments] {
        out.extend_from_slice(&v.to_le_bytes());
    }
    for v in [h.default_thickness, h.default_transparency] {
        out.extend_from_slice(&v.to_le_bytes());
    }
    push_vec3s(&mut out, &[h.default_color]);
    let mut info_len = h.info.len().min(INFO_BYTES - 1);
    while !h.info.is_char_boundary(info_len) {
        info_len -= 1;
    }
    let mut info = [0u8; INFO_BYTES];
    if let (Some(dst), Some(src)) = (info.get_mut(..info_len), h.info.as_bytes().get(..info_len)) {
        dst.copy_from_slice(src);
    }
    out.extend_from_slice(&info);
    if let Some(seg) = &h.segments {
        seg.iter().for_each(|s| out.extend_from_slice(&s.to_le_bytes()));
    }
    if let Some(p) = &h.points {
        push_vec3s(&mut out, p);
    }
    for a in [&h.thickness, &h.transparency].into_iter().flatten() {
        a.iter().for_each(|v| out.extend_from_slice(&v.to_le_bytes()));
    }
    if let Some(c) = &h.color {
        push_vec3s(&mut out, c);
    }
    out
}

fn push_vec3s(out: &mut Vec<u8>, v: &[Vec3]) {
    for p in v {
        for c in p.to_array() {
            out.extend_from_slice(&c.to_le_bytes());
        }
    }
}

/// Validates `h` and writes it to `path` atomically ([`crate::io::write_atomic_io`]), so a failure never leaves
/// a half-written file or a temporary file behind.
pub fn write_hair_file(path: &Path, h: &HairFile) -> Result<(), HairError> {
    h.validate().map_err(|e| HairError::InFile {
        path: path.to_owned(),
        cause: Box::new(e),
    })?;
    crate::io::write_atomic_io(path, &write_hair(h)).map_err(|cause| HairError::Io {
        path: path.to_owned(),
        cause,
    })
}
