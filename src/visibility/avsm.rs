//! Adaptive volumetric shadow maps (AVSM; Salvi, Vidimče, Lauritzen & Lefohn, "Adaptive Volumetric Shadow
//! Maps", EGSR 2010, §3-4; Intel's AVSM sample, `AVSM_Gen`: `AVSMGenInsertFragmentSoft` and its area metric
//! `AVSMCompMetricSoft`). Each texel stores at most `N` nodes `(depth d_i, transmittance t_i)`, sorted by depth,
//! and the transmittance curve is piecewise linear between them. This model is the specification of
//! `shaders/avsm.wgsl` (compression) and `shaders/methods/avsm.wgsl` (lookup).
//!
//! # The curve
//! With `k` = the number of nodes with `d_i < z` (strictly less, so that a fragment does not shadow itself, as in
//! the reference): `V(z) = 1` when `k = 0` (in front of the first node, and in an empty texel); `V(z) = t_last`
//! when `k` is the node count (behind the last node); otherwise the linear interpolation between nodes `k - 1`
//! and `k` ([`interpolate`]), clamped between their transmittances so that f32 rounding cannot make `V` rise.
//!
//! # Inserting a hair fragment
//! A hair fragment is a surface occluder: the paper inserts a volume segment `[d_0, d_1]` as its entry and exit
//! nodes, and a segment of zero length (a fragment of a strand, which has no thickness along the light in a
//! light-space rasterisation) becomes two nodes at one depth, a vertical step, as the reference curve has. A
//! fragment of depth `d` and factor `f = 1 - alpha` (alpha clamped to `[0, MAX_ALPHA]` as in
//! `optical_depth`; [`fragment_factor`]) goes behind every node with `d_i <= d`: with `t_in` the curve's value
//! there (1 with no node in front, `t_last` with none behind, else [`interpolate`] between its neighbours), it
//! inserts `(d, t_in)` and `(d, t_in * f)` and multiplies the transmittance of every node behind by `f`. With
//! `N >= 2 n` nodes for `n` fragments the curve is exactly the reference's.
//!
//! # Compression
//! While a texel holds more than `N` nodes, the node whose removal changes the area under the curve least is
//! removed (§4.2; the sample's metric): for an interior node `i`, twice the triangle area
//! `|(d_{i+1} - d_{i-1}) (t_{i+1} - t_i) - (d_{i+1} - d_i) (t_{i+1} - t_{i-1})|` ([`removal_area`]). The first
//! and the last node are never removed (the paper keeps both; the sample's candidates are `1..count-1`). Ties go
//! to the node nearest the light (the lowest index, as the sample's strict `<`).
//!
//! # Insertion order
//! The lossy compression makes the result depend on the order of insertion. [`InsertionOrder::Depth`] sorts a
//! texel's fragments by (depth, segment, alpha) — deterministic, front to back; [`InsertionOrder::Submission`]
//! by (segment, depth, alpha): the primitive order a rasteriser-ordered implementation would see, reproducible
//! because every fragment carries its segment ([`Fragment::segment`]). Fragments equal in all three keys are
//! identical, so their order is immaterial; depth comparisons treat `-0.0` and `0.0` as equal, as the GPU's `<`.
//!
//! Transmittances and areas below `1e-30` are taken as 0 ([`flush`]), the same on every device (some flush
//! subnormals, some keep them).
//!
//! GPU: the same f32 expressions ([`interpolate`], [`removal_area`], [`fragment_factor`], [`flush`]); the node buffer holds
//! `N` slots of `vec2<f32>` per texel, the nodes followed by copies of the last node (an empty texel: `N` copies
//! of `(1.0, 1.0)`, the paper's clear value), which the lookup rule above reads as the same curve.

use super::{Fragment, MAX_ALPHA, Model, Stored, TexelModel, list, valid};
use std::cmp::Ordering;

/// Fewest and most nodes per texel (the paper's and the sample's 4..=16).
pub const MIN_NODES: usize = 4;
pub const MAX_NODES: usize = 16;

/// The order fragments are inserted in.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum InsertionOrder {
    /// By (depth, segment, alpha): front to back.
    #[default]
    Depth,
    /// By (segment, depth, alpha): primitive order, as a rasteriser-ordered implementation inserts.
    Submission,
}

/// AVSM parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AvsmParams {
    /// Nodes per texel `N`, in `MIN_NODES..=MAX_NODES`.
    pub nodes: usize,
    pub order: InsertionOrder,
}

impl Default for AvsmParams {
    /// 8 nodes (the sample's default), depth order.
    fn default() -> Self {
        Self {
            nodes: 8,
            order: InsertionOrder::Depth,
        }
    }
}

/// One node of the transmittance curve.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Node {
    pub depth: f32,
    pub trans: f32,
}

/// An AVSM texel: at most `N` nodes sorted by depth (non-decreasing), transmittance non-increasing.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct AvsmTexel {
    pub nodes: Vec<Node>,
}

/// Transmittances and removal areas below this are 0: GPUs may flush subnormal f32 results to zero, so the model
/// flushes well above the subnormal range (`1.2e-38`), where every product and difference it takes of such values
/// rounds alike with or without subnormals. Physically nothing: `V < 1e-30` is black.
pub const FLUSH_BELOW: f32 = 1e-30;

/// `x`, or 0 below [`FLUSH_BELOW`]. GPU: `select(x, 0.0, x < 1e-30)`.
pub fn flush(x: f32) -> f32 {
    if x < FLUSH_BELOW { 0.0 } else { x }
}

/// The transmittance factor `1 - alpha` of a fragment, alpha clamped to `[0, MAX_ALPHA]` (NaN counts as 0).
/// GPU: `1.0 - clamp(alpha, 0.0, 1.0 - 1e-6)`.
pub fn fragment_factor(alpha: f32) -> f32 {
    1.0 - if alpha > 0.0 { alpha.min(MAX_ALPHA) } else { 0.0 }
}

/// The curve between nodes `a` and `b` (`a.depth < b.depth`) at `z`:
/// `flush(clamp(a.t + (b.t - a.t) * ((z - a.d) / (b.d - a.d)), b.t, a.t))`. GPU: the same expression.
pub fn interpolate(a: Node, b: Node, z: f32) -> f32 {
    let s = (z - a.depth) / (b.depth - a.depth);
    flush((a.trans + (b.trans - a.trans) * s).max(b.trans).min(a.trans))
}

/// Twice the area the curve loses or gains when node `m` between `l` and `r` is removed:
/// `flush(|(r.d - l.d) * (r.t - m.t) - (r.d - m.d) * (r.t - l.t)|)`. GPU: the same expression.
pub fn removal_area(l: Node, m: Node, r: Node) -> f32 {
    flush(((r.depth - l.depth) * (r.trans - m.trans) - (r.depth - m.depth) * (r.trans - l.trans)).abs())
}

/// Inserts a fragment of depth `depth` and factor `f` ([`fragment_factor`]) as a step (see the module doc); every
/// product is flushed ([`flush`]).
pub fn insert(nodes: &mut Vec<Node>, depth: f32, f: f32) {
    let k = nodes.partition_point(|n| n.depth <= depth);
    let t_in = if k == 0 {
        1.0
    } else if k == nodes.len() {
        nodes[k - 1].trans
    } else {
        interpolate(nodes[k - 1], nodes[k], depth)
    };
    for n in &mut nodes[k..] {
        n.trans = flush(n.trans * f);
    }
    nodes.splice(
        k..k,
        [
            Node { depth, trans: t_in },
            Node {
                depth,
                trans: flush(t_in * f),
            },
        ],
    );
}

/// Removes the interior node of least [`removal_area`] (ties: the lowest index). Needs at least 3 nodes.
pub fn remove_one(nodes: &mut Vec<Node>) {
    let mut best = 1;
    let mut best_area = removal_area(nodes[0], nodes[1], nodes[2]);
    for i in 2..nodes.len() - 1 {
        let a = removal_area(nodes[i - 1], nodes[i], nodes[i + 1]);
        if a < best_area {
            best = i;
            best_area = a;
        }
    }
    nodes.remove(best);
}

/// Compares depths as the GPU's `<` does (`-0.0 == 0.0`); depths here are finite.
fn depth_cmp(a: f32, b: f32) -> Ordering {
    a.partial_cmp(&b).unwrap_or(Ordering::Equal)
}

/// The insertion order of two fragments (see [`InsertionOrder`]).
pub fn insertion_cmp(order: InsertionOrder, a: &Fragment, b: &Fragment) -> Ordering {
    let alpha = a.alpha.partial_cmp(&b.alpha).unwrap_or(Ordering::Equal);
    match order {
        InsertionOrder::Depth => depth_cmp(a.depth, b.depth).then(a.segment.cmp(&b.segment)),
        InsertionOrder::Submission => a.segment.cmp(&b.segment).then(depth_cmp(a.depth, b.depth)),
    }
    .then(alpha)
}

/// `V(z)` of a texel (the curve of the module doc).
pub fn visibility(texel: &AvsmTexel, z: f32) -> f32 {
    let nodes = &texel.nodes;
    let k = nodes.partition_point(|n| n.depth < z);
    if k == 0 {
        1.0
    } else if k == nodes.len() {
        nodes[k - 1].trans
    } else {
        interpolate(nodes[k - 1], nodes[k], z)
    }
}

impl AvsmParams {
    fn node_count(&self) -> usize {
        self.nodes.clamp(MIN_NODES, MAX_NODES)
    }

    /// The `N` slots the GPU stores, `[depth, trans]` each: the nodes, then copies of the last (see the module
    /// doc).
    pub fn slots(&self, texel: &AvsmTexel) -> Vec<[f32; 2]> {
        let pad = texel.nodes.last().copied().unwrap_or(Node {
            depth: 1.0,
            trans: 1.0,
        });
        (0..self.node_count())
            .map(|i| {
                let n = texel.nodes.get(i).copied().unwrap_or(pad);
                [n.depth, n.trans]
            })
            .collect()
    }
}

impl Model for AvsmParams {
    type Texel = AvsmTexel;

    fn build(&self, fragments: &[Fragment]) -> AvsmTexel {
        let n = self.node_count();
        let mut sorted: Vec<&Fragment> = valid(fragments).collect();
        sorted.sort_by(|a, b| insertion_cmp(self.order, a, b));
        let mut nodes = Vec::with_capacity(n + 2);
        for f in sorted {
            insert(&mut nodes, f.depth, fragment_factor(f.alpha));
            while nodes.len() > n {
                remove_one(&mut nodes);
            }
        }
        AvsmTexel { nodes }
    }

    fn visibility(&self, texel: &AvsmTexel, z: f32) -> f32 {
        visibility(texel, z)
    }
}

impl TexelModel for AvsmParams {
    fn label(&self) -> String {
        match self.order {
            InsertionOrder::Depth => format!("avsm-{}", self.node_count()),
            InsertionOrder::Submission => format!("avsm-{}-submission", self.node_count()),
        }
    }

    fn curve(&self, fragments: &[Fragment], zs: &[f32]) -> Vec<f32> {
        super::model_curve(self, fragments, zs)
    }

    /// The `N` slots, depth then transmittance each.
    fn stored_values(&self, fragments: &[Fragment]) -> Vec<f32> {
        self.slots(&self.build(fragments)).into_iter().flatten().collect()
    }

    fn stored(&self, fragments: &[Fragment]) -> Option<Stored> {
        let texel = self.build(fragments);
        let mut s = Stored::new(self.label());
        let depths: Vec<f32> = texel.nodes.iter().map(|n| n.depth).collect();
        let trans: Vec<f32> = texel.nodes.iter().map(|n| n.trans).collect();
        s.summary = vec![
            format!(
                "{} of {} nodes, {:?} order",
                texel.nodes.len(),
                self.node_count(),
                self.order
            ),
            format!("node depths: {}", list(&depths)),
            format!("node transmittances: {}", list(&trans)),
        ];
        s.knots = texel.nodes.iter().map(|n| [n.depth, n.trans]).collect();
        Some(s)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::visibility::Reference;
    use crate::visibility::test_support::{Rng, assert_valid_curve, extreme_texels, random_texel};

    fn p(nodes: usize, order: InsertionOrder) -> AvsmParams {
        AvsmParams { nodes, order }
    }

    fn node(depth: f32, trans: f32) -> Node {
        Node { depth, trans }
    }

    fn seg(depth: f32, alpha: f32, segment: u32) -> Fragment {
        Fragment {
            segment,
            ..Fragment::new(depth, alpha)
        }
    }

    #[test]
    fn two_fragments_are_two_steps() {
        // Alphas 0.5 and 0.75 at 0.2 and 0.6: nodes (0.2, 1), (0.2, 0.5), (0.6, 0.5), (0.6, 0.125).
        let t = p(4, InsertionOrder::Depth).build(&[Fragment::new(0.6, 0.75), Fragment::new(0.2, 0.5)]);
        assert_eq!(
            t.nodes,
            [node(0.2, 1.0), node(0.2, 0.5), node(0.6, 0.5), node(0.6, 0.125)]
        );
        // Strictly less: a fragment does not shadow itself.
        assert_eq!(visibility(&t, 0.2), 1.0);
        assert_eq!(visibility(&t, 0.3), 0.5);
        assert_eq!(visibility(&t, 0.6), 0.5);
        assert_eq!(visibility(&t, 0.61), 0.125);
        assert_eq!(visibility(&t, 7.0), 0.125);
        assert_eq!(visibility(&t, -1.0), 1.0);
    }

    #[test]
    fn a_fragment_in_front_multiplies_every_node_behind() {
        // Submission order inserts segment 0 (depth 0.6, alpha 0.5) first, then segment 1 in front of it
        // (depth 0.2, alpha 0.5): t_in = 1, the nodes behind are halved.
        let t = p(4, InsertionOrder::Submission).build(&[seg(0.2, 0.5, 1), seg(0.6, 0.5, 0)]);
        assert_eq!(
            t.nodes,
            [node(0.2, 1.0), node(0.2, 0.5), node(0.6, 0.5), node(0.6, 0.25)]
        );
        // Behind a node, inside an interval: t_in interpolated between the neighbours.
        let mut nodes = vec![node(0.0, 1.0), node(1.0, 0.5)];
        insert(&mut nodes, 0.5, 0.5);
        assert_eq!(
            nodes,
            [node(0.0, 1.0), node(0.5, 0.75), node(0.5, 0.375), node(1.0, 0.25)]
        );
    }

    #[test]
    fn overflow_removes_the_least_area_node() {
        // Five fragments of alpha 0.5 at 1/8, 2/8, 3/8, 4/8 and 1 (binary fractions: every area below is exact
        // in f32) with 8 nodes: 10 nodes after the fifth pair,
        // 0:(1/8, 1) 1:(1/8, 1/2) 2:(2/8, 1/2) 3:(2/8, 1/4) 4:(3/8, 1/4) 5:(3/8, 1/8) 6:(4/8, 1/8)
        // 7:(4/8, 1/16) 8:(1, 1/16) 9:(1, 1/32).
        // Twice the triangle areas, h = 1/8: node 1 h/2, 2 h/4, 3 h/4, 4 h/8, 5 h/8, 6 h/16 (the least),
        // 7 (1/2)(1/16), 8 (1/2)(1/32). Node 6 goes. Then node 4 h/8 = 1/64, node 5 (between (3/8, 1/4) and
        // (4/8, 1/16)) |h (1/16 - 1/8) - h (1/16 - 1/4)| = h/8 = 1/64, node 6 (4/8, 1/16) between (3/8, 1/8) and
        // (1, 1/16): (1/2)(1/16) = 1/32, node 7 (1, 1/16): (1/2)(1/32) = 1/64: a three-way tie, node 4 goes.
        let f: Vec<Fragment> = [0.125, 0.25, 0.375, 0.5, 1.0]
            .map(|d| Fragment::new(d, 0.5))
            .to_vec();
        let t = p(8, InsertionOrder::Depth).build(&f);
        let depths: Vec<f32> = t.nodes.iter().map(|n| n.depth).collect();
        let trans: Vec<f32> = t.nodes.iter().map(|n| n.trans).collect();
        assert_eq!(depths, [0.125, 0.125, 0.25, 0.25, 0.375, 0.5, 1.0, 1.0]);
        assert_eq!(trans, [1.0, 0.5, 0.5, 0.25, 0.125, 0.0625, 0.0625, 0.03125]);
        // The step at 3/8 became a ramp from (2/8, 1/4) to (3/8, 1/8).
        assert_eq!(visibility(&t, 0.3125), 0.1875);
    }

    #[test]
    fn removal_ties_go_to_the_node_nearest_the_light() {
        // Equal areas at nodes 1 and 2 (a symmetric step): node 1 goes.
        let mut nodes = vec![node(0.0, 1.0), node(0.5, 1.0), node(0.5, 0.5), node(1.0, 0.5)];
        assert_eq!(removal_area(nodes[0], nodes[1], nodes[2]), 0.25);
        assert_eq!(removal_area(nodes[1], nodes[2], nodes[3]), 0.25);
        remove_one(&mut nodes);
        assert_eq!(nodes, [node(0.0, 1.0), node(0.5, 0.5), node(1.0, 0.5)]);
    }

    #[test]
    fn enough_nodes_give_the_reference() {
        let mut rng = Rng::new(5);
        for _ in 0..50 {
            let f = random_texel(&mut rng, 8);
            let t = p(16, InsertionOrder::Depth).build(&f);
            let r = Reference.build(&f);
            for &z in &crate::visibility::test_support::probe_depths(&f) {
                let (a, b) = (visibility(&t, z), Reference.visibility(&r, z));
                assert!((a - b).abs() < 1e-5, "z {z}: avsm {a} vs reference {b}; {f:?}");
            }
        }
    }

    #[test]
    fn orders_sort_by_their_keys() {
        let f = [
            seg(0.5, 0.3, 0),
            seg(0.2, 0.3, 2),
            seg(0.2, 0.3, 1),
            seg(0.2, 0.1, 1),
        ];
        let mut d = f.to_vec();
        d.sort_by(|a, b| insertion_cmp(InsertionOrder::Depth, a, b));
        assert_eq!(d, [f[3], f[2], f[1], f[0]]);
        let mut s = f.to_vec();
        s.sort_by(|a, b| insertion_cmp(InsertionOrder::Submission, a, b));
        assert_eq!(s, [f[0], f[3], f[2], f[1]]);
        // The input order never matters.
        let mut rng = Rng::new(8);
        for order in [InsertionOrder::Depth, InsertionOrder::Submission] {
            let mut f: Vec<Fragment> = random_texel(&mut rng, 60)
                .into_iter()
                .enumerate()
                .map(|(i, f)| Fragment {
                    segment: (i as u32 * 7) % 13,
                    ..f
                })
                .collect();
            let a = p(8, order).build(&f);
            f.reverse();
            assert_eq!(a, p(8, order).build(&f));
        }
    }

    #[test]
    fn slots_pad_with_the_last_node_and_read_the_same() {
        let params = p(8, InsertionOrder::Depth);
        let f = [Fragment::new(0.3, 0.5), Fragment::new(0.7, 0.5)];
        let t = params.build(&f);
        let slots = params.slots(&t);
        assert_eq!(slots.len(), 8);
        assert_eq!(slots[3], [0.7, 0.25]);
        assert!(slots[4..].iter().all(|s| *s == [0.7, 0.25]));
        let padded = AvsmTexel {
            nodes: slots.iter().map(|s| node(s[0], s[1])).collect(),
        };
        for z in [-1.0, 0.3, 0.5, 0.7, 0.71, 2.0] {
            assert_eq!(visibility(&padded, z), visibility(&t, z));
        }
        assert_eq!(params.slots(&AvsmTexel::default()), vec![[1.0, 1.0]; 8]);
        assert_eq!(params.stored_values(&f).len(), 16);
    }

    #[test]
    fn stored_knots_are_the_nodes() {
        let params = AvsmParams::default();
        let f = [Fragment::new(0.3, 0.5)];
        let s = params.stored(&f).unwrap();
        assert_eq!(s.knots, [[0.3, 1.0], [0.3, 0.5]]);
        assert_eq!(s.label, params.label());
    }

    #[test]
    fn properties() {
        let mut rng = Rng::new(3);
        for n in [4, 5, 8, 12, 16] {
            for order in [InsertionOrder::Depth, InsertionOrder::Submission] {
                let params = p(n, order);
                for f in extreme_texels() {
                    assert_valid_curve(&params, &f, "avsm");
                }
                for _ in 0..60 {
                    let f: Vec<Fragment> = random_texel(&mut rng, 80)
                        .into_iter()
                        .map(|f| Fragment {
                            segment: rng.int(0, 40) as u32,
                            ..f
                        })
                        .collect();
                    assert_valid_curve(&params, &f, "avsm");
                    let t = params.build(&f);
                    assert!(t.nodes.len() <= n);
                    // In front of every fragment: lit; behind all: the product of the factors.
                    let first = f.iter().map(|f| f.depth).fold(f32::INFINITY, f32::min);
                    assert_eq!(visibility(&t, first), 1.0);
                    let exact: f32 = f.iter().map(|f| fragment_factor(f.alpha)).product();
                    let behind = visibility(&t, 2.0);
                    assert!(
                        (behind - exact).abs() <= 1e-5 * exact.max(1e-3),
                        "{behind} vs {exact}"
                    );
                }
            }
        }
    }
}
