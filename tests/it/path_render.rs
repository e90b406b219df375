//! `hairlab render` under `render.mode = path`: the CPU path-traced reference of a preset, written as PNG, and
//! its settings checked before anything is written; Ctrl-C on it and on `measure visibility` writes what was done.

use crate::common::cli::{assert_fails, hairlab, stderr};
use crate::common::measured_preset;
use hairlab::gpu::Gpu;
use hairlab::measure::fibre_visibility::compare_map;

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

/// The same render as PNG and as EXR: the PNG is the EXR's linear image in sRGB (over black), the image is lit
/// in the groom's middle third, and the EXR holds finite, non-negative radiance.
#[test]
fn renders_the_default_scene_to_a_png_and_its_linear_image_to_an_exr() {
    let dir = tempfile::tempdir().unwrap();
    let mut images = Vec::new();
    for name in ["shot.png", "shot.exr"] {
        let out = dir.path().join(name);
        let mut args = TINY.to_vec();
        args.extend(["24", "--set", "render.spp=2", "--out", out.to_str().unwrap()]);
        let o = hairlab(&args);
        assert!(o.status.success(), "{}", stderr(&o));
        assert!(
            stderr(&o).contains("100 % path tracing: 2/2 spp"),
            "{}",
            stderr(&o)
        );
        images.push(image::open(&out).unwrap());
    }
    let (png, exr) = (images[0].to_rgba8(), images[1].to_rgb32f());
    assert_eq!((png.dimensions(), exr.dimensions()), ((32, 24), (32, 24)));
    let srgb = |c: f32| {
        let c = c.clamp(0.0, 1.0);
        if c <= 0.003_130_8 {
            12.92 * c
        } else {
            1.055 * c.powf(1.0 / 2.4) - 0.055
        }
    };
    let mut lit_middle = 0;
    for (x, y, p) in exr.enumerate_pixels() {
        for k in 0..3 {
            assert!(p.0[k].is_finite() && p.0[k] >= 0.0, "({x}, {y}): {:?}", p.0);
            let want = srgb(p.0[k]) * 255.0;
            let got = png.get_pixel(x, y).0[k] as f32;
            assert!(
                (got - want).abs() <= 1.0,
                "({x}, {y}) channel {k}: PNG {got}, EXR in sRGB {want}"
            );
        }
        lit_middle += ((11..21).contains(&x) && p.0.iter().any(|&c| c > 0.0)) as u32;
    }
    assert!(lit_middle >= 40, "{lit_middle} pixels of the groom's middle lit");
}

/// `export --format mitsuba` writes the scene's strands (`x y z radius` per point, a blank line after each
/// strand), its meshes and a scene XML whose sensor, film, light and fibre BSDF are the preset's: the absorption
/// is Chiang et al. 2016's colour inversion, written out here.
#[test]
fn exports_a_mitsuba_scene_of_the_preset() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("scene");
    let o = hairlab(&[
        "export",
        "--format",
        "mitsuba",
        "--preset",
        "default",
        "--width",
        "64",
        "--height",
        "48",
        "--set",
        "render.spp=8",
        "--set",
        "render.strand_width=0.002",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let xml = std::fs::read_to_string(out.join("scene.xml")).unwrap();
    for want in [
        "<integer name=\"width\" value=\"64\"/>",
        "<integer name=\"height\" value=\"48\"/>",
        "<integer name=\"sample_count\" value=\"8\"/>",
        "<integer name=\"max_depth\" value=\"1025\"/>",
        "<rfilter type=\"box\"/>",
        "<string name=\"filename\" value=\"hair.txt\"/>",
        "<string name=\"filename\" value=\"mesh0.obj\"/>",
    ] {
        assert!(xml.contains(want), "scene.xml lacks {want}:\n{xml}");
    }
    // The default hair colour (0.30, 0.18, 0.09) at β_n = 0.3: σ_a = (ln c / 5.8885)².
    let poly = 5.969 - 0.215 * 0.3 + 2.532 * 0.09 - 10.73 * 0.027 + 5.574 * 0.0081 + 0.245 * 0.00243;
    let sigma: Vec<f64> = [0.30f64, 0.18, 0.09]
        .iter()
        .map(|c| (c.ln() / poly).powi(2))
        .collect();
    let line = xml.lines().find(|l| l.contains("name=\"sigma_a\"")).unwrap();
    let got: Vec<f64> = line
        .split('"')
        .nth(3)
        .unwrap()
        .split(',')
        .map(|v| v.trim().parse().unwrap())
        .collect();
    for (g, w) in got.iter().zip(&sigma) {
        assert!(
            (g - w).abs() < 1e-5 * w,
            "sigma_a {got:?}, Chiang et al.'s inversion {sigma:?}"
        );
    }
    // The fibre's lobes as wide as the raster's: β_m solves 0.726 β + 0.812 β² + 3.7 β²⁰ = 2 sin 7.5°.
    let line = xml
        .lines()
        .find(|l| l.contains("name=\"longitudinal_roughness\""))
        .unwrap();
    let beta_m: f64 = line.split('"').nth(3).unwrap().parse().unwrap();
    let width = 0.726 * beta_m + 0.812 * beta_m.powi(2) + 3.7 * beta_m.powi(20);
    assert!(
        (width - 2.0 * 7.5f64.to_radians().sin()).abs() < 1e-6,
        "longitudinal_roughness {beta_m}: lobe width {width}"
    );
    let hair = std::fs::read_to_string(out.join("hair.txt")).unwrap();
    let strands: Vec<&str> = hair.split("\n\n").filter(|s| !s.trim().is_empty()).collect();
    assert!(strands.len() > 100, "{} strands", strands.len());
    for s in &strands {
        let points: Vec<Vec<f32>> = s
            .lines()
            .map(|l| l.split(' ').map(|v| v.parse().unwrap()).collect())
            .collect();
        assert!(points.len() >= 2 && points.iter().all(|p| p.len() == 4 && p[3] == 0.001));
    }
    assert!(
        std::fs::read_to_string(out.join("mesh0.obj"))
            .unwrap()
            .lines()
            .any(|l| l.starts_with("f "))
    );
}

/// A spot light exports as Mitsuba's `spot`: cutoff at half of `light.cone_deg`, full beam within the angle where
/// the raster's edge ramp `smoothstep(edge, edge + 0.15 (1 − edge), cos θ)` reaches 1; and it path-traces as
/// the directional light it stands for. Its intensity gives the directional light's irradiance at the scene's
/// centre, so placed 50 scene radii away (1/d² within ±4 % over the hair) its image's mean over the hair is the
/// directional one's within 3 % (measured 0.998; two seeds of the directional image differ by 0.7 %), lit on
/// as many pixels within 5 %; at the preset's distance its 50° cone holds the whole hair: it lights at least
/// 90 % of the pixels the directional light does (measured 290 of 299).
#[test]
fn a_spot_light_exports_as_mitsubas_spot_and_path_traces() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("scene");
    let spot = ["--set", "light.kind=spot", "--set", "light.cone_deg=50"];
    let mut args = vec!["export", "--format", "mitsuba", "--out", out.to_str().unwrap()];
    args.extend(spot);
    let o = hairlab(&args);
    assert!(o.status.success(), "{}", stderr(&o));
    let xml = std::fs::read_to_string(out.join("scene.xml")).unwrap();
    let value = |name: &str| -> f64 {
        let line = xml
            .lines()
            .find(|l| l.contains(&format!("name=\"{name}\"")))
            .unwrap();
        line.split('"').nth(3).unwrap().parse().unwrap()
    };
    let edge = 25f64.to_radians().cos();
    let beam = (edge + 0.15 * (1.0 - edge)).acos().to_degrees();
    assert!((value("cutoff_angle") - 25.0).abs() < 1e-4, "{xml}");
    assert!(
        (value("beam_width") - beam).abs() < 1e-3,
        "beam {} for {beam}",
        value("beam_width")
    );
    assert!(xml.contains("<emitter type=\"spot\">") && !xml.contains("directional"));
    let render = |name: &str, light: &[&str]| -> image::Rgb32FImage {
        let shot = dir.path().join(name);
        let mut args = TINY.to_vec();
        args.extend(["24", "--set", "render.spp=4", "--out", shot.to_str().unwrap()]);
        args.extend(light);
        let o = hairlab(&args);
        assert!(o.status.success(), "{}", stderr(&o));
        image::open(&shot).unwrap().to_rgb32f()
    };
    let directional = render("directional.exr", &[]);
    let far = render(
        "far.exr",
        &[spot.as_slice(), &["--set", "light.distance=50"]].concat(),
    );
    let near = render("near.exr", &spot);
    let lit = |p: &image::Rgb<f32>| p.0.iter().any(|&c| c > 0.0);
    let count = |image: &image::Rgb32FImage| image.pixels().filter(|p| lit(p)).count() as f64;
    let (mut sums, mut hair) = ((0.0f64, 0.0f64), 0);
    for (d, f) in directional.pixels().zip(far.pixels()) {
        if lit(d) || lit(f) {
            hair += 1;
            sums.0 += d.0.iter().map(|&c| f64::from(c)).sum::<f64>();
            sums.1 += f.0.iter().map(|&c| f64::from(c)).sum::<f64>();
        }
    }
    let (n_dir, n_far, n_near) = (count(&directional), count(&far), count(&near));
    let report = format!(
        "{hair} hair pixels, mean {:.4} directional, {:.4} far spot; lit {n_dir} directional, {n_far} far, \
         {n_near} near",
        sums.0 / (3.0 * hair as f64),
        sums.1 / (3.0 * hair as f64)
    );
    eprintln!("{report}");
    assert!(n_dir >= 100.0, "{report}");
    assert!((sums.1 / sums.0 - 1.0).abs() < 0.03, "{report}");
    assert!((n_far / n_dir - 1.0).abs() < 0.05, "{report}");
    assert!(n_near >= 0.9 * n_dir, "{report}");
}

#[test]
fn a_bad_spp_width_or_strand_width_fails_naming_the_key_and_writes_nothing() {
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
    // Fibres wider than the whole hair (a unit mistake): refused by the path tracer and by the export.
    let mut args = TINY.to_vec();
    args.extend(["24", "--set", "render.strand_width=5", "--out", out_arg]);
    assert_fails(
        &hairlab(&args),
        &["render.strand_width = 5", "wider than the hair"],
    );
    let scene_dir = dir.path().join("scene");
    let o = hairlab(&[
        "export",
        "--format",
        "mitsuba",
        "--preset",
        "default",
        "--set",
        "render.strand_width=5",
        "--out",
        scene_dir.to_str().unwrap(),
    ]);
    assert_fails(&o, &["render.strand_width = 5", "wider than the hair"]);
    for bad in ["nan", "0", "-1"] {
        let mut args = TINY.to_vec();
        let set = format!("render.strand_width={bad}");
        args.extend(["24", "--set", &set, "--out", out_arg]);
        assert_fails(&hairlab(&args), &["render.strand_width must be in (0,"]);
    }
    assert_eq!(
        std::fs::read_dir(dir.path()).unwrap().count(),
        0,
        "a file was left behind"
    );
}

/// The ray-traced texels line up with the reference's: on a small head whose fibres are most of a texel wide,
/// a fibre crosses the footprint of nearly every texel the reference has fragments in (a flipped or shifted
/// footprint would miss most), and the fibres leave visible what the fragments do, to within the opacity model
/// (measured: 1227 of 1227 texels crossed, mean |ΔV| 0.097, best-fitting α 0.685 for `hair_alpha` 0.35). The
/// bands are the measurement's own spread widened 2.5×: over generator seeds 1–6 and 6², 8², 12² rays a texel,
/// α 0.683–0.695 (the rays move it ≤ 0.001) and mean |ΔV| 0.092–0.099; so α within 0.685 ± 0.03 and mean |ΔV|
/// < 0.11 (a fit off by a tenth, or the α of `hair_alpha` 0.35 itself, fails).
#[test]
fn the_ray_traced_map_lines_up_with_the_reference() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let settings = measured_preset(
        "default",
        &[
            "scene.generator.strands=600".into(),
            "scene.generator.segments=12".into(),
            "render.map_resolution=64".into(),
            "render.strand_width=0.004".into(),
        ],
    );
    let m = compare_map(&gpu, &settings, 8, &mut hairlab::progress::Quiet).unwrap();
    let crossed = m.texels.iter().filter(|t| t.ray_visibility < 1.0).count();
    eprintln!(
        "{} texels, {crossed} crossed by a fibre; mean |dV| {:.4}, best alpha {:.3}",
        m.texels.len(),
        m.mean_abs_dv,
        m.best_alpha
    );
    assert!(m.texels.len() > 300, "{} occupied texels", m.texels.len());
    assert!(
        crossed as f64 >= 0.95 * m.texels.len() as f64,
        "{crossed} of {} texels crossed",
        m.texels.len()
    );
    assert!(
        m.mean_abs_dv < 0.11 && (m.best_alpha - 0.685).abs() < 0.03,
        "mean |dV| {:.4}, best alpha {:.4}",
        m.mean_abs_dv,
        m.best_alpha
    );
}

/// Runs `hairlab ARGS` until it prints a line on stderr holding `needle`, then sends it SIGINT (Ctrl-C); returns
/// its exit status and its stderr lines. Fails the test when it ends first or says nothing for 10 minutes.
fn interrupt_once_said(args: &[&str], needle: &str) -> (std::process::ExitStatus, Vec<String>) {
    use std::io::BufRead;
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_hairlab"))
        .args(args)
        .env("RUST_LOG", "warn")
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("run hairlab");
    let err = child.stderr.take().unwrap();
    let (tx, rx) = std::sync::mpsc::channel();
    let reader = std::thread::spawn(move || {
        let mut lines = Vec::new();
        for line in std::io::BufReader::new(err).lines().map_while(Result::ok) {
            let _ = tx.send(line.clone());
            lines.push(line);
        }
        lines
    });
    loop {
        let line = rx
            .recv_timeout(std::time::Duration::from_secs(600))
            .unwrap_or_else(|e| panic!("hairlab said no {needle:?} ({e})"));
        if line.contains(needle) {
            break;
        }
    }
    let kill = std::process::Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .expect("run kill");
    assert!(kill.success());
    let status = child.wait().expect("wait for hairlab");
    (status, reader.join().unwrap())
}

/// The one `error:` line of `lines`.
fn the_error(lines: &[String]) -> String {
    let errors: Vec<&String> = lines
        .iter()
        .filter(|l| l.starts_with("error: ") && !l.contains("XDG_RUNTIME_DIR"))
        .collect();
    assert_eq!(errors.len(), 1, "{lines:?}");
    errors[0].clone()
}

/// Ctrl-C during a path-traced `render` stops it after the pass in progress: it writes the image of the samples
/// taken, whole, and exits 130 naming how many and the file; that image is exactly the render asked for that
/// many samples (each pixel's samples are summed in order, whatever the passes).
#[test]
fn sigint_writes_the_path_traced_image_of_the_samples_taken_and_exits_130() {
    let dir = tempfile::tempdir().unwrap();
    let (stopped, whole) = (dir.path().join("stopped.exr"), dir.path().join("whole.exr"));
    let mut args = TINY.to_vec();
    args.extend([
        "24",
        "--set",
        "render.spp=1000",
        "--out",
        stopped.to_str().unwrap(),
    ]);
    let (status, lines) = interrupt_once_said(&args, "path tracing: ");
    assert_eq!(status.code(), Some(130), "{lines:?}");
    let error = the_error(&lines);
    let done: u32 = error
        .strip_prefix("error: interrupted (Ctrl-C) after ")
        .and_then(|r| r.split(' ').next())
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("{error}"));
    assert!(done > 0 && done < 1000 && done.is_multiple_of(50), "{error}");
    assert!(
        error.ends_with(&format!(
            "of 1000 samples per pixel; {} holds those {done}",
            stopped.display()
        )),
        "{error}"
    );
    let mut args = TINY.to_vec();
    let spp = format!("render.spp={done}");
    args.extend(["24", "--set", &spp, "--out", whole.to_str().unwrap()]);
    let o = hairlab(&args);
    assert!(o.status.success(), "{}", stderr(&o));
    let (a, b) = (
        image::open(&stopped).unwrap().to_rgb32f(),
        image::open(&whole).unwrap().to_rgb32f(),
    );
    assert_eq!(a.dimensions(), (32, 24));
    assert!(a.pixels().any(|p| p.0.iter().any(|&c| c > 0.0)));
    assert!(a == b, "the stopped render differs from {done} spp asked for");
}

/// Ctrl-C during `measure visibility` stops it after the texel in progress: it writes visibility_texels.csv of
/// the texels measured, each row whole, and exits 130 naming how many (fewer than the map's).
#[test]
fn sigint_writes_the_visibility_texels_measured_and_exits_130() {
    if Gpu::for_tests().is_none() {
        return;
    }
    let out = tempfile::tempdir().unwrap();
    let (status, lines) = interrupt_once_said(
        &[
            "measure",
            "visibility",
            "--preset",
            "default",
            "--set",
            "scene.generator.strands=600",
            "--set",
            "render.map_resolution=64",
            "--rays",
            "64",
            "--out",
            out.path().to_str().unwrap(),
        ],
        "ray-tracing ",
    );
    assert_eq!(status.code(), Some(130), "{lines:?}");
    let total: usize = lines
        .iter()
        .find_map(|l| l.split("ray-tracing ").nth(1)?.split(' ').next()?.parse().ok())
        .unwrap();
    let csv = out.path().join("visibility_texels.csv");
    let mut r = csv::Reader::from_path(&csv).unwrap();
    let width = r.headers().unwrap().len();
    let rows = r
        .records()
        .map(|rec| rec.unwrap())
        .inspect(|rec| assert_eq!(rec.len(), width, "{rec:?}"))
        .count();
    assert!(rows > 0 && rows < total, "{rows} of {total} texels written");
    assert_eq!(
        the_error(&lines),
        format!(
            "error: interrupted (Ctrl-C) after {rows} texels; {} holds those {rows}",
            csv.display()
        )
    );
}
