//! Strand styling, as Andersen, Falster, Frisvad, Christensen 2016, "Hybrid fur rendering: combining volumetric
//! fur with explicit hair strands", The Visual Computer, §3.1, styles its guard hairs (explicit strands grown on
//! a fur base mesh by [`super::generate::guard_hairs`]): per-point `thickness` falling
//! linearly from 1 at the root to `taper` at the tip (a chain of truncated cones, the paper's tubes of variable
//! radius after Goldman) and per-point `alpha = exp(−τ_tip · s)`, the paper's transparency "increasing
//! exponentially towards the hair strand tips", with `s = j / segments` the point's fraction of the strand's
//! steps (its arc-length fraction for every unclumped generated strand, whose steps are all equally long).
//!
//! Guard hairs are ordinary [`Strands`], so every light-space shadow method of hairlab draws and shadows them
//! like any other hair; with fur on they are also darkened towards the base, the paper's local self-shadowing
//! ([`crate::fur::darkening`]). Everything is deterministic from the generator's seed.

use super::Strands;

/// Thickness at `s` ∈ [0, 1] (root to tip) of a strand whose tip is `taper` times as thick as its root (1).
pub fn thickness_at(s: f32, taper: f32) -> f32 {
    1.0 + (taper - 1.0) * s
}

/// Alpha at `s` ∈ [0, 1] (root to tip) under tip transparency `tip_transparency` (τ_tip).
pub fn alpha_at(s: f32, tip_transparency: f32) -> f32 {
    (-tip_transparency * s).exp()
}

/// Writes per-point thickness ([`thickness_at`]) and alpha ([`alpha_at`]) into `strands`, multiplying any
/// arrays already there; the neutral values (`taper` 1, `tip_transparency` 0) leave `strands` as they are.
/// A single-point strand is all root.
pub fn style(strands: &mut Strands, taper: f32, tip_transparency: f32) {
    let n = strands.point_count();
    let fractions: Vec<f32> = strands
        .ranges()
        .flat_map(|(_, count)| {
            let last = count.saturating_sub(1).max(1) as f32;
            (0..count).map(move |j| j as f32 / last)
        })
        .collect();
    if taper != 1.0 {
        let t = strands.thickness.get_or_insert_with(|| vec![1.0; n]);
        for (v, &s) in t.iter_mut().zip(&fractions) {
            *v *= thickness_at(s, taper);
        }
    }
    if tip_transparency != 0.0 {
        let a = strands.alpha.get_or_insert_with(|| vec![1.0; n]);
        for (v, &s) in a.iter_mut().zip(&fractions) {
            *v *= alpha_at(s, tip_transparency);
        }
    }
}
