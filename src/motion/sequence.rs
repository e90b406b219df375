//! Recorded motion: a folder of `.hair` files of identical topology, sorted by name, one per frame, or a USD
//! stage whose BasisCurves points are time-sampled (one frame per time code, in time-code order). The whole
//! recording is read and checked when it is opened, so a missing, unreadable or differently shaped frame is one
//! error naming its file (or time code) before anything is shown.

use crate::scene::Strands;
use crate::scene::hair::read_hair_file;
use anyhow::{Context, Result, bail};
use glam::Vec3;
use std::path::{Path, PathBuf};

/// The frames of a sequence: the first frame's strands (topology, thickness, alpha, colour) and every frame's
/// points.
pub struct Sequence {
    files: Vec<PathBuf>,
    strands: Strands,
    frames: Vec<Vec<Vec3>>,
}

impl Sequence {
    /// Reads every `.hair` file in `dir` (sorted by file name), or the frames of the USD stage `dir` names.
    pub fn open(dir: &Path) -> Result<Sequence> {
        let ext = dir.extension().map(|e| e.to_string_lossy().to_ascii_lowercase());
        if matches!(ext.as_deref(), Some("usda" | "usdc" | "usdz")) {
            return Self::open_usd(dir);
        }
        let entries = std::fs::read_dir(dir)
            .with_context(|| format!("motion.path: {}: cannot read the folder", dir.display()))?;
        let mut files = Vec::new();
        for e in entries {
            let e = e.with_context(|| format!("motion.path: {}: cannot list the folder", dir.display()))?;
            let path = e.path();
            if path.extension().is_some_and(|x| x.eq_ignore_ascii_case("hair")) {
                files.push(path);
            }
        }
        files.sort_by(|a, b| a.file_name().cmp(&b.file_name()));
        let Some(first) = files.first() else {
            bail!("motion.path: {} holds no .hair files", dir.display());
        };
        let strands = read_hair_file(first)
            .and_then(|h| h.to_strands())
            .map_err(|e| anyhow::anyhow!("motion.path: frame 0: {e}"))?;
        let mut frames = Vec::with_capacity(files.len());
        frames.push(strands.points.clone());
        for (k, f) in files.iter().enumerate().skip(1) {
            let s = read_hair_file(f)
                .and_then(|h| h.to_strands())
                .map_err(|e| anyhow::anyhow!("motion.path: frame {k}: {e}"))?;
            if s.counts != strands.counts {
                bail!(
                    "motion.path: frame {k}: {}: its topology differs from the first frame {} ({} strands, {} \
                     points against {} strands, {} points{}): a sequence's frames must have identical topology",
                    f.display(),
                    first.display(),
                    s.strand_count(),
                    s.point_count(),
                    strands.strand_count(),
                    strands.point_count(),
                    if s.strand_count() == strands.strand_count() && s.point_count() == strands.point_count()
                    {
                        ", points per strand differ"
                    } else {
                        ""
                    }
                );
            }
            frames.push(s.points);
        }
        Ok(Sequence {
            files,
            strands,
            frames,
        })
    }

    /// The time-sampled frames of a USD stage (`crate::scene::usd::read_usd_frames`: constant topology, else
    /// one error naming the time code).
    #[cfg(feature = "usd")]
    fn open_usd(path: &Path) -> Result<Sequence> {
        let usd =
            crate::scene::usd::read_usd_frames(path).map_err(|e| anyhow::anyhow!("motion.path: {e}"))?;
        let Some(first) = usd.frames.first() else {
            bail!("motion.path: {}: the stage holds no frames", path.display());
        };
        Ok(Sequence {
            files: vec![path.to_path_buf(); usd.frames.len()],
            strands: first.clone(),
            frames: usd.frames.into_iter().map(|f| f.points).collect(),
        })
    }

    #[cfg(not(feature = "usd"))]
    fn open_usd(path: &Path) -> Result<Sequence> {
        bail!(
            "motion.path: {}: this hairlab was built without the `usd` feature",
            path.display()
        )
    }

    /// The first frame's strands.
    pub fn strands(&self) -> &Strands {
        &self.strands
    }

    pub fn len(&self) -> usize {
        self.frames.len()
    }

    pub fn is_empty(&self) -> bool {
        self.frames.is_empty()
    }

    /// The file of frame `k`.
    pub fn file(&self, k: usize) -> Option<&Path> {
        self.files.get(k).map(PathBuf::as_path)
    }

    /// Frame `k`'s points.
    pub fn frame(&self, k: u32) -> Result<&[Vec3]> {
        match self.frames.get(k as usize) {
            Some(p) => Ok(p),
            None => bail!(
                "frame {k} is beyond the sequence's {} frames (0..={})",
                self.frames.len(),
                self.frames.len() - 1
            ),
        }
    }
}
