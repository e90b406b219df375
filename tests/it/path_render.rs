//! `hairlab render` under `render.mode = path`: the CPU path-traced reference of a preset, written as PNG, and
//! its settings checked before anything is written.

use crate::common::cli::{assert_fails, hairlab, stderr};

const TINY: [&str; 8] = [
    "render",
    "--preset",
    "default",
    "--set",
    "render.mode=path",
    "--width",
    "32",
    "--height",
];

#[test]
fn renders_the_default_scene_to_a_png_lit_where_the_hair_is() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("shot.png");
    let out_arg = out.to_str().unwrap();
    let mut args = TINY.to_vec();
    args.extend(["24", "--set", "render.spp=2", "--out", out_arg]);
    let o = hairlab(&args);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).contains("path: 2/2 spp (100%"), "{}", stderr(&o));
    let image = image::open(&out).unwrap().to_rgba8();
    assert_eq!(image.dimensions(), (32, 24));
    // The framed groom stands in the middle third of the view, lit on the light's side: lit pixels are there and
    // only there (the path tracer has no background: pixels no camera ray hits are black).
    let lit = |x: u32, y: u32| image.get_pixel(x, y).0[..3].iter().any(|&c| c > 0);
    let all = (0..32).flat_map(|x| (0..24).map(move |y| (x, y)));
    let lit_count = all.clone().filter(|&(x, y)| lit(x, y)).count();
    assert!(lit_count >= 10, "{lit_count} pixels lit");
    let outside: Vec<_> = all.filter(|&(x, y)| !(6..26).contains(&x) && lit(x, y)).collect();
    assert!(outside.is_empty(), "lit beside the groom: {outside:?}");
}

#[test]
fn a_bad_spp_or_width_fails_naming_the_key_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("shot.png");
    let out_arg = out.to_str().unwrap();
    let mut args = TINY.to_vec();
    args.extend(["24", "--set", "render.spp=0", "--out", out_arg]);
    assert_fails(&hairlab(&args), &["render.spp", "(got 0)"]);
    let mut args = TINY.to_vec();
    args.extend(["24", "--set", "render.spp=65537", "--out", out_arg]);
    assert_fails(&hairlab(&args), &["render.spp", "(got 65537)"]);
    let mut args = TINY.to_vec();
    args[6] = "0";
    args.extend(["24", "--set", "render.spp=1", "--out", out_arg]);
    assert_fails(&hairlab(&args), &["render.width"]);
    assert_eq!(
        std::fs::read_dir(dir.path()).unwrap().count(),
        0,
        "a file was left behind"
    );
}
