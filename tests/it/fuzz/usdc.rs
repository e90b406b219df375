//! Binary USD: mutations of `.usdc` stages and of the `.usdc` inside a `.usdz` (issue 34), and of a large tiled
//! groom (issue 43) whose sizes are claimed beyond what their bytes hold. The patched `openusd` reader must refuse
//! (an error naming the file), never panic or abort, and never turn a claimed size into an allocation larger than
//! the bytes could decode to: a compressed block's LZ4 output (at most 255 times the block), an uncompressed
//! array's bytes left in the file. `HAIRLAB_FUZZ_USDC_MB` sets the large seed's size in MiB (unset: 64 KiB, for
//! CI); the long campaign runs 50 under `ulimit -v 4194304`, where one allocation sized by the old bound (256 times
//! the file) aborts the process.

use std::ops::Range;

use hairlab::rng::SplitMix64;
use hairlab::scene::load::load_scene;
use openusd::sdf::{AbstractData, Value};
use openusd::usdc::{CrateFile, CrateWriter};

use super::{env, fuzz_strand_format_with, mutate_binary, word32};

/// 64-bit words a `.usdc` mutation puts in place of a count, size or offset (the crate file's are `u64`).
const WORDS64: [u64; 9] = [
    0,
    1,
    0xffff_ffff,
    0x1_0000_0000,
    0x7fff_ffff_ffff_ffff,
    0x8000_0000_0000_0000,
    0xffff_ffff_ffff_ffff,
    0x0000_1000_0000_00ae,
    1 << 40,
];

/// One of [`WORDS64`] or a small random count.
fn word64(rng: &mut SplitMix64) -> u64 {
    match rng.int(0, WORDS64.len()) {
        i if i < WORDS64.len() => WORDS64[i],
        _ => rng.int(0, 256) as u64,
    }
}

/// [`mutate_binary`], then, in half the cases, one aligned 64-bit little-endian word replaced by [`word64`]
/// (issue 34: the crate file's sizes, offsets and counts are `u64`).
fn mutate_usdc(rng: &mut SplitMix64, seed: &[u8]) -> Vec<u8> {
    let mut bytes = mutate_binary(rng, seed);
    if rng.int(0, 1) == 0 && bytes.len() >= 8 {
        let at = 8 * rng.int(0, bytes.len() / 8 - 1);
        bytes[at..at + 8].copy_from_slice(&word64(rng).to_le_bytes());
    }
    bytes
}

/// The `.usdc` seeds: the USD tests' hand stage (BasisCurves with widths and time samples, transforms) and the
/// writer's groom (every array), each re-encoded by the `openusd` crate's usdc writer.
fn usdc_seeds() -> Vec<Vec<u8>> {
    let written =
        hairlab::scene::usda_write::write_usda(&[crate::groom_formats::uniform_groom()], 24.0).unwrap();
    [crate::usd_format::HAND_STAGE.to_string(), written]
        .iter()
        .map(|text| encode(&openusd::usda::parse(text).unwrap()))
        .collect()
}

/// `data` as a `.usdc` file, by the crate's writer.
fn encode(data: &dyn AbstractData) -> Vec<u8> {
    let mut out = std::io::Cursor::new(Vec::new());
    CrateWriter::write(data, &mut out).unwrap();
    out.into_inner()
}

/// Binary mutations of `.usdc` stages (issue 34): the patched `openusd` reader must refuse, never panic or abort.
#[test]
fn mutated_usdc_files_fail_cleanly() {
    fuzz_strand_format_with("usdc", &usdc_seeds(), mutate_usdc);
}

/// The same mutations of the inner `.usdc` of a `.usdz` whose zip stays valid (stored, 64-byte aligned).
#[test]
fn mutated_usdz_files_fail_cleanly() {
    fuzz_strand_format_with("usdz", &usdc_seeds(), |rng, seed| {
        crate::usd_format::usdz_of("stage.usdc", &mutate_usdc(rng, seed))
    });
}

/// Points of the writer's groom (2 strands of 4).
const GROOM_POINTS: usize = 8;

/// The writer's groom with each of its arrays (counts, points, widths, colours, opacities) repeated `times` times,
/// as a `.usdc`: `2 * times` strands, 32 bytes a point, the point arrays uncompressed, the counts LZ4 blocks.
fn tiled_groom_usdc(times: usize) -> Vec<u8> {
    let text =
        hairlab::scene::usda_write::write_usda(&[crate::groom_formats::uniform_groom()], 24.0).unwrap();
    let mut data = openusd::usda::parse(&text).unwrap();
    for path in data.spec_paths() {
        match data.spec_mut(&path).and_then(|spec| spec.get_mut("default")) {
            Some(Value::IntVec(v)) => *v = v.repeat(times),
            Some(Value::FloatVec(v)) => *v = v.repeat(times),
            Some(Value::Vec3fVec(v)) => *v = v.repeat(times),
            _ => {}
        }
    }
    encode(&data)
}

/// Where a claimed size sits in a crate file: its sections (the structure after the arrays) and the count in
/// front of each point array.
struct Layout {
    /// Start of each section by name.
    sections: Vec<(String, usize)>,
    /// The first section's start: the arrays lie before it.
    tail: usize,
    /// Offsets of the `u64` element counts of the point arrays.
    array_counts: Vec<usize>,
}

impl Layout {
    fn of(file: &[u8], points: usize) -> Layout {
        let crate_file = CrateFile::open(std::io::Cursor::new(file)).unwrap();
        let sections: Vec<(String, usize)> = crate_file
            .sections
            .iter()
            .map(|s| (s.name().to_string(), s.start as usize))
            .collect();
        let tail = sections.iter().map(|s| s.1).min().unwrap();
        let array_counts = (32..tail - 8)
            .filter(|&at| file[at..at + 8] == (points as u64).to_le_bytes())
            .collect();
        Layout {
            sections,
            tail,
            array_counts,
        }
    }

    fn section(&self, name: &str) -> usize {
        self.sections.iter().find(|s| s.0 == name).unwrap().1
    }

    /// Byte ranges a structural mutation aims at: the bootstrap header, each array's count and the sections.
    fn hot(&self, len: usize) -> Vec<Range<usize>> {
        let mut hot = vec![0..32, self.tail..len];
        hot.extend(self.array_counts.iter().map(|&at| at - 8..at + 16));
        hot
    }
}

/// The u64 at `at` of `file` set to `value`.
fn patched(file: &[u8], at: usize, value: u64) -> Vec<u8> {
    let mut out = file.to_vec();
    out[at..at + 8].copy_from_slice(&value.to_le_bytes());
    out
}

/// One to three mutations of the large seed, each at a structural offset ([`Layout::hot`]) three times in four,
/// else anywhere: a 64-bit word set by [`word64`], a 32-bit word by [`word32`], a byte at random, or (one in
/// eight) the file cut there.
fn mutate_large(rng: &mut SplitMix64, seed: &[u8], hot: &[Range<usize>]) -> Vec<u8> {
    let mut bytes = seed.to_vec();
    for _ in 0..rng.int(1, 3) {
        if bytes.len() < 8 {
            break;
        }
        let at = if rng.int(0, 3) < 3 {
            let range = &hot[rng.int(0, hot.len() - 1)];
            rng.int(range.start, range.end - 1)
        } else {
            rng.int(0, seed.len() - 1)
        };
        let at = at.min(bytes.len() - 8);
        match rng.int(0, 7) {
            0..=2 => bytes[at..at + 8].copy_from_slice(&word64(rng).to_le_bytes()),
            3 | 4 => bytes[at..at + 4].copy_from_slice(&word32(rng).to_le_bytes()),
            5 | 6 => bytes[at] = rng.next_u64() as u8,
            _ => bytes.truncate(at),
        }
    }
    bytes
}

/// Issue 43: a large groom (`HAIRLAB_FUZZ_USDC_MB`, 64 KiB unset) loads whole; three sizes patched to claim far
/// more than their bytes hold are refused, each by its bound; then `HAIRLAB_FUZZ_CASES` mutations aimed at its
/// structure load or fail cleanly.
///
/// The claims, for a file of `n` bytes: the TOKENS section's decompressed size set to `128 n` (the old bound, `256
/// n`, let it through: 6.7 GB for the 52 MB seed) from a block of a few hundred bytes; a points array's count set to
/// 2^40; the FIELDS section's count set to `16 n` (an estimated buffer of `68 n` bytes under the old bound). With
/// the bounds, the largest allocation a claim can ask for is 255 times its compressed block plus 64 bytes (32
/// times that for the ints it decodes, 2 bits a code) or the bytes left in the file, so under `ulimit -v` the
/// patched files are refused where the old reader aborted.
#[test]
fn large_usdc_claims_fail_cleanly() {
    let mib = env("HAIRLAB_FUZZ_USDC_MB", 0) as usize;
    let times = if mib == 0 { 256 } else { mib << 12 };
    let seed = tiled_groom_usdc(times);
    let n = seed.len();
    assert!(n >= (mib << 20), "{n} bytes");
    let layout = Layout::of(&seed, GROOM_POINTS * times);
    assert_eq!(layout.array_counts.len(), 4, "points, widths, colours, opacities");

    let dir = tempfile::tempdir().expect("tempdir");
    let whole = dir.path().join("seed.usdc");
    std::fs::write(&whole, &seed).unwrap();
    let scene = load_scene(&whole).unwrap();
    assert_eq!(scene.strands.counts.len(), 2 * times);
    assert_eq!(scene.strands.points.len(), GROOM_POINTS * times);

    let tokens = layout.section("TOKENS");
    let fields = layout.section("FIELDS");
    let claims = [
        (
            "tokens.usdc",
            patched(&seed, tokens + 8, 128 * n as u64),
            "more than the",
        ),
        (
            "points.usdc",
            patched(&seed, layout.array_counts[0], 1 << 40),
            "runs past the end of the file",
        ),
        (
            "fields.usdc",
            patched(&seed, fields, 16 * n as u64),
            "code table past end of buffer",
        ),
    ];
    for (name, bytes, bound) in claims {
        let path = dir.path().join(name);
        std::fs::write(&path, bytes).unwrap();
        let msg = format!("{:#}", load_scene(&path).unwrap_err());
        assert!(msg.contains(name) && msg.contains(bound), "{msg}");
        std::fs::remove_file(&path).unwrap();
    }

    let hot = layout.hot(n);
    fuzz_strand_format_with("usdc", &[seed], |rng, seed| mutate_large(rng, seed, &hot));
}

/// The TOKENS section's decompressed size against its LZ4 block of `b` bytes: `255 b + 64` (LZ4's largest
/// expansion, written here by hand) passes the bound and fails on the size the block really gives; one byte more
/// is refused by the bound, before the reader allocates it.
#[test]
fn tokens_claim_is_bounded_by_its_block() {
    let seed = &usdc_seeds()[1];
    let tokens = Layout::of(seed, GROOM_POINTS).section("TOKENS");
    let block = u64::from_le_bytes(seed[tokens + 16..tokens + 24].try_into().unwrap());
    let dir = tempfile::tempdir().expect("tempdir");
    for (claim, cause) in [
        (255 * block + 64, "Decompressed size mismatch"),
        (255 * block + 65, "more than the"),
    ] {
        let path = dir.path().join(format!("claim{claim}.usdc"));
        std::fs::write(&path, patched(seed, tokens + 8, claim)).unwrap();
        let msg = format!("{:#}", load_scene(&path).unwrap_err());
        assert!(
            msg.contains(&format!("claim{claim}.usdc")) && msg.contains(cause),
            "{msg}"
        );
    }
}
