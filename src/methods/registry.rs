//! The one list of shadow methods. Everything else (UI panel, CLI, presets, pipelines) goes through it.

use super::ShadowMethod;
use super::bom::Bom;
use super::dc::Dc;
use super::dom::Dom;
use super::none::NoShadow;
use super::occupancy::Occupancy;
use super::opaque_shadow_map::OpaqueShadowMap;
use super::osm::Osm;
use super::reference::Reference;

static METHODS: &[&dyn ShadowMethod] = &[
    &NoShadow,
    &OpaqueShadowMap,
    &Reference,
    &Osm,
    &Dom,
    &Bom,
    &Occupancy,
    &Dc,
];

/// Every registered method, in UI order.
pub fn all() -> &'static [&'static dyn ShadowMethod] {
    METHODS
}

/// The method called `name`, or an error listing the known names.
pub fn find(name: &str) -> Result<&'static dyn ShadowMethod, String> {
    METHODS.iter().copied().find(|m| m.name() == name).ok_or_else(|| {
        let names: Vec<_> = METHODS.iter().map(|m| m.name()).collect();
        format!("unknown shadow method '{name}' (known: {})", names.join(", "))
    })
}
