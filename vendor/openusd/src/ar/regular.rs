//! Every asset is read the way a root layer is (hairlab patch): regular files only, looked at through their
//! metadata *before* they are opened — so a named pipe, which would block the open until a writer comes, a device
//! (`/dev/zero`) or a folder is one error naming the path, never a hang — and at most [`max_asset_bytes`] bytes
//! (1 GiB unless [`set_max_asset_bytes`] says otherwise), reading no more than the size the file had when opened.
//! Package (`.usdz`) entries get the same cap on their uncompressed size.

use std::fs;
use std::io::{self, Read, Seek, SeekFrom};
use std::path::Path;
use std::sync::atomic::{AtomicU64, Ordering};

use super::Asset;

/// The default of [`max_asset_bytes`]: 1 GiB.
pub const DEFAULT_MAX_ASSET_BYTES: u64 = 1 << 30;

static MAX_ASSET_BYTES: AtomicU64 = AtomicU64::new(DEFAULT_MAX_ASSET_BYTES);

/// The most bytes a layer, package or package entry may hold to be read, process-wide.
pub fn max_asset_bytes() -> u64 {
    MAX_ASSET_BYTES.load(Ordering::Relaxed)
}

/// Sets [`max_asset_bytes`] for every later read in the process.
pub fn set_max_asset_bytes(bytes: u64) {
    MAX_ASSET_BYTES.store(bytes, Ordering::Relaxed);
}

fn refused(path: &Path, what: impl std::fmt::Display) -> io::Error {
    io::Error::new(io::ErrorKind::InvalidInput, format!("{}: {what}", path.display()))
}

/// What a file that is not a regular file is, for errors.
fn kind(file_type: fs::FileType) -> &'static str {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if file_type.is_fifo() {
            return "a named pipe (FIFO)";
        }
        if file_type.is_char_device() || file_type.is_block_device() {
            return "a device";
        }
        if file_type.is_socket() {
            return "a socket";
        }
    }
    if file_type.is_dir() {
        "a folder"
    } else {
        "a special file"
    }
}

/// Checks `meta` (of `path`) is a regular file within [`max_asset_bytes`].
fn check(path: &Path, meta: &fs::Metadata) -> io::Result<()> {
    if !meta.is_file() {
        return Err(refused(path, format!("{}, not a regular file", kind(meta.file_type()))));
    }
    check_size(path, meta.len())
}

/// Checks `len` bytes of `path` are within [`max_asset_bytes`].
pub(crate) fn check_size(path: &Path, len: u64) -> io::Result<()> {
    let max = max_asset_bytes();
    if len > max {
        return Err(refused(path, format!("{len} bytes, more than the {max} bytes read")));
    }
    Ok(())
}

/// Refuses `path` when the file system holds something there that is not a regular file within
/// [`max_asset_bytes`]; a path it does not hold (an asset a custom resolver serves) passes.
pub fn refuse_special_file(path: &Path) -> io::Result<()> {
    match fs::metadata(path) {
        Ok(meta) => check(path, &meta),
        Err(_) => Ok(()),
    }
}

/// Opens `path` when it is a regular file (also through a symlink) of at most [`max_asset_bytes`]: its metadata is
/// checked before the open, and again through the opened handle (the file may have been replaced in between).
pub fn open_regular_file(path: &Path) -> io::Result<RegularFile> {
    check(path, &fs::metadata(path)?)?;
    let file = fs::File::open(path)?;
    let meta = file.metadata()?;
    check(path, &meta)?;
    Ok(RegularFile {
        file,
        len: meta.len(),
        pos: 0,
    })
}

/// A regular file read as an [`Asset`]: no byte past the size it had when opened is read.
pub struct RegularFile {
    file: fs::File,
    len: u64,
    pos: u64,
}

impl RegularFile {
    /// The file itself, for readers that need a [`fs::File`] (its size was checked).
    pub(crate) fn into_file(self) -> fs::File {
        self.file
    }
}

impl Read for RegularFile {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        let left = usize::try_from(self.len.saturating_sub(self.pos)).unwrap_or(usize::MAX);
        let n = buf.len().min(left);
        if n == 0 {
            return Ok(0);
        }
        let read = self.file.read(&mut buf[..n])?;
        self.pos += read as u64;
        Ok(read)
    }
}

impl Seek for RegularFile {
    fn seek(&mut self, pos: SeekFrom) -> io::Result<u64> {
        let pos = match pos {
            SeekFrom::End(offset) => SeekFrom::Start(self.len.saturating_add_signed(offset)),
            other => other,
        };
        self.pos = self.file.seek(pos)?;
        Ok(self.pos)
    }
}

impl Asset for RegularFile {
    fn size(&self) -> io::Result<u64> {
        Ok(self.len)
    }

    fn read_all(&mut self) -> io::Result<Vec<u8>> {
        let left = self.len.saturating_sub(self.pos);
        let mut bytes = reserve(left)?;
        self.read_to_end(&mut bytes)?;
        Ok(bytes)
    }
}

/// An empty buffer for `len` bytes: a memory error instead of an abort when the process may not have them (a
/// large sparse file under an address-space limit).
fn reserve(len: u64) -> io::Result<Vec<u8>> {
    let mut bytes = Vec::new();
    usize::try_from(len)
        .ok()
        .and_then(|n| bytes.try_reserve_exact(n).ok())
        .ok_or_else(|| io::Error::new(io::ErrorKind::OutOfMemory, format!("no memory for {len} bytes")))?;
    Ok(bytes)
}

/// Reads a package entry of `declared` uncompressed bytes (its central directory's word), named `name` in errors:
/// refused past [`max_asset_bytes`], and never more than it declared.
pub(crate) fn read_entry(entry: impl Read, declared: u64, name: &Path) -> io::Result<Vec<u8>> {
    check_size(name, declared)?;
    let mut bytes = reserve(declared)?;
    entry.take(declared).read_to_end(&mut bytes)?;
    Ok(bytes)
}
