//! Shaders from a folder (`--shaders DIR`): a broken file is reported at its own file, line and column (by the
//! library, the CLI and the window) and nothing is used from it; a valid change is what the next render draws.

use crate::common::cli::{assert_fails, hairlab, stderr};
use egui_kittest::Harness;
use hairlab::app::{HairlabApp, wgpu_setup};
use hairlab::gpu::AdapterPreference;
use hairlab::live_shaders::check_all;
use hairlab::shaders::SOURCES;
use hairlab::shaders::live::{Folder, LiveError};
use std::path::Path;

/// The file the tests break: included by the eye and light passes.
const BROKEN_FILE: &str = "common/frame.wgsl";

fn embedded(path: &str) -> &'static str {
    SOURCES.iter().find(|(p, _)| *p == path).unwrap().1
}

/// `dir/path` holding `text`.
fn write(dir: &Path, path: &str, text: &str) {
    let file = dir.join(path);
    std::fs::create_dir_all(file.parent().unwrap()).unwrap();
    std::fs::write(file, text).unwrap();
}

/// A folder whose copy of [`BROKEN_FILE`] has a syntax error on its line 2: `fn broken() -> f32 { return 1.0 +; }`
/// has its `;` in column 34.
fn broken_folder() -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    let text = format!(
        "// a copy with a syntax error\nfn broken() -> f32 {{ return 1.0 +; }}\n{}",
        embedded(BROKEN_FILE)
    );
    write(dir.path(), BROKEN_FILE, &text);
    dir
}

fn broken_place(dir: &Path) -> String {
    format!("{}:2:34", dir.join(BROKEN_FILE).display())
}

#[test]
fn a_syntax_error_in_a_folder_names_that_file_line_and_column() {
    let dir = broken_folder();
    let folder = Folder::read(dir.path()).unwrap();
    assert_eq!(folder.paths().collect::<Vec<_>>(), [BROKEN_FILE]);
    let e = check_all(Some(&folder)).unwrap_err().to_string();
    assert!(e.starts_with(&format!("{}: ", broken_place(dir.path()))), "{e}");
}

#[test]
fn a_folder_with_a_valid_copy_validates_as_the_embedded_shaders_do() {
    let dir = tempfile::tempdir().unwrap();
    write(
        dir.path(),
        BROKEN_FILE,
        &format!("// an edited copy\n{}", embedded(BROKEN_FILE)),
    );
    let folder = Folder::read(dir.path()).unwrap();
    assert_eq!(folder.coverage(), (1, SOURCES.len() - 1));
    let embedded_count = check_all(None).unwrap();
    assert!(embedded_count >= 100, "only {embedded_count} shaders");
    assert_eq!(check_all(Some(&folder)).unwrap(), embedded_count);
}

#[test]
fn a_folder_without_shaders_or_missing_is_refused_by_name() {
    let dir = tempfile::tempdir().unwrap();
    let e = Folder::read(dir.path()).unwrap_err();
    assert!(matches!(e, LiveError::Empty { .. }), "{e}");
    assert!(e.to_string().contains(&dir.path().display().to_string()));
    let missing = dir.path().join("missing");
    let e = Folder::read(&missing).unwrap_err();
    assert!(matches!(e, LiveError::Read { .. }), "{e}");
    assert!(e.to_string().starts_with(&missing.display().to_string()), "{e}");
}

/// The CLI refuses a broken folder, from the flag or the environment, with one error at the file, line and column,
/// before doing anything (no device needed).
#[test]
fn the_cli_reports_a_broken_shader_at_its_file_and_line() {
    let dir = broken_folder();
    let place = broken_place(dir.path());
    let d = dir.path().to_str().unwrap();
    let o = hairlab(&["adapters", "--shaders", d]);
    assert_fails(&o, &[&place]);
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_hairlab"))
        .arg("adapters")
        .env("HAIRLAB_SHADERS", d)
        .env("RUST_LOG", "warn")
        .output()
        .unwrap();
    assert_fails(&o, &[&place]);
    let o = hairlab(&[
        "adapters",
        "--shaders",
        dir.path().join("missing").to_str().unwrap(),
    ]);
    assert_fails(&o, &["missing"]);
}

/// A valid change is drawn: the default method's lookup in a folder returning 0 (every hair point in full shadow)
/// renders no pixel brighter than the embedded shaders do, leaves the background alone and darkens the lit hair.
#[test]
fn a_valid_change_in_a_folder_is_what_the_render_draws() {
    if hairlab::gpu::Gpu::for_tests().is_none() {
        return;
    }
    let settings = hairlab::settings::Settings::load_preset("default", &[]).unwrap();
    let method = hairlab::methods::registry::find(&settings.method.name).unwrap();
    let lookup = method.lookup_wgsl();
    let dir = tempfile::tempdir().unwrap();
    let text = embedded(lookup).replacen("fn visibility_at(", "fn visibility_at_embedded(", 1)
        + "\nfn visibility_at(texel: vec2<i32>, z: f32) -> f32 {\n    return 0.0;\n}\n";
    write(dir.path(), lookup, &text);
    let render = |shaders: Option<&Path>| {
        let out = dir.path().join(if shaders.is_some() {
            "folder.png"
        } else {
            "embedded.png"
        });
        let mut args = vec![
            "render".to_string(),
            "--set".into(),
            "scene.generator.strands=200".into(),
            "--width".into(),
            "64".into(),
            "--height".into(),
            "48".into(),
            "--out".into(),
            out.to_str().unwrap().into(),
        ];
        if let Some(d) = shaders {
            args.extend(["--shaders".into(), d.to_str().unwrap().into()]);
        }
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let o = hairlab(&args);
        assert!(o.status.success(), "{}", stderr(&o));
        image::open(&out).unwrap().to_rgba8()
    };
    let embedded_png = render(None);
    let folder_png = render(Some(dir.path()));
    let (mut darker, mut brighter, mut background_changed) = (0, 0, 0);
    let corner = embedded_png.get_pixel(0, 0);
    for (a, b) in embedded_png.pixels().zip(folder_png.pixels()) {
        let sum = |p: &image::Rgba<u8>| p.0[..3].iter().map(|&c| c as i32).sum::<i32>();
        if a == corner && b != corner {
            background_changed += 1;
        }
        if sum(b) + 3 < sum(a) {
            darker += 1;
        }
        if sum(b) > sum(a) + 3 {
            brighter += 1;
        }
    }
    assert_eq!(brighter, 0, "no pixel brighter in full shadow");
    assert_eq!(background_changed, 0, "the background does not change");
    assert!(darker >= 100, "only {darker} pixels darker");
}

/// The window shows a broken folder's error at its file, line and column in the message line.
#[test]
fn the_window_shows_a_broken_shader_at_its_file_and_line() {
    if hairlab::gpu::Gpu::for_tests().is_none() {
        return;
    }
    let dir = broken_folder();
    let place = broken_place(dir.path());
    let settings = crate::common::small_settings(160, 120);
    let watched = dir.path().to_path_buf();
    let mut harness = Harness::builder()
        .with_size([1000.0, 640.0])
        .wgpu_setup(wgpu_setup(AdapterPreference::Software))
        .build_eframe(move |cc| {
            let mut app = HairlabApp::new(cc, Some(settings));
            app.watch_shaders(&watched);
            app
        });
    harness.step();
    let (text, error) = harness.state().message().expect("a message");
    assert!(error, "{text}");
    assert!(text.starts_with(&format!("{place}: ")), "{text}");
}
