//! Picking geometry: the strand segment under a click in an image, the opaque surface in front of it, and the
//! light-map texel of the picked point. Pure geometry on the scene's strands and meshes, no UI.

use super::{Mesh, Strands};
use glam::{Mat4, UVec2, Vec2, Vec3, Vec4};

/// Texels around the picked one searched for the clicked segment's fragments: the rasteriser's line rule can put a
/// segment's fragment in a neighbour of the texel its clicked point projects to.
pub const PICK_SEARCH: i64 = 2;

/// A strand segment under a click: its id (the index of its first point, as the light passes number segments) and
/// the clicked point on it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pick {
    pub segment: u32,
    pub world: Vec3,
    /// Normalised device depth of the point (0 near, 1 far).
    pub ndc_depth: f32,
}

/// Clips the segment `(a, b)` (clip-space and world pairs) to `z >= 0` (the near plane of a 0..1 depth range).
fn clip_near(mut a: (Vec4, Vec3), mut b: (Vec4, Vec3)) -> Option<((Vec4, Vec3), (Vec4, Vec3))> {
    if a.0.z < 0.0 && b.0.z < 0.0 {
        return None;
    }
    let cut = |p: (Vec4, Vec3), q: (Vec4, Vec3)| {
        let t = p.0.z / (p.0.z - q.0.z);
        (p.0.lerp(q.0, t), p.1.lerp(q.1, t))
    };
    if a.0.z < 0.0 {
        a = cut(a, b);
    } else if b.0.z < 0.0 {
        b = cut(b, a);
    }
    (a.0.w > 0.0 && b.0.w > 0.0).then_some((a, b))
}

/// Pixel position (origin top left, y down) and NDC depth of a clip-space point in an image of `size` pixels.
pub fn to_pixels(c: Vec4, size: Vec2) -> (Vec2, f32) {
    let n = c.truncate() / c.w;
    (
        Vec2::new((n.x * 0.5 + 0.5) * size.x, (0.5 - n.y * 0.5) * size.y),
        n.z,
    )
}

/// The front-most strand segment within `radius` pixels of `cursor` (pixels, origin top left) in an image of
/// `size` pixels drawn with `world_to_clip`, nearer than `max_ndc_depth` (an opaque surface under the cursor),
/// and its point closest to the cursor.
pub fn pick_segment(
    strands: &Strands,
    world_to_clip: Mat4,
    size: Vec2,
    cursor: Vec2,
    radius: f32,
    max_ndc_depth: f32,
) -> Option<Pick> {
    let mut best: Option<Pick> = None;
    for (start, n) in strands.ranges() {
        for i in start..(start + n).saturating_sub(1) {
            let (wa, wb) = (strands.points[i], strands.points[i + 1]);
            let a = (world_to_clip * wa.extend(1.0), wa);
            let b = (world_to_clip * wb.extend(1.0), wb);
            let Some((a, b)) = clip_near(a, b) else { continue };
            let ((pa, za), (pb, zb)) = (to_pixels(a.0, size), to_pixels(b.0, size));
            let d = pb - pa;
            let t = if d.length_squared() > 0.0 {
                ((cursor - pa).dot(d) / d.length_squared()).clamp(0.0, 1.0)
            } else {
                0.0
            };
            if (pa + d * t).distance(cursor) > radius {
                continue;
            }
            // NDC depth is affine in screen space; the world point needs the perspective-correct parameter.
            let z = za + (zb - za) * t;
            if z > max_ndc_depth || best.is_some_and(|p| p.ndc_depth <= z) {
                continue;
            }
            let s = (t / b.0.w) / ((1.0 - t) / a.0.w + t / b.0.w);
            best = Some(Pick {
                segment: i as u32,
                world: a.1.lerp(b.1, s),
                ndc_depth: z,
            });
        }
    }
    best
}

/// NDC depth of the nearest opaque triangle under `cursor` (1 when none): strands behind it cannot be picked.
pub fn mesh_depth(meshes: &[Mesh], world_to_clip: Mat4, size: Vec2, cursor: Vec2) -> f32 {
    let inv = world_to_clip.inverse();
    let ndc = Vec2::new(cursor.x / size.x * 2.0 - 1.0, 1.0 - cursor.y / size.y * 2.0);
    let origin = inv.project_point3(ndc.extend(0.0));
    let dir = inv.project_point3(ndc.extend(1.0)) - origin;
    let mut nearest = f32::INFINITY;
    for m in meshes {
        for tri in m.indices.chunks_exact(3) {
            let [a, b, c] = [0, 1, 2].map(|k| m.positions.get(tri[k] as usize).copied());
            let (Some(a), Some(b), Some(c)) = (a, b, c) else {
                continue;
            };
            // Möller-Trumbore, both faces.
            let (e1, e2) = (b - a, c - a);
            let p = dir.cross(e2);
            let det = e1.dot(p);
            if det.abs() < 1e-12 {
                continue;
            }
            let s = origin - a;
            let u = s.dot(p) / det;
            let q = s.cross(e1);
            let v = dir.dot(q) / det;
            let t = e2.dot(q) / det;
            if u >= 0.0 && v >= 0.0 && u + v <= 1.0 && (0.0..nearest).contains(&t) {
                nearest = t;
            }
        }
    }
    if nearest.is_finite() {
        world_to_clip.project_point3(origin + dir * nearest).z
    } else {
        1.0
    }
}

/// The texel of world point `p` in a `resolution`² light map drawn with `world_to_clip` (`uv = (ndc.x * 0.5 +
/// 0.5, 0.5 - ndc.y * 0.5)`, texel `floor(uv * resolution)`); `None` outside the map.
pub fn light_texel(world_to_clip: Mat4, resolution: u32, p: Vec3) -> Option<[u32; 2]> {
    let c = world_to_clip * p.extend(1.0);
    if c.w <= 0.0 || resolution == 0 {
        return None;
    }
    let uv = Vec2::new(c.x / c.w * 0.5 + 0.5, 0.5 - c.y / c.w * 0.5);
    if !(0.0..1.0).contains(&uv.x) || !(0.0..1.0).contains(&uv.y) {
        return None;
    }
    let t = (uv * resolution as f32)
        .floor()
        .as_uvec2()
        .min(UVec2::splat(resolution - 1));
    Some([t.x, t.y])
}

/// The texel near `texel` (within [`PICK_SEARCH`]) of a `resolution`² map that holds a fragment of `segment`, the
/// nearest one first and then the one whose fragment depth is closest to `depth`; `texel` itself when none does.
/// `fragments` gives the `(segment, depth)` of each fragment of a texel.
pub fn resolve_pick<I>(
    resolution: u32,
    texel: [u32; 2],
    segment: u32,
    depth: f32,
    fragments: impl Fn([u32; 2]) -> I,
) -> [u32; 2]
where
    I: IntoIterator<Item = (u32, f32)>,
{
    let res = i64::from(resolution);
    let mut best: Option<((i64, f32), [u32; 2])> = None;
    for dy in -PICK_SEARCH..=PICK_SEARCH {
        for dx in -PICK_SEARCH..=PICK_SEARCH {
            let (x, y) = (i64::from(texel[0]) + dx, i64::from(texel[1]) + dy);
            if !(0..res).contains(&x) || !(0..res).contains(&y) {
                continue;
            }
            let at = [x as u32, y as u32];
            for (_, d) in fragments(at).into_iter().filter(|(s, _)| *s == segment) {
                let key = (dx.abs().max(dy.abs()), (d - depth).abs());
                if best.is_none_or(|(k, _)| key < k) {
                    best = Some((key, at));
                }
            }
        }
    }
    best.map_or(texel, |(_, t)| t)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::light_frame::LightFrame;

    /// A camera looking down -z with an orthographic projection: world (x, y) in [-1, 1]² fills the image, depth
    /// runs from z = -0.5 (NDC 0) to z = -4.5 (NDC 1).
    fn eye() -> Mat4 {
        Mat4::orthographic_rh(-1.0, 1.0, -1.0, 1.0, 0.5, 4.5)
    }

    fn strands(segments: &[[Vec3; 2]]) -> Strands {
        Strands {
            points: segments.iter().flatten().copied().collect(),
            counts: vec![2; segments.len()],
            ..Default::default()
        }
    }

    #[test]
    fn picks_the_front_segment_under_the_cursor_and_its_light_texel() {
        let size = Vec2::new(200.0, 100.0);
        // World (0.6, 0.6) is pixel ((0.6 * 0.5 + 0.5) * 200, (0.5 - 0.6 * 0.5) * 100) = (160, 20).
        let cursor = Vec2::new(160.0, 20.0);
        let s = strands(&[
            // Behind, crossing the cursor.
            [Vec3::new(-0.5, 0.6, -3.0), Vec3::new(0.9, 0.6, -3.0)],
            // In front, crossing the cursor: the one to pick (segment id = its first point, 2).
            [Vec3::new(0.6, -0.5, -1.0), Vec3::new(0.6, 0.9, -1.0)],
            // Nearer still, but 0.1 (10 pixels) to the left of the cursor.
            [Vec3::new(0.5, -0.5, -0.6), Vec3::new(0.5, 0.9, -0.6)],
        ]);
        let pick = pick_segment(&s, eye(), size, cursor, 4.0, 1.0).expect("a segment under the cursor");
        assert_eq!(pick.segment, 2);
        assert!(
            pick.world.distance(Vec3::new(0.6, 0.6, -1.0)) < 1e-5,
            "{}",
            pick.world
        );
        // An opaque surface in front of it (NDC depth 0.1) hides every strand.
        assert!(pick_segment(&s, eye(), size, cursor, 4.0, 0.1).is_none());
        // Nothing within 4 pixels of an empty corner.
        assert!(pick_segment(&s, eye(), size, Vec2::new(5.0, 95.0), 4.0, 1.0).is_none());

        // A light frame looking down -z from z = 0: uv = (x * 0.5 + 0.5, 0.5 - y * 0.5) = (0.8, 0.2), so on a
        // 4² map texel (3, 0); depth (1 - 0) / (2 - 0) = 0.5.
        let frame = LightFrame {
            world_to_view: Mat4::IDENTITY,
            view_to_clip: Mat4::orthographic_rh(-1.0, 1.0, -1.0, 1.0, 0.0, 2.0),
            near: 0.0,
            far: 2.0,
            position: Vec3::ZERO,
            to_light: Vec3::Z,
        };
        assert_eq!(light_texel(frame.world_to_clip(), 4, pick.world), Some([3, 0]));
        assert!((frame.depth(pick.world) - 0.5).abs() < 1e-6);
        assert_eq!(
            light_texel(frame.world_to_clip(), 4, Vec3::new(1.5, 0.0, -1.0)),
            None
        );
        assert_eq!(light_texel(frame.world_to_clip(), 0, pick.world), None);
    }

    #[test]
    fn perspective_pick_finds_the_point_under_the_cursor() {
        // A perspective camera: the picked world point projects back onto the cursor.
        let cam = Mat4::perspective_rh(0.8, 1.5, 0.1, 10.0)
            * Mat4::look_at_rh(Vec3::new(0.3, 0.2, 3.0), Vec3::ZERO, Vec3::Y);
        let size = Vec2::new(300.0, 200.0);
        let s = strands(&[[Vec3::new(-1.0, -0.4, 0.5), Vec3::new(1.0, 0.3, -1.5)]]);
        let target = Vec3::new(-1.0, -0.4, 0.5).lerp(Vec3::new(1.0, 0.3, -1.5), 0.3);
        let (cursor, _) = to_pixels(cam * target.extend(1.0), size);
        let pick = pick_segment(&s, cam, size, cursor, 1.0, 1.0).unwrap();
        assert!(pick.world.distance(target) < 1e-4, "{} vs {target}", pick.world);
    }

    #[test]
    fn mesh_in_front_blocks_picking() {
        let size = Vec2::new(100.0, 100.0);
        // A triangle at z = -1 covering the image centre.
        let mesh = Mesh {
            positions: vec![
                Vec3::new(-0.5, -0.5, -1.0),
                Vec3::new(0.5, -0.5, -1.0),
                Vec3::new(0.0, 0.5, -1.0),
            ],
            indices: vec![0, 1, 2],
            ..Default::default()
        };
        let d = mesh_depth(&[mesh], eye(), size, Vec2::new(50.0, 50.0));
        // z = -1 is 0.5 of the way into [0.5, 4.5]: NDC 0.125.
        assert!((d - 0.125).abs() < 1e-5, "{d}");
        assert_eq!(mesh_depth(&[], eye(), size, Vec2::new(50.0, 50.0)), 1.0);
    }

    #[test]
    fn resolve_pick_prefers_the_nearest_texel_then_the_closest_depth() {
        // A 6² map: segment 7 has fragments two texels right of (2, 2) at depth 0.5, one texel up at depth 0.9 and
        // one texel down-left at depth 0.31; segment 3 sits in (2, 2) itself.
        let fragments = |t: [u32; 2]| -> Vec<(u32, f32)> {
            match t {
                [4, 2] => vec![(7, 0.5)],
                [2, 1] => vec![(7, 0.9)],
                [1, 3] => vec![(3, 0.3), (7, 0.31)],
                [2, 2] => vec![(3, 0.3)],
                _ => Vec::new(),
            }
        };
        // Ring 1 beats an exact depth in ring 2; within ring 1 the depth closest to the clicked one wins.
        assert_eq!(resolve_pick(6, [2, 2], 7, 0.5, fragments), [1, 3]);
        assert_eq!(resolve_pick(6, [2, 2], 7, 0.8, fragments), [2, 1]);
        assert_eq!(resolve_pick(6, [0, 3], 3, 0.3, fragments), [1, 3]);
        // No fragment of the segment nearby: the texel itself; neighbours off the map are skipped.
        assert_eq!(resolve_pick(6, [0, 5], 9, 0.3, fragments), [0, 5]);
        assert_eq!(resolve_pick(6, [5, 0], 7, 0.5, fragments), [4, 2]);
    }
}
