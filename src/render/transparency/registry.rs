//! The one list of eye transparency techniques: settings validation, the renderer, the pipelines, the CLI and the
//! shader tests go through it, so adding a technique is its own files plus one line here. Two lists: the
//! techniques compared on bare strands ([`all`]: the bench, `measure`, the claims, the GPU = CPU tests), and those
//! that show a scene's fur ([`fur`]), which the renderer names when a scene with fur meets a technique that
//! cannot show it; [`every`] is both, for names, settings and the panel.

use super::EyeTransparency;
use super::depth_peel::DepthPeel;
use super::mboit::MomentBasedOit;
use super::occupancy_order::OccupancyOrder;
use super::opaque::Opaque;
use super::shortcut::Shortcut;
use super::sorted::Sorted;
use super::wboit::Wboit;
use super::weighted_average::WeightedAverage;
use crate::render::fur::typed::FurTechnique;
use crate::render::method::{ParamError, ParamSpec, UnknownName};

static TECHNIQUES: &[&dyn EyeTransparency] = &[
    &Sorted,
    &OccupancyOrder,
    &DepthPeel,
    &WeightedAverage,
    &Wboit,
    &MomentBasedOit,
    &Shortcut,
    &Opaque,
];

/// The techniques that show a scene's fur as well as its strands.
static FUR_TECHNIQUES: &[&dyn EyeTransparency] = &[&FurTechnique];

/// The techniques compared on bare strands, in UI order.
pub fn all() -> &'static [&'static dyn EyeTransparency] {
    TECHNIQUES
}

/// Every registered technique: those of [`all`], then those that show fur.
pub fn every() -> impl Iterator<Item = &'static dyn EyeTransparency> {
    TECHNIQUES.iter().chain(FUR_TECHNIQUES).copied()
}

/// The technique a scene with fur is drawn with (the fur's typed lists).
pub fn fur() -> &'static dyn EyeTransparency {
    &FurTechnique
}

/// The technique of new settings (it keeps every existing preset's image).
pub fn default_technique() -> &'static dyn EyeTransparency {
    &Wboit
}

/// The exact reference every technique is measured against.
pub fn reference() -> &'static dyn EyeTransparency {
    &Sorted
}

/// Sintorn & Assarsson 2009's method and its cost baseline, depth peeling (the speed ratio of Fig. 2).
pub fn paper_and_baseline() -> (&'static dyn EyeTransparency, &'static dyn EyeTransparency) {
    (&OccupancyOrder, &DepthPeel)
}

/// The other two images of Sintorn & Assarsson's Fig. 2 besides the reference and their method: weighted-average
/// blending and no transparency.
pub fn fig2_comparisons() -> [&'static dyn EyeTransparency; 2] {
    [&WeightedAverage, &Opaque]
}

/// The technique called `name`, or an error listing the known names.
pub fn find(name: &str) -> Result<&'static dyn EyeTransparency, UnknownName> {
    every().find(|t| t.name() == name).ok_or_else(|| {
        let names: Vec<_> = every().map(|t| t.name()).collect();
        UnknownName {
            family: "eye transparency technique",
            name: name.to_string(),
            known: names.join(", "),
        }
    })
}

/// The parameter `key` of `technique`, or an error listing its parameters.
pub fn spec(technique: &dyn EyeTransparency, key: &str) -> Result<&'static ParamSpec, ParamError> {
    let params = technique.info().params;
    params.iter().find(|p| p.key == key).ok_or_else(|| {
        let known: Vec<_> = params.iter().map(|p| p.key).collect();
        ParamError::UnknownKey {
            family: "technique",
            name: technique.name(),
            key: key.to_string(),
            known: if known.is_empty() {
                "no parameters".to_string()
            } else {
                known.join(", ")
            },
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_unknown_name_is_an_error_listing_the_known_names() {
        let known: Vec<_> = every().map(|t| t.name()).collect();
        assert_eq!(
            find("no-such-technique").err().map(|e| e.to_string()),
            Some(format!(
                "unknown eye transparency technique 'no-such-technique' (known: {})",
                known.join(", ")
            ))
        );
        assert!(find("").is_err());
    }

    #[test]
    fn the_fur_technique_shows_fur_and_the_compared_ones_do_not() {
        assert!(fur().shows_fur());
        assert!(all().iter().all(|t| !t.shows_fur()));
        assert_eq!(find(fur().name()).map(|t| t.name()), Ok(fur().name()));
    }

    #[test]
    fn every_technique_is_found_by_its_unique_kebab_case_name() {
        let mut names = Vec::new();
        for t in every() {
            let name = t.name();
            assert!(
                !name.is_empty() && name.chars().all(|c| c.is_ascii_lowercase() || c == '-'),
                "{name}: names are kebab-case"
            );
            assert!(!names.contains(&name), "{name}: registered twice");
            assert_eq!(find(name).map(|f| f.name()), Ok(name));
            for p in t.info().params {
                assert!(
                    p.check(p.default).is_ok(),
                    "{name}.{}: default out of range",
                    p.key
                );
                assert_eq!(spec(t, p.key).map(|s| s.key), Ok(p.key));
            }
            names.push(name);
        }
    }
}
