//! Hybrid fur (Andersen et al. 2016, "Hybrid fur rendering: combining volumetric fur with explicit hair
//! strands"), the CPU half: a base mesh welded, oriented and neighboured ([`mesh`]), extruded into a prismatic
//! shell with dynamic resolution ([`shell`]), its sub-elements indexed by eqs. (1)–(3) ([`index`]), the simplex
//! noise ([`noise`]) the volume densities and tangents come from ([`volume`]), the ray march through them
//! ([`march`]), the combination of typed fragments ([`blend`]), the guard hairs' base darkening ([`darkening`]) and environment of lights ([`environment`]), the `[fur]` settings with the fur of a scene
//! ([`settings`]) and the paper's Table 1 for a frame ([`table`]). The paper's base meshes and the guard hairs'
//! styling are scene data (`crate::scene::fur_shapes`, `crate::scene::style`). These functions are the
//! specification the GPU ray march mirrors.

pub mod blend;
pub mod darkening;
pub mod env_map;
pub mod environment;
pub mod index;
pub mod march;
pub mod mesh;
pub mod noise;
pub mod settings;
pub mod shell;
pub mod table;
pub mod volume;

/// A fur parameter outside its range: the message names the key, the value and the rule.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("invalid {key} = {value}: {rule}")]
pub struct InvalidParam {
    pub key: String,
    pub value: String,
    pub rule: String,
}

impl InvalidParam {
    pub fn new(key: &str, value: impl std::fmt::Display, rule: &str) -> InvalidParam {
        InvalidParam {
            key: key.to_string(),
            value: value.to_string(),
            rule: rule.to_string(),
        }
    }
}
