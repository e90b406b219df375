//! The Rust mirrors of WGSL declarations: uniform structs, vertex inputs, constants and walk states match their
//! WGSL layout.

use super::validate;
use hairlab::methods::registry;
use hairlab::render::caster::raster_model::{RASTER_FRAGMENT_FIELDS, RasterFragment};
use hairlab::render::geometry::{HAIR_VERTEX_FIELDS, HairVertex, MeshVertex};
use hairlab::render::transparency::registry as techniques;
use hairlab::render::uniforms::{FRAME_UNIFORMS_FIELDS, FrameUniforms};
use hairlab::shaders::{compose, compose_with};

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
