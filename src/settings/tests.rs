//! Settings: presets load and validate, words and old numbers read, overrides reach nested keys, TOML round trips.

use super::*;

#[test]
fn builtin_presets_parse_and_validate() {
    for (name, _) in BUILTIN_PRESETS {
        Settings::load_preset(name, &[]).unwrap_or_else(|e| panic!("preset {name}: {e:#}"));
    }
}

#[test]
fn render_mode_and_spp_parse_and_spp_is_bounded() {
    let s = Settings::load_preset("default", &["render.mode=path".into(), "render.spp=4".into()]).unwrap();
    assert_eq!(s.render.mode, crate::render::render_settings::RenderMode::Path);
    assert_eq!(s.render.spp, 4);
    for spp in ["0", "65537"] {
        let e = Settings::load_preset("default", &[format!("render.spp={spp}")]).unwrap_err();
        let text = format!("{e:#}");
        assert!(
            text.contains(&format!("render.spp must be in 1..=65536 (got {spp})")),
            "{text}"
        );
        assert_eq!(text.lines().count(), 1, "{text}");
    }
}

#[test]
fn angles_and_positions_must_be_meaningful_numbers() {
    for (set, key) in [
        (
            "camera.yaw_deg=nan",
            "camera.yaw_deg must be a finite number (got NaN)",
        ),
        ("camera.pitch_deg=nan", "camera.pitch_deg must be a finite number"),
        (
            "camera.pitch_deg=1e30",
            "camera.pitch_deg must be in [-90, 90] (got 1e30)",
        ),
        (
            "light.azimuth_deg=1e30",
            "light.azimuth_deg must be within ±36000 degrees",
        ),
        (
            "camera.yaw_deg=-inf",
            "camera.yaw_deg must be a finite number (got -inf)",
        ),
        ("light.intensity=nan", "light.intensity must be a finite number"),
        (
            "camera.target=[0.0, nan, 0.0]",
            "camera.target must be a finite number",
        ),
    ] {
        let e = Settings::load_preset("default", &[set.to_string()]).unwrap_err();
        let text = format!("{e:#}");
        assert!(text.contains(key), "{set}: {text}");
    }
    let turned = Settings::load_preset("default", &["light.azimuth_deg=720".into()]).unwrap();
    assert_eq!(turned.light.azimuth_deg, 720.0);
}

#[test]
fn overrides_reach_nested_keys_and_are_validated() {
    let s = Settings::from_toml_with(
        "",
        "test",
        &[
            "render.hair_alpha=0.5".into(),
            format!(
                "method.name={}",
                crate::methods::LightMethod::name(&crate::methods::none::NoShadow)
            ),
            "scene.generator.seed=7".into(),
        ],
    )
    .unwrap();
    assert_eq!(s.render.hair_alpha, 0.5);
    assert_eq!(
        s.method.name,
        crate::methods::LightMethod::name(&crate::methods::none::NoShadow)
    );
    assert_eq!(s.scene.generator.seed, 7);
    let e = Settings::from_toml_with("", "test", &["render.hair_alpha=2".into()]).unwrap_err();
    assert!(format!("{e:#}").contains("hair_alpha"), "{e:#}");
    let e = Settings::from_toml_with("", "test", &["method.params.bias=5".into()]).unwrap_err();
    assert!(format!("{e:#}").contains("'bias' = 5 is out of range"), "{e:#}");
    let e = Settings::from_toml_with("[render]\nwidht = 3\n", "x.toml", &[]).unwrap_err();
    assert!(
        format!("{e:#}").contains("x.toml") && format!("{e:#}").contains("widht"),
        "{e:#}"
    );
}

#[test]
fn the_transparency_technique_is_validated_against_the_registry() {
    let default = techniques::default_technique().name();
    assert_eq!(Settings::default().transparency.name, default);
    let s = Settings::from_toml_with("", "test", &[format!("transparency.name={default}")]).unwrap();
    assert_eq!(s, Settings::default());
    let e = Settings::from_toml_with("", "x.toml", &["transparency.name=none-such".into()]).unwrap_err();
    assert!(
        format!("{e:#}").starts_with(
            "x.toml: invalid preset: transparency.name: unknown eye transparency technique 'none-such' (known: "
        ),
        "{e:#}"
    );
    let e = Settings::from_toml_with("", "x.toml", &["transparency.params.nope=1".into()]).unwrap_err();
    assert!(
        format!("{e:#}").starts_with("x.toml: invalid preset: transparency.params.nope: technique '"),
        "{e:#}"
    );
    let e = Settings::from_toml_with("[render]\ntransparency = \"x\"\n", "x.toml", &[]).unwrap_err();
    assert!(format!("{e:#}").contains("transparency"), "{e:#}");
}

#[test]
fn choices_are_words_in_toml_and_old_numbers_still_load() {
    let s = Settings::from_toml_with(
        "[method]\nname = \"dom\"\nparams = { spacing = \"uniform\", beyond = 2 }\n",
        "test",
        &["method.params.layers=5".into()],
    )
    .unwrap();
    assert_eq!(s.method.params["spacing"], 1.0);
    assert_eq!(s.method.params["beyond"], 2.0);
    let text = s.to_toml();
    assert!(
        text.contains("spacing = \"uniform\"") && text.contains("beyond = \"stretch\""),
        "{text}"
    );
    assert_eq!(Settings::from_toml(&text, "roundtrip").unwrap(), s);
    let e = Settings::from_toml_with(
        "",
        "test",
        &["method.name=dom".into(), "method.params.spacing=wide".into()],
    )
    .unwrap_err();
    assert!(
        format!("{e:#}")
            .contains("method.params.spacing: parameter 'spacing': 'wide' is not one of linear, uniform"),
        "{e:#}"
    );
}

#[test]
fn alpha_mode_and_strand_width_are_read_and_checked_by_name() {
    let s = Settings::from_toml_with(
        "",
        "test",
        &["render.alpha=coverage".into(), "render.strand_width=8e-5".into()],
    )
    .unwrap();
    assert_eq!(s.render.alpha, crate::render::AlphaMode::Coverage);
    assert_eq!(s.render.strand_width, 8e-5);
    assert_eq!(
        Settings::default().render.alpha,
        crate::render::AlphaMode::Constant
    );
    for bad in ["0", "-1e-3", "nan", "inf", "1e5"] {
        let e = Settings::from_toml_with("", "x.toml", &[format!("render.strand_width={bad}")]).unwrap_err();
        assert!(
            format!("{e:#}").starts_with("x.toml: invalid preset: render.strand_width must be in (0, 10000]"),
            "{bad}: {e:#}"
        );
    }
    let e = Settings::from_toml_with("", "x.toml", &["render.alpha=cover".into()]).unwrap_err();
    assert!(
        format!("{e:#}").contains("render.alpha") && format!("{e:#}").contains("coverage"),
        "{e:#}"
    );
}

#[test]
fn shading_model_is_read_by_its_word_and_bad_words_name_the_key() {
    use crate::shading::ShadingModel;
    assert_eq!(Settings::default().render.shading, ShadingModel::KajiyaKay);
    for model in ShadingModel::ALL {
        let set = format!("render.shading={}", model.word());
        let s = Settings::from_toml_with("", "test", &[set]).unwrap();
        assert_eq!(s.render.shading, model);
        assert_eq!(Settings::from_toml(&s.to_toml(), "roundtrip").unwrap(), s);
    }
    let e = Settings::from_toml_with("", "x.toml", &["render.shading=phong".into()]).unwrap_err();
    let text = format!("{e:#}");
    assert!(
        text.contains("x.toml") && text.contains("render.shading"),
        "{text}"
    );
    for model in ShadingModel::ALL {
        assert!(text.contains(model.word()), "{text}");
    }
}

#[test]
fn round_trips_through_toml() {
    let mut s = Settings::default();
    s.render.hair_alpha = 0.25;
    s.method.params.insert("bias".into(), 0.01);
    let back = Settings::from_toml(&s.to_toml(), "roundtrip").unwrap();
    assert_eq!(back, s);
}

/// `render.light_strands` defaults to `auto`, which draws ribbons under the fibres model on the hardware
/// rasteriser and lines under the absorber model or the compute rasteriser; a word given is drawn as it is.
#[test]
fn auto_light_strands_follow_the_hair_model() {
    use crate::render::LightStrands;
    let drawn = |sets: &[&str]| {
        let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
        let s = Settings::load_preset("default", &sets).unwrap();
        (s.render.light_strands, s.render.strands_drawn())
    };
    assert_eq!(drawn(&[]), (LightStrands::Auto, LightStrands::Lines));
    assert_eq!(
        drawn(&["render.hair_model=fibres"]),
        (LightStrands::Auto, LightStrands::Ribbons)
    );
    assert_eq!(
        drawn(&["render.hair_model=fibres", "render.raster=compute"]).1,
        LightStrands::Lines
    );
    assert_eq!(
        drawn(&["render.hair_model=fibres", "render.light_strands=lines"]).1,
        LightStrands::Lines
    );
    assert_eq!(drawn(&["render.light_strands=ribbons"]).1, LightStrands::Ribbons);
    let e = Settings::load_preset(
        "default",
        &[
            "render.light_strands=ribbons".into(),
            "render.raster=compute".into(),
        ],
    )
    .unwrap_err();
    assert!(format!("{e:#}").contains("render.light_strands"), "{e:#}");
}
