//! The compute rasteriser's coverage rule, written down: the CPU model `shaders/common/raster_coverage.wgsl`
//! follows operation for operation (the `compute_raster` tests check GPU = CPU fragment for fragment).
//!
//! The rule is the major-axis rule of hardware lines (the "diamond-exit" lines of Direct3D and Vulkan cover one
//! pixel per column or row crossed along the major axis): a segment from `a` to `b` in texel space (x right,
//! y down, texel `(i, j)` spans `[i, i + 1) × [j, j + 1)`) covers, for every texel centre line `u = i + 0.5` of
//! its major axis (the axis of the larger extent; x on a tie) that it crosses at `t = (i + 0.5 − a_u) / (b_u −
//! a_u)` with `0 ≤ t < 1`, the texel `(i, floor(a_v + t · (b_v − a_v)))` on the minor axis. Half-open at `b`, so
//! consecutive segments of a strand never cover the centre line of a shared point twice; a segment crossing no
//! centre line (inside one texel, or parallel to the minor axis) covers nothing. Depth and alpha are the
//! endpoints' (`light_depth`, `strand_alpha` over one texel at the point's depth, as the `lines` caster's vertex
//! stage computes them) interpolated linearly in `t`; the segment id is its first point. Fragments come in
//! segment order, each segment's from `a` to `b`. A segment with an endpoint at or behind the light's plane
//! (clip w ≤ 0) covers nothing; depth is not clipped (the hair frame is fitted to the strands).
//! After the compute strand rasterisers of Unreal Engine 5 (`HairStrandsVisibilityRasterCompute`) and Frostbite
//! (Tafuri 2019; `docs/citations.md`), reduced to the light-fragment contract.

use crate::render::geometry::HairVertex;
use crate::render::uniforms::FrameUniforms;
use bytemuck::{Pod, Zeroable};
use glam::{Mat4, Vec2, Vec3, Vec4};

/// One fragment of the stream (`RasterFragment` in `shaders/common/raster_stream.wgsl`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct RasterFragment {
    /// Row-major light texel.
    pub texel: u32,
    /// Normalised light depth.
    pub depth: f32,
    pub alpha: f32,
    /// The segment's first point.
    pub segment: u32,
}

/// [`RasterFragment`]'s field names and byte offsets, in declaration order, for the layout test.
pub const RASTER_FRAGMENT_FIELDS: &[(&str, usize)] = {
    use std::mem::offset_of;
    &[
        ("texel", offset_of!(RasterFragment, texel)),
        ("depth", offset_of!(RasterFragment, depth)),
        ("alpha", offset_of!(RasterFragment, alpha)),
        ("segment", offset_of!(RasterFragment, segment)),
    ]
};

/// The texels a segment from `a` to `b` (texel space) covers under the rule, in order from `a`, each with its
/// `t` along the segment, on a `resolution`² map.
pub fn cover(a: Vec2, b: Vec2, resolution: u32) -> Vec<((u32, u32), f32)> {
    let d = b - a;
    let major_y = d.y.abs() > d.x.abs();
    let (au, av, bu, bv) = if major_y {
        (a.y, a.x, b.y, b.x)
    } else {
        (a.x, a.y, b.x, b.y)
    };
    let (du, dv) = (bu - au, bv - av);
    let res = resolution as f32;
    let lo = (au.min(bu) - 0.5).floor().max(0.0);
    let hi = (au.max(bu) - 0.5).ceil().min(res - 1.0);
    let mut out = Vec::new();
    if du == 0.0 || lo > hi {
        return out;
    }
    let n = (hi - lo) as u32 + 1;
    for m in 0..n {
        let iu = if du < 0.0 { hi - m as f32 } else { lo + m as f32 };
        let t = (iu + 0.5 - au) / du;
        if !(0.0..1.0).contains(&t) {
            continue;
        }
        let jv = (av + t * dv).floor();
        if !(0.0..res).contains(&jv) {
            continue;
        }
        let (x, y) = if major_y { (jv, iu) } else { (iu, jv) };
        out.push(((x as u32, y as u32), t));
    }
    out
}

/// What the rule reads of a frame: [`FrameUniforms`]' light frame and alpha inputs.
struct Frame<'a>(&'a FrameUniforms);

impl Frame<'_> {
    fn clip(&self, p: Vec3) -> Vec4 {
        Mat4::from_cols_array_2d(&self.0.world_to_light_clip) * p.extend(1.0)
    }

    /// `light_depth` of `shaders/common/frame.wgsl`.
    fn depth(&self, p: Vec3) -> f32 {
        let view = Mat4::from_cols_array_2d(&self.0.world_to_light_view) * p.extend(1.0);
        (-view.z - self.0.light_near) / (self.0.light_far - self.0.light_near)
    }

    /// `strand_alpha(…)` of `shaders/common/frame.wgsl`: what a light fragment stores.
    fn alpha(&self, point_alpha: f32, thickness: f32, footprint: f32) -> f32 {
        let u = self.0;
        if u.alpha_mode == 0 {
            (point_alpha * u.hair_alpha).clamp(0.0, 1.0)
        } else {
            let width = thickness * u.strand_width;
            let coverage = (u.hair_alpha * width / footprint.max(1e-30)).clamp(0.0, 1.0);
            coverage * point_alpha.clamp(0.0, 1.0)
        }
    }
}

/// Texel-space position of clip-space `c` on a `res`-texel map (x right, y down).
fn texel_space(c: Vec4, res: f32) -> Vec2 {
    let ndc = Vec2::new(c.x, c.y) / c.w;
    Vec2::new((ndc.x * 0.5 + 0.5) * res, (0.5 - ndc.y * 0.5) * res)
}

/// The fragment stream of the strands `points`/`segments` (one index pair per segment) under the light frame
/// of `u`: the CPU model of the compute rasteriser.
pub fn rasterise(u: &FrameUniforms, points: &[HairVertex], segments: &[u32]) -> Vec<RasterFragment> {
    let f = Frame(u);
    let res = u.light_map_resolution;
    let mut out = Vec::new();
    for pair in segments.chunks_exact(2) {
        let (p0, p1) = (&points[pair[0] as usize], &points[pair[1] as usize]);
        let (w0, w1) = (Vec3::from(p0.position), Vec3::from(p1.position));
        let (c0, c1) = (f.clip(w0), f.clip(w1));
        if !(c0.w > 0.0 && c1.w > 0.0) {
            continue;
        }
        let (d0, d1) = (f.depth(w0), f.depth(w1));
        let a0 = f.alpha(p0.alpha, p0.thickness, u.light_footprint * c0.w);
        let a1 = f.alpha(p1.alpha, p1.thickness, u.light_footprint * c1.w);
        let a = texel_space(c0, res as f32);
        let b = texel_space(c1, res as f32);
        for ((x, y), t) in cover(a, b, res) {
            out.push(RasterFragment {
                texel: y * res + x,
                depth: d0 + t * (d1 - d0),
                alpha: a0 + t * (a1 - a0),
                segment: pair[0],
            });
        }
    }
    out
}

/// The CPU model of the binning (`render.raster_tile` = `tile`): per `tile`-texel tile of a `resolution`² map
/// (row-major), the segments (first points) with a fragment of `stream` in it, each once, in stream order.
pub fn tile_lists(stream: &[RasterFragment], resolution: u32, tile: u32) -> Vec<Vec<u32>> {
    let across = resolution.div_ceil(tile);
    let mut lists = vec![Vec::new(); (across * across) as usize];
    for f in stream {
        let (x, y) = (f.texel % resolution, f.texel / resolution);
        let list: &mut Vec<u32> = &mut lists[((y / tile) * across + x / tile) as usize];
        if !list.contains(&f.segment) {
            list.push(f.segment);
        }
    }
    lists
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Row 2 from x = 1.2 to 9.7 on a 10² map in 4-texel tiles (3 across, the last 2 texels wide): columns 1..=9
    /// fall in tiles 0, 1 and 2 of the first row, the segment listed once in each; a second segment inside tile
    /// 4 (texel (5, 5)) is listed there alone.
    #[test]
    fn tile_lists_hold_each_segment_once_per_tile_it_covers() {
        let fragment = |(x, y): (u32, u32), segment| RasterFragment {
            texel: y * 10 + x,
            segment,
            ..Default::default()
        };
        let mut stream: Vec<RasterFragment> = cover(Vec2::new(1.2, 2.5), Vec2::new(9.7, 2.5), 10)
            .into_iter()
            .map(|(texel, _)| fragment(texel, 7))
            .collect();
        assert_eq!(stream.len(), 9);
        stream.push(fragment((5, 5), 9));
        let lists = tile_lists(&stream, 10, 4);
        let mut expected = vec![Vec::<u32>::new(); 9];
        expected[0] = vec![7];
        expected[1] = vec![7];
        expected[2] = vec![7];
        expected[4] = vec![9];
        assert_eq!(lists, expected);
    }

    fn texels(a: (f32, f32), b: (f32, f32)) -> Vec<(u32, u32)> {
        cover(Vec2::from(a), Vec2::from(b), 8)
            .into_iter()
            .map(|(t, _)| t)
            .collect()
    }

    /// Column centres 1.5, 2.5, 3.5, 4.5 lie in [1.2, 4.7): four texels of row 2, the first at t = 0.3 / 3.5.
    #[test]
    fn horizontal_segment_covers_one_texel_per_column_crossed() {
        let c = cover(Vec2::new(1.2, 2.5), Vec2::new(4.7, 2.5), 8);
        let got: Vec<(u32, u32)> = c.iter().map(|(t, _)| *t).collect();
        assert_eq!(got, [(1, 2), (2, 2), (3, 2), (4, 2)]);
        assert!((c[0].1 - 0.3 / 3.5).abs() < 1e-6);
    }

    /// Upwards along column 5 from y = 6.9 to 3.1: row centres 6.5, 5.5, 4.5, 3.5 in (3.1, 6.9], from a.
    #[test]
    fn vertical_segment_covers_rows_in_its_direction() {
        assert_eq!(texels((5.5, 6.9), (5.5, 3.1)), [(5, 6), (5, 5), (5, 4), (5, 3)]);
    }

    /// (0.5, 0.2) to (3.5, 2.0): x is major; centres 0.5, 1.5, 2.5 at t = 0, 1/3, 2/3 meet y = 0.2, 0.8, 1.4.
    #[test]
    fn diagonal_segment_takes_the_row_at_each_column_centre() {
        assert_eq!(texels((0.5, 0.2), (3.5, 2.0)), [(0, 0), (1, 0), (2, 1)]);
    }

    /// Inside texel (3, 3): crossing the row centre 3.5 (y major) covers it once; crossing no centre line covers
    /// nothing.
    #[test]
    fn segment_inside_one_texel() {
        assert_eq!(texels((3.1, 3.2), (3.4, 3.7)), [(3, 3)]);
        assert_eq!(texels((3.1, 3.6), (3.3, 3.9)), Vec::new());
        assert_eq!(texels((3.5, 3.5), (3.5, 3.5)), Vec::new());
    }

    /// A strand through (2.5, 1.5), a texel centre: the first segment stops before it, the second starts on it,
    /// so texel (2, 1) is covered once; the same the other way round.
    #[test]
    fn shared_endpoints_are_not_covered_twice() {
        let forward = [texels((0.2, 1.5), (2.5, 1.5)), texels((2.5, 1.5), (4.8, 1.5))];
        assert_eq!(forward, [vec![(0, 1), (1, 1)], vec![(2, 1), (3, 1), (4, 1)]]);
        let back = [texels((4.8, 1.5), (2.5, 1.5)), texels((2.5, 1.5), (0.2, 1.5))];
        assert_eq!(back, [vec![(4, 1), (3, 1)], vec![(2, 1), (1, 1), (0, 1)]]);
    }

    /// Outside the map nothing is covered; a segment leaving it is cut at the edge.
    #[test]
    fn the_map_edge_cuts_segments() {
        assert_eq!(texels((-3.0, 2.5), (1.7, 2.5)), [(0, 2), (1, 2)]);
        assert_eq!(texels((9.0, 2.5), (12.0, 2.5)), Vec::new());
        assert_eq!(texels((2.5, 7.2), (2.6, 9.0)), [(2, 7)]);
    }
}
