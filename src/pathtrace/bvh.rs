//! A bounding volume hierarchy over fibre segments and mesh triangles: a top-down binary build binned by the
//! surface area heuristic (Wald 2007, "On fast construction of SAH-based bounding volume hierarchies": 16 bins on
//! each axis over the centroids, a node visit costed as one primitive test), collapsed into four-wide nodes whose
//! four child boxes a ray tests at once (Wald et al. 2008), and stack traversal nearest child first (the box
//! test ordered by the direction's signs where no component is 0). A slanted segment enters the build as a few
//! boxes along its length (its one box is mostly empty), and each leaf keeps its primitives with their segments'
//! axes side by side so the cheap test before the exact solve (`fibre::misses_axis`: the ray's distance from
//! the segment's line, and where along the ray and the axis it passes that near) reads no other memory. A query
//! remembers the last few primitives it tested (a segment's pieces sit in several leaves) and skips the
//! primitive its ray leaves; a shadow query first tests the primitive that last blocked one on its thread.
//! Written in-tree rather than taken from a crate: the primitives are our own round fibres (`fibre.rs`) and we
//! need every hit along a ray besides the first.

use glam::{UVec4, Vec3, Vec4};

use super::fibre::{Hit, Ray, Segment, misses_axis};
use super::triangle::Triangle;
use crate::scene::Aabb;

const BINS: usize = 16;
/// A node holds at most this many segments as a leaf when a split would not pay.
const MAX_LEAF: usize = 8;
/// The cost of visiting a node relative to testing a primitive, for the surface area heuristic.
const TRAVERSAL_COST: f32 = 1.0;
/// A segment enters the hierarchy as at most this many boxes along its length (4 made 3.2 boxes a segment of
/// `default`'s groom, 2 makes 2.0 and its render about 5 % faster).
const MAX_PIECES: usize = 2;
/// Traversal keeps its stack of nodes to visit on the stack up to this many entries.
const STACK: usize = 64;
/// The `from` of a ray that leaves no primitive.
pub const NO_PRIMITIVE: u32 = u32::MAX;
/// Traversal remembers this many primitives last tested, not to test a segment's pieces' leaves again.
const RECENT: usize = 4;

thread_local! {
    /// The primitive that last blocked a shadow ray on this thread ([`Bvh::any_hit_from`]); an index beyond the
    /// hierarchy's primitives (another hierarchy's) is not tested.
    static LAST_OCCLUDER: std::cell::Cell<u32> = const { std::cell::Cell::new(NO_PRIMITIVE) };
}

#[derive(Clone, Copy, Debug)]
struct Node {
    min: Vec3,
    max: Vec3,
    /// First child (the second is `first + 1`) of an inner node, first entry of `order` (the build's list) of a
    /// leaf.
    first: u32,
    /// Segments in a leaf; 0 for an inner node.
    count: u32,
}

/// A leaf's entry: the primitive and, for a segment, its line as the leaf's first test reads it (an end, the axis
/// to the other end, the widest radius; all 0 for a triangle). One entry is half a cache line.
#[derive(Clone, Copy, Debug, Default)]
#[repr(C, align(32))]
struct Entry {
    a: Vec3,
    r: f32,
    axis: Vec3,
    primitive: u32,
}

/// A node of the four-wide hierarchy the queries walk: its children's boxes side by side, one lane each (Wald et
/// al. 2008, "Getting rid of packets": a binary tree collapsed into nodes whose four boxes a ray tests at once).
#[derive(Clone, Copy, Debug)]
#[repr(align(64))]
struct Node4 {
    min: [Vec4; 3],
    max: [Vec4; 3],
    /// Per lane: the child node, or the first of a leaf's `entries`.
    first: [u32; 4],
    /// Per lane: the primitives of a leaf; 0 for a child node, [`UNUSED`] for a lane not in use.
    count: [u32; 4],
}

/// The `count` of a lane a node does not use (which keeps a node two cache lines).
const UNUSED: u32 = u32::MAX;

/// The binary tree `nodes` (root first) as four-wide nodes (root first) and their depth: each node takes the
/// children of a binary node and opens the largest inner one among them until it has four.
fn collapse(nodes: &[Node]) -> (Vec<Node4>, usize) {
    let empty = Node4 {
        min: [Vec4::ZERO; 3],
        max: [Vec4::ZERO; 3],
        first: [0; 4],
        count: [UNUSED; 4],
    };
    let mut out = vec![empty];
    let mut depth = 0;
    let mut todo = vec![(0usize, 0usize, 0usize)];
    while let Some((b, o, level)) = todo.pop() {
        depth = depth.max(level);
        let node = nodes[b];
        let mut kids = if node.count > 0 {
            vec![b]
        } else {
            vec![node.first as usize, node.first as usize + 1]
        };
        while kids.len() < 4 {
            let area_of = |k: usize| {
                area(&Aabb {
                    min: nodes[k].min,
                    max: nodes[k].max,
                })
            };
            let Some(j) = (0..kids.len())
                .filter(|&j| nodes[kids[j]].count == 0)
                .max_by(|&i, &j| area_of(kids[i]).total_cmp(&area_of(kids[j])))
            else {
                break;
            };
            let k = kids.swap_remove(j);
            kids.extend([nodes[k].first as usize, nodes[k].first as usize + 1]);
        }
        let mut wide = empty;
        for (lane, &k) in kids.iter().enumerate() {
            for axis in 0..3 {
                wide.min[axis][lane] = nodes[k].min[axis];
                wide.max[axis][lane] = nodes[k].max[axis];
            }
            if nodes[k].count > 0 {
                (wide.first[lane], wide.count[lane]) = (nodes[k].first, nodes[k].count);
            } else {
                (wide.first[lane], wide.count[lane]) = (out.len() as u32, 0);
                todo.push((k, out.len(), level + 1));
                out.push(empty);
            }
        }
        out[o] = wide;
    }
    (out, depth)
}

/// The segments, the triangles (primitive `segments.len() + k` is triangle `k`) and their hierarchy.
#[derive(Clone, Debug)]
pub struct Bvh {
    segments: Vec<Segment>,
    triangles: Vec<Triangle>,
    nodes: Vec<Node4>,
    /// The leaves' primitives, leaf after leaf, each with its line side by side with the leaf's others, for a
    /// cheap first test that needs no other memory.
    entries: Vec<Entry>,
    /// The longest path from the root to a leaf, in edges.
    depth: usize,
}

fn area(b: &Aabb) -> f32 {
    if b.is_empty() {
        return 0.0;
    }
    let e = b.extent();
    e.x * e.y + e.y * e.z + e.z * e.x
}

/// The entry and exit distances of the ray from `o` (inverse direction `inv`, one axis a vector) through each of
/// `node`'s closed boxes, the entry no less than 0; a box is met where entry ≤ exit. The exit is grown by pbrt's
/// `1 + 2γ₃` so rounding never culls a box the ray touches. A ray parallel to an axis's planes (`inv` ±∞) whose
/// origin lies in one of them gives `0 × ∞ = NaN` there; it runs along the box's face all its length, so that
/// axis bounds nothing (where `min`/`max` would pass the NaN on, or drop the other bound, by operand order).
fn slab4(node: &Node4, o: [Vec4; 3], inv: [Vec4; 3]) -> (Vec4, Vec4) {
    let (mut near, mut far) = (Vec4::ZERO, Vec4::INFINITY);
    for axis in 0..3 {
        let t1 = (node.min[axis] - o[axis]) * inv[axis];
        let t2 = (node.max[axis] - o[axis]) * inv[axis];
        let in_plane = t1.is_nan_mask() | t2.is_nan_mask();
        near = near.max(Vec4::select(in_plane, Vec4::NEG_INFINITY, t1.min(t2)));
        far = far.min(Vec4::select(in_plane, Vec4::INFINITY, t1.max(t2)));
    }
    (near, far * (1.0 + 2.0 * 3.0 * f32::EPSILON))
}

/// [`slab4`] for a ray with no direction component 0 (`inv` finite, so no `0 × ∞`): per axis the plane met first
/// is known from the direction's sign (`back[axis]`: the ray runs towards −axis, meeting `max` first), which
/// spares the ordering of the two distances.
fn slab4_finite(node: &Node4, o: [Vec4; 3], inv: [Vec4; 3], back: [bool; 3]) -> (Vec4, Vec4) {
    let (mut near, mut far) = (Vec4::ZERO, Vec4::INFINITY);
    for axis in 0..3 {
        let (first, last) = if back[axis] {
            (node.max[axis], node.min[axis])
        } else {
            (node.min[axis], node.max[axis])
        };
        near = near.max((first - o[axis]) * inv[axis]);
        far = far.min((last - o[axis]) * inv[axis]);
    }
    (near, far * (1.0 + 2.0 * 3.0 * f32::EPSILON))
}

/// How many pieces of `s` to bound apart: the count, up to [`MAX_PIECES`], whose boxes' areas sum least (a
/// segment's box grows with the square of its length when it runs diagonally; pieces' boxes overlap at the
/// joints only by the radius).
fn pieces(s: &Segment) -> usize {
    let r = Vec3::splat(s.ra.max(s.rb));
    let d = (s.b - s.a).abs();
    let cost = |k: usize| {
        let e = d / k as f32 + 2.0 * r;
        k as f32 * (e.x * e.y + e.y * e.z + e.z * e.x)
    };
    (1..=MAX_PIECES).fold(1, |best, k| if cost(k) < cost(best) { k } else { best })
}

/// The boxes of [`pieces`]`(s)` pieces of `s`, each around its stretch of the axis grown by the larger end
/// radius (and a hair more, so rounding at the cuts leaves no gap).
fn piece_bounds(s: &Segment) -> impl Iterator<Item = Aabb> + use<> {
    let k = pieces(s);
    let (a, b) = (s.a, s.b);
    let pad = Vec3::splat(s.ra.max(s.rb) * (1.0 + 1e-3) + 1e-6 * (1.0 + a.abs().max(b.abs()).max_element()));
    (0..k).map(move |j| {
        let (p, q) = (
            a.lerp(b, j as f32 / k as f32),
            a.lerp(b, (j + 1) as f32 / k as f32),
        );
        Aabb {
            min: p.min(q) - pad,
            max: p.max(q) + pad,
        }
    })
}

impl Bvh {
    /// Builds the hierarchy over `segments` (their indices are the hits' `segment`).
    pub fn new(segments: Vec<Segment>) -> Bvh {
        Bvh::with_triangles(segments, Vec::new())
    }

    /// Builds the hierarchy over `segments` and `triangles`.
    pub fn with_triangles(segments: Vec<Segment>, triangles: Vec<Triangle>) -> Bvh {
        // References (primitive, box): a slanted segment enters as a few boxes along its length, which hug it
        // closer than one box around it.
        let n = segments.len();
        let refs: Vec<(u32, Aabb)> = segments
            .iter()
            .enumerate()
            .flat_map(|(i, s)| piece_bounds(s).map(move |b| (i as u32, b)))
            .chain(
                triangles
                    .iter()
                    .enumerate()
                    .map(|(k, t)| ((n + k) as u32, t.bounds())),
            )
            .collect();
        let bounds: Vec<Aabb> = refs.iter().map(|r| r.1).collect();
        let centres: Vec<Vec3> = bounds.iter().map(Aabb::center).collect();
        let mut order: Vec<u32> = (0..bounds.len() as u32).collect();
        let mut nodes = vec![Node {
            min: Vec3::ZERO,
            max: Vec3::ZERO,
            first: 0,
            count: 0,
        }];
        let mut stack = vec![(0usize, 0usize, order.len())];
        while let Some((node, first, count)) = stack.pop() {
            let items = &mut order[first..first + count];
            let b = items
                .iter()
                .fold(Aabb::EMPTY, |b, &i| b.union(bounds[i as usize]));
            nodes[node] = Node {
                min: b.min,
                max: b.max,
                first: first as u32,
                count: count as u32,
            };
            if count <= 1 {
                if let Some(i) = items.first_mut() {
                    *i = refs[*i as usize].0;
                }
                continue;
            }
            let cb = Aabb::from_points(items.iter().map(|&i| &centres[i as usize]));
            // Best (cost, axis, bin boundary) over the three axes.
            let mut best = (f32::MAX, 0, 0);
            for (axis, (lo, ext)) in cb
                .min
                .to_array()
                .into_iter()
                .zip(cb.extent().to_array())
                .enumerate()
            {
                if ext <= 0.0 {
                    continue;
                }
                let mut bins = [(Aabb::EMPTY, 0usize); BINS];
                for &i in items.iter() {
                    let k = (((centres[i as usize][axis] - lo) / ext * BINS as f32) as usize).min(BINS - 1);
                    bins[k] = (bins[k].0.union(bounds[i as usize]), bins[k].1 + 1);
                }
                let mut right = [(0.0f32, 0usize); BINS];
                let (mut rb, mut rn) = (Aabb::EMPTY, 0);
                for k in (1..BINS).rev() {
                    rb = rb.union(bins[k].0);
                    rn += bins[k].1;
                    right[k] = (area(&rb), rn);
                }
                let (mut lb, mut ln) = (Aabb::EMPTY, 0);
                for k in 1..BINS {
                    lb = lb.union(bins[k - 1].0);
                    ln += bins[k - 1].1;
                    let cost = area(&lb) * ln as f32 + right[k].0 * right[k].1 as f32;
                    if ln > 0 && right[k].1 > 0 && cost < best.0 {
                        best = (cost, axis, k);
                    }
                }
            }
            let leaf_cost = area(&b) * count as f32;
            if best.0 == f32::MAX || (best.0 + TRAVERSAL_COST * area(&b) >= leaf_cost && count <= MAX_LEAF) {
                if count <= MAX_LEAF {
                    // A leaf lists each primitive once, however many of its references it holds.
                    for i in items.iter_mut() {
                        *i = refs[*i as usize].0;
                    }
                    items.sort_unstable();
                    let mut unique = 0;
                    for j in 0..count {
                        if j == 0 || items[j] != items[unique - 1] {
                            items[unique] = items[j];
                            unique += 1;
                        }
                    }
                    nodes[node].count = unique as u32;
                } else {
                    // All centres coincide: halve the list.
                    let half = count / 2;
                    let child = nodes.len();
                    nodes.extend([nodes[node]; 2]);
                    nodes[node] = Node {
                        first: child as u32,
                        count: 0,
                        ..nodes[node]
                    };
                    stack.extend([(child, first, half), (child + 1, first + half, count - half)]);
                }
                continue;
            }
            let (axis, split) = (best.1, best.2);
            let (lo, ext) = (cb.min[axis], cb.extent()[axis]);
            let bin =
                |i: u32| (((centres[i as usize][axis] - lo) / ext * BINS as f32) as usize).min(BINS - 1);
            let mut left = 0;
            for j in 0..count {
                if bin(items[j]) < split {
                    items.swap(j, left);
                    left += 1;
                }
            }
            let child = nodes.len();
            nodes.extend([nodes[node]; 2]);
            nodes[node].count = 0;
            nodes[node].first = child as u32;
            stack.extend([(child, first, left), (child + 1, first + left, count - left)]);
        }
        let (nodes, depth) = if order.is_empty() {
            (Vec::new(), 0)
        } else {
            collapse(&nodes)
        };
        let entries = order
            .iter()
            .map(|&i| match segments.get(i as usize) {
                Some(s) => Entry {
                    a: s.a,
                    r: s.ra.max(s.rb),
                    axis: s.b - s.a,
                    primitive: i,
                },
                None => Entry {
                    primitive: i,
                    ..Entry::default()
                },
            })
            .collect();
        Bvh {
            segments,
            triangles,
            nodes,
            entries,
            depth,
        }
    }

    pub fn segments(&self) -> &[Segment] {
        &self.segments
    }

    pub fn triangle_count(&self) -> usize {
        self.triangles.len()
    }

    /// Whether primitive `i` is convex, so that a ray leaving its surface does not meet it again: a triangle, or
    /// a segment of one radius (a capsule); a tapered segment's cone meets its narrower end's sphere in a
    /// concave kink, where a ray leaving the surface may enter it again.
    fn convex(&self, i: u32) -> bool {
        self.segments.get(i as usize).is_none_or(|s| s.ra == s.rb)
    }

    /// Primitive `i`'s crossing with `t` in `(0, t_max)`, `segment` set to `i`, for a ray that [`misses_axis`]
    /// has not ruled out.
    fn intersect(&self, i: u32, ray: &Ray, t_max: f32) -> Option<Hit> {
        let n = self.segments.len();
        let hit = match self.segments.get(i as usize) {
            Some(s) => s.crossing(ray, 0.0, t_max),
            None => self.triangles[i as usize - n].intersect(ray, 0.0, t_max),
        };
        hit.map(|h| Hit { primitive: i, ..h })
    }

    /// Calls `visit` with each primitive of each leaf whose box the ray meets within `(0, t_max)`, nearest box
    /// first, but for primitive `from` and for segments the ray cannot meet within `t_max` ([`misses_axis`]); `visit`
    /// returns the new `t_max` (a shorter one prunes), or `None` to stop.
    fn traverse(&self, ray: &Ray, t_max: f32, from: u32, visit: impl FnMut(u32, f32) -> Option<f32>) {
        if self.nodes.is_empty() {
            return;
        }
        let from = if self.convex(from) { from } else { NO_PRIMITIVE };
        let inv = ray.dir.recip();
        if inv.is_finite() {
            let back = ray.dir.cmplt(Vec3::ZERO).into();
            self.walk(ray, t_max, from, visit, |node, o, inv| {
                slab4_finite(node, o, inv, back)
            });
        } else {
            self.walk(ray, t_max, from, visit, slab4);
        }
    }

    /// [`Self::traverse`] with the box test `slab`.
    fn walk(
        &self,
        ray: &Ray,
        mut t_max: f32,
        from: u32,
        mut visit: impl FnMut(u32, f32) -> Option<f32>,
        slab: impl Fn(&Node4, [Vec4; 3], [Vec4; 3]) -> (Vec4, Vec4),
    ) {
        let (o, inv) = (
            ray.origin.to_array().map(Vec4::splat),
            ray.dir.recip().to_array().map(Vec4::splat),
        );
        // Nodes and leaves still to visit, (first, count, entry distance); at most three per level besides the
        // one being visited.
        let mut fixed = [(0u32, 0u32, 0.0f32); STACK];
        let mut grown;
        let stack: &mut [(u32, u32, f32)] = if 3 * self.depth + 4 <= STACK {
            &mut fixed
        } else {
            grown = vec![(0u32, 0u32, 0.0f32); 3 * self.depth + 4];
            &mut grown
        };
        let mut top = 0;
        // The primitives last tested, a ring.
        let (mut recent, mut seen) = ([u32::MAX; RECENT], 0);
        // The node or leaf being visited, (first, count).
        let (mut first, mut count) = (0u32, 0u32);
        loop {
            if count > 0 {
                for e in &self.entries[first as usize..(first + count) as usize] {
                    // A segment in pieces may sit in several leaves: one met lately is not tested again (its
                    // crossing, if any, is already in, within a `t_max` no shorter than now).
                    let i = e.primitive;
                    if i == from || recent.contains(&i) {
                        continue;
                    }
                    recent[seen % RECENT] = i;
                    seen += 1;
                    if misses_axis(e.a, e.axis, e.r, ray, t_max) {
                        continue;
                    }
                    t_max = match visit(i, t_max) {
                        Some(t) => t,
                        None => return,
                    };
                }
            } else {
                let node = &self.nodes[first as usize];
                let (near, far) = slab(node, o, inv);
                let used = UVec4::from_array(node.count)
                    .cmpne(UVec4::splat(UNUSED))
                    .bitmask();
                let mut met = near.cmple(far.min(Vec4::splat(t_max))).bitmask() & used;
                if met != 0 {
                    // The lanes met onto the stack farthest first, then the nearest visited next.
                    let near = near.to_array();
                    let mut lanes = [(0.0f32, 0usize); 4];
                    let mut n = 0;
                    while met != 0 {
                        let lane = met.trailing_zeros() as usize;
                        met &= met - 1;
                        let mut j = n;
                        while j > 0 && lanes[j - 1].0 < near[lane] {
                            lanes[j] = lanes[j - 1];
                            j -= 1;
                        }
                        lanes[j] = (near[lane], lane);
                        n += 1;
                    }
                    for &(t, lane) in &lanes[..n - 1] {
                        stack[top] = (node.first[lane], node.count[lane], t);
                        top += 1;
                    }
                    let lane = lanes[n - 1].1;
                    (first, count) = (node.first[lane], node.count[lane]);
                    continue;
                }
            }
            // The next entry on the stack the ray can still reach.
            loop {
                if top == 0 {
                    return;
                }
                top -= 1;
                let (f, c, entry) = stack[top];
                if entry <= t_max {
                    (first, count) = (f, c);
                    break;
                }
            }
        }
    }

    /// The nearest fibre crossing within `(0, t_max)`.
    pub fn closest_hit(&self, ray: &Ray, t_max: f32) -> Option<Hit> {
        self.closest_hit_from(ray, t_max, NO_PRIMITIVE)
    }

    /// [`Self::closest_hit`] for a ray leaving primitive `from`'s surface, which is not tested where the ray
    /// cannot meet it again ([`Self::convex`]).
    pub fn closest_hit_from(&self, ray: &Ray, t_max: f32, from: u32) -> Option<Hit> {
        let mut best: Option<Hit> = None;
        self.traverse(ray, t_max, from, |i, t_max| {
            if let Some(h) = self.intersect(i, ray, t_max) {
                best = Some(h);
                return Some(h.t);
            }
            Some(t_max)
        });
        best
    }

    /// Whether any fibre crosses the ray within `(0, t_max)` (a shadow ray).
    pub fn any_hit(&self, ray: &Ray, t_max: f32) -> bool {
        self.any_hit_from(ray, t_max, NO_PRIMITIVE)
    }

    /// [`Self::any_hit`] for a ray leaving primitive `from` (as [`Self::closest_hit_from`]). The thread's last
    /// occluder is tested first: shadow rays from nearby points (a pixel's samples, neighbouring pixels) are
    /// mostly blocked by the same fibre. The answer is the walk's, which would test that primitive too.
    pub fn any_hit_from(&self, ray: &Ray, t_max: f32, from: u32) -> bool {
        let last = LAST_OCCLUDER.get();
        if last != from
            && (last as usize) < self.segments.len() + self.triangles.len()
            && self.intersect(last, ray, t_max).is_some()
        {
            return true;
        }
        let mut hit = false;
        self.traverse(ray, t_max, from, |i, t_max| {
            hit = self.intersect(i, ray, t_max).is_some();
            if hit {
                LAST_OCCLUDER.set(i);
            }
            (!hit).then_some(t_max)
        });
        hit
    }

    /// Whether a mesh triangle crosses the ray within `(0, t_max)` (a shadow ray the fibres do not block), for a
    /// ray leaving primitive `from` (as [`Self::closest_hit_from`]; [`NO_PRIMITIVE`] for none).
    pub fn any_mesh_hit_from(&self, ray: &Ray, t_max: f32, from: u32) -> bool {
        let n = self.segments.len() as u32;
        let mut hit = false;
        self.traverse(ray, t_max, from, |i, t_max| {
            hit = i >= n && self.intersect(i, ray, t_max).is_some();
            (!hit).then_some(t_max)
        });
        hit
    }

    /// Every primitive the ray crosses within `(0, t_max)`, each with its nearest crossing, in order of `t`.
    pub fn all_hits(&self, ray: &Ray, t_max: f32) -> Vec<Hit> {
        let mut hits = Vec::new();
        self.traverse(ray, t_max, NO_PRIMITIVE, |i, t_max| {
            if let Some(h) = self.intersect(i, ray, t_max) {
                hits.push(h);
            }
            Some(t_max)
        });
        // A segment bounded in pieces may sit in several leaves.
        hits.sort_by(|a, b| a.t.total_cmp(&b.t).then(a.primitive.cmp(&b.primitive)));
        hits.dedup_by_key(|h| h.primitive);
        hits
    }
}

#[cfg(test)]
mod tests;
