//! Every WGSL file is embedded, composes, parses and validates with naga (no GPU needed), and the Rust uniform
//! and vertex structs match the WGSL declarations.

use hairlab::methods::registry;
use hairlab::render::geometry::{HairVertex, MeshVertex};
use hairlab::render::uniforms::{FRAME_UNIFORMS_FIELDS, FrameUniforms};
use hairlab::shaders::{METHOD_PASSES, SOURCES, compose};
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
    SOURCES
        .iter()
        .map(|(p, _)| *p)
        .filter(|p| !p.starts_with("common/") && !p.starts_with("methods/"))
}

#[test]
fn every_shader_file_is_embedded() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("shaders");
    let mut on_disk = Vec::new();
    for dir in ["", "common", "methods"] {
        for e in std::fs::read_dir(root.join(dir)).unwrap() {
            let p = e.unwrap().path();
            if p.extension().is_some_and(|x| x == "wgsl") {
                on_disk.push(
                    p.strip_prefix(&root)
                        .unwrap()
                        .to_string_lossy()
                        .replace('\\', "/"),
                );
            }
        }
    }
    on_disk.sort();
    let mut embedded: Vec<String> = SOURCES.iter().map(|(p, _)| p.to_string()).collect();
    embedded.sort();
    assert_eq!(
        on_disk, embedded,
        "shaders/ and hairlab::shaders::SOURCES disagree"
    );
}

#[test]
fn every_pass_validates_with_every_method() {
    let mut checked = 0;
    for pass in pass_shaders() {
        if METHOD_PASSES.contains(&pass) {
            for m in registry::all() {
                let src = compose(pass, Some(m.lookup_wgsl())).unwrap();
                validate(&format!("{pass} + {}", m.lookup_wgsl()), &src);
                checked += 1;
            }
        } else {
            let src = compose(pass, None).unwrap();
            validate(pass, &src);
            checked += 1;
        }
    }
    assert_eq!(
        checked,
        pass_shaders().count() + METHOD_PASSES.len() * (registry::all().len() - 1)
    );
}

#[test]
fn method_passes_refuse_to_compose_without_a_method() {
    for pass in METHOD_PASSES {
        assert!(compose(pass, None).is_err(), "{pass}");
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

/// Checks a Rust mirror (its size and `(WGSL field name, Rust offset)` list) against the WGSL struct `name`
/// declared in `file`.
fn check_mirror(rust_size: usize, rust: &[(&str, usize)], file: &str, name: &str) {
    let rust: Vec<(String, usize)> = rust.iter().map(|(n, o)| (n.to_string(), *o)).collect();
    let (size, fields) = wgsl_struct(file, None, name);
    assert_eq!(size, rust_size, "{name} in {file}: size");
    assert_eq!(
        fields, rust,
        "{name} in {file}: field names/offsets differ between Rust and WGSL"
    );
}

#[test]
fn frame_uniforms_match_wgsl_layout() {
    check_mirror(
        std::mem::size_of::<FrameUniforms>(),
        FRAME_UNIFORMS_FIELDS,
        "common/frame.wgsl",
        "FrameUniforms",
    );
}

/// Every method's uniform struct against its single WGSL declaration, which its light pass and its lookup both
/// include.
#[test]
fn method_uniforms_match_wgsl_layout() {
    use hairlab::methods::{bom::BomUniforms, dc::DcUniforms, dom::DomUniforms};
    use hairlab::methods::{occupancy::OccupancyUniforms, osm::OsmUniforms};
    use std::mem::{offset_of, size_of};
    check_mirror(
        size_of::<OsmUniforms>(),
        &[
            ("slices", offset_of!(OsmUniforms, slices)),
            ("pad0", 4),
            ("pad1", 8),
            ("pad2", 12),
        ],
        "common/osm_uniforms.wgsl",
        "OsmUniforms",
    );
    let pad = offset_of!(DomUniforms, pad);
    check_mirror(
        size_of::<DomUniforms>(),
        &[
            ("ends", offset_of!(DomUniforms, ends)),
            ("layers", offset_of!(DomUniforms, layers)),
            ("beyond", offset_of!(DomUniforms, beyond)),
            ("pad0", pad),
            ("pad1", pad + 4),
        ],
        "common/dom_uniforms.wgsl",
        "DomUniforms",
    );
    let pad = offset_of!(BomUniforms, pad);
    check_mirror(
        size_of::<BomUniforms>(),
        &[
            ("layers", offset_of!(BomUniforms, layers)),
            ("split_ratio", offset_of!(BomUniforms, split_ratio)),
            ("pad0", pad),
            ("pad1", pad + 4),
        ],
        "common/bom_uniforms.wgsl",
        "BomUniforms",
    );
    check_mirror(
        size_of::<DcUniforms>(),
        &[
            ("clusters", offset_of!(DcUniforms, clusters)),
            ("pad0", offset_of!(DcUniforms, pad0)),
            ("pad1", offset_of!(DcUniforms, pad1)),
            ("pad2", offset_of!(DcUniforms, pad2)),
        ],
        "common/dc_uniforms.wgsl",
        "DcUniforms",
    );
    check_mirror(
        size_of::<OccupancyUniforms>(),
        &[
            ("variant", offset_of!(OccupancyUniforms, variant)),
            ("pad0", offset_of!(OccupancyUniforms, pad0)),
            ("pad1", offset_of!(OccupancyUniforms, pad1)),
            ("pad2", offset_of!(OccupancyUniforms, pad2)),
        ],
        "common/occupancy_uniforms.wgsl",
        "OccupancyUniforms",
    );
}

/// Names declared (`struct X` or `fn x(`) in `src`.
fn declarations(src: &str) -> Vec<String> {
    src.lines()
        .filter_map(|l| l.strip_prefix("struct ").or_else(|| l.strip_prefix("fn ")))
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
    for part in ["log(1.0 -", "select(select(", "max(floor(", "exp(", "(b - a) * f"] {
        let copies: Vec<&str> = SOURCES
            .iter()
            .filter(|(_, s)| code(s).contains(part))
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
    let src = compose(pass, Some("methods/none.wgsl")).unwrap();
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
    assert_eq!(std::mem::size_of::<HairVertex>(), 48);
    assert_eq!(std::mem::size_of::<MeshVertex>(), 36);
}
