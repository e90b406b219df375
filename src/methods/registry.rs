//! The one list of shadow methods. Everything else (UI panel, inspector, CLI, presets, bench, tests, pipelines)
//! goes through it: adding a method is its own files plus one line here.

use super::adsm::Adsm;
use super::avsm::Avsm;
use super::bom::Bom;
use super::dc::Dc;
use super::dom::Dom;
use super::dsm::Dsm;
use super::fom::Fom;
use super::msm::Msm;
use super::none::NoShadow;
use super::occupancy::Occupancy;
use super::opaque_shadow_map::OpaqueShadowMap;
use super::osm::Osm;
use super::reference::Reference;
use super::{ShadowMethod, UnknownName};

static METHODS: &[&dyn ShadowMethod] = &[
    &NoShadow,
    &OpaqueShadowMap,
    &Reference,
    &Osm,
    &Dom,
    &Bom,
    &Occupancy,
    &Dc,
    &Adsm,
    &Fom,
    &Dsm,
    &Msm,
    &Avsm,
];

/// Every registered method, in UI order.
pub fn all() -> &'static [&'static dyn ShadowMethod] {
    METHODS
}

/// The method called `name`, or an error listing the known names.
pub fn find(name: &str) -> Result<&'static dyn ShadowMethod, UnknownName> {
    METHODS.iter().copied().find(|m| m.name() == name).ok_or_else(|| {
        let names: Vec<_> = METHODS.iter().map(|m| m.name()).collect();
        UnknownName {
            family: "shadow method",
            name: name.to_string(),
            known: names.join(", "),
        }
    })
}

/// The method a new workbench (and a preset that names none) starts with: the opaque shadow map, the classic
/// baseline every semi-transparent method improves on.
pub fn default_method() -> &'static dyn ShadowMethod {
    &OpaqueShadowMap
}

/// The exact reference every method is measured against.
pub fn reference() -> &'static dyn ShadowMethod {
    &Reference
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::methods::Role;

    #[test]
    fn names_are_unique_and_one_method_is_the_reference() {
        let mut names: Vec<_> = METHODS.iter().map(|m| m.name()).collect();
        names.sort();
        names.dedup();
        assert_eq!(names.len(), METHODS.len(), "duplicate method names");
        let refs: Vec<_> = METHODS
            .iter()
            .filter(|m| m.info().role == Role::Reference)
            .collect();
        assert_eq!(refs.len(), 1);
        assert_eq!(refs[0].name(), reference().name());
    }
}
