//! A bounding volume hierarchy over fibre segments and mesh triangles: a top-down build binned by the surface area heuristic
//! (Wald 2007, "On fast construction of SAH-based bounding volume hierarchies": 16 bins on each axis over the
//! centroids), and stack traversal nearest child first. Written in-tree rather than taken from a crate: the
//! primitives are our own round fibres (`fibre.rs`), we need every hit along a ray besides the first, and the
//! whole of it is ~200 lines.

use glam::Vec3;

use super::fibre::{Hit, Ray, Segment};
use super::triangle::Triangle;
use crate::scene::Aabb;

const BINS: usize = 16;
/// A node holds at most this many segments as a leaf when a split would not pay.
const MAX_LEAF: usize = 8;
/// Traversal keeps its stack on the stack for trees up to this deep.
const STACK: usize = 64;

#[derive(Clone, Copy, Debug)]
struct Node {
    min: Vec3,
    max: Vec3,
    /// First child (the second is `first + 1`) of an inner node, first entry of `order` of a leaf.
    first: u32,
    /// Segments in a leaf; 0 for an inner node.
    count: u32,
}

/// The segments, the triangles (primitive `segments.len() + k` is triangle `k`) and their hierarchy.
#[derive(Clone, Debug)]
pub struct Bvh {
    segments: Vec<Segment>,
    triangles: Vec<Triangle>,
    nodes: Vec<Node>,
    order: Vec<u32>,
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

/// The entry distance of `ray` (inverse direction `inv`) into the box, if it meets it within `(0, t_max)`. The far
/// distance is grown by pbrt's `1 + 2γ₃` so rounding never culls a box the ray touches.
fn slab(min: Vec3, max: Vec3, ray: &Ray, inv: Vec3, t_max: f32) -> Option<f32> {
    let t1 = (min - ray.origin) * inv;
    let t2 = (max - ray.origin) * inv;
    let near = t1.min(t2).max_element().max(0.0);
    let far = t1.max(t2).min_element() * (1.0 + 2.0 * 3.0 * f32::EPSILON);
    (near <= far.min(t_max)).then_some(near)
}

impl Bvh {
    /// Builds the hierarchy over `segments` (their indices are the hits' `segment`).
    pub fn new(segments: Vec<Segment>) -> Bvh {
        Bvh::with_triangles(segments, Vec::new())
    }

    /// Builds the hierarchy over `segments` and `triangles`.
    pub fn with_triangles(segments: Vec<Segment>, triangles: Vec<Triangle>) -> Bvh {
        let bounds: Vec<Aabb> = segments
            .iter()
            .map(Segment::bounds)
            .chain(triangles.iter().map(Triangle::bounds))
            .collect();
        let centres: Vec<Vec3> = bounds.iter().map(Aabb::center).collect();
        let mut bvh = Bvh {
            order: (0..bounds.len() as u32).collect(),
            segments,
            triangles,
            nodes: Vec::new(),
            depth: 0,
        };
        bvh.nodes.push(Node {
            min: Vec3::ZERO,
            max: Vec3::ZERO,
            first: 0,
            count: 0,
        });
        let mut stack = vec![(0usize, 0usize, bvh.order.len(), 0usize)];
        while let Some((node, first, count, level)) = stack.pop() {
            bvh.depth = bvh.depth.max(level);
            let items = &mut bvh.order[first..first + count];
            let b = items
                .iter()
                .fold(Aabb::EMPTY, |b, &i| b.union(bounds[i as usize]));
            bvh.nodes[node] = Node {
                min: b.min,
                max: b.max,
                first: first as u32,
                count: count as u32,
            };
            if count <= 2 {
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
            if best.0 == f32::MAX || (best.0 >= leaf_cost && count <= MAX_LEAF) {
                if count > MAX_LEAF {
                    // All centres coincide: halve the list.
                    let half = count / 2;
                    let child = bvh.nodes.len();
                    bvh.nodes.extend([bvh.nodes[node]; 2]);
                    bvh.nodes[node] = Node {
                        first: child as u32,
                        count: 0,
                        ..bvh.nodes[node]
                    };
                    stack.extend([
                        (child, first, half, level + 1),
                        (child + 1, first + half, count - half, level + 1),
                    ]);
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
            let child = bvh.nodes.len();
            bvh.nodes.extend([bvh.nodes[node]; 2]);
            bvh.nodes[node].count = 0;
            bvh.nodes[node].first = child as u32;
            stack.extend([
                (child, first, left, level + 1),
                (child + 1, first + left, count - left, level + 1),
            ]);
        }
        bvh
    }

    pub fn segments(&self) -> &[Segment] {
        &self.segments
    }

    pub fn triangle_count(&self) -> usize {
        self.triangles.len()
    }

    /// Primitive `i`'s crossing with `t` in `(0, t_max)`, `segment` set to `i`.
    fn intersect(&self, i: u32, ray: &Ray, t_max: f32) -> Option<Hit> {
        let n = self.segments.len();
        let hit = match self.segments.get(i as usize) {
            Some(s) => s.intersect(ray, 0.0, t_max),
            None => self.triangles[i as usize - n].intersect(ray, 0.0, t_max),
        };
        hit.map(|h| Hit { segment: i, ..h })
    }

    /// Calls `visit` with each segment whose box the ray meets within `(0, t_max)`, nearest box first where
    /// cheap; `visit` returns the new `t_max` (a shorter one prunes), or `None` to stop.
    fn traverse(&self, ray: &Ray, mut t_max: f32, mut visit: impl FnMut(u32, f32) -> Option<f32>) {
        if self.order.is_empty() {
            return;
        }
        let inv = ray.dir.recip();
        // Nodes to visit with their entry distance; at most one per level besides the one being visited.
        let mut fixed = [(0u32, 0.0f32); STACK];
        let mut grown;
        let stack: &mut [(u32, f32)] = if self.depth < STACK {
            &mut fixed
        } else {
            grown = vec![(0u32, 0.0f32); self.depth + 1];
            &mut grown
        };
        let Some(entry) = slab(self.nodes[0].min, self.nodes[0].max, ray, inv, t_max) else {
            return;
        };
        stack[0] = (0, entry);
        let mut top = 1;
        while top > 0 {
            top -= 1;
            let (n, entry) = stack[top];
            if entry > t_max {
                continue;
            }
            let node = self.nodes[n as usize];
            if node.count > 0 {
                for &i in &self.order[node.first as usize..(node.first + node.count) as usize] {
                    t_max = match visit(i, t_max) {
                        Some(t) => t,
                        None => return,
                    };
                }
                continue;
            }
            let (l, r) = (node.first, node.first + 1);
            let near = |c: u32| {
                let c = self.nodes[c as usize];
                slab(c.min, c.max, ray, inv, t_max)
            };
            let mut push = |c: u32, t: f32| {
                stack[top] = (c, t);
                top += 1;
            };
            match (near(l), near(r)) {
                (Some(tl), Some(tr)) if tl <= tr => {
                    push(r, tr);
                    push(l, tl);
                }
                (Some(tl), Some(tr)) => {
                    push(l, tl);
                    push(r, tr);
                }
                (Some(tl), None) => push(l, tl),
                (None, Some(tr)) => push(r, tr),
                (None, None) => {}
            }
        }
    }

    /// The nearest fibre crossing within `(0, t_max)`.
    pub fn closest_hit(&self, ray: &Ray, t_max: f32) -> Option<Hit> {
        let mut best: Option<Hit> = None;
        self.traverse(ray, t_max, |i, t_max| {
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
        let mut hit = false;
        self.traverse(ray, t_max, |i, t_max| {
            hit = self.intersect(i, ray, t_max).is_some();
            (!hit).then_some(t_max)
        });
        hit
    }

    /// Every primitive the ray crosses within `(0, t_max)`, each with its nearest crossing, in order of `t`.
    pub fn all_hits(&self, ray: &Ray, t_max: f32) -> Vec<Hit> {
        let mut hits = Vec::new();
        self.traverse(ray, t_max, |i, t_max| {
            if let Some(h) = self.intersect(i, ray, t_max) {
                hits.push(h);
            }
            Some(t_max)
        });
        hits.sort_by(|a, b| a.t.total_cmp(&b.t));
        hits
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pathtrace::fibre::tests::random_segment;
    use crate::rng::SplitMix64;

    fn random_scene(rng: &mut SplitMix64, n: usize) -> Vec<Segment> {
        (0..n)
            .map(|_| {
                let mut s = random_segment(rng);
                s.ra *= 0.1;
                s.rb *= 0.1;
                s.b = s.a + (s.b - s.a) * 0.2;
                s
            })
            .collect()
    }

    fn random_ray(rng: &mut SplitMix64) -> Ray {
        let o = Vec3::new(rng.normal(), rng.normal(), rng.normal()) * 2.0;
        let target = Vec3::new(rng.normal(), rng.normal(), rng.normal()) * 0.4;
        Ray::new(o, target - o)
    }

    #[test]
    fn queries_equal_brute_force() {
        let mut rng = SplitMix64::new(7);
        let triangles = (0..300)
            .map(|_| {
                let mut v = || Vec3::new(rng.normal(), rng.normal(), rng.normal());
                Triangle {
                    p0: v() * 0.5,
                    e1: v() * 0.1,
                    e2: v() * 0.1,
                    albedo: Vec3::ONE,
                }
            })
            .collect();
        let bvh = Bvh::with_triangles(random_scene(&mut rng, 3000), triangles);
        let mut hits = 0;
        for _ in 0..3000 {
            let ray = random_ray(&mut rng);
            let t_max = rng.range(1.0, 6.0);
            let all: Vec<Hit> = (0..bvh.order.len() as u32)
                .filter_map(|i| bvh.intersect(i, &ray, t_max))
                .collect();
            let brute = all.iter().copied().reduce(|a, b| if b.t < a.t { b } else { a });
            let got = bvh.closest_hit(&ray, t_max);
            assert_eq!(got.map(|h| (h.segment, h.t)), brute.map(|h| (h.segment, h.t)));
            assert_eq!(bvh.any_hit(&ray, t_max), brute.is_some());
            let mut sorted = all.clone();
            sorted.sort_by(|a, b| a.t.total_cmp(&b.t));
            let listed = bvh.all_hits(&ray, t_max);
            assert_eq!(listed.len(), sorted.len());
            assert!(listed.iter().zip(&sorted).all(|(a, b)| a.t == b.t));
            hits += brute.is_some() as usize;
        }
        assert!(hits > 500, "only {hits} rays hit");
    }
}
