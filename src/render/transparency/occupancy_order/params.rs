//! Occupancy-ordered blending's parameters: the words of `transparency.*`, the CPU model's parameters they
//! give, and the uniforms every pass reads (`OccupancyOrderUniforms`, mirrored in
//! `shaders/common/occupancy_order_uniforms.wgsl`).

use crate::render::method::{ParamKind, ParamSpec, ParamValues, UniformMirror, value};
use crate::transparency::occupancy_order::OccupancyOrderParams;
use crate::visibility::OccupancyVariant;
use bytemuck::{Pod, Zeroable};

pub(super) const PARAMS: &[ParamSpec] = &[
    ParamSpec {
        key: "variant",
        label: "variant",
        help: "slab-map: occupancy map + slab map (4 slabs of 32 slices, the paper's method); occupancy-only: the \
               occupancy map with one count for the whole range",
        kind: ParamKind::Choice {
            options: &["slab-map", "occupancy-only"],
        },
        default: 0.0,
    },
    ParamSpec {
        key: "correction",
        label: "Λ correction",
        help: "on: rescale the hair colour so its total weight is Λ = 1 - (1 - α)^n (S&A §3.4); off: the plain sum",
        kind: ParamKind::Choice {
            options: &["on", "off"],
        },
        default: 0.0,
    },
    ParamSpec {
        key: "order_bias",
        label: "order bias",
        help: "paper: the paper's estimate; half: subtract ½ from every order estimate (clamped at 0), the \
               estimate's mean bias",
        kind: ParamKind::Choice {
            options: &["paper", "half"],
        },
        default: 0.0,
    },
    ParamSpec {
        key: "precision",
        label: "accumulation",
        help: "f32: Rgba32Float accumulation (the paper's 32-bit target); f16: Rgba16Float, to show why it is needed",
        kind: ParamKind::Choice {
            options: &["f32", "f16"],
        },
        default: 0.0,
    },
];

/// The technique's parameters from `values` (missing keys take their defaults).
pub(super) fn params(values: &ParamValues) -> OccupancyOrderParams {
    let on = |i: usize| value(values, &PARAMS[i]) >= 0.5;
    OccupancyOrderParams {
        variant: if on(0) {
            OccupancyVariant::OccupancyOnly
        } else {
            OccupancyVariant::SlabMap
        },
        lambda_correction: !on(1),
        order_bias: if on(2) { -0.5 } else { 0.0 },
        half_precision: on(3),
    }
}

/// The WGSL mirror of [`OccupancyOrderUniforms`] (`common/occupancy_order_uniforms.wgsl`), for the layout test.
pub fn uniform_mirror() -> UniformMirror {
    crate::uniform_mirror!(
        "OccupancyOrderUniforms",
        OccupancyOrderUniforms {
            variant,
            correction,
            order_bias,
            hair_alpha
        }
    )
}

/// Mirrors `OccupancyOrderUniforms` in `shaders/common/occupancy_order_uniforms.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable, PartialEq)]
pub struct OccupancyOrderUniforms {
    /// 0: slab map, 1: occupancy only.
    pub variant: u32,
    /// 1: the Λ correction on.
    pub correction: u32,
    /// Added to every order estimate before clamping at 0.
    pub order_bias: f32,
    /// The global hair alpha.
    pub hair_alpha: f32,
}

impl OccupancyOrderUniforms {
    pub(super) fn new(p: &OccupancyOrderParams, hair_alpha: f32) -> Self {
        Self {
            variant: u32::from(p.variant == OccupancyVariant::OccupancyOnly),
            correction: u32::from(p.lambda_correction),
            order_bias: p.order_bias,
            hair_alpha,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::HAIR;
    use super::*;

    fn parsed(pairs: &[(&str, &str)]) -> OccupancyOrderParams {
        let values: ParamValues = pairs
            .iter()
            .map(|(k, v)| {
                let spec = PARAMS.iter().find(|p| p.key == *k).unwrap();
                (k.to_string(), spec.parse(v).unwrap())
            })
            .collect();
        params(&values)
    }

    #[test]
    fn defaults_are_the_papers_method() {
        assert_eq!(parsed(&[]), OccupancyOrderParams::default());
        let u = OccupancyOrderUniforms::new(&parsed(&[]), 0.35);
        assert_eq!(
            u,
            OccupancyOrderUniforms {
                variant: 0,
                correction: 1,
                order_bias: 0.0,
                hair_alpha: 0.35
            }
        );
    }

    #[test]
    fn every_word_reaches_the_model_and_the_uniforms() {
        let p = parsed(&[
            ("variant", "occupancy-only"),
            ("correction", "off"),
            ("order_bias", "half"),
            ("precision", "f16"),
        ]);
        assert_eq!(
            p,
            OccupancyOrderParams {
                variant: OccupancyVariant::OccupancyOnly,
                lambda_correction: false,
                order_bias: -0.5,
                half_precision: true,
            }
        );
        let u = OccupancyOrderUniforms::new(&p, 0.2);
        assert_eq!((u.variant, u.correction, u.order_bias), (1, 0, -0.5));
        assert_eq!(
            HAIR[usize::from(p.half_precision)].targets[0].format,
            wgpu::TextureFormat::Rgba16Float
        );
    }
}
