//! Strand shading models: what a lit hair point sends towards the eye, per unit of light radiance, before the
//! shadow method's visibility. [`ShadingModel`] is the one list (`render.shading`); each model has its CPU model
//! here (the specification) and one WGSL file (`shaders/common/<model>.wgsl`), selected in the eye pass by
//! `frame.shading_model` through `shaders/common/strand_shading.wgsl`.

pub mod dual_scattering;
pub mod kajiya_kay;
pub mod marschner;

use glam::Vec3;
use serde::{Deserialize, Serialize};

/// The registered strand shading models (`render.shading = "kajiya-kay" | "marschner" | "dual-scattering"`).
///
/// Dual scattering is a model of its own rather than a flag on Marschner: it is what `render.shading` selects,
/// the panels and `measure --shading` list, and the one uniform value the eye pass branches on; a flag would
/// be a second setting, a second uniform and a combination (Kajiya-Kay with dual scattering) that means
/// nothing.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum ShadingModel {
    /// Kajiya & Kay 1989: a diffuse cylinder and a specular cone ([`kajiya_kay`]).
    #[default]
    KajiyaKay,
    /// Marschner et al. 2003 R, TT and TRT lobes in Karis 2016's practical form ([`marschner`]).
    Marschner,
    /// The Marschner lobes plus Zinke et al. 2008's multiple scattering from the method's hair count
    /// ([`dual_scattering`]).
    DualScattering,
}

impl ShadingModel {
    /// Every model, in the order of their uniform values.
    pub const ALL: [ShadingModel; 3] = [
        ShadingModel::KajiyaKay,
        ShadingModel::Marschner,
        ShadingModel::DualScattering,
    ];

    /// The word presets and `--set render.shading=…` use.
    pub fn word(self) -> &'static str {
        match self {
            ShadingModel::KajiyaKay => "kajiya-kay",
            ShadingModel::Marschner => "marschner",
            ShadingModel::DualScattering => "dual-scattering",
        }
    }

    /// The name people read (panels, reports).
    pub fn label(self) -> &'static str {
        match self {
            ShadingModel::KajiyaKay => "Kajiya-Kay",
            ShadingModel::Marschner => "Marschner",
            ShadingModel::DualScattering => "Dual scattering",
        }
    }

    /// One line for a tooltip.
    pub fn description(self) -> &'static str {
        match self {
            ShadingModel::KajiyaKay => "diffuse cylinder and specular cone (Kajiya & Kay 1989)",
            ShadingModel::Marschner => {
                "R, TT and TRT lobes with absorption from the hair colour (Marschner et al. 2003, Karis 2016)"
            }
            ShadingModel::DualScattering => {
                "Marschner plus multiple scattering from the shadow method's hair count (Zinke et al. 2008)"
            }
        }
    }

    /// `frame.shading_model` for this model; `shaders/common/strand_shading.wgsl` names the same value
    /// `SHADING_<WORD>` (a test compares them).
    pub fn uniform(self) -> u32 {
        self as u32
    }

    /// The name of the WGSL constant holding [`ShadingModel::uniform`].
    pub fn wgsl_const(self) -> String {
        format!("SHADING_{}", self.word().to_uppercase().replace('-', "_"))
    }

    /// The CPU model: the radiance a hair point with `tangent` (unit, root to tip) and base colour `colour`
    /// sends towards `to_eye` per unit of radiance arriving from `to_light` (both unit, pointing away from the
    /// point), what `strand_shading()` returns on the GPU; dual scattering with nothing in front (`V = 1`, no
    /// strand).
    pub fn shade(self, tangent: Vec3, to_light: Vec3, to_eye: Vec3, colour: Vec3) -> Vec3 {
        match self {
            ShadingModel::KajiyaKay => kajiya_kay::kajiya_kay(tangent, to_light, to_eye, colour),
            ShadingModel::Marschner => marschner::marschner(tangent, to_light, to_eye, colour),
            ShadingModel::DualScattering => {
                dual_scattering::dual_scattering(tangent, to_light, to_eye, colour, 1.0, 0.0)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each model's uniform value is the one `strand_shading.wgsl` tests for, read from the parsed module.
    #[test]
    fn wgsl_constants_match_the_uniform_values() {
        let src = crate::shaders::compose("common/strand_shading.wgsl", None).unwrap();
        let module = naga::front::wgsl::parse_str(&src).unwrap();
        for model in ShadingModel::ALL {
            let name = model.wgsl_const();
            let (_, c) = module
                .constants
                .iter()
                .find(|(_, c)| c.name.as_deref() == Some(name.as_str()))
                .unwrap_or_else(|| panic!("{name} missing from strand_shading.wgsl"));
            match module.global_expressions[c.init] {
                naga::Expression::Literal(naga::Literal::U32(v)) => assert_eq!(v, model.uniform(), "{name}"),
                ref e => panic!("{name}: not a u32 literal: {e:?}"),
            }
        }
    }

    /// The word round-trips through serde and names the variant.
    #[test]
    fn words_round_trip_through_serde() {
        #[derive(Serialize, Deserialize)]
        struct Holder {
            shading: ShadingModel,
        }
        for model in ShadingModel::ALL {
            let text = toml::to_string(&Holder { shading: model }).unwrap();
            assert_eq!(text.trim(), format!("shading = \"{}\"", model.word()));
            assert_eq!(toml::from_str::<Holder>(&text).unwrap().shading, model);
        }
    }
}
