//! Every WGSL file is embedded, composes, parses and validates with naga (no GPU needed), and the Rust uniform
//! and vertex structs match the WGSL declarations.

use hairlab::methods::registry;
use hairlab::render::caster::ALL_STAGES;
use hairlab::render::caster::raster_model::{RASTER_FRAGMENT_FIELDS, RasterFragment};
use hairlab::render::geometry::{HAIR_VERTEX_FIELDS, HairVertex, MeshVertex};
use hairlab::render::transparency::registry as techniques;
use hairlab::render::uniforms::{FRAME_UNIFORMS_FIELDS, FrameUniforms};
use hairlab::shaders::{METHOD_PASSES, SOURCES, TECHNIQUE_PASSES, compose, compose_light, compose_with};
use std::path::Path;

fn validate(label: &str, src: &str) -> (naga::Module, naga::valid::ModuleInfo) {
    let module =
        naga::front::wgsl::parse_str(src).unwrap_or_else(|e| panic!("{label}: {}", e.emit_to_string(src)));
    let info = naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::all(),
    )
    .validate(&module)
    .unwrap_or_else(|e| panic!("{label}: {}", e.emit_to_string(src)));
    (module, info)
}

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

/// `(location, component count)` of the outputs of the entry point `entry` of `module`.
fn fragment_outputs(module: &naga::Module, entry: &str) -> Vec<(u32, u64)> {
    let ep = module.entry_points.iter().find(|e| e.name == entry).unwrap();
    let Some(result) = ep.function.result.as_ref() else {
        return Vec::new();
    };
    let components = |ty: naga::Handle<naga::Type>| match &module.types[ty].inner {
        naga::TypeInner::Scalar(_) => 1,
        naga::TypeInner::Vector { size, .. } => *size as u64,
        other => panic!("{entry}: output of type {other:?}"),
    };
    let mut out = Vec::new();
    let mut collect = |ty, binding: &Option<naga::Binding>| {
        if let Some(naga::Binding::Location { location, .. }) = binding {
            out.push((*location, components(ty)));
        }
    };
    match &module.types[result.ty].inner {
        naga::TypeInner::Struct { members, .. } => members.iter().for_each(|m| collect(m.ty, &m.binding)),
        _ => collect(result.ty, &result.binding),
    }
    out.sort();
    out
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

/// A registered technique is complete, as a method is (`every_registered_method_is_complete`): a label and a
/// paper, its WGSL embedded and validating, hair entries whose outputs match their targets, a colour of its own, a
/// CPU model giving a valid colour (the exact composite for a reference), parameters with valid defaults, a sweep
/// of valid configurations, a stated tolerance; its uniform mirror is checked by `technique_uniforms_match_wgsl_layout`.
#[test]
fn every_registered_technique_is_complete() {
    use hairlab::render::method::Role;
    use hairlab::transparency::{EyeFragment, ModelContext};
    let embedded = |p: &str| SOURCES.iter().any(|(s, _)| *s == p);
    let fragments = [
        (0.30, 4, [0.8, 0.2, 0.1], 0.5),
        (0.10, 9, [0.1, 0.7, 0.3], 0.4),
        (0.30, 2, [0.2, 0.2, 0.9], 0.6),
        (0.55, 1, [0.5, 0.5, 0.5], 0.3),
    ]
    .map(|(depth, segment, color, alpha)| EyeFragment {
        depth,
        segment,
        color,
        alpha,
    });
    let ctx = ModelContext {
        hair_alpha: 0.5,
        depth_range: [0.1, 0.55],
    };
    let exact = techniques::reference().model(&Default::default(), &ctx);
    let mut colors = Vec::new();
    for t in techniques::every() {
        let info = t.info();
        let name = info.name;
        assert!(
            !info.label.is_empty() && !info.paper.is_empty(),
            "{name}: label and paper"
        );
        assert!(
            !colors.contains(&info.color),
            "{name}: colour {:?} taken",
            info.color
        );
        colors.push(info.color);
        for spec in info.params {
            spec.check(spec.default)
                .unwrap_or_else(|e| panic!("{name}: default of {}: {e}", spec.key));
        }
        let sweep = t.sweep();
        assert!(!sweep.is_empty(), "{name}: no bench sweep");
        for values in &sweep {
            for (key, v) in values {
                let spec = techniques::spec(t, key).unwrap_or_else(|e| panic!("{name}: sweep: {e}"));
                spec.check(*v)
                    .unwrap_or_else(|e| panic!("{name}: sweep {key} = {v}: {e}"));
            }
            let model = t.model(values, &ctx);
            for background in [[0.0; 3], [1.0; 3]] {
                let c = model.composite(&fragments, background);
                assert!(
                    c.iter()
                        .all(|c| c.is_finite() && (-1e-6..=1.0 + 1e-6).contains(c)),
                    "{name}: CPU model over {background:?} gives {c:?}"
                );
                if info.role == Role::Reference {
                    assert_eq!(
                        c,
                        exact.composite(&fragments, background),
                        "{name}: a reference is exact"
                    );
                }
            }
        }
        for file in std::iter::once(&info.hair_wgsl).chain(info.pass_wgsl) {
            assert!(embedded(file), "{name}: {file} not embedded");
        }
        assert!(!info.hair_entries.is_empty(), "{name}: no hair entry");
        let src = compose_with("hair.wgsl", Some("methods/none.wgsl"), Some(info.hair_wgsl)).unwrap();
        let (module, _) = validate(name, &src);
        for entry in info.hair_entries {
            let outputs = fragment_outputs(&module, entry.entry);
            // A target nothing is written to (the null target of storage-only passes) needs no output.
            let written = entry.targets.iter().filter(|t| !t.write_mask.is_empty()).count();
            assert_eq!(
                outputs.len(),
                written,
                "{name}.{}: outputs vs targets",
                entry.entry
            );
            for (i, ((location, components), target)) in outputs.iter().zip(entry.targets).enumerate() {
                assert_eq!(*location, i as u32, "{name}: output locations");
                assert!(
                    *components >= target.format.components() as u64,
                    "{name}: output {location} has {components} components for a {:?} target",
                    target.format
                );
            }
        }
        assert!(
            info.gpu_tolerance > 0.0 && info.gpu_tolerance < 0.01,
            "{name}: tolerance"
        );
    }
}

/// Size and `(field name, byte offset)` of the WGSL struct `name` in the composed `pass`.
fn wgsl_struct(pass: &str, method: Option<&str>, name: &str) -> (usize, Vec<(String, usize)>) {
    let src = compose(pass, method).unwrap();
    let (module, _) = validate(pass, &src);
    let (_, ty) = module
        .types
        .iter()
        .find(|(_, t)| t.name.as_deref() == Some(name))
        .unwrap_or_else(|| panic!("no struct {name} in {pass}"));
    let naga::TypeInner::Struct { members, span } = &ty.inner else {
        panic!("{name} is not a struct")
    };
    (
        *span as usize,
        members
            .iter()
            .map(|m| (m.name.clone().unwrap_or_default(), m.offset as usize))
            .collect(),
    )
}

/// Checks a Rust mirror (its size and `(WGSL field name, Rust offset)` list) against the WGSL struct in every
/// `(shader, method lookup, struct name)`: each composed shader must see the struct, with the same layout.
fn check_mirror(rust_size: usize, rust: &[(&'static str, usize)], wgsl: &[(&str, Option<&str>, &str)]) {
    let rust: Vec<(String, usize)> = rust.iter().map(|(n, o)| (n.to_string(), *o)).collect();
    for (file, method, name) in wgsl {
        let (size, fields) = wgsl_struct(file, *method, name);
        assert_eq!(size, rust_size, "{name} in {file}: size");
        assert_eq!(
            fields, rust,
            "{name} in {file}: field names/offsets differ between Rust and WGSL"
        );
    }
}

#[test]
fn frame_uniforms_match_wgsl_layout() {
    check_mirror(
        std::mem::size_of::<FrameUniforms>(),
        FRAME_UNIFORMS_FIELDS,
        &[("common/frame.wgsl", None, "FrameUniforms")],
    );
}

/// The strand simulation's uniforms: the substep's `Params`, the follow pass's `FollowParams`, and the collider
/// in both passes that include `motion/collide.wgsl`.
#[test]
fn motion_params_match_wgsl_layout() {
    use hairlab::motion::gpu::{self as motion, ColliderParams, FollowParams, Params};
    check_mirror(
        std::mem::size_of::<Params>(),
        motion::PARAMS_FIELDS,
        &[("motion/simulate.wgsl", None, "Params")],
    );
    check_mirror(
        std::mem::size_of::<FollowParams>(),
        motion::FOLLOW_PARAMS_FIELDS,
        &[("motion/follow.wgsl", None, "FollowParams")],
    );
    check_mirror(
        std::mem::size_of::<ColliderParams>(),
        motion::COLLIDER_PARAMS_FIELDS,
        &[
            ("motion/simulate.wgsl", None, "ColliderParams"),
            ("motion/follow.wgsl", None, "ColliderParams"),
        ],
    );
}

/// The ribbons' storage view of a strand point (`HairPoint`, pulled by `eye_ribbon_point`) is the Rust
/// `HairVertex` the vertex buffer holds, field by field.
#[test]
fn ribbon_hair_points_match_the_rust_hair_vertex() {
    check_mirror(
        std::mem::size_of::<HairVertex>(),
        HAIR_VERTEX_FIELDS,
        &[("common/eye_vertex.wgsl", None, "HairPoint")],
    );
}

/// The compute rasteriser's stream fragment, in the passes that write it and the caster that draws it.
#[test]
fn raster_fragment_matches_wgsl_layout() {
    check_mirror(
        std::mem::size_of::<RasterFragment>(),
        RASTER_FRAGMENT_FIELDS,
        &[
            ("raster/raster.wgsl", None, "RasterFragment"),
            ("raster/tiles.wgsl", None, "RasterFragment"),
            ("common/raster_stream.wgsl", None, "RasterFragment"),
        ],
    );
}

/// The fur volume pass's uniforms, and the prisms it shares with the shell pass (`common/fur_face.wgsl`), against
/// their Rust mirrors in every pass that reads them.
#[test]
fn fur_density_structs_match_wgsl_layout() {
    use hairlab::render::fur::density::{FUR_DENSITY_UNIFORMS_FIELDS, FurDensityUniforms};
    use hairlab::render::fur::shell_gpu::{FUR_FACE_FIELDS, FurFace};
    check_mirror(
        std::mem::size_of::<FurDensityUniforms>(),
        FUR_DENSITY_UNIFORMS_FIELDS,
        &[("fur/density.wgsl", None, "FurDensityUniforms")],
    );
    check_mirror(
        std::mem::size_of::<FurFace>(),
        FUR_FACE_FIELDS,
        &[
            ("fur/density.wgsl", None, "FurFace"),
            ("fur/shell.wgsl", None, "FurFace"),
        ],
    );
}

/// The opacity-layer family's atomic build uniforms against its count passes (the family's light shaders) and
/// its resolve pass, and the resolve's part of a band.
#[test]
fn opacity_layer_build_uniforms_match_wgsl_layout() {
    let u = hairlab::methods::opacity_layers::build_uniforms_mirror();
    let wgsl: Vec<_> = ["osm.wgsl", "dom.wgsl", "bom.wgsl", "layer_resolve.wgsl"]
        .iter()
        .map(|p| (*p, None, u.wgsl_name))
        .collect();
    check_mirror(u.size, &u.fields, &wgsl);
    let part = hairlab::methods::opacity_layers::resolve_part_mirror();
    check_mirror(
        part.size,
        &part.fields,
        &[("layer_resolve.wgsl", None, part.wgsl_name)],
    );
}

/// The A-buffer list sort's part of a dispatch.
#[test]
fn list_sort_part_matches_wgsl_layout() {
    let part = hairlab::render::passes::list_sort::sort_part_mirror();
    check_mirror(
        part.size,
        &part.fields,
        &[("list_sort.wgsl", None, part.wgsl_name)],
    );
}

/// A `u32` constant declared in a composed shader.
fn wgsl_u32(module: &naga::Module, name: &str) -> u32 {
    let constant = module
        .constants
        .iter()
        .map(|(_, c)| c)
        .find(|c| c.name.as_deref() == Some(name))
        .unwrap_or_else(|| panic!("no constant {name}"));
    match module.global_expressions[constant.init] {
        naga::Expression::Literal(naga::Literal::U32(v)) => v,
        ref e => panic!("{name} is not a u32 literal: {e:?}"),
    }
}

/// The list sort's chunk and the walk's largest batch, which the CPU adapter's loop budgets are counted in.
#[test]
fn list_sort_and_walk_constants_match_wgsl() {
    use hairlab::render::passes::{abuffer, list_sort};
    let src = compose("list_sort.wgsl", None).unwrap();
    let (module, _) = validate("list_sort.wgsl", &src);
    assert_eq!(u64::from(wgsl_u32(&module, "SORT_CHUNK")), list_sort::CHUNK);
    let src = compose("avsm.wgsl", None).unwrap();
    let (module, _) = validate("avsm.wgsl", &src);
    assert_eq!(wgsl_u32(&module, "LIST_BATCH_MAX"), abuffer::WALK_BATCH_MAX);
}

/// Every registered method's uniform mirror against every WGSL shader of the method (its light passes, and its
/// lookup composed into the evaluation pass).
#[test]
fn method_uniforms_match_wgsl_layout() {
    let mut checked = 0;
    for m in registry::all() {
        let Some(u) = m.uniform_mirror() else { continue };
        let mut shaders: Vec<(&str, Option<&str>)> = m.info().light_wgsl.iter().map(|p| (*p, None)).collect();
        shaders.push(("evaluate.wgsl", Some(m.lookup_wgsl())));
        let wgsl: Vec<_> = shaders.iter().map(|(p, l)| (*p, *l, u.wgsl_name)).collect();
        check_mirror(u.size, &u.fields, &wgsl);
        checked += 1;
    }
    assert!(checked >= 5, "only {checked} methods have uniform mirrors");
}

/// Every registered technique's uniform mirror against every WGSL shader of the technique that declares the
/// struct (its own passes, and its hair file composed into the hair pass); a technique whose shaders bind a uniform
/// struct of their own must have a mirror.
#[test]
fn technique_uniforms_match_wgsl_layout() {
    let mut checked = 0;
    for t in techniques::every() {
        let info = t.info();
        let mut sources: Vec<(String, String)> = info
            .pass_wgsl
            .iter()
            .map(|p| (p.to_string(), compose(p, None).unwrap()))
            .collect();
        sources.push((
            format!("hair.wgsl + {}", info.hair_wgsl),
            compose_with("hair.wgsl", Some("methods/none.wgsl"), Some(info.hair_wgsl)).unwrap(),
        ));
        let own_struct = sources.iter().any(|(_, src)| {
            src.lines().any(|l| {
                l.contains("var<uniform>")
                    && l.trim_end().ends_with("Uniforms;")
                    && !l.contains("FrameUniforms")
            })
        });
        let Some(u) = t.uniform_mirror() else {
            assert!(
                !own_struct,
                "{}: binds a uniform struct of its own but has no mirror",
                info.name
            );
            continue;
        };
        let rust: Vec<(String, usize)> = u.fields.iter().map(|(n, o)| (n.to_string(), *o)).collect();
        let mut seen = 0;
        for (label, src) in &sources {
            let (module, _) = validate(label, src);
            let Some((_, ty)) = module
                .types
                .iter()
                .find(|(_, t)| t.name.as_deref() == Some(u.wgsl_name))
            else {
                continue;
            };
            let naga::TypeInner::Struct { members, span } = &ty.inner else {
                panic!("{}: {} is not a struct", info.name, u.wgsl_name)
            };
            let wgsl: Vec<(String, usize)> = members
                .iter()
                .map(|m| (m.name.clone().unwrap_or_default(), m.offset as usize))
                .collect();
            assert_eq!(
                *span as usize, u.size,
                "{}: {} in {label}: size",
                info.name, u.wgsl_name
            );
            assert_eq!(
                wgsl, rust,
                "{}: {} in {label}: field names/offsets",
                info.name, u.wgsl_name
            );
            seen += 1;
        }
        assert!(seen > 0, "{}: no shader declares {}", info.name, u.wgsl_name);
        checked += 1;
    }
    assert!(checked >= 4, "only {checked} techniques have uniform mirrors");
}

/// A registered method is complete: a CPU model giving valid curves, light and lookup WGSL that validate, a
/// uniform mirror (approximations), parameters whose defaults are valid, a sweep of valid configurations (a
/// baseline may have none), a colour of its own. Adding a method to the registry without one of these fails here.
#[test]
fn every_registered_method_is_complete() {
    use hairlab::methods::{Role, validate as validate_values};
    use hairlab::visibility::Fragment;
    let texel: Vec<Fragment> = [(0.1, 0.3), (0.4, 0.5), (0.45, 0.2), (0.9, 0.6)]
        .map(Fragment::from)
        .to_vec();
    let zs: Vec<f32> = (0..=50).map(|i| i as f32 / 50.0).collect();
    let mut colors = Vec::new();
    for m in registry::all() {
        let info = m.info();
        let name = info.name;
        assert!(
            !name.is_empty() && name.chars().all(|c| c.is_ascii_lowercase() || c == '-'),
            "{name}: names are kebab-case"
        );
        assert!(
            !info.label.is_empty() && !info.paper.is_empty(),
            "{name}: label and paper"
        );
        assert!(
            !colors.contains(&info.color),
            "{name}: colour {:?} taken",
            info.color
        );
        colors.push(info.color);
        for spec in info.params {
            spec.check(spec.default)
                .unwrap_or_else(|e| panic!("{name}: default of {}: {e}", spec.key));
        }
        let v = m.model(&Default::default(), 0.4).curve(&texel, &zs);
        assert!(
            v.iter().all(|v| (0.0..=1.0).contains(v)) && v.windows(2).all(|w| w[1] <= w[0] + 1e-6),
            "{name}: CPU model curve {v:?}"
        );
        let embedded = |p: &str| SOURCES.iter().any(|(s, _)| *s == p);
        assert!(
            embedded(info.lookup_wgsl),
            "{name}: lookup {} not embedded",
            info.lookup_wgsl
        );
        for pass in info.light_wgsl {
            assert!(embedded(pass), "{name}: light pass {pass} not embedded");
            validate(
                &format!("{name}: {pass}"),
                &compose(pass, None).unwrap_or_else(|e| panic!("{name}: {pass}: {e}")),
            );
        }
        let sweep = m.sweep();
        assert!(
            !sweep.is_empty() || info.role == Role::Baseline,
            "{name}: no bench sweep (only a baseline may have none)"
        );
        for p in &sweep {
            validate_values(*m, &p.values)
                .unwrap_or_else(|e| panic!("{name}: sweep point {:?}: {e}", p.values));
            assert!(
                !p.analysed || m.analysis().is_some(),
                "{name}: analysed point without an analysis"
            );
        }
        for c in m.usual_configs() {
            validate_values(*m, &c).unwrap_or_else(|e| panic!("{name}: usual config {c:?}: {e}"));
        }
        if info.role == Role::Approximation {
            // A method with passes of its own has uniforms of its own; one that reads only the shared maps
            // (ADSM) takes its parameters from the frame uniforms.
            assert!(
                info.light_wgsl.is_empty() || m.uniform_mirror().is_some(),
                "{name}: light passes but no uniform mirror"
            );
            assert!(sweep.len() >= 2, "{name}: a sweep of one configuration");
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
    // The hair BSDF's Gaussians and absorption (single and dual scattering) are exponentials that are not
    // visibility.
    let bsdf = |path: &str, part: &str| {
        ["common/marschner.wgsl", "common/dual_scattering.wgsl"].contains(&path) && part == "exp("
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

/// The vertex formats Rust declares match the WGSL `vs_main` inputs location by location.
fn check_vertex_inputs(pass: &str, attrs: &[wgpu::VertexAttribute]) {
    let src = compose_with(pass, Some("methods/none.wgsl"), Some("transparency/wboit.wgsl")).unwrap();
    let (module, _) = validate(pass, &src);
    let ep = module.entry_points.iter().find(|e| e.name == "vs_main").unwrap();
    let mut found = Vec::new();
    let mut collect = |ty: naga::Handle<naga::Type>, binding: &Option<naga::Binding>| {
        if let Some(naga::Binding::Location { location, .. }) = binding {
            found.push((*location, module.types[ty].inner.clone()));
        }
    };
    for arg in &ep.function.arguments {
        match &module.types[arg.ty].inner {
            naga::TypeInner::Struct { members, .. } => members.iter().for_each(|m| collect(m.ty, &m.binding)),
            _ => collect(arg.ty, &arg.binding),
        }
    }
    found.sort_by_key(|(l, _)| *l);
    assert_eq!(found.len(), attrs.len(), "{pass}: attribute count");
    for ((loc, inner), a) in found.iter().zip(attrs) {
        assert_eq!(*loc, a.shader_location, "{pass}");
        let comps = match inner {
            naga::TypeInner::Scalar(_) => 1,
            naga::TypeInner::Vector { size, .. } => *size as u64,
            other => panic!("{pass}: location {loc} has type {other:?}"),
        };
        assert_eq!(comps * 4, a.format.size(), "{pass}: location {loc} size");
    }
}

#[test]
fn vertex_layouts_match_wgsl() {
    check_vertex_inputs("hair.wgsl", &HairVertex::ATTRIBUTES);
    check_vertex_inputs("mesh.wgsl", &MeshVertex::ATTRIBUTES);
    // 48 bytes of point data, the base height and 12 bytes of padding to the 16-byte storage alignment.
    assert_eq!(std::mem::size_of::<HairVertex>(), 64);
    assert_eq!(std::mem::size_of::<MeshVertex>(), 36);
}

/// The per-texel walk states the list compressors keep between dispatches are sized in Rust from their WGSL
/// structs' sizes.
#[test]
fn walk_states_match_wgsl_size() {
    assert_eq!(
        wgsl_struct("avsm.wgsl", None, "AvsmWalk").0 as u64,
        hairlab::methods::avsm::WALK_BYTES
    );
    assert_eq!(
        wgsl_struct("dsm.wgsl", None, "DsmWalk").0 as u64,
        hairlab::methods::dsm::WALK_BYTES
    );
}
