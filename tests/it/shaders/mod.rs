//! Every WGSL file is embedded, composes, parses and validates with naga (no GPU needed), and the Rust uniform
//! and vertex structs match the WGSL declarations. A file per concern: composition and the shared WGSL text
//! (`compose`), every registered method and technique complete (`plugins`), the Rust mirrors of WGSL layouts
//! (`layouts`). naga's validation, which they all use, is here.

mod compose;
mod layouts;
mod plugins;

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
