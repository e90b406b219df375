//! Bounded mutation runs over every input format hairlab reads (issue 11's "fuzzing as a habit"): glTF and glb,
//! `.hair`, TressFX `.tfx`, USC-HairSalon `.data`, USD (text and composed stages in [`usda`], binary and zipped in
//! [`usdc`]), the fragment CSV of `hairlab curve`, and preset TOML with `--set` overrides. Each seed is a file the tests write; each case mutates it a few times (a number token replaced by an
//! extreme, a byte overwritten, the text cut short; for `.tfx` and `.data` also an aligned 32-bit word — a count,
//! an offset, a coordinate — replaced by an extreme) and must load or fail with an error naming its source — never
//! panic (a panic fails the test)
//! and, for glTF, never get as far as a panic inside the `gltf` crate. 2000 cases per format run in about a second;
//! a long run sets `HAIRLAB_FUZZ_CASES` (cases per format) and `HAIRLAB_FUZZ_SEED`. Every case is timed: one over
//! [`TIMEOUT`] is a hang the mutation found (a failure), and the slowest case of each format is printed.

use hairlab::rng::SplitMix64;
use hairlab::scene::gltf_load::load_gltf;
use hairlab::scene::hair::{HairFile, read_hair_file, write_hair};
use hairlab::scene::load::load_scene;
use hairlab::scene::tfx::{TfxFile, write_tfx};
use hairlab::scene::usc_data::write_data;
use hairlab::settings::Settings;
use std::time::{Duration, Instant};

#[cfg(feature = "usd")]
mod usda;
#[cfg(feature = "usd")]
mod usdc;

/// Number tokens a mutation puts in place of another.
const NUMBERS: [&str; 10] = [
    "0",
    "1",
    "3",
    "7",
    "99",
    "65536",
    "4294967295",
    "-1",
    "1e30",
    "nan",
];

/// A case slower than this is a timeout (a loop or read the input made unbounded), not a slow machine: the
/// slowest case measured is under a millisecond.
const TIMEOUT: Duration = Duration::from_secs(10);

/// The slowest case of a run.
#[derive(Default)]
struct Slowest {
    time: Duration,
    case: u64,
}

impl Slowest {
    /// Runs case `case`, keeping its time when it is the slowest so far; a timeout fails the test.
    fn time<T>(&mut self, case: u64, f: impl FnOnce() -> T) -> T {
        let start = Instant::now();
        let out = f();
        let t = start.elapsed();
        assert!(
            t < TIMEOUT,
            "case {case} took {t:?}, over the {TIMEOUT:?} timeout"
        );
        if t > self.time {
            (self.time, self.case) = (t, case);
        }
        out
    }
}

impl std::fmt::Display for Slowest {
    fn fmt(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        write!(
            f,
            "slowest case {} in {:.3} ms",
            self.case,
            self.time.as_secs_f64() * 1e3
        )
    }
}

fn env(key: &str, default: u64) -> u64 {
    std::env::var(key)
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

/// Judges one case's outcome: a scene it loaded must be whole (the strand counts sum to the points, every point
/// finite), an error must name `file` (the case's file); `true` when it loaded.
fn loaded_whole(case: u64, outcome: anyhow::Result<hairlab::scene::Scene>, file: &str) -> bool {
    match outcome {
        Ok(scene) => {
            let s = &scene.strands;
            let total: u64 = s.counts.iter().map(|&c| u64::from(c)).sum();
            assert_eq!(total, s.points.len() as u64, "case {case}");
            assert!(s.points.iter().all(|p| p.is_finite()), "case {case}");
            true
        }
        Err(e) => {
            let msg = format!("{e:#}");
            assert!(msg.contains(file), "{msg}");
            false
        }
    }
}

/// Cases per format and the generator of the run.
fn run() -> (u64, SplitMix64) {
    (
        env("HAIRLAB_FUZZ_CASES", 2000),
        SplitMix64::new(env("HAIRLAB_FUZZ_SEED", 11)),
    )
}

/// `seed` mutated one to three times.
fn mutate(rng: &mut SplitMix64, seed: &[u8]) -> Vec<u8> {
    let mut bytes = seed.to_vec();
    for _ in 0..rng.int(1, 3) {
        match rng.int(0, 3) {
            // A number token replaced (indices, counts, offsets, lengths, strides, depths, alphas, keys' values).
            0 | 1 => {
                let starts: Vec<usize> = (1..bytes.len())
                    .filter(|&i| bytes[i].is_ascii_digit() && !bytes[i - 1].is_ascii_alphanumeric())
                    .collect();
                if !starts.is_empty() {
                    let at = starts[rng.int(0, starts.len() - 1)];
                    let end = (at..bytes.len()).find(|&i| !bytes[i].is_ascii_digit() && bytes[i] != b'.');
                    let n = NUMBERS[rng.int(0, NUMBERS.len() - 1)];
                    bytes.splice(at..end.unwrap_or(bytes.len()), n.bytes());
                }
            }
            2 if !bytes.is_empty() => {
                let at = rng.int(0, bytes.len() - 1);
                bytes[at] = rng.next_u64() as u8;
            }
            _ => {
                let keep = rng.int(0, bytes.len().saturating_sub(1));
                bytes.truncate(keep);
            }
        }
    }
    bytes
}

/// 32-bit words a binary mutation writes over an aligned word: counts and offsets at and past every bound, and
/// the extreme floats.
const WORDS: [u32; 12] = [
    0,
    1,
    2,
    3,
    4,
    160,
    0x7fff_ffff,
    0x8000_0000,
    0xffff_ffff,
    0x7fc0_0000, // NaN
    0x7f80_0000, // +inf
    0xbf80_0000, // -1.0
];

/// [`mutate`], then, in half the cases, one aligned 32-bit little-endian word replaced by one of [`WORDS`] or a
/// small random count.
fn mutate_binary(rng: &mut SplitMix64, seed: &[u8]) -> Vec<u8> {
    let mut bytes = mutate(rng, seed);
    if rng.int(0, 1) == 0 && bytes.len() >= 4 {
        let at = 4 * rng.int(0, bytes.len() / 4 - 1);
        bytes[at..at + 4].copy_from_slice(&word32(rng).to_le_bytes());
    }
    bytes
}

/// One of [`WORDS`] or a small random count.
fn word32(rng: &mut SplitMix64) -> u32 {
    match rng.int(0, WORDS.len()) {
        i if i < WORDS.len() => WORDS[i],
        _ => rng.int(0, 64) as u32,
    }
}

/// One binary format's run: `cases` mutations of `seeds` (picked in turn) loaded through [`load_scene`] as
/// `case<N>.<ext>`. A loaded groom must be consistent (its counts add up to its points, every point finite);
/// a refusal must name the file.
fn fuzz_strand_format(ext: &str, seeds: &[Vec<u8>]) {
    fuzz_strand_format_with(ext, seeds, mutate_binary);
}

/// [`fuzz_strand_format`] with the mutation `mutator`.
fn fuzz_strand_format_with(
    ext: &str,
    seeds: &[Vec<u8>],
    mutator: impl Fn(&mut SplitMix64, &[u8]) -> Vec<u8>,
) {
    let dir = tempfile::tempdir().expect("tempdir");
    let (cases, mut rng) = run();
    let (mut loaded, mut refused) = (0, 0);
    let mut slowest = Slowest::default();
    let start = Instant::now();
    for case in 0..cases {
        let seed = &seeds[case as usize % seeds.len()];
        let path = dir.path().join(format!("case{case}.{ext}"));
        std::fs::write(&path, mutator(&mut rng, seed)).unwrap();
        let outcome = slowest.time(case, || load_scene(&path));
        if loaded_whole(case, outcome, &format!("case{case}.{ext}")) {
            loaded += 1;
        } else {
            refused += 1;
        }
        std::fs::remove_file(&path).unwrap();
    }
    eprintln!(
        ".{ext}: {cases} cases, {loaded} load, {refused} refused, {slowest}, {:.1} s in all",
        start.elapsed().as_secs_f64()
    );
    assert!(loaded > 0 && refused > 0, "{loaded} loaded, {refused} refused");
}

#[test]
fn mutated_tfx_files_fail_cleanly() {
    let groom = TfxFile::from_strands(&crate::groom_formats::uniform_groom()).unwrap();
    fuzz_strand_format(
        "tfx",
        &[write_tfx(&groom), crate::groom_formats::hand_built_tfx()],
    );
}

#[test]
fn mutated_data_files_fail_cleanly() {
    let groom = write_data(&crate::groom_formats::uniform_groom()).unwrap();
    fuzz_strand_format("data", &[groom, crate::groom_formats::hand_built_data()]);
}

/// The glb form of a text glTF: its JSON as the one chunk.
fn glb_of(text: &[u8]) -> Vec<u8> {
    let mut json = text.to_vec();
    while !json.len().is_multiple_of(4) {
        json.push(b' ');
    }
    let mut glb = b"glTF".to_vec();
    glb.extend_from_slice(&2u32.to_le_bytes());
    glb.extend_from_slice(&((12 + 8 + json.len()) as u32).to_le_bytes());
    glb.extend_from_slice(&(json.len() as u32).to_le_bytes());
    glb.extend_from_slice(b"JSON");
    glb.extend_from_slice(&json);
    glb
}

#[test]
fn mutated_gltf_and_glb_files_fail_cleanly() {
    let dir = tempfile::tempdir().expect("tempdir");
    let text = std::fs::read(crate::gltf_load::sample(dir.path())).unwrap();
    let glb = glb_of(&text);
    let (cases, mut rng) = run();
    let (mut loaded, mut refused, mut gave_up) = (0, 0, Vec::new());
    let mut slowest = Slowest::default();
    for case in 0..cases {
        let (seed, ext) = if case % 2 == 0 {
            (&text, "gltf")
        } else {
            (&glb, "glb")
        };
        let path = dir.path().join(format!("case{case}.{ext}"));
        std::fs::write(&path, mutate(&mut rng, seed)).unwrap();
        match slowest.time(case, || load_gltf(&path)) {
            Ok(_) => loaded += 1,
            Err(e) => {
                let msg = e.to_string();
                assert!(msg.contains(&format!("case{case}.{ext}")), "{msg}");
                if msg.contains("the glTF reader gave up") {
                    gave_up.push(msg);
                }
                refused += 1;
            }
        }
        std::fs::remove_file(&path).unwrap();
    }
    eprintln!(
        "glTF/glb: {cases} cases, {loaded} load, {refused} refused, {} crate panics, {slowest}",
        gave_up.len()
    );
    assert!(loaded > 0 && refused > 0, "{loaded} loaded, {refused} refused");
    assert!(
        gave_up.is_empty(),
        "{} panics inside the glTF crate: {gave_up:#?}",
        gave_up.len()
    );
}

#[test]
fn mutated_hair_files_fail_cleanly() {
    let dir = tempfile::tempdir().expect("tempdir");
    let file = HairFile::from_strands(&crate::hair_format::full_strands(), "fuzz seed").unwrap();
    let seed = write_hair(&file);
    let (cases, mut rng) = run();
    let (mut loaded, mut refused) = (0, 0);
    let mut slowest = Slowest::default();
    for case in 0..cases {
        let path = dir.path().join(format!("case{case}.hair"));
        std::fs::write(&path, mutate(&mut rng, &seed)).unwrap();
        match slowest.time(case, || {
            read_hair_file(&path).and_then(|h| h.to_strands().map(|_| ()))
        }) {
            Ok(()) => loaded += 1,
            Err(e) => {
                assert!(e.to_string().contains(&format!("case{case}.hair")), "{e}");
                refused += 1;
            }
        }
        std::fs::remove_file(&path).unwrap();
    }
    eprintln!(".hair: {cases} cases, {loaded} load, {refused} refused, {slowest}");
    assert!(loaded > 0 && refused > 0, "{loaded} loaded, {refused} refused");
}

#[test]
fn mutated_fragment_csv_fails_cleanly() {
    let seed = b"# a texel\ndepth,alpha\n0.10,0.35\n0.25,0.5\n\n0.5,0.2\n0.75,0.9\n1.0,0.05\n";
    let (cases, mut rng) = run();
    let (mut parsed, mut refused) = (0, 0);
    let mut slowest = Slowest::default();
    for case in 0..cases {
        let text = String::from_utf8_lossy(&mutate(&mut rng, seed)).into_owned();
        let source = format!("case{case}.csv");
        match slowest.time(case, || hairlab::cli::parse_fragments_csv(&text, &source)) {
            Ok(frags) => {
                assert!(
                    frags
                        .iter()
                        .all(|f| (0.0..=1.0).contains(&f.depth) && (0.0..1.0).contains(&f.alpha)),
                    "{text:?}: {frags:?}"
                );
                parsed += 1;
            }
            Err(e) => {
                assert!(e.to_string().starts_with(&source), "{e}");
                refused += 1;
            }
        }
    }
    eprintln!("fragment CSV: {cases} cases, {parsed} parse, {refused} refused, {slowest}");
    assert!(parsed > 0 && refused > 0, "{parsed} parsed, {refused} refused");
}

#[test]
fn mutated_presets_and_overrides_fail_cleanly() {
    let seeds: Vec<&str> = hairlab::settings::BUILTIN_PRESETS
        .iter()
        .map(|(_, t)| *t)
        .collect();
    let keys = [
        "camera.yaw_deg",
        "light.azimuth_deg",
        "render.map_resolution",
        "render.hair_alpha",
        "render.strand_width",
        "scene.generator.strands",
        "method.name",
        "render",
        "fur.mode",
        "fur.layers",
        "fur.height",
        "fur.group_steps",
    ];
    let (cases, mut rng) = run();
    let (mut loaded, mut refused) = (0, 0);
    let mut slowest = Slowest::default();
    for case in 0..cases {
        let seed = seeds[rng.int(0, seeds.len() - 1)];
        let text = String::from_utf8_lossy(&mutate(&mut rng, seed.as_bytes())).into_owned();
        let overrides: Vec<String> = (0..rng.int(0, 2))
            .map(|_| {
                let key = keys[rng.int(0, keys.len() - 1)];
                format!("{key}={}", NUMBERS[rng.int(0, NUMBERS.len() - 1)])
            })
            .collect();
        let origin = format!("case{case}.toml");
        match slowest.time(case, || Settings::from_toml_with(&text, &origin, &overrides)) {
            Ok(s) => {
                s.validate().expect("a loaded preset is valid");
                loaded += 1;
            }
            Err(e) => {
                let msg = format!("{e:#}");
                assert!(msg.contains(&origin) || msg.contains("--set"), "{msg}");
                refused += 1;
            }
        }
    }
    eprintln!("presets: {cases} cases, {loaded} load, {refused} refused, {slowest}");
    assert!(loaded > 0 && refused > 0, "{loaded} loaded, {refused} refused");
}
