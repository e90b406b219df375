//! The shell ray march, the CPU model of the undercoat (spec B.5, decisions B.3 #4–#9).
//!
//! From a shell fragment (entry point `p0` on the shell's surface at ray distance `t0`, in prism `f`) the eye
//! ray is sampled at step mid-points `t0 + (k + ½)Δs`. Each sample is located by B.5's neighbour walk
//! ([`Shell::locate`] with at most [`MarchParams::hops`] hops; unlike [`Shell::walk`] it tests the shell
//! height before the sides, as B.5 does, so a ray grazing out of the top is not sent hopping round the
//! extrapolated prisms above it); the march stops when the sample lies under the base
//! (the base mesh, opaque), over the top (the ray left; a re-entry is its own shell fragment), across a
//! boundary edge, when the walk runs out of hops (a *lost* ray, counted), when `T < ε_T`, or after
//! `max_steps`. At each sample inside, with `σ = σ_0 ρ` and `T_s = e^{−σΔs}`,
//! `L += T (1 − T_s) φ L_in` and `T *= T_s` (B.3 #8), `φ` the Kajiya–Kay phase function with the voxel's
//! tangent and `L_in` the light's radiance attenuated by a march of `n_light` steps towards the light
//! (`n_light = 0` ⇒ `T_light = 1`).
//!
//! The light march walks from the sample's prism; a light sample under the base means the base mesh shadows
//! the point (`T_light = 0`); one over the top or across a boundary ends the light march (the light path's
//! re-entries into the shell are ignored, a decision: the paper says only "ray march toward external light
//! sources"); one lost ends it too and is counted in [`MarchStats::light_lost`].
//!
//! Emission: one SHELL fragment `(t0, c = L/(1 − T), α = 1 − T)`, or one VIRTUAL fragment per group of `k`
//! steps with local `α_g`, `c_g = L_g/α_g` (`T` restarting at 1 at the group's start) at the group's front
//! `t0 + g k Δs` (B.3 #9), so that compositing the groups with "over" is the single fragment exactly
//! (FC-2a). Fragments with `α = 0` (no density met) are not emitted.

use glam::Vec3;

use super::mesh::NONE;
use super::shell::{Location, Shell};
use super::volume::Volume;
use crate::shading::kajiya_kay::kajiya_kay;

/// A sample this close outside a side (in barycentrics) counts as inside: without it a ray running exactly
/// along an edge sees `λ ≈ −10⁻⁹` from both faces and hops between them until it is lost (measured: a ray
/// along one of the cylinder's rings).
const SIDE_TOLERANCE: f32 = 1e-6;
/// Steps per smallest shell height for [`MarchParams::for_shell`] (B.3 #7).
pub const STEPS_PER_THICKNESS: u32 = 32;
/// Default step cap per fragment (B.3 #7).
pub const MAX_STEPS: u32 = 256;
/// Default transmittance cut-off `ε_T` (B.3 #7; 0 for the reference).
pub const EPSILON_T: f32 = 1e-3;

/// What to emit.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Emit {
    /// One shell fragment for the whole march.
    Shell,
    /// One virtual fragment per group of `k ≥ 1` steps.
    Virtual(u32),
}

/// March parameters (the paper gives none; B.3 #7).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MarchParams {
    /// Extinction `σ_0` per world unit at `ρ = 1`.
    pub sigma: f32,
    /// Step `Δs`, world units.
    pub step: f32,
    pub max_steps: u32,
    /// Hop cap per step `H_max`.
    pub hops: u32,
    /// Stop when `T < ε_T`.
    pub epsilon_t: f32,
    /// Light-march steps `n_light` (0 ⇒ unattenuated light).
    pub light_steps: u32,
    /// Light-march step `Δs_l`.
    pub light_step: f32,
    /// Unit direction towards the (directional) light.
    pub to_light: Vec3,
    /// The light's radiance.
    pub light: Vec3,
    /// Undercoat colour (Kajiya–Kay base).
    pub colour: Vec3,
    pub emit: Emit,
}

impl MarchParams {
    /// Defaults for `shell`: `Δs = Δs_l = h_min / 32`, 256 steps, the shell's hop cap, `ε_T = 10⁻³`, 8 light
    /// steps (a quarter of the thickness: the undercoat shadows itself locally), `σ_0 = 8 / h_0` (a full
    /// vertical column of `ρ = 1` transmits e⁻⁸; with the default volume on `fur-cylinder`, measured: mean
    /// `ρ` 0.34 and a radial column's mean transmittance 0.31 — dense clumps with skin showing between them,
    /// as in the paper's Fig. 2), a warm brown undercoat, white light from above-front.
    pub fn for_shell(shell: &Shell) -> MarchParams {
        let h_min = shell.heights.iter().fold(f32::INFINITY, |m, &h| m.min(h));
        let step = h_min / STEPS_PER_THICKNESS as f32;
        MarchParams {
            sigma: 8.0 / shell.height,
            step,
            max_steps: MAX_STEPS,
            hops: shell.hop_cap(),
            epsilon_t: EPSILON_T,
            light_steps: 8,
            light_step: step,
            to_light: Vec3::new(0.3, 1.0, 0.5).normalize(),
            light: Vec3::ONE,
            colour: Vec3::new(0.45, 0.3, 0.2),
            emit: Emit::Shell,
        }
    }

    /// Checks the parameters; the error names the key.
    pub fn validate(&self) -> Result<(), super::InvalidParam> {
        let bad = |key: &str, v: String, rule: &str| Err(super::InvalidParam::new(key, v, rule));
        if !(self.sigma.is_finite() && self.sigma >= 0.0) {
            return bad("fur.sigma", self.sigma.to_string(), "must be finite and ≥ 0");
        }
        if !(self.step.is_finite() && self.step > 0.0) {
            return bad("fur.march_step", self.step.to_string(), "must be finite and > 0");
        }
        if !(self.light_step.is_finite() && self.light_step > 0.0) {
            return bad(
                "fur.light_step",
                self.light_step.to_string(),
                "must be finite and > 0",
            );
        }
        if !(self.epsilon_t.is_finite() && (0.0..1.0).contains(&self.epsilon_t)) {
            return bad("fur.epsilon_t", self.epsilon_t.to_string(), "must be in [0, 1)");
        }
        if self.emit == Emit::Virtual(0) {
            return bad("fur.k", "0".into(), "must be ≥ 1");
        }
        if !(self.to_light.is_finite() && (self.to_light.length() - 1.0).abs() < 1e-3) {
            return bad(
                "fur.light_dir",
                format!("{}", self.to_light),
                "must be a unit vector",
            );
        }
        Ok(())
    }
}

/// Why a march stopped.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Stop {
    /// Reached the base mesh.
    Base,
    /// Left through the top.
    Top,
    /// Left across a boundary edge.
    Boundary,
    /// The walk ran out of hops.
    Lost,
    /// `T < ε_T`.
    Transmittance,
    /// `max_steps` taken.
    MaxSteps,
}

/// A shell or virtual fragment: ray distance, non-premultiplied colour, alpha.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Fragment {
    pub t: f32,
    pub colour: Vec3,
    pub alpha: f32,
}

/// One ray's march.
#[derive(Clone, Debug, PartialEq)]
pub struct March {
    /// Front to back.
    pub fragments: Vec<Fragment>,
    pub stop: Stop,
    /// Samples inside the shell.
    pub steps: u32,
    /// Hops of the eye walk (every sample's, the last one's included).
    pub hops: u32,
    /// Light-march samples inside the shell.
    pub light_steps: u32,
    /// Light marches lost.
    pub light_lost: u32,
    /// Final eye transmittance `T`.
    pub transmittance: f32,
    /// Accumulated radiance `L` (premultiplied).
    pub radiance: Vec3,
}

/// Counters over many rays.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MarchStats {
    pub rays: u64,
    pub steps: u64,
    pub hops: u64,
    pub light_steps: u64,
    /// Eye rays stopped by the hop cap.
    pub lost: u64,
    pub light_lost: u64,
    /// Rays stopped by `max_steps` (capped).
    pub capped: u64,
}

impl MarchStats {
    pub fn add(&mut self, m: &March) {
        self.rays += 1;
        self.steps += u64::from(m.steps);
        self.hops += u64::from(m.hops);
        self.light_steps += u64::from(m.light_steps);
        self.lost += u64::from(m.stop == Stop::Lost);
        self.light_lost += u64::from(m.light_lost);
        self.capped += u64::from(m.stop == Stop::MaxSteps);
    }
}

/// The first shell fragment along the ray `o + t r` (`r` unit): the nearest front-facing hit on a top triangle
/// or an outward wall quad on a boundary edge (B.3 #6), as `(t, face)` — the CPU stand-in for the rasteriser.
pub fn entry(shell: &Shell, o: Vec3, r: Vec3) -> Option<(f32, u32)> {
    let mut best: Option<(f32, u32)> = None;
    let mut consider = |t: Option<f32>, f: usize| {
        if let Some(t) = t
            && best.is_none_or(|(b, _)| t < b)
        {
            best = Some((t, f as u32));
        }
    };
    for f in 0..shell.mesh.faces.len() {
        let (b, t) = shell.prism(f);
        consider(front_hit(o, r, [t[0], t[1], t[2]]), f);
        for e in 0..3 {
            if shell.mesh.neighbours[f][e] != NONE {
                continue;
            }
            // Edge e runs from corner e + 1 to e + 2; the wall wound so its normal points out of the prism.
            let (i, j) = ((e + 1) % 3, (e + 2) % 3);
            consider(front_hit(o, r, [b[i], b[j], t[j]]), f);
            consider(front_hit(o, r, [b[i], t[j], t[i]]), f);
        }
    }
    best
}

/// One of the shell's entry triangles (B.3 #6) of a prism: its top, or half `half` (0 or 1) of the outward wall
/// quad on its boundary edge `edge`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EntryTriangle {
    Top,
    Wall { edge: usize, half: usize },
}

/// The entry triangles of prism `f`: its top, then the two halves of the wall on each boundary edge.
fn face_entry_triangles(shell: &Shell, f: usize) -> impl Iterator<Item = EntryTriangle> + '_ {
    std::iter::once(EntryTriangle::Top).chain(
        (0..3)
            .filter(move |&edge| shell.mesh.neighbours[f][edge] == NONE)
            .flat_map(|edge| (0..2).map(move |half| EntryTriangle::Wall { edge, half })),
    )
}

/// Every entry triangle of `shell` as `(face, triangle)`, in the order [`entry`] tests them.
pub fn entry_triangles(shell: &Shell) -> Vec<(u32, EntryTriangle)> {
    (0..shell.mesh.faces.len())
        .flat_map(|f| face_entry_triangles(shell, f).map(move |which| (f as u32, which)))
        .collect()
}

/// The corners of entry triangle `which` of prism `f`, counter-clockwise seen from outside the prism (as
/// [`entry`] winds them).
pub fn entry_corners(shell: &Shell, f: usize, which: EntryTriangle) -> [Vec3; 3] {
    let (b, t) = shell.prism(f);
    match which {
        EntryTriangle::Top => t,
        EntryTriangle::Wall { edge, half } => {
            let (i, j) = ((edge + 1) % 3, (edge + 2) % 3);
            if half == 0 {
                [b[i], b[j], t[j]]
            } else {
                [b[i], t[j], t[i]]
            }
        }
    }
}

/// Every front-facing entry hit along rays through a shell: its entry triangles built once, with a bounding
/// sphere per prism so that a ray tests only the prisms it passes near (the sphere holds the prism's corners,
/// hence its triangles; it is widened by 0.1 % and by 10⁻⁵ of the ray's distance to it, far beyond the
/// rounding of the test, so no hit is culled).
pub struct EntryHits {
    /// Per prism: face, sphere centre, radius, its triangles' range in `triangles`.
    prisms: Vec<(u32, Vec3, f32, std::ops::Range<usize>)>,
    triangles: Vec<[Vec3; 3]>,
}

impl EntryHits {
    pub fn new(shell: &Shell) -> EntryHits {
        let mut prisms = Vec::with_capacity(shell.mesh.faces.len());
        let mut triangles = Vec::new();
        for f in 0..shell.mesh.faces.len() {
            let (b, t) = shell.prism(f);
            let centre = (b[0] + b[1] + b[2] + t[0] + t[1] + t[2]) / 6.0;
            let radius = b.iter().chain(&t).fold(0.0f32, |m, c| m.max(c.distance(centre)));
            let start = triangles.len();
            triangles.extend(face_entry_triangles(shell, f).map(|which| entry_corners(shell, f, which)));
            prisms.push((f as u32, centre, radius, start..triangles.len()));
        }
        EntryHits { prisms, triangles }
    }

    /// The hits along the ray `o + t r` (`r` unit) as `(t, face)`, nearest first (ties by face): what the
    /// rasteriser makes of one pixel's ray, each hit the start of a march of its own; [`entry`] is the first.
    pub fn along(&self, o: Vec3, r: Vec3) -> Vec<(f32, u32)> {
        let mut hits = Vec::new();
        for (f, centre, radius, range) in &self.prisms {
            let oc = *centre - o;
            let off = oc - oc.dot(r) * r;
            let reach = radius * 1.001 + 1e-5 * oc.length();
            if off.length_squared() > reach * reach {
                continue;
            }
            hits.extend(
                self.triangles[range.clone()]
                    .iter()
                    .filter_map(|&v| front_hit(o, r, v).map(|t| (t, *f))),
            );
        }
        hits.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        hits
    }
}

/// Ray–triangle intersection (Möller–Trumbore) with triangle `v` seen from its front (counter-clockwise).
fn front_hit(o: Vec3, r: Vec3, v: [Vec3; 3]) -> Option<f32> {
    let (e1, e2) = (v[1] - v[0], v[2] - v[0]);
    let pv = r.cross(e2);
    let det = e1.dot(pv);
    if det <= 0.0 {
        return None; // det = −r · n: back-facing or parallel
    }
    let inv = 1.0 / det;
    let s = o - v[0];
    let u = s.dot(pv) * inv;
    let q = s.cross(e1);
    let v2 = r.dot(q) * inv;
    if u < 0.0 || v2 < 0.0 || u + v2 > 1.0 {
        return None;
    }
    let t = e2.dot(q) * inv;
    (t > 0.0).then_some(t)
}

/// A group being accumulated (virtual fragments) or the whole march.
#[derive(Clone, Copy)]
struct Acc {
    t: f32,
    transmittance: f32,
    radiance: Vec3,
}

impl Acc {
    fn new(t: f32) -> Acc {
        Acc {
            t,
            transmittance: 1.0,
            radiance: Vec3::ZERO,
        }
    }

    fn fragment(&self) -> Option<Fragment> {
        let alpha = 1.0 - self.transmittance;
        (alpha > 0.0).then(|| Fragment {
            t: self.t,
            colour: self.radiance / alpha,
            alpha,
        })
    }
}

/// Marches the eye ray `o + t r` (`r` unit) from its shell fragment at `t0` in prism `face` (B.5).
pub fn march(shell: &Shell, volume: &Volume, p: &MarchParams, o: Vec3, r: Vec3, t0: f32, face: u32) -> March {
    let mut out = March {
        fragments: Vec::new(),
        stop: Stop::MaxSteps,
        steps: 0,
        hops: 0,
        light_steps: 0,
        light_lost: 0,
        transmittance: 1.0,
        radiance: Vec3::ZERO,
    };
    let mut whole = Acc::new(t0);
    let mut group = Acc::new(t0);
    let k = match p.emit {
        Emit::Shell => u32::MAX,
        Emit::Virtual(k) => k,
    };
    let mut f = face;
    for step in 0..p.max_steps {
        if step > 0 && step % k == 0 {
            out.fragments.extend(group.fragment());
            group = Acc::new(t0 + step as f32 * p.step);
        }
        let t = t0 + (step as f32 + 0.5) * p.step;
        let x = o + t * r;
        let (g, at) = match locate(shell, x, f, p.hops, &mut out.hops) {
            Ok(found) => found,
            Err(stop) => {
                out.stop = stop;
                break;
            }
        };
        f = g;
        out.steps += 1;
        let (layer, local, _) = shell.sub_element(f as usize, &at);
        let s = volume.sample(shell, f as usize, layer, local);
        let ts = (-p.sigma * s.density * p.step).exp();
        let t_light = light_transmittance(shell, volume, p, x, f, &mut out);
        let phase = kajiya_kay(s.tangent, p.to_light, -r, p.colour);
        let lit = phase * p.light * t_light;
        for acc in [&mut whole, &mut group] {
            acc.radiance += acc.transmittance * (1.0 - ts) * lit;
            acc.transmittance *= ts;
        }
        if whole.transmittance < p.epsilon_t {
            out.stop = Stop::Transmittance;
            break;
        }
    }
    match p.emit {
        Emit::Shell => out.fragments.extend(whole.fragment()),
        Emit::Virtual(_) => out.fragments.extend(group.fragment()),
    }
    out.transmittance = whole.transmittance;
    out.radiance = whole.radiance;
    out
}

/// B.5's point location with hops: `x` located in prism `f` (shell height first: under the base or over the
/// top stops, `w` being continuous across shared lateral faces), then across the exit edge (opposite the
/// most negative barycentric) to the neighbour, at most `max_hops` times; within [`SIDE_TOLERANCE`] of a side
/// is inside. Hops taken are added to `hops`.
fn locate(shell: &Shell, x: Vec3, f: u32, max_hops: u32, hops: &mut u32) -> Result<(u32, Location), Stop> {
    let mut f = f;
    for hop in 0..=max_hops {
        let at = shell.locate(x, f as usize);
        if at.w < 0.0 {
            return Err(Stop::Base);
        }
        if at.w > 1.0 {
            return Err(Stop::Top);
        }
        let (edge, m) = at.min_lambda();
        if m >= -SIDE_TOLERANCE {
            return Ok((f, at));
        }
        if hop == max_hops {
            break;
        }
        match shell.mesh.neighbours[f as usize][edge] {
            NONE => return Err(Stop::Boundary),
            g => {
                f = g;
                *hops += 1;
            }
        }
    }
    Err(Stop::Lost)
}

/// `T_light` at `x` (in prism `f`): `n_light` mid-point samples towards the light (module docs).
fn light_transmittance(
    shell: &Shell,
    volume: &Volume,
    p: &MarchParams,
    x: Vec3,
    f: u32,
    out: &mut March,
) -> f32 {
    let mut optical = 0.0;
    let mut f = f;
    for j in 0..p.light_steps {
        let y = x + (j as f32 + 0.5) * p.light_step * p.to_light;
        let mut hops = 0;
        match locate(shell, y, f, p.hops, &mut hops) {
            Ok((face, at)) => {
                f = face;
                out.light_steps += 1;
                let (layer, local, _) = shell.sub_element(f as usize, &at);
                optical += p.sigma * volume.sample(shell, f as usize, layer, local).density * p.light_step;
            }
            Err(Stop::Base) => return 0.0,
            Err(Stop::Lost) => {
                out.light_lost += 1;
                break;
            }
            Err(_) => break,
        }
    }
    (-optical).exp()
}

/// Composites `fragments` (any order) back to front with "over" onto `background`: the resolved colour and
/// the total alpha.
pub fn composite(fragments: &[Fragment], background: Vec3) -> (Vec3, f32) {
    let mut sorted = fragments.to_vec();
    sorted.sort_by(|a, b| b.t.total_cmp(&a.t));
    sorted.iter().fold((background, 0.0), |(c, a), f| {
        (
            f.colour * f.alpha + c * (1.0 - f.alpha),
            f.alpha + a * (1.0 - f.alpha),
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bad_march_parameters_name_their_key() {
        let p = MarchParams {
            sigma: 1.0,
            step: 0.1,
            max_steps: 8,
            hops: 4,
            epsilon_t: 0.0,
            light_steps: 0,
            light_step: 0.1,
            to_light: Vec3::Y,
            light: Vec3::ONE,
            colour: Vec3::ONE,
            emit: Emit::Shell,
        };
        assert_eq!(p.validate(), Ok(()));
        let e = |q: MarchParams| q.validate().unwrap_err().to_string();
        assert_eq!(
            e(MarchParams { step: 0.0, ..p }),
            "invalid fur.march_step = 0: must be finite and > 0"
        );
        assert_eq!(
            e(MarchParams {
                emit: Emit::Virtual(0),
                ..p
            }),
            "invalid fur.k = 0: must be ≥ 1"
        );
        assert!(e(MarchParams { sigma: -1.0, ..p }).starts_with("invalid fur.sigma = -1"));
        assert!(e(MarchParams { epsilon_t: 1.0, ..p }).starts_with("invalid fur.epsilon_t = 1"));
        assert!(
            e(MarchParams {
                to_light: Vec3::X * 2.0,
                ..p
            })
            .starts_with("invalid fur.light_dir")
        );
    }

    #[test]
    fn composite_by_hand() {
        // Back (t = 2) red α 0.5 over black, then front (t = 1) green α 0.5: (0.25, 0.5, 0), α 0.75.
        let f = [
            Fragment {
                t: 1.0,
                colour: Vec3::Y,
                alpha: 0.5,
            },
            Fragment {
                t: 2.0,
                colour: Vec3::X,
                alpha: 0.5,
            },
        ];
        assert_eq!(composite(&f, Vec3::ZERO), (Vec3::new(0.25, 0.5, 0.0), 0.75));
    }
}
