//! Strand shading models: what a lit hair point sends towards the eye, per unit of light radiance, before the
//! shadow method's visibility. [`ShadingModel`] is the one list (`render.shading`); each model has its CPU model
//! here (the specification) and one WGSL file (`shaders/common/<model>.wgsl`), selected in the eye pass by
//! `frame.shading_model` through `shaders/common/strand_shading.wgsl`.

pub mod chiang;
pub mod dual_scattering;
pub mod fibre_transport;
pub mod hair_cover;
pub mod hair_density;
pub mod hair_scatter;
pub mod kajiya_kay;
pub mod marschner;
pub mod mesh_bounce;
pub mod probe_light;

use glam::Vec3;
use serde::{Deserialize, Serialize};

/// The registered strand shading models (`render.shading = "kajiya-kay" | "marschner" | "dual-scattering" |
/// "chiang"`).
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
    /// Chiang et al. 2016's fibre, the path tracer's BSDF, averaged across the fibre ([`chiang`]).
    Chiang,
}

impl ShadingModel {
    /// Every model, in the order of their uniform values.
    pub const ALL: [ShadingModel; 4] = [
        ShadingModel::KajiyaKay,
        ShadingModel::Marschner,
        ShadingModel::DualScattering,
        ShadingModel::Chiang,
    ];

    /// The word presets and `--set render.shading=…` use.
    pub fn word(self) -> &'static str {
        match self {
            ShadingModel::KajiyaKay => "kajiya-kay",
            ShadingModel::Marschner => "marschner",
            ShadingModel::DualScattering => "dual-scattering",
            ShadingModel::Chiang => "chiang",
        }
    }

    /// The name people read (panels, reports).
    pub fn label(self) -> &'static str {
        match self {
            ShadingModel::KajiyaKay => "Kajiya-Kay",
            ShadingModel::Marschner => "Marschner",
            ShadingModel::DualScattering => "Dual scattering",
            ShadingModel::Chiang => "Chiang",
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
            ShadingModel::Chiang => {
                "the path tracer's fibre averaged across its width, from a table (Chiang et al. 2016)"
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
            ShadingModel::DualScattering => dual_scattering::dual_scattering(
                HairModel::Absorber,
                tangent,
                to_light,
                to_eye,
                colour,
                1.0,
                0.0,
            ),
            ShadingModel::Chiang => chiang::chiang(tangent, to_light, to_eye, colour),
        }
    }
}

/// The raster's ambient terms at `render.ambient = 1` (the absorber model's look, [`HairModel::Absorber`]): what
/// `shaders/hair.wgsl` and `shaders/mesh.wgsl` add to every lit colour, times the colour (`frame.hair_ambient`,
/// `frame.mesh_ambient`); the path tracer's raster first hit adds the same.
pub const HAIR_AMBIENT: f32 = 0.08;
pub const MESH_AMBIENT: f32 = 0.12;

/// The registered hair models (`render.hair_model = "absorber" | "fibres"`): how light crosses the strands in
/// front of a point and how a strand's opacity is found. Beside [`ShadingModel`] (what one lit point sends to
/// the eye), each combination measurable against the path tracer (docs/truth.md).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum HairModel {
    /// Strands are absorbers of opacity `render.hair_alpha` (or their coverage under `render.alpha =
    /// coverage`), light through them `(1 − α)ⁿ`, plus the raster's ambient terms: TressFX's model and the
    /// workbench's look.
    #[default]
    Absorber,
    /// Strands are fibres: opacity from geometry (each fragment's coverage of its pixel or light texel at
    /// material opacity 1), the light map's `−ln V` a hair count, light through `n` fibres their forward
    /// scattering `d_f ā_f(θ)ⁿ` ([`fibre_transport`]), dual scattering's constants those of the path tracer's
    /// fibre, and no ambient term (the path tracer has no environment).
    Fibres,
}

impl HairModel {
    /// Every model, in the order of their uniform values.
    pub const ALL: [HairModel; 2] = [HairModel::Absorber, HairModel::Fibres];

    /// The word presets and `--set render.hair_model=…` use.
    pub fn word(self) -> &'static str {
        match self {
            HairModel::Absorber => "absorber",
            HairModel::Fibres => "fibres",
        }
    }

    /// The name people read (panels, reports).
    pub fn label(self) -> &'static str {
        match self {
            HairModel::Absorber => "Absorbers",
            HairModel::Fibres => "Fibres",
        }
    }

    /// One line for a tooltip.
    pub fn description(self) -> &'static str {
        match self {
            HairModel::Absorber => "strands absorb a constant alpha, plus an ambient term (TressFX's model)",
            HairModel::Fibres => {
                "coverage from geometry, hair counts, forward-scattering transmittance and dual scattering's \
                 constants measured on the path tracer's fibre (Zinke et al. 2008), no ambient"
            }
        }
    }

    /// `frame.hair_model` for this model; `shaders/common/frame.wgsl` names the same value
    /// `HAIR_MODEL_<WORD>` (a test compares them).
    pub fn uniform(self) -> u32 {
        self as u32
    }

    /// The name of the WGSL constant holding [`HairModel::uniform`].
    pub fn wgsl_const(self) -> String {
        format!("HAIR_MODEL_{}", self.word().to_uppercase())
    }

    /// The hair count the eye pass reads from the method's visibility `v`: `−ln V / b(hair_alpha)` for
    /// absorbers of opacity `hair_alpha` (`visibility::count_from_visibility`), `−ln V` for fibres
    /// ([`fibre_transport::count`]).
    pub fn count(self, v: f32, hair_alpha: f32) -> f32 {
        match self {
            HairModel::Absorber => crate::visibility::count_from_visibility(v, hair_alpha),
            HairModel::Fibres => fibre_transport::count(v),
        }
    }
}

/// One scattering event of `shading`'s lobes: the light through the method's `V` alone, shaded by the model's
/// single-scattering lobes (dual scattering by Marschner's), lit as `hair` lights them (the irradiance π under
/// fibres, [`fibre_transport::IRRADIANCE`]); none of the model's light beyond one event (its forward and
/// multiple-scattering terms). [`strand_lit`] under the traced probe, and the `shading` step of the error
/// decomposition (`measure::decompose`), which holds the lobes against the fibres' BSDF at one event.
pub fn strand_direct(
    shading: ShadingModel,
    hair: HairModel,
    tangent: Vec3,
    to_light: Vec3,
    to_eye: Vec3,
    colour: Vec3,
    v: f32,
) -> Vec3 {
    let lobes = match shading {
        ShadingModel::DualScattering => ShadingModel::Marschner,
        other => other,
    };
    let irradiance = match hair {
        HairModel::Absorber => 1.0,
        HairModel::Fibres => fibre_transport::IRRADIANCE,
    };
    lobes.shade(tangent, to_light, to_eye, colour) * v.clamp(0.0, 1.0) * irradiance
}

/// The CPU model of `strand_lit` (`shaders/common/strand_shading.wgsl`): the radiance a hair point sends towards
/// `to_eye` per unit of the light's `colour × intensity`, with the method's visibility `v` and hair count `count`
/// towards the light. Dual scattering carries its shadow itself; the single-scattering models are multiplied
/// by what arrives: `V` for absorbers; under fibres Marschner (and Chiang) shades the direct `V` and adds the light
/// forward-scattered through the strands in front, spread (Zinke et al.'s global term,
/// [`dual_scattering::Terms::forward_scattered`]: the sharp TT lobe must not shade light that no longer arrives along
/// the light, which made back-lit hair 4× too bright), and Kajiya-Kay, which has no lobes to spread, takes
/// `max(V, T_f)` ([`fibre_transport::arriving`]). Under the
/// fibres model the models' `f · |cos θ_i|` is lit by the irradiance `π × colour × intensity`, as a mesh's Lambert
/// (`colour × light × N·L`) and the path tracer take the light; the absorber model keeps the workbench's
/// look, one unit of light per unit of radiance ([`fibre_transport::IRRADIANCE`]). Under the fibres model with
/// the traced probe (`probe` [`mesh_bounce::Probe::Traced`]) the probe holds the light the fibres scatter, every
/// event (the path tracer's gather), but for the light arriving from about the light's own direction
/// (`probe_light`): every model shades the direct `V` (dual scattering by Marschner's lobes, its local term in the
/// probe) and adds the global forward-scattered term from the method's count, which follows the strands in front
/// pixel by pixel where a lattice node would spread it (docs/truth.md, "The probe's light by where it comes
/// from").
#[allow(clippy::too_many_arguments)]
pub fn strand_lit(
    shading: ShadingModel,
    hair: HairModel,
    probe: mesh_bounce::Probe,
    tangent: Vec3,
    to_light: Vec3,
    to_eye: Vec3,
    colour: Vec3,
    v: f32,
    count: f32,
) -> Vec3 {
    if hair == HairModel::Fibres && probe == mesh_bounce::Probe::Traced {
        let v = v.clamp(0.0, 1.0);
        let forward =
            dual_scattering::terms(hair, tangent, to_light, to_eye, colour, v, count).forward_scattered();
        return strand_direct(shading, hair, tangent, to_light, to_eye, colour, v)
            + forward * fibre_transport::IRRADIANCE;
    }
    if shading == ShadingModel::DualScattering {
        let f = dual_scattering::dual_scattering(hair, tangent, to_light, to_eye, colour, v, count);
        return match hair {
            HairModel::Absorber => f,
            HairModel::Fibres => f * fibre_transport::IRRADIANCE,
        };
    }
    let s = shading.shade(tangent, to_light, to_eye, colour);
    match (hair, shading) {
        (HairModel::Absorber, _) => s * v,
        (HairModel::Fibres, ShadingModel::Marschner | ShadingModel::Chiang) => {
            let scattered =
                dual_scattering::terms(hair, tangent, to_light, to_eye, colour, v, count).forward_scattered();
            (s * v.clamp(0.0, 1.0) + scattered) * fibre_transport::IRRADIANCE
        }
        (HairModel::Fibres, _) => {
            let sin_i = tangent.dot(to_light).clamp(-1.0, 1.0);
            s * fibre_transport::arriving(v, sin_i, marschner::absorption(colour), count)
                * fibre_transport::IRRADIANCE
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The `u32` constants `names` of the composed `file`, read from the parsed module (a panic naming the one
    /// missing or not a `u32` literal).
    pub(super) fn wgsl_u32_constants(file: &str, names: &[String]) -> Vec<u32> {
        let src = crate::shaders::compose(file, None).unwrap();
        let module = naga::front::wgsl::parse_str(&src).unwrap();
        names
            .iter()
            .map(|name| {
                let (_, c) = module
                    .constants
                    .iter()
                    .find(|(_, c)| c.name.as_deref() == Some(name.as_str()))
                    .unwrap_or_else(|| panic!("{name} missing from {file}"));
                match module.global_expressions[c.init] {
                    naga::Expression::Literal(naga::Literal::U32(v)) => v,
                    ref e => panic!("{name}: not a u32 literal: {e:?}"),
                }
            })
            .collect()
    }

    /// Each model's uniform value is the one `strand_shading.wgsl` tests for.
    #[test]
    fn wgsl_constants_match_the_uniform_values() {
        let names: Vec<String> = ShadingModel::ALL.iter().map(|m| m.wgsl_const()).collect();
        let values: Vec<u32> = ShadingModel::ALL.iter().map(|m| m.uniform()).collect();
        assert_eq!(
            wgsl_u32_constants("common/strand_shading.wgsl", &names),
            values,
            "{names:?}"
        );
    }

    /// Each hair model's uniform value is the one `hair_model.wgsl` names.
    #[test]
    fn wgsl_hair_model_constants_match_the_uniform_values() {
        let names: Vec<String> = HairModel::ALL.iter().map(|m| m.wgsl_const()).collect();
        let values: Vec<u32> = HairModel::ALL.iter().map(|m| m.uniform()).collect();
        assert_eq!(
            wgsl_u32_constants("common/hair_model.wgsl", &names),
            values,
            "{names:?}"
        );
    }

    /// Under absorbers the single-scattering models are `shade × V`. Under fibres, `π ×` (the irradiance of a
    /// unit light): Kajiya-Kay `shade × d_f ā_f^n` beyond the first strand (brighter than `V = e^-n` there);
    /// Marschner the direct `V × shade` plus the forward-scattered light, more than the direct alone, less than
    /// dual scattering (which adds the back-scattering to the same two), and back-lit at the TT peak far less
    /// than `shade × T_f` would give (the sharp lobe no longer shades spread light); both `π × shade` with
    /// nothing in front.
    #[test]
    fn strand_lit_carries_each_hair_models_transport() {
        let (t, l, e) = (Vec3::Y, Vec3::Z, Vec3::new(0.0, 0.3, 0.95).normalize());
        let colour = Vec3::new(0.30, 0.18, 0.09);
        let shade = ShadingModel::Marschner.shade(t, l, e, colour);
        let kk = ShadingModel::KajiyaKay.shade(t, l, e, colour);
        let v = 0.5f32;
        let absorber = strand_lit(
            ShadingModel::Marschner,
            HairModel::Absorber,
            mesh_bounce::Probe::Voxels,
            t,
            l,
            e,
            colour,
            v,
            1.6,
        );
        assert!(
            (absorber - shade * v).abs().max_element() <= 1e-7,
            "{absorber} {shade}"
        );
        let n = 3.0f32;
        let lit = |shading, t: Vec3, l: Vec3, e: Vec3, v: f32, n: f32| {
            strand_lit(
                shading,
                HairModel::Fibres,
                mesh_bounce::Probe::Voxels,
                t,
                l,
                e,
                colour,
                v,
                n,
            )
        };
        let (af, _) = fibre_transport::attenuation(0.0, marschner::absorption(colour));
        let t_f = fibre_transport::DENSITY_FORWARD * Vec3::new(af.x.powi(3), af.y.powi(3), af.z.powi(3));
        let want = kk * fibre_transport::IRRADIANCE * t_f;
        let fibres = lit(ShadingModel::KajiyaKay, t, l, e, (-n).exp(), n);
        assert!(
            (fibres - want).abs().max_element() <= 1e-5 * want.max_element(),
            "{fibres} {want}"
        );
        assert!(fibres.min_element() > (kk * (-n).exp()).max_element());
        let pi = fibre_transport::IRRADIANCE;
        let m = lit(ShadingModel::Marschner, t, l, e, (-n).exp(), n);
        let ds = dual_scattering::dual_scattering(HairModel::Fibres, t, l, e, colour, (-n).exp(), n) * pi;
        let direct = shade * (-n).exp() * pi;
        assert!(
            (m - direct).min_element() > 1e-4 * m.max_element() && (ds - m).min_element() > 0.0,
            "direct {direct}, Marschner {m}, dual scattering {ds}"
        );
        // Back-lit, the eye on the far side of a strand from the light: the TT lobe's peak.
        let (l_back, e_back) = (
            Vec3::new(0.0, 0.05, 1.0).normalize(),
            Vec3::new(0.0, -0.05, -1.0).normalize(),
        );
        let sharp = ShadingModel::Marschner.shade(t, l_back, e_back, colour) * t_f * pi;
        let spread = lit(ShadingModel::Marschner, t, l_back, e_back, (-n).exp(), n);
        assert!(
            spread.max_element() < 0.5 * sharp.max_element(),
            "back-lit: spread {spread} against the sharp lobe's {sharp}"
        );
        for shading in [ShadingModel::KajiyaKay, ShadingModel::Marschner] {
            let front = lit(shading, t, l, e, 1.0, 0.0);
            let want = shading.shade(t, l, e, colour) * pi;
            assert!((front - want).abs().max_element() <= 1e-6, "{front} {want}");
        }
        assert!((HairModel::Fibres.count((-n).exp(), 0.35) - n).abs() <= 1e-6);
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
        #[derive(Serialize, Deserialize)]
        struct HairHolder {
            hair_model: HairModel,
        }
        for model in HairModel::ALL {
            let text = toml::to_string(&HairHolder { hair_model: model }).unwrap();
            assert_eq!(text.trim(), format!("hair_model = \"{}\"", model.word()));
            assert_eq!(toml::from_str::<HairHolder>(&text).unwrap().hair_model, model);
        }
    }
}
