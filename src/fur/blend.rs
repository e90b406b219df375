//! The combination of hybrid fur's typed per-pixel fragments (Andersen et al. 2016 §3.3, spec B.7 and
//! B.3 #10), the CPU model of `shaders/fur/resolve.wgsl`. A pixel's fragments — explicit guard-hair
//! fragments, shell fragments (one per ray entering the shell) or virtual fragments (one per group of march
//! steps) — are sorted front to back on (depth, id, kind) and composited with "over":
//! `H = Σ_j T_j α_j c_j`, `T = Π_j (1 − α_j)`, onto the opaque meshes (`C = H + T·B`).
//!
//! Simplified blending (eq. 4) first lowers each shell fragment's alpha by the explicit fragments directly
//! behind it, `α_s' = clamp(α_s − Σ_e exp(−a (t_e − t_s)), 0, 1)`, over the explicit fragments `e` between
//! the shell fragment and the next shell fragment (B.3 #10; fragments behind the meshes never reach the
//! lists), `t` the distance along the eye ray in world units and `a` per world unit. With no explicit
//! fragment behind it the shell fragment keeps its alpha (FC-4). The opaque meshes are not stored as
//! fragments: the meshes' depth culls what they hide and their colour is the background (B.7).

use glam::Vec3;

use super::settings::{Blending, FurView};

/// Fragment kinds of the typed lists (the node's `kind` word; 0 is what every strand fragment already carries).
pub const EXPLICIT: u32 = 0;
pub const SHELL: u32 = 1;
pub const VIRTUAL: u32 = 2;

/// The type view's colour of each kind (explicit, shell, virtual), as `type_colour` in `shaders/fur/resolve.wgsl`.
pub const TYPE_COLOURS: [Vec3; 3] = [
    Vec3::new(1.0, 0.8, 0.1),
    Vec3::new(0.1, 0.4, 1.0),
    Vec3::new(0.1, 0.9, 0.8),
];

/// The fragments-per-pixel view's colour of a list of `n` when the frame's deepest holds `deepest`, as
/// `count_colour` in `shaders/fur/resolve.wgsl`.
pub fn count_colour(n: u32, deepest: u32) -> Vec3 {
    let x = n as f32 / deepest.max(1) as f32;
    Vec3::new(2.0 * x - 1.0, 1.0 - (2.0 * x - 1.0).abs(), 1.0 - 2.0 * x).clamp(Vec3::ZERO, Vec3::ONE)
}

/// One typed fragment as the lists hold it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Typed {
    /// Eye distance in units of the camera distance (the lists' depth).
    pub depth: f32,
    /// Segment id (explicit) or entry face (shell, virtual).
    pub id: u32,
    pub kind: u32,
    /// Non-premultiplied colour.
    pub colour: Vec3,
    pub alpha: f32,
}

/// Sorts front to back on (depth bits, id, kind): the resolve's total order.
pub fn front_to_back(fragments: &mut [Typed]) {
    fragments.sort_by_key(|f| (f.depth.abs().to_bits(), f.id, f.kind));
}

/// Eq. (4) applied to every shell fragment of `sorted` (front to back): the alphas to composite with.
/// `a` is per world unit; depths become world distances through `camera_distance`.
pub fn simplified_alphas(sorted: &[Typed], a: f32, camera_distance: f32) -> Vec<f32> {
    let mut alphas: Vec<f32> = sorted.iter().map(|f| f.alpha).collect();
    for (i, s) in sorted.iter().enumerate() {
        if s.kind != SHELL {
            continue;
        }
        let mut sub = 0.0f32;
        for e in &sorted[i + 1..] {
            if e.kind == SHELL {
                break;
            }
            if e.kind == EXPLICIT {
                sub += (-a * (e.depth - s.depth) * camera_distance).exp();
            }
        }
        alphas[i] = (s.alpha - sub).clamp(0.0, 1.0);
    }
    alphas
}

/// The pixel's premultiplied colour `H` and transmittance `T` under `blending` (`a` per world unit), its
/// fragments coloured by `view`.
pub fn combine_view(
    fragments: &[Typed],
    blending: Blending,
    a: f32,
    camera_distance: f32,
    view: FurView,
    deepest: u32,
) -> (Vec3, f32) {
    match view {
        FurView::Fragments if !fragments.is_empty() => (count_colour(fragments.len() as u32, deepest), 0.0),
        FurView::Types => {
            let typed: Vec<Typed> = fragments
                .iter()
                .map(|f| Typed {
                    colour: TYPE_COLOURS[(f.kind as usize).min(2)],
                    ..*f
                })
                .collect();
            combine(&typed, blending, a, camera_distance)
        }
        _ => combine(fragments, blending, a, camera_distance),
    }
}

/// The pixel's premultiplied colour `H` and transmittance `T` under `blending` (`a` per world unit).
pub fn combine(fragments: &[Typed], blending: Blending, a: f32, camera_distance: f32) -> (Vec3, f32) {
    let mut sorted = fragments.to_vec();
    front_to_back(&mut sorted);
    let alphas = match blending {
        Blending::Simplified => simplified_alphas(&sorted, a, camera_distance),
        Blending::Naive | Blending::Virtual => sorted.iter().map(|f| f.alpha).collect(),
    };
    let (mut h, mut t) = (Vec3::ZERO, 1.0f32);
    for (f, alpha) in sorted.iter().zip(alphas) {
        h += t * alpha * f.colour;
        t *= 1.0 - alpha;
    }
    (h, t)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frag(depth: f32, kind: u32, alpha: f32) -> Typed {
        Typed {
            depth,
            id: 0,
            kind,
            colour: Vec3::ONE,
            alpha,
        }
    }

    #[test]
    fn simplified_keeps_a_shell_alpha_with_nothing_explicit_behind_it() {
        // FC-4: a shell fragment alone, or with only a shell fragment behind it.
        let f = [
            frag(1.0, SHELL, 0.6),
            frag(1.5, SHELL, 0.3),
            frag(2.0, EXPLICIT, 0.5),
        ];
        let a = simplified_alphas(&f, 3.0, 1.0);
        assert_eq!(a[0], 0.6);
        // The second shell fragment has the explicit one 0.5 behind it: 0.3 − e^{−1.5} = 0.0769…
        assert!((a[1] - (0.3 - (-1.5f32).exp())).abs() < 1e-7, "{}", a[1]);
        assert_eq!(a[2], 0.5);
    }

    #[test]
    fn simplified_at_distance_zero_removes_the_shell_fragment_and_rises_with_a() {
        let f = [frag(1.0, SHELL, 0.6), frag(1.0, EXPLICIT, 0.5)];
        assert_eq!(simplified_alphas(&f, 2.0, 1.0)[0], 0.0);
        let g = |a: f32| simplified_alphas(&[frag(1.0, SHELL, 0.9), frag(1.2, EXPLICIT, 0.5)], a, 2.0)[0];
        // d_pe = 0.2 · 2 = 0.4 world units: 0.9 − e^{−0.4 a}, non-decreasing in a.
        assert!((g(1.0) - (0.9 - (-0.4f32).exp())).abs() < 1e-6);
        assert!(g(0.0) <= g(1.0) && g(1.0) <= g(10.0) && g(10.0) <= g(100.0));
    }

    #[test]
    fn combine_by_hand() {
        // Front explicit α 0.5 colour red, back shell α 0.5 green, naive: H = 0.5 r + 0.25 g, T = 0.25.
        let f = [
            Typed {
                colour: Vec3::Y,
                ..frag(2.0, SHELL, 0.5)
            },
            Typed {
                colour: Vec3::X,
                ..frag(1.0, EXPLICIT, 0.5)
            },
        ];
        let (h, t) = combine(&f, Blending::Naive, 1.0, 1.0);
        assert_eq!((h, t), (Vec3::new(0.5, 0.25, 0.0), 0.25));
        // Simplified: the shell fragment is behind the explicit one, so nothing changes.
        assert_eq!(combine(&f, Blending::Simplified, 1.0, 1.0), (h, t));
    }
}
