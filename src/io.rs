//! Input files are read bounded ([`read_regular_file`]: regular files only, at most a stated size). Output files
//! are written whole or not at all: to a [`tempfile`] temporary file beside the target, then persisted (renamed)
//! over it. A failed write removes the temporary file. Every PNG is encoded by [`encode_png`] and written by
//! [`write_png`]; CSV text comes from [`csv_text`] (serde rows) or [`csv_table`] (columns known at run time).

use anyhow::{Context, Result};
use std::io::Write;
use std::path::Path;

/// Largest input file hairlab reads (a `.hair`, glTF or glb file, a buffer, a preset, a fragment CSV): 1 GiB.
pub const MAX_INPUT_BYTES: u64 = 1 << 30;

/// The bytes [`read_regular_file_observed`] reads between two reports: 1 MiB.
pub const READ_CHUNK: u64 = 1 << 20;

/// Reads `path` when it is a regular file (not a device, FIFO or folder, also through a symlink) of at most
/// [`MAX_INPUT_BYTES`], and no more than the size it had when opened.
pub fn read_regular_file(path: &Path) -> std::io::Result<Vec<u8>> {
    read_regular_file_observed(path, &mut |_, _| true)
}

/// [`read_regular_file`] telling `on_bytes(read, size)` how far it got every [`READ_CHUNK`] bytes; once it answers
/// `false` the read stops with an [`std::io::ErrorKind::Interrupted`] error.
pub fn read_regular_file_observed(
    path: &Path,
    on_bytes: &mut dyn FnMut(u64, u64) -> bool,
) -> std::io::Result<Vec<u8>> {
    use std::io::{Error, ErrorKind, Read};
    let meta = std::fs::metadata(path)?;
    if !meta.is_file() {
        return Err(Error::new(ErrorKind::InvalidInput, "not a regular file"));
    }
    if meta.len() > MAX_INPUT_BYTES {
        return Err(Error::new(
            ErrorKind::InvalidInput,
            format!(
                "{} bytes, more than the {MAX_INPUT_BYTES} bytes hairlab reads",
                meta.len()
            ),
        ));
    }
    let mut bytes = Vec::with_capacity(meta.len() as usize);
    let mut file = std::fs::File::open(path)?.take(meta.len());
    while (&mut file).take(READ_CHUNK).read_to_end(&mut bytes)? > 0 {
        if !on_bytes(bytes.len() as u64, meta.len()) {
            return Err(Error::new(ErrorKind::Interrupted, "stopped"));
        }
    }
    Ok(bytes)
}

/// [`read_regular_file`] as UTF-8 text.
pub fn read_regular_text(path: &Path) -> std::io::Result<String> {
    String::from_utf8(read_regular_file(path)?)
        .map_err(|_| std::io::Error::new(std::io::ErrorKind::InvalidData, "not UTF-8 text"))
}

/// Checks, before any work, that `path` can take an output file of type `extension` (e.g. `png`, any case): a file
/// name with that extension in an existing folder. The error names `path`.
pub fn check_output(path: &Path, extension: &str) -> Result<()> {
    if path
        .extension()
        .is_none_or(|e| !e.eq_ignore_ascii_case(extension))
    {
        anyhow::bail!("{}: the output must be a .{extension} file", path.display());
    }
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    if !dir.is_dir() {
        anyhow::bail!("{}: the folder {} does not exist", path.display(), dir.display());
    }
    if path.is_dir() {
        anyhow::bail!("{}: is a folder, not a file", path.display());
    }
    Ok(())
}

/// Writes `bytes` to `path` atomically; the error names `path`.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    write_atomic_io(path, bytes).with_context(|| format!("{}: cannot write", path.display()))
}

/// [`write_atomic`] with the bare I/O error, for writers with their own error type. The file gets the usual
/// permissions of a new file (read-write for all, less the umask), not the temporary file's owner-only ones.
pub fn write_atomic_io(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    if path.file_name().is_none() {
        return Err(std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            "not a file path",
        ));
    }
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let mut builder = tempfile::Builder::new();
    #[cfg(unix)]
    builder.permissions(std::os::unix::fs::PermissionsExt::from_mode(0o666));
    // tempfile's own error names its random file name, which never exists; name the folder instead.
    let mut tmp = builder.tempfile_in(dir).map_err(|e| {
        std::io::Error::new(
            e.kind(),
            format!("cannot create a file in {}: {}", dir.display(), e.kind()),
        )
    })?;
    tmp.as_file_mut().write_all(bytes)?;
    tmp.as_file().sync_all()?;
    // On failure the error hands the temporary file back, and dropping it deletes it.
    tmp.persist(path).map_err(|e| e.error)?;
    Ok(())
}

/// A table whose columns are known only at run time (one per model, per plotted curve) as CSV text: `header`,
/// then `rows`, each a sequence of fields (a `Vec`, a tuple; numbers as [`csv_text`] writes them), each field
/// quoted where it needs it, through the same `csv` writer as [`csv_text`].
pub fn csv_table<R: serde::Serialize>(
    name: &str,
    header: &[String],
    rows: impl IntoIterator<Item = R>,
) -> Result<String> {
    let mut w = csv::Writer::from_writer(Vec::new());
    w.write_record(header)
        .with_context(|| format!("cannot encode {name}"))?;
    for r in rows {
        w.serialize(r).with_context(|| format!("cannot encode {name}"))?;
    }
    let bytes = w
        .into_inner()
        .map_err(|e| anyhow::anyhow!("cannot encode {name}: {}", e.error()))?;
    String::from_utf8(bytes).with_context(|| format!("cannot encode {name}"))
}

/// `rows` as CSV text: a header from the first row's field names, then one line per row (none when empty).
pub fn csv_text<T: serde::Serialize>(name: &str, rows: impl IntoIterator<Item = T>) -> Result<String> {
    let mut w = csv::Writer::from_writer(Vec::new());
    for r in rows {
        w.serialize(r).with_context(|| format!("cannot encode {name}"))?;
    }
    let bytes = w
        .into_inner()
        .map_err(|e| anyhow::anyhow!("cannot encode {name}: {}", e.error()))?;
    String::from_utf8(bytes).with_context(|| format!("cannot encode {name}"))
}

/// The rows of a small hand-written CSV (`curve`'s fragments, `composite`'s pixel), each with its line number:
/// blank lines and `#` comments skipped, an optional first line naming exactly `columns` (any order and case),
/// then rows of exactly `columns.len()` fields read into `T` (in `columns` order without a header). The one
/// reader of such files; an error names `source:line` and, for a bad row, what a row must be (`shape`).
pub fn read_rows<T: serde::de::DeserializeOwned>(
    text: &str,
    source: &str,
    columns: &[&str],
    shape: &str,
) -> Result<Vec<(usize, T)>> {
    let mut header: Option<csv::StringRecord> = None;
    let mut first = true;
    let mut out = Vec::new();
    // Line by line, so that line numbers count blank and comment lines (the reader's own count skips them).
    for (i, text_line) in text.lines().enumerate() {
        let line = i + 1;
        let row_text = text_line.trim();
        if row_text.is_empty() || row_text.starts_with('#') {
            continue;
        }
        let record = csv::ReaderBuilder::new()
            .has_headers(false)
            .trim(csv::Trim::All)
            .from_reader(row_text.as_bytes())
            .records()
            .next();
        let Some(Ok(record)) = record else {
            anyhow::bail!("{source}:{line}: cannot read `{row_text}` as CSV");
        };
        if std::mem::replace(&mut first, false) {
            let names: csv::StringRecord = record.iter().map(str::to_ascii_lowercase).collect();
            let mut sorted: Vec<&str> = names.iter().collect();
            sorted.sort_unstable();
            let mut expected = columns.to_vec();
            expected.sort_unstable();
            if sorted == expected {
                header = Some(names);
                continue;
            }
        }
        match record.deserialize(header.as_ref()) {
            Ok(row) if record.len() == columns.len() => out.push((line, row)),
            _ => anyhow::bail!("{source}:{line}: expected {shape}, got `{row_text}`"),
        }
    }
    Ok(out)
}

/// An image [`encode_png`] takes: an `image` buffer of any 8- or 16-bit pixel, or a `DynamicImage`.
pub trait PngSource {
    /// The pixels as bytes, the width, the height and their colour type.
    fn png_parts(&self) -> (&[u8], u32, u32, image::ExtendedColorType);
}

impl<P> PngSource for image::ImageBuffer<P, Vec<P::Subpixel>>
where
    P: image::PixelWithColorType,
    [P::Subpixel]: image::EncodableLayout,
{
    fn png_parts(&self) -> (&[u8], u32, u32, image::ExtendedColorType) {
        use image::EncodableLayout;
        (
            self.as_raw().as_bytes(),
            self.width(),
            self.height(),
            P::COLOR_TYPE,
        )
    }
}

impl PngSource for image::DynamicImage {
    fn png_parts(&self) -> (&[u8], u32, u32, image::ExtendedColorType) {
        (self.as_bytes(), self.width(), self.height(), self.color().into())
    }
}

/// `image` encoded as PNG: the one PNG encoder (files go through [`write_png`]).
pub fn encode_png(image: &impl PngSource) -> Result<Vec<u8>> {
    use image::ImageEncoder;
    let (bytes, width, height, color) = image.png_parts();
    let mut png = Vec::new();
    image::codecs::png::PngEncoder::new(&mut png)
        .write_image(bytes, width, height, color)
        .context("cannot encode the image as PNG")?;
    Ok(png)
}

/// `image` as a PNG file at `path`, whole or not at all ([`encode_png`], then [`write_atomic`]); the error names
/// `path`.
pub fn write_png(path: &Path, image: &impl PngSource) -> Result<()> {
    let png = encode_png(image).with_context(|| format!("{}: cannot write", path.display()))?;
    write_atomic(path, &png)
}

/// Linear `c` clamped to `[0, 1]` and sRGB-encoded (IEC 61966-2-1), in `[0, 1]`.
pub fn srgb(c: f32) -> f32 {
    let c = c.clamp(0.0, 1.0);
    if c <= 0.003_130_8 {
        12.92 * c
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    }
}

/// [`srgb`] to 8 bits.
pub fn srgb8(c: f32) -> u8 {
    (srgb(c) * 255.0).round() as u8
}

/// A premultiplied linear capture over black as an 8-bit sRGB image: each pixel's colour `H` clamped to `[0, 1]`
/// and sRGB-encoded (IEC 61966-2-1, [`srgb8`]), row-major `(H, 1 − T)` of a `width`-wide capture.
pub fn over_black(capture: &[[f32; 4]], width: u32, height: u32) -> image::RgbaImage {
    let encode = srgb8;
    image::RgbaImage::from_fn(width, height, |x, y| {
        let p = capture
            .get(y as usize * width as usize + x as usize)
            .copied()
            .unwrap_or_default();
        image::Rgba([encode(p[0]), encode(p[1]), encode(p[2]), 255])
    })
}

/// `image` (`width × height` linear RGB, row after row) as an OpenEXR file of 32-bit floats.
pub fn encode_exr(image: &[glam::Vec3], width: u32, height: u32) -> Result<Vec<u8>> {
    let data: Vec<f32> = image.iter().flat_map(|v| v.to_array()).collect();
    let buffer = image::Rgb32FImage::from_raw(width, height, data)
        .ok_or_else(|| anyhow::anyhow!("{width}×{height} does not match {} pixels", image.len()))?;
    let mut out = std::io::Cursor::new(Vec::new());
    image::DynamicImage::ImageRgb32F(buffer).write_to(&mut out, image::ImageFormat::OpenExr)?;
    Ok(out.into_inner())
}

#[cfg(test)]
mod tests {
    use super::{check_output, encode_png, over_black, read_regular_file, write_atomic, write_png};

    fn names(dir: &std::path::Path) -> Vec<String> {
        let mut v: Vec<String> = std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        v.sort();
        v
    }

    #[test]
    fn replaces_the_file_whole_and_leaves_nothing_else() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("out.txt");
        std::fs::write(&path, "old contents, longer than the new").unwrap();
        write_atomic(&path, b"new").unwrap();
        assert_eq!(std::fs::read(&path).unwrap(), b"new");
        assert_eq!(names(dir.path()), ["out.txt"]);
        #[cfg(unix)]
        {
            use std::os::unix::fs::PermissionsExt;
            let mode = std::fs::metadata(&path).unwrap().permissions().mode();
            let reference = dir.path().join("plain.txt");
            std::fs::write(&reference, b"").unwrap();
            let plain = std::fs::metadata(&reference).unwrap().permissions().mode();
            assert_eq!(
                mode & 0o777,
                plain & 0o777,
                "permissions of a plainly created file"
            );
        }
    }

    #[test]
    fn a_failed_write_names_the_path_and_leaves_no_temporary_file() {
        let dir = tempfile::tempdir().unwrap();
        // The target is a non-empty folder: the temporary file is written, then cannot replace it.
        let target = dir.path().join("taken");
        std::fs::create_dir(&target).unwrap();
        std::fs::write(target.join("inside"), b"x").unwrap();
        let e = format!("{:#}", write_atomic(&target, b"data").unwrap_err());
        assert!(
            e.starts_with(&format!("{}: cannot write", target.display())),
            "{e}"
        );
        assert_eq!(names(dir.path()), ["taken"]);
        assert_eq!(names(&target), ["inside"]);
        // A missing folder.
        let missing = dir.path().join("no-such-folder").join("out.txt");
        let e = format!("{:#}", write_atomic(&missing, b"data").unwrap_err());
        assert!(
            e.starts_with(&format!("{}: cannot write", missing.display())),
            "{e}"
        );
        assert_eq!(names(dir.path()), ["taken"]);
    }

    #[test]
    fn a_png_is_written_whole_or_not_at_all() {
        let dir = tempfile::tempdir().unwrap();
        let rgba = image::RgbaImage::from_fn(3, 2, |x, y| image::Rgba([x as u8 * 80, y as u8 * 200, 7, 255]));
        let path = dir.path().join("a.png");
        write_png(&path, &rgba).unwrap();
        assert_eq!(image::open(&path).unwrap().to_rgba8(), rgba);
        assert_eq!(names(dir.path()), ["a.png"]);
        // A `DynamicImage` of RGB pixels keeps its three channels.
        let rgb = image::DynamicImage::ImageRgb8(image::RgbImage::from_pixel(2, 2, image::Rgb([1, 2, 3])));
        let back = image::load_from_memory(&encode_png(&rgb).unwrap()).unwrap();
        assert_eq!(back.color(), image::ColorType::Rgb8);
        assert_eq!(back.to_rgb8().get_pixel(1, 1).0, [1, 2, 3]);
        // Pixels PNG cannot hold (32-bit float) are refused before anything is written; so is a missing folder.
        let bad = image::DynamicImage::ImageRgb32F(image::Rgb32FImage::new(1, 1));
        let e = format!("{:#}", write_png(&dir.path().join("f.png"), &bad).unwrap_err());
        assert!(e.contains("f.png: cannot write"), "{e}");
        let missing = dir.path().join("no-such-folder").join("b.png");
        let e = format!("{:#}", write_png(&missing, &rgba).unwrap_err());
        assert!(
            e.starts_with(&format!("{}: cannot write", missing.display())),
            "{e}"
        );
        assert_eq!(names(dir.path()), ["a.png"]);
    }

    #[test]
    fn outputs_are_checked_before_the_work() {
        let dir = tempfile::tempdir().unwrap();
        let ok = dir.path().join("shot.PNG");
        check_output(&ok, "png").unwrap();
        let e = format!(
            "{:#}",
            check_output(&dir.path().join("a.txt"), "hair").unwrap_err()
        );
        assert!(e.ends_with("a.txt: the output must be a .hair file"), "{e}");
        let missing = dir.path().join("nowhere/shot.png");
        let e = format!("{:#}", check_output(&missing, "png").unwrap_err());
        assert!(
            e.contains("nowhere/shot.png: the folder") && e.ends_with("does not exist"),
            "{e}"
        );
        let folder = dir.path().join("x.png");
        std::fs::create_dir(&folder).unwrap();
        let e = format!("{:#}", check_output(&folder, "png").unwrap_err());
        assert!(e.ends_with("x.png: is a folder, not a file"), "{e}");
    }

    #[test]
    fn reads_are_bounded_to_regular_files() {
        let dir = tempfile::tempdir().unwrap();
        let e = read_regular_file(dir.path()).unwrap_err();
        assert_eq!(e.to_string(), "not a regular file");
        let f = dir.path().join("a.bin");
        std::fs::write(&f, [1, 2, 3]).unwrap();
        assert_eq!(read_regular_file(&f).unwrap(), [1, 2, 3]);
        #[cfg(unix)]
        {
            let e = read_regular_file(std::path::Path::new("/dev/zero")).unwrap_err();
            assert_eq!(e.to_string(), "not a regular file");
            let link = dir.path().join("zero.hair");
            std::os::unix::fs::symlink("/dev/zero", &link).unwrap();
            assert_eq!(
                read_regular_file(&link).unwrap_err().to_string(),
                "not a regular file"
            );
        }
        assert!(read_regular_file(&dir.path().join("missing")).is_err());
    }

    #[test]
    fn over_black_encodes_premultiplied_linear_colour_as_srgb() {
        // sRGB of linear 0.5 is 1.055 · 0.5^(1/2.4) − 0.055 = 0.735357 → 187.52 → 188; 0.002 is on the linear
        // segment: 12.92 · 0.002 · 255 = 6.59 → 7; out-of-range values clamp. Alpha (1 − T) is not drawn.
        let capture = [
            [0.5, 0.002, 0.0, 0.3],
            [1.0, 2.0, -1.0, 1.0],
            [0.0, 0.0, 0.0, 0.0],
        ];
        let img = over_black(&capture, 3, 1);
        assert_eq!(img.get_pixel(0, 0).0, [188, 7, 0, 255]);
        assert_eq!(img.get_pixel(1, 0).0, [255, 255, 0, 255]);
        assert_eq!(img.get_pixel(2, 0).0, [0, 0, 0, 255]);
    }
}
