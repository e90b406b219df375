//! Every shader file embedded; every pass composed with every light caster, method and technique and validated;
//! method and technique passes refused without one; the shared declarations and visibility expressions written
//! once.

use super::validate;
use hairlab::methods::registry;
use hairlab::render::caster::ALL_STAGES;
use hairlab::render::transparency::registry as techniques;
use hairlab::shaders::{METHOD_PASSES, SOURCES, TECHNIQUE_PASSES, compose, compose_light, compose_with};
use std::path::Path;

fn pass_shaders() -> impl Iterator<Item = &'static str> {
    SOURCES.iter().map(|(p, _)| *p).filter(|p| {
        !["common/", "methods/", "transparency/", "casters/"]
            .iter()
            .any(|d| p.starts_with(d))
    })
}

/// The build script embeds every WGSL file of `shaders/`, at any depth, under its path relative to it.
#[test]
fn every_shader_file_is_embedded() {
    fn walk(root: &Path, dir: &Path, out: &mut Vec<String>) {
        for e in std::fs::read_dir(dir).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                walk(root, &p, out);
            } else if p.extension().is_some_and(|x| x == "wgsl") {
                out.push(p.strip_prefix(root).unwrap().to_string_lossy().replace('\\', "/"));
            }
        }
    }
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("shaders");
    let mut on_disk = Vec::new();
    walk(&root, &root, &mut on_disk);
    on_disk.sort();
    let mut embedded: Vec<String> = SOURCES.iter().map(|(p, _)| p.to_string()).collect();
    embedded.sort();
    assert!(on_disk.len() >= 90, "only {} shader files", on_disk.len());
    assert_eq!(
        on_disk, embedded,
        "shaders/ and hairlab::shaders::SOURCES disagree"
    );
}

/// Every light pass (a shader taking the light vertex stage) composes and validates with every light caster's
/// vertex stage, and its vertex entry reads what that caster provides.
#[test]
fn every_light_pass_validates_with_every_caster() {
    let light_passes: Vec<&str> = pass_shaders()
        .filter(|p| compose(p, None).is_ok_and(|src| src.contains("fn light_vertex(")))
        .collect();
    assert!(light_passes.len() >= 10, "only {light_passes:?}");
    for stage in ALL_STAGES {
        for pass in &light_passes {
            let src = compose_light(pass, stage.wgsl).unwrap();
            let (module, _) = validate(&format!("{pass} + {}", stage.wgsl), &src);
            let vs = module.entry_points.iter().find(|e| e.name == "vs_main").unwrap();
            let locations = vs.function.arguments.iter().filter(|a| {
                matches!(a.binding, Some(naga::Binding::Location { .. }))
                    || matches!(module.types[a.ty].inner, naga::TypeInner::Struct { ref members, .. }
                        if members.iter().any(|m| matches!(m.binding, Some(naga::Binding::Location { .. }))))
            });
            assert_eq!(
                locations.count() > 0,
                stage.vertex_buffer.is_some(),
                "{pass} + {}: vertex inputs against the caster's vertex buffer",
                stage.wgsl
            );
        }
    }
}

/// Every pass shader composes and validates: with every method's lookup where it takes one, with every eye
/// transparency technique's store function too where it takes one (the hair pass: method × technique), and every
/// technique's resolve pass.
#[test]
fn every_pass_validates_with_every_method() {
    let mut checked = 0;
    for pass in pass_shaders() {
        if METHOD_PASSES.contains(&pass) {
            for m in registry::all() {
                if TECHNIQUE_PASSES.contains(&pass) {
                    for t in techniques::all() {
                        let store = t.info().hair_wgsl;
                        let src = compose_with(pass, Some(m.lookup_wgsl()), Some(store)).unwrap();
                        validate(&format!("{pass} + {} + {store}", m.lookup_wgsl()), &src);
                        checked += 1;
                    }
                } else {
                    let src = compose(pass, Some(m.lookup_wgsl())).unwrap();
                    validate(&format!("{pass} + {}", m.lookup_wgsl()), &src);
                    checked += 1;
                }
            }
        } else {
            let src = compose(pass, None).unwrap();
            validate(pass, &src);
            checked += 1;
        }
    }
    let mut own_passes = 0;
    for t in techniques::all() {
        for pass in t.info().pass_wgsl {
            validate(&format!("{}: {pass}", t.name()), &compose(pass, None).unwrap());
            own_passes += 1;
        }
    }
    let (methods, technique_count) = (registry::all().len(), techniques::all().len());
    assert_eq!(
        checked,
        pass_shaders().count()
            + METHOD_PASSES.len() * (methods - 1)
            + TECHNIQUE_PASSES.len() * methods * (technique_count - 1)
    );
    assert!(
        own_passes >= technique_count - 1,
        "every technique but opaque has a pass of its own"
    );
    assert!(TECHNIQUE_PASSES.iter().all(|p| METHOD_PASSES.contains(p)));
}

#[test]
fn method_passes_refuse_to_compose_without_a_method() {
    for pass in METHOD_PASSES {
        assert!(compose(pass, None).is_err(), "{pass}");
    }
}

#[test]
fn technique_passes_refuse_to_compose_without_a_technique() {
    for pass in TECHNIQUE_PASSES {
        assert_eq!(
            compose(pass, Some("methods/none.wgsl")).unwrap_err().to_string(),
            format!("{pass}: needs an eye transparency technique")
        );
    }
}

/// A registered technique is complete: its store function and resolve are embedded, the hair pass's fragment
/// outputs (`HairOutput`) are the technique's colour targets location by location, each with at least the
/// target format's components, and its label and paper are written.
/// The exact reference's and the fur's resolves validate with their sorts instantiated for every size.
#[test]
fn the_list_resolves_validate_at_every_sort_size() {
    use hairlab::render::transparency::sorted::{SORT_SIZES, resolve_source};
    for path in ["transparency/sorted_resolve.wgsl", "fur/resolve.wgsl"] {
        for max in SORT_SIZES {
            validate(
                &format!("{path} up to {max}"),
                &resolve_source(path, max).unwrap(),
            );
        }
    }
}

/// Names declared (`struct X` or `fn x(`) in `src`, entry points (`@vertex`, `@fragment`, `@compute`) aside: a
/// pass names its own.
fn declarations(src: &str) -> Vec<String> {
    let lines: Vec<&str> = src.lines().collect();
    let entry = |i: usize| {
        i > 0
            && ["@vertex", "@fragment", "@compute"]
                .iter()
                .any(|a| lines[i - 1].starts_with(a))
    };
    lines
        .iter()
        .enumerate()
        .filter(|&(i, _)| !entry(i))
        .filter_map(|(_, l)| l.strip_prefix("struct ").or_else(|| l.strip_prefix("fn ")))
        .map(|rest| {
            rest.split(|c: char| !(c.is_alphanumeric() || c == '_'))
                .next()
                .unwrap()
                .to_string()
        })
        .collect()
}

/// Every struct and function of a shared file (`common/`) is declared in that one file: the others include it
/// instead of copying it.
#[test]
fn shared_declarations_are_written_once() {
    let shared = |p: &str| p.starts_with("common/");
    let mut checked = 0;
    for (path, src) in SOURCES.iter().filter(|(p, _)| shared(p)) {
        for name in declarations(src) {
            let elsewhere: Vec<&str> = SOURCES
                .iter()
                .filter(|(p, s)| p != path && declarations(s).contains(&name))
                .map(|(p, _)| *p)
                .collect();
            assert!(
                elsewhere.is_empty(),
                "{name} of {path} is declared again in {elsewhere:?}"
            );
            checked += 1;
        }
    }
    for name in [
        "OsmUniforms",
        "DomUniforms",
        "BomUniforms",
        "DcUniforms",
        "OccupancyUniforms",
        "relative_depth",
    ] {
        assert!(
            SOURCES
                .iter()
                .any(|(p, s)| shared(p) && declarations(s).iter().any(|d| d == name)),
            "{name} is not in a shared file"
        );
    }
    assert!(checked > 20, "only {checked} shared declarations found");
}

/// The expressions `visibility/mod.rs` names as the GPU's (its doc comments) are written once, in
/// `common/visibility.wgsl`; every other file calls those functions.
#[test]
fn shared_visibility_expressions_are_written_once() {
    let expressions = [
        "-log(1.0 - clamp(alpha, 0.0, 1.0 - 1e-6))",
        "select(select(0.0, 1.0, z > near), (z - near) / (far - near), far > near)",
        "min(u32(max(floor(x), 0.0)), n - 1u)",
        "min(a + (b - a) * f, b)",
        "exp(-omega)",
    ];
    let visibility = SOURCES
        .iter()
        .find(|(p, _)| *p == "common/visibility.wgsl")
        .unwrap()
        .1;
    for e in expressions {
        assert!(visibility.contains(e), "common/visibility.wgsl lacks {e}");
    }
    // Parts of the expressions that no other file's code (comments aside) may repeat.
    let code = |src: &str| -> String {
        src.lines()
            .map(|l| l.split("//").next().unwrap())
            .collect::<Vec<_>>()
            .join("\n")
    };
    // The hair BSDFs' Gaussians, longitudinal terms and absorption (Marschner, dual scattering, Chiang) are
    // exponentials that are not visibility.
    let bsdf = |path: &str, part: &str| {
        [
            "common/marschner.wgsl",
            "common/dual_scattering.wgsl",
            "common/chiang.wgsl",
        ]
        .contains(&path)
            && part == "exp("
    };
    for part in ["log(1.0 -", "select(select(", "max(floor(", "exp(", "(b - a) * f"] {
        let copies: Vec<&str> = SOURCES
            .iter()
            .filter(|(p, s)| code(s).contains(part) && !bsdf(p, part))
            .map(|(p, _)| *p)
            .collect();
        assert_eq!(
            copies,
            ["common/visibility.wgsl"],
            "'{part}' is written in {copies:?}"
        );
    }
}
