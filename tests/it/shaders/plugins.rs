//! Every registered method and technique is complete: its shaders, fragment outputs and what the registry says
//! of it.

use super::validate;
use hairlab::methods::registry;
use hairlab::render::transparency::registry as techniques;
use hairlab::shaders::{SOURCES, compose, compose_with};

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
