//! Text USD: mutations of one stage (numbers, bytes, cuts) and of a stage composed across sibling files (issue
//! 43): a root layer with a sublayer, a reference, a payload, an internal reference and classes inherited and
//! specialized across the files, whose asset paths are rewritten (to a sibling, to the layer itself, to a missing
//! file, to a folder, to a named pipe, to `/dev/null`-like specials) and prim paths rewritten (to existing prims,
//! to an ancestor or the prim itself, to a missing prim). Each stage must load or fail with an error naming its
//! file, within the fuzz timeout, and never panic, overflow the stack or hang.

use hairlab::rng::SplitMix64;
use hairlab::scene::load::load_scene;

use super::{Slowest, env, fuzz_strand_format_with, mutate, run};

/// Text mutations of two stages: the hand-written one of the USD tests (Z-up centimetres, linear, bezier with time
/// samples, bspline, transforms, vertex, constant, uniform and varying primvars) and the writer's output for a
/// groom with every array. The `openusd` crate parses; a panic in it fails this test like one in hairlab.
#[test]
fn mutated_usda_files_fail_cleanly() {
    let written =
        hairlab::scene::usda_write::write_usda(&[crate::groom_formats::uniform_groom()], 24.0).unwrap();
    fuzz_strand_format_with(
        "usda",
        &[
            crate::usd_format::HAND_STAGE.as_bytes().to_vec(),
            written.into_bytes(),
        ],
        mutate,
    );
}

/// The root layer: a sublayer, class `_Hair` (inheriting `_Base` of the sublayer), curves inheriting and
/// specializing it, a reference, a payload and an internal reference.
const ROOT: &str = r#"#usda 1.0
(
    defaultPrim = "Groom"
    metersPerUnit = 1
    upAxis = "Y"
    subLayers = [
        @./sub.usda@
    ]
)

class "_Hair" (
    inherits = </_Base>
)
{
    uniform token type = "linear"
    int[] curveVertexCounts = [2]
    point3f[] points = [(0, 0, 0), (0, 1, 0)]
}

def Xform "Groom"
{
    def BasisCurves "Inherited" (
        inherits = </_Hair>
    )
    {
        point3f[] points = [(1, 0, 0), (1, 1, 0)]
    }

    def BasisCurves "Specialized" (
        specializes = </_Hair>
    )
    {
    }

    def "Referenced" (
        references = @./ref.usda@</Strands>
    )
    {
    }

    def "Paid" (
        payload = @./payload.usda@</Strands>
    )
    {
    }

    def "Internal" (
        references = </Groom/Inherited>
    )
    {
    }
}
"#;

/// The sublayer: classes `_Base` (specializing `_Root`) and `_Root`, and a prim over `/Groom` referencing the
/// binary form of `ref.usda`.
const SUB: &str = r#"#usda 1.0

class "_Base" (
    specializes = </_Root>
)
{
    uniform token wrap = "nonperiodic"
}

class "_Root"
{
    uniform token basis = "bezier"
}

over "Groom"
{
    def "FromSub" (
        references = @./ref.usdc@</Strands>
    )
    {
    }
}
"#;

/// The referenced layer: curves inheriting a local class and carrying a payload of their own.
const REF: &str = r#"#usda 1.0
(
    defaultPrim = "Strands"
)

class "_Local"
{
    uniform token type = "linear"
}

def BasisCurves "Strands" (
    inherits = </_Local>
    payload = @./payload.usda@</Strands>
)
{
    int[] curveVertexCounts = [3]
    point3f[] points = [(0, 0, 1), (0, 0.5, 1), (0, 1, 1)]
    float[] widths = [0.01, 0.01, 0.01]
}
"#;

/// The payload layer.
const PAYLOAD: &str = r#"#usda 1.0

def BasisCurves "Strands"
{
    uniform token type = "linear"
    int[] curveVertexCounts = [2, 2]
    point3f[] points = [(2, 0, 0), (2, 1, 0), (3, 0, 0), (3, 1, 0)]
}

def Xform "Other"
{
}
"#;

/// The text layers a case mutates, by file name.
const LAYERS: [(&str, &str); 4] = [
    ("root.usda", ROOT),
    ("sub.usda", SUB),
    ("ref.usda", REF),
    ("payload.usda", PAYLOAD),
];

/// Asset paths a rewrite puts in place of another; `SELF` stands for the mutated layer's own name.
const ASSETS: [&str; 16] = [
    "./root.usda",
    "./sub.usda",
    "./ref.usda",
    "./payload.usda",
    "./ref.usdc",
    "SELF",
    "./missing.usda",
    "missing.usdc",
    "./folder.usda",
    "./fifo.usda",
    ".",
    "./",
    "",
    "/dev/null",
    "/dev/zero",
    "/proc/self/stat",
];

/// Prim paths a rewrite puts in place of another: prims of the layers (each an ancestor or the prim itself for
/// some arc), the pseudo-root, a property and missing prims.
const PRIMS: [&str; 14] = [
    "/Groom",
    "/Groom/Inherited",
    "/Groom/Specialized",
    "/Groom/Referenced",
    "/_Hair",
    "/_Base",
    "/_Root",
    "/_Local",
    "/Strands",
    "/Other",
    "/",
    "/Groom.points",
    "/Missing",
    "/Groom/Inherited/Missing",
];

/// Each `open…close` span's inside in `bytes` (an asset path's `@…@`, a prim path's `<…>`).
fn spans(bytes: &[u8], open: u8, close: u8) -> Vec<std::ops::Range<usize>> {
    let mut out = Vec::new();
    let mut at = 0;
    while let Some(start) = bytes[at..].iter().position(|&b| b == open).map(|i| at + i + 1) {
        let Some(len) = bytes[start..].iter().position(|&b| b == close || b == b'\n') else {
            break;
        };
        if bytes[start + len] == close {
            out.push(start..start + len);
        }
        at = start + len + 1;
    }
    out
}

/// One span between `open` and `close` replaced by one of `choices` (`SELF` by `./own`).
fn rewrite(rng: &mut SplitMix64, bytes: &mut Vec<u8>, (open, close): (u8, u8), choices: &[&str], own: &str) {
    let found = spans(bytes, open, close);
    if found.is_empty() {
        return;
    }
    let span = found[rng.int(0, found.len() - 1)].clone();
    let new = match choices[rng.int(0, choices.len() - 1)] {
        "SELF" => format!("./{own}"),
        other => other.to_string(),
    };
    bytes.splice(span, new.into_bytes());
}

/// One to three mutations of the layer `own`: an asset path or a prim path rewritten (two times in five each), or
/// [`mutate`]'s numbers, bytes and cuts.
fn mutate_layer(rng: &mut SplitMix64, text: &[u8], own: &str) -> Vec<u8> {
    let mut bytes = text.to_vec();
    for _ in 0..rng.int(1, 3) {
        match rng.int(0, 4) {
            0 | 1 => rewrite(rng, &mut bytes, (b'@', b'@'), &ASSETS, own),
            2 | 3 => rewrite(rng, &mut bytes, (b'<', b'>'), &PRIMS, own),
            _ => bytes = mutate(rng, &bytes),
        }
    }
    bytes
}

/// Writes the seed layers, `ref.usdc` (the crate's binary form of `ref.usda`), the folder `folder.usda` and the
/// named pipe `fifo.usda` (nothing ever writes to it: a reader that opens it blocks) into `dir`.
fn write_layers(dir: &std::path::Path) {
    for (name, text) in LAYERS {
        std::fs::write(dir.join(name), text).unwrap();
    }
    let mut usdc = std::io::Cursor::new(Vec::new());
    openusd::usdc::CrateWriter::write(&openusd::usda::parse(REF).unwrap(), &mut usdc).unwrap();
    std::fs::write(dir.join("ref.usdc"), usdc.into_inner()).unwrap();
    std::fs::create_dir(dir.join("folder.usda")).unwrap();
    let fifo = std::process::Command::new("mkfifo")
        .arg(dir.join("fifo.usda"))
        .status()
        .expect("mkfifo");
    assert!(fifo.success(), "mkfifo: {fifo}");
}

/// `path`'s file replaced by `bytes`: removed and written anew, as overwriting an ext4 file in place flushes it
/// to disk (7 ms a case instead of under 1).
fn replace(path: &std::path::Path, bytes: &[u8]) {
    std::fs::remove_file(path).unwrap();
    std::fs::write(path, bytes).unwrap();
}

/// Issue 43: the composed stage loads whole (the curves of every arc), then `HAIRLAB_FUZZ_CASES` cases (1000
/// unset) each mutate one layer ([`mutate_layer`]) in the directory `case<N>` and load the root: a refusal names
/// the case's directory. After a failure the failing case's files stay in the printed folder.
#[test]
fn mutated_usda_compositions_fail_cleanly() {
    // Kept after a failure (a panic, an abort, a hang killed) with the failing case's files; removed at the end.
    let base = tempfile::tempdir().expect("tempdir").keep();
    let mut dir = base.join("case0");
    std::fs::create_dir(&dir).unwrap();
    write_layers(&dir);
    let mut counts = load_scene(&dir.join("root.usda")).unwrap().strands.counts;
    counts.sort();
    // Inherited, Specialized and Internal 2 each, Paid 2 + 2, Referenced and FromSub 3 each.
    assert_eq!(counts, [2, 2, 2, 2, 2, 3, 3]);

    let (_, mut rng) = run();
    let cases = env("HAIRLAB_FUZZ_CASES", 1000);
    eprintln!("composition cases in {}", base.display());
    let (mut loaded, mut refused) = (0, 0);
    let mut slowest = Slowest::default();
    let start = std::time::Instant::now();
    for case in 0..cases {
        let next = base.join(format!("case{case}"));
        std::fs::rename(&dir, &next).unwrap();
        dir = next;
        let (name, text) = LAYERS[rng.int(0, LAYERS.len() - 1)];
        replace(&dir.join(name), &mutate_layer(&mut rng, text.as_bytes(), name));
        let outcome = slowest.time(case, || load_scene(&dir.join("root.usda")));
        if super::loaded_whole(case, outcome, &format!("case{case}")) {
            loaded += 1;
        } else {
            refused += 1;
        }
        replace(&dir.join(name), text.as_bytes());
    }
    eprintln!(
        "composed .usda: {cases} cases, {loaded} load, {refused} refused, {slowest}, {:.1} s in all",
        start.elapsed().as_secs_f64()
    );
    assert!(loaded > 0 && refused > 0, "{loaded} loaded, {refused} refused");
    std::fs::remove_dir_all(&base).unwrap();
}
