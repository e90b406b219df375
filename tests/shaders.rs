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

#[test]
fn frame_uniforms_match_wgsl_layout() {
    let src = compose("hair.wgsl", Some("methods/none.wgsl")).unwrap();
    let (module, _) = validate("hair.wgsl", &src);
    let (_, ty) = module
        .types
        .iter()
        .find(|(_, t)| t.name.as_deref() == Some("FrameUniforms"))
        .expect("FrameUniforms in WGSL");
    let naga::TypeInner::Struct { members, span } = &ty.inner else {
        panic!("FrameUniforms is not a struct")
    };
    assert_eq!(
        *span as usize,
        std::mem::size_of::<FrameUniforms>(),
        "struct size"
    );
    let wgsl: Vec<(String, usize)> = members
        .iter()
        .map(|m| (m.name.clone().unwrap_or_default(), m.offset as usize))
        .collect();
    let rust: Vec<(String, usize)> = FRAME_UNIFORMS_FIELDS
        .iter()
        .map(|(n, o)| (n.to_string(), *o))
        .collect();
    assert_eq!(wgsl, rust, "field names/offsets differ between Rust and WGSL");
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
