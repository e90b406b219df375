//! Hostile text-USD composition (issue 43): every stage ends in a scene or one error naming the file, never a hang,
//! an abort or a panic. Cycles through each arc drop the closing arc with a warning naming the file and the prims;
//! nesting and arc chains are read on a thread with a 2 MiB stack (a recursion per level would overflow it); a
//! sublayer, reference or payload that is missing, a named pipe, a device, a folder or over the 1 GiB cap is one
//! warning naming the arc and the path; `info`, `convert` and `render` say it, and `--strict` fails instead.

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

use hairlab::scene::usd::{UsdScene, read_usd_file};

/// A linear curve of 3 points (0,0,0)–(0,2,0) named `hair`, with `meta` as its metadata (may be empty).
fn curve(meta: &str) -> String {
    format!(
        "def BasisCurves \"hair\" ({meta})\n{{\n    uniform token type = \"linear\"\n    int[] curveVertexCounts = \
         [3]\n    point3f[] points = [(0,0,0), (0,1,0), (0,2,0)]\n}}\n"
    )
}

/// Writes `#usda 1.0` and `text` to `dir/name`.
fn stage(dir: &Path, name: &str, text: &str) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, format!("#usda 1.0\n{text}")).unwrap();
    path
}

/// Reads `path` on a thread with a 2 MiB stack (a test thread's size), so a recursion per nesting level or per
/// arc would overflow it; the error as its message.
fn read_small_stack(path: &Path) -> Result<UsdScene, String> {
    let path = path.to_owned();
    std::thread::Builder::new()
        .stack_size(2 << 20)
        .spawn(move || read_usd_file(&path).map_err(|e| e.to_string()))
        .unwrap()
        .join()
        .unwrap()
}

/// The stage loads its one 3-point curve and gave a warning containing each of `words`.
fn loads_warning(path: &Path, words: &[&str]) -> UsdScene {
    let s = read_small_stack(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    assert_eq!(s.strands.counts, vec![3], "{}", path.display());
    assert!(
        s.warnings.iter().any(|w| words.iter().all(|x| w.contains(x))),
        "{}: no warning with {words:?} in {:?}",
        path.display(),
        s.warnings
    );
    s
}

fn hairlab(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_hairlab"))
        .args(args)
        .output()
        .unwrap()
}

/// `hairlab info path`, killed if it runs past 5 s (a hang or a runaway allocation fails the test, not the run).
fn info_within_5_s(path: &Path) -> Output {
    let mut child = Command::new(env!("CARGO_BIN_EXE_hairlab"))
        .arg("info")
        .arg(path)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let start = Instant::now();
    while child.try_wait().unwrap().is_none() {
        if start.elapsed() > Duration::from_secs(5) {
            child.kill().unwrap();
            panic!("hairlab info {} ran past 5 s", path.display());
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    child.wait_with_output().unwrap()
}

#[test]
fn class_cycles_drop_the_closing_arc_naming_file_and_prims() {
    let dir = tempfile::tempdir().unwrap();
    for arc in ["inherits", "specializes"] {
        let name = format!("{arc}-cycle.usda");
        let text = format!(
            "class \"A\" ({arc} = </B>) {{}}\nclass \"B\" ({arc} = </A>) {{}}\n{}",
            curve(&format!("{arc} = </A>"))
        );
        let p = stage(dir.path(), &name, &text);
        loads_warning(&p, &["composition arc cycle", &name, "</A>", "</B>"]);
    }
}

#[test]
fn reference_and_payload_cycles_drop_the_closing_arc() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let self_ref = stage(
        d,
        "self-ref.usda",
        &curve("references = @./self-ref.usda@</hair>"),
    );
    loads_warning(&self_ref, &["composition arc cycle", "self-ref.usda", "</hair>"]);
    let self_payload = stage(
        d,
        "self-payload.usda",
        &curve("payload = @./self-payload.usda@</hair>"),
    );
    loads_warning(&self_payload, &["composition arc cycle", "self-payload.usda"]);
    let internal = stage(
        d,
        "internal.usda",
        &format!(
            "def Xform \"R\" (references = </R>) {{}}\n{}",
            curve("references = </R>")
        ),
    );
    loads_warning(&internal, &["composition arc cycle", "internal.usda", "</R>"]);
    stage(
        d,
        "b.usda",
        "def Xform \"hair\" (references = @./a.usda@</hair>) {}\n",
    );
    let a = stage(d, "a.usda", &curve("references = @./b.usda@</hair>"));
    loads_warning(&a, &["composition arc cycle", "a.usda", "b.usda"]);
}

#[test]
fn sublayer_cycles_are_said_and_the_stage_opens() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let own = stage(
        d,
        "own.usda",
        &format!("(\n    subLayers = [@./own.usda@]\n)\n{}", curve("")),
    );
    loads_warning(&own, &["sublayer cycle", "own.usda"]);
    stage(d, "y.usda", "(\n    subLayers = [@./x.usda@]\n)\n");
    let x = stage(
        d,
        "x.usda",
        &format!("(\n    subLayers = [@./y.usda@]\n)\n{}", curve("")),
    );
    loads_warning(&x, &["sublayer cycle", "x.usda", "y.usda"]);
}

/// `depth` nested `def Xform "x<i>"` around the curve.
fn nested(depth: usize) -> String {
    let open: String = (0..depth).map(|i| format!("def Xform \"x{i}\" {{\n")).collect();
    format!("{open}{}{}", curve(""), "}\n".repeat(depth))
}

#[test]
fn a_2000_deep_stage_reads_on_a_small_stack() {
    let dir = tempfile::tempdir().unwrap();
    let p = stage(dir.path(), "nested-2000.usda", &nested(2000));
    let s = read_small_stack(&p).unwrap();
    assert_eq!(s.strands.counts, vec![3]);
    // No transform anywhere: the last point is the authored (0, 2, 0) in centimetres, 0.02 m up (f32 rounding).
    let last = s.strands.points[2];
    assert!(
        last.x == 0.0 && (last.y - 0.02).abs() < 1e-8 && last.z == 0.0,
        "{last}"
    );
    assert!(s.warnings.is_empty(), "{:?}", s.warnings);
}

#[test]
fn deeper_nesting_is_one_error_stating_the_limit() {
    let dir = tempfile::tempdir().unwrap();
    let p = stage(dir.path(), "nested-20000.usda", &nested(20_000));
    let e = read_small_stack(&p).unwrap_err();
    assert!(
        e.contains("nested-20000.usda") && e.contains("more than 2048 deep"),
        "{e}"
    );
    // Dictionaries and metadata arrays have their own bound.
    let deep_dict = format!(
        "def Xform \"x\" (customData = {}{{}}{})\n{{}}\n",
        "{ dictionary a = ".repeat(100),
        " }".repeat(100)
    );
    let p = stage(dir.path(), "dict.usda", &deep_dict);
    let e = read_small_stack(&p).unwrap_err();
    assert!(e.contains("dict.usda") && e.contains("more than 64 deep"), "{e}");
}

#[test]
fn long_arc_chains_are_cut_at_the_stated_depth() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let n = 1000;
    for arc in ["inherits", "specializes"] {
        let classes: String = (0..n)
            .map(|i| format!("class \"C{i}\" ({arc} = </C{}>) {{}}\n", i + 1))
            .collect();
        let text = format!(
            "{classes}class \"C{n}\" {{}}\n{}",
            curve(&format!("{arc} = </C0>"))
        );
        let p = stage(d, &format!("{arc}-chain.usda"), &text);
        loads_warning(&p, &["more than 32 arcs deep"]);
    }
    let refs: String = (0..n)
        .map(|i| format!("def Xform \"R{i}\" (references = </R{}>) {{}}\n", i + 1))
        .collect();
    let p = stage(
        d,
        "reference-chain.usda",
        &format!("{refs}def Xform \"R{n}\" {{}}\n{}", curve("references = </R0>")),
    );
    loads_warning(&p, &["Reference", "more than 32 arcs deep"]);
    // A chain of 200 files, each payload-ing the next.
    for i in 1..200 {
        stage(
            d,
            &format!("p{i}.usda"),
            &format!("def Xform \"hair\" (payload = @./p{}.usda@</hair>) {{}}\n", i + 1),
        );
    }
    stage(d, "p200.usda", "def Xform \"hair\" {}\n");
    let p = stage(d, "p0.usda", &curve("payload = @./p1.usda@</hair>"));
    loads_warning(&p, &["Payload", "more than 32 arcs deep"]);
}

#[test]
fn nested_variant_selections_are_cut_at_the_stated_depth() {
    let dir = tempfile::tempdir().unwrap();
    let n = 100;
    let open: String = (0..n)
        .map(|i| {
            format!(
                "def Xform \"v{i}\" (variants = {{string s = \"a\"}}) {{ variantSet \"s\" = {{ \"a\" {{\n"
            )
        })
        .collect();
    let text = format!("{open}{}{}", curve(""), "} } }\n".repeat(n));
    let p = stage(dir.path(), "variants.usda", &text);
    let s = read_small_stack(&p).unwrap();
    // The curve lies under 100 variant selections: past the 32nd the selection is dropped, and the curve with it.
    assert!(s.strands.counts.is_empty());
    assert!(
        s.warnings
            .iter()
            .any(|w| w.contains("Variant") && w.contains("more than 32 arcs deep")),
        "{:?}",
        s.warnings
    );
}

#[test]
fn a_chain_of_1000_sublayers_reads_on_a_small_stack() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    for i in 1..1000 {
        stage(
            d,
            &format!("s{i}.usda"),
            &format!("(\n    subLayers = [@./s{}.usda@]\n)\n", i + 1),
        );
    }
    // Only the last layer, 1,000 layers down, gives the curve its width (0.5 cm).
    stage(
        d,
        "s1000.usda",
        "over \"hair\" { float[] widths = [0.5] (interpolation = \"constant\") }\n",
    );
    let p = stage(
        d,
        "s0.usda",
        &format!("(\n    subLayers = [@./s1.usda@]\n)\n{}", curve("")),
    );
    let s = read_small_stack(&p).unwrap();
    assert!(s.warnings.is_empty(), "{:?}", s.warnings);
    let width = s.strands.thickness.expect("the width from the last sublayer")[0];
    assert!((width - 0.005).abs() < 1e-9, "{width}");
}

#[test]
fn a_missing_layer_through_each_arc_is_said() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let sub = stage(
        d,
        "sub.usda",
        &format!("(\n    subLayers = [@./gone.usda@]\n)\n{}", curve("")),
    );
    loads_warning(&sub, &["unresolved sublayer", "gone.usda", "sub.usda"]);
    let r = stage(d, "ref.usda", &curve("references = @./gone.usda@</X>"));
    loads_warning(&r, &["unresolved Reference", "gone.usda", "/hair"]);
    let p = stage(d, "pay.usda", &curve("payload = @./gone.usda@</X>"));
    loads_warning(&p, &["unresolved Payload", "gone.usda", "/hair"]);
}

#[test]
fn special_files_and_huge_layers_are_refused_by_name_without_blocking() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let fifo = d.join("fifo.usda");
    let made = Command::new("mkfifo").arg(&fifo).status().unwrap();
    assert!(made.success());
    // Nothing ever writes to the pipe: opening it would block forever.
    for (arc, meta, said) in [
        ("sublayer", "", "sublayer"),
        ("reference", "references = @./fifo.usda@</X>", "Reference"),
        ("payload", "payload = @./fifo.usda@</X>", "Payload"),
    ] {
        let text = if arc == "sublayer" {
            format!("(\n    subLayers = [@./fifo.usda@]\n)\n{}", curve(""))
        } else {
            curve(meta)
        };
        let p = stage(d, &format!("{arc}-fifo.usda"), &text);
        loads_warning(
            &p,
            &[said, "fifo.usda", "a named pipe (FIFO), not a regular file"],
        );
    }
    let p = stage(
        d,
        "zero.usda",
        &format!("(\n    subLayers = [@/dev/zero@]\n)\n{}", curve("")),
    );
    loads_warning(&p, &["sublayer", "/dev/zero", "a device, not a regular file"]);
    std::fs::create_dir(d.join("folder.usda")).unwrap();
    let p = stage(
        d,
        "sub-folder.usda",
        &format!("(\n    subLayers = [@./folder.usda@]\n)\n{}", curve("")),
    );
    loads_warning(&p, &["sublayer", "folder.usda", "a folder, not a regular file"]);
    // 5 GiB of nothing (a sparse file): refused by its size, before a byte is read.
    let huge = std::fs::File::create(d.join("huge.usda")).unwrap();
    huge.set_len(5 << 30).unwrap();
    let p = stage(
        d,
        "huge-sub.usda",
        &format!("(\n    subLayers = [@./huge.usda@]\n)\n{}", curve("")),
    );
    loads_warning(
        &p,
        &[
            "sublayer",
            "huge.usda",
            "5368709120 bytes, more than the 1073741824",
        ],
    );
    let p = stage(d, "huge-ref.usda", &curve("references = @./huge.usda@</X>"));
    loads_warning(&p, &["Reference", "huge.usda", "more than the 1073741824"]);
}

#[test]
fn info_convert_and_render_name_a_missing_layer_and_strict_fails() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let p = stage(
        d,
        "groom.usda",
        &format!("(\n    subLayers = [@./gone.usda@]\n)\n{}", curve("")),
    );
    let p = p.to_str().unwrap();
    let o = hairlab(&["info", p]);
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success(), "{out}");
    assert!(
        out.lines()
            .any(|l| l.starts_with("warning:") && l.contains("sublayer @./gone.usda@")),
        "{out}"
    );
    let o = hairlab(&["info", "--strict", p]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(err.contains("--strict") && err.contains("gone.usda"), "{err}");
    // convert says it on stderr and writes; with --strict it fails and writes nothing.
    let out = d.join("out.hair");
    let out = out.to_str().unwrap();
    let o = hairlab(&["convert", p, out]);
    assert!(o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("gone.usda"));
    std::fs::remove_file(out).unwrap();
    let o = hairlab(&["convert", "--strict", p, out]);
    assert_eq!(o.status.code(), Some(1));
    assert!(!Path::new(out).exists());
    // render (the CPU path tracer, 1 sample of 32×24) the same.
    let png = d.join("out.png");
    let png = png.to_str().unwrap();
    let scene = format!("scene.file={p}");
    let render = |strict: bool| {
        let mut args = vec![
            "render",
            "--set",
            &scene,
            "--set",
            "render.mode=path",
            "--set",
            "render.spp=1",
        ];
        args.extend(["--width", "32", "--height", "24", "--out", png]);
        if strict {
            args.push("--strict");
        }
        hairlab(&args)
    };
    let o = render(false);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(String::from_utf8_lossy(&o.stderr).contains("gone.usda"));
    std::fs::remove_file(png).unwrap();
    let o = render(true);
    assert_eq!(o.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&o.stderr).contains("--strict"));
    assert!(!Path::new(png).exists());
}

/// Findings 1 and 3 of the composed `.usda` fuzz target: a `}` (or `{`) in an arc's prim path that is no variant
/// selection `{set=sel}` made `/A}` its own parent, so composition spun forever (1) or grew memory until it aborted
/// (3). In the root layer it is one parse error naming the file and the path; in a sublayer one warning naming the
/// sublayer, and the root's curve opens.
#[test]
fn a_stray_brace_in_an_arc_path_is_refused_naming_the_file() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let target = "def BasisCurves \"A\"\n{\n    uniform token type = \"linear\"\n    int[] curveVertexCounts = [2]\n    \
                  point3f[] points = [(0, 0, 0), (0, 1, 0)]\n}\n";
    let arcs = [
        ("references", "</A}>", "reference"),
        ("references", "</A}x>", "reference"),
        ("references", "</A.b}>", "reference"),
        ("references", "</A{>", "reference"),
        ("payload", "</A}>", "payload"),
        ("inherits", "</A}>", "inherit"),
        ("specializes", "</A}>", "specializes"),
        ("inherits", "</A{v=}}>", "inherit"),
    ];
    for (i, (arc, path, said)) in arcs.iter().enumerate() {
        let name = format!("brace{i}.usda");
        let p = stage(
            d,
            &name,
            &format!("{target}\ndef \"B\" (\n    {arc} = {path}\n)\n{{\n}}\n"),
        );
        let o = info_within_5_s(&p);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{name}: {err}");
        let inner = &path[1..path.len() - 1];
        assert!(
            err.contains(&name) && err.contains(inner) && err.to_lowercase().contains(said),
            "{name}: {err}"
        );
    }
    // Finding 3's stage: a class specializing </_Roo}>, inherited by the curve.
    let finding3 = format!(
        "class \"_Base\" (\n    specializes = </_Roo}}>\n)\n{{\n}}\n\n{}",
        curve("inherits = </_Base>")
    );
    let p = stage(d, "finding3.usda", &finding3);
    let o = info_within_5_s(&p);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(err.contains("finding3.usda") && err.contains("</_Roo}>"), "{err}");
    // The same class in a sublayer: a warning naming it, and the root's own curve opens.
    let p = stage(
        d,
        "over-finding3.usda",
        &format!("(\n    subLayers = [@./finding3.usda@]\n)\n{}", curve("")),
    );
    let o = info_within_5_s(&p);
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success(), "{out}{}", String::from_utf8_lossy(&o.stderr));
    assert!(
        out.lines().any(|l| l.starts_with("warning:")
            && l.contains("sublayer @./finding3.usda@")
            && l.contains("</_Roo}>")),
        "{out}"
    );
    assert!(
        out.lines()
            .any(|l| l.starts_with("strands:") && l.ends_with(" 1")),
        "{out}"
    );
}

/// The root of findings 1 and 3: a stray brace is refused by `Path::new`, and a path built unchecked with one
/// still has a strictly shorter parent, so every ancestor walk ends.
#[test]
fn stray_braces_are_refused_and_no_path_is_its_own_parent() {
    use openusd::sdf::Path as UsdPath;
    for bad in [
        "/A}",
        "/A}x",
        "/A.b}",
        "/A{",
        "/A{v}",
        "/A{=s}",
        "/A{v=s",
        "/A{v=}}",
        "/A{v={w=x}}",
        "/A{v=s/B}",
    ] {
        assert!(UsdPath::new(bad).is_err(), "{bad:?} accepted");
    }
    for good in ["/A{v=s}", "/A{v=}", "/A{v=s}B{w=t}C.attr", "/A.rel[/T{v=x}B]"] {
        assert!(UsdPath::new(good).is_ok(), "{good:?} refused");
    }
    let cases: [(&str, &[&str]); 6] = [
        ("/A}", &["/"]),
        ("/A/B}", &["/A", "/"]),
        ("/A}x}", &["/"]),
        ("A}", &[]),
        ("}", &[]),
        ("/A{x=y}}", &["/A", "/"]),
    ];
    for (path, expected) in cases {
        let walk: Vec<String> = UsdPath::from(path)
            .strict_ancestors()
            .map(|p| p.to_string())
            .collect();
        assert_eq!(walk, expected, "ancestors of {path:?}");
    }
}

/// Finding 2 of the composed `.usda` fuzz target: a class-arc chain whose target comes back one namespace level
/// deeper each turn (`/Groom/Specialized` → `/Groom/Inherited/Missing` → `/_Hair/Missing` →
/// `/Groom/Specialized/Missing` …) ran 32 arcs deep before the depth limit cut it (0.9–1.7 s for 20 lines). A
/// target nested in a site still under composition is a cycle (C++ `_CheckForCycle`): the closing arc is dropped with
/// the cycle warning, never the depth one, and both curves open.
#[test]
fn a_class_chain_that_deepens_its_path_is_a_cycle() {
    let dir = tempfile::tempdir().unwrap();
    let body = "{\n        uniform token type = \"linear\"\n        int[] curveVertexCounts = [2]\n        point3f[] \
                points = [(0, 0, 0), (0, 1, 0)]\n    }\n";
    let text = format!(
        "class \"_Hair\" (\n    inherits = </Groom/Specialized>\n)\n{{\n}}\n\ndef Xform \"Groom\"\n{{\n    def \
         BasisCurves \"Inherited\" (\n        inherits = </_Hair>\n    )\n    {body}\n    def BasisCurves \
         \"Specialized\" (\n        specializes = </Groom/Inherited/Missing>\n    )\n    {body}}}\n"
    );
    let p = stage(dir.path(), "deepening.usda", &text);
    let s = read_small_stack(&p).unwrap();
    assert_eq!(s.strands.counts, vec![2, 2]);
    assert!(
        s.warnings
            .iter()
            .any(|w| w.contains("composition arc cycle at /Groom/Specialized")
                && w.contains("deepening.usda")
                && w.contains("Inherit </Groom/Specialized>")),
        "{:?}",
        s.warnings
    );
    assert!(
        !s.warnings.iter().any(|w| w.contains("arcs deep")),
        "{:?}",
        s.warnings
    );
}
