//! The hair as a density of fibres for the mesh-bounce probe (`shading::mesh_bounce`) under the fibres model: a
//! voxel grid over the strands of the mean number of fibres a ray crosses per unit length, as engines voxelise
//! their hair for the light that does not come from the light maps (Unreal's hair strands voxelise a
//! coverage-weighted hair count; docs/truth.md, "The fibres model"). A segment of length `L` and width `w` in a
//! cell of volume `U` adds `(π/4) w L / U`: a line crosses a fibre at angle `ψ` to it over the width
//! `w |sin ψ|`, and `π/4` is the mean of `|sin ψ|` over directions. A ray's count is the sum of the cells'
//! densities times the length it runs in them.

use glam::{UVec3, Vec3};

/// Cells a side of the grid.
pub const CELLS: usize = 24;

/// Fibres crossed per unit length, per cell, over a box around the strands.
#[derive(Clone, Debug, PartialEq)]
pub struct HairDensity {
    min: Vec3,
    /// The size of a cell.
    cell: Vec3,
    /// Cell `(x, y, z)` at `(z · CELLS + y) · CELLS + x`.
    density: Vec<f32>,
}

impl HairDensity {
    /// No hair: every ray crosses no fibre.
    pub fn empty() -> HairDensity {
        HairDensity {
            min: Vec3::ZERO,
            cell: Vec3::ONE,
            density: Vec::new(),
        }
    }

    /// The density of the strands `ranges` (`(first point, point count)` into `points`), the point `k`'s width
    /// `width(k)` (a segment takes the mean of its two points'). The box holds every point with half a cell to
    /// spare; a segment adds its share to the cells along it (split into pieces that move at most half a cell
    /// along each axis).
    pub fn from_strands(
        points: &[Vec3],
        ranges: impl Iterator<Item = (usize, usize)>,
        width: impl Fn(usize) -> f32,
    ) -> HairDensity {
        let finite = || points.iter().filter(|p| p.is_finite());
        let (lo, hi) = finite().fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), &p| {
            (lo.min(p), hi.max(p))
        });
        if lo.cmpgt(hi).any() {
            return HairDensity::empty();
        }
        let span = (hi - lo).max(Vec3::splat(1e-6));
        let cell = span / (CELLS as f32 - 1.0);
        let mut grid = HairDensity {
            min: lo - cell * 0.5,
            cell,
            density: vec![0.0; CELLS * CELLS * CELLS],
        };
        let volume = cell.x * cell.y * cell.z;
        for (first, count) in ranges {
            for k in first
                ..(first + count)
                    .saturating_sub(1)
                    .min(points.len().saturating_sub(1))
            {
                let (a, b) = (points[k], points[k + 1]);
                let length = a.distance(b);
                if !length.is_finite() || length <= 0.0 {
                    continue;
                }
                let w = 0.5 * (width(k) + width(k + 1)).max(0.0);
                let pieces = ((b - a).abs() / (cell * 0.5)).max_element().ceil().max(1.0) as usize;
                let share = std::f32::consts::FRAC_PI_4 * w * length / pieces as f32 / volume;
                for j in 0..pieces {
                    let p = a.lerp(b, (j as f32 + 0.5) / pieces as f32);
                    if let Some(c) = grid.cell_of(p) {
                        grid.density[c] += share;
                    }
                }
            }
        }
        grid
    }

    /// The index of the cell holding `p`, if any.
    fn cell_of(&self, p: Vec3) -> Option<usize> {
        let t = (p - self.min) / self.cell;
        if self.density.is_empty() || t.cmplt(Vec3::ZERO).any() || !t.is_finite() {
            return None;
        }
        let c = t.floor().as_uvec3();
        if c.cmpge(UVec3::splat(CELLS as u32)).any() {
            return None;
        }
        Some((c.z as usize * CELLS + c.y as usize) * CELLS + c.x as usize)
    }

    /// The mean number of fibres a ray from `origin` along the unit `dir` crosses before `max` (midpoint rule in
    /// steps of at most half a cell along each axis over the part of the ray inside the grid).
    pub fn crossed(&self, origin: Vec3, dir: Vec3, max: f32) -> f32 {
        self.march(origin, dir, max).count
    }

    /// What a ray from `origin` along the unit `dir` meets before `max`: [`Crossing::count`] as
    /// [`HairDensity::crossed`], and [`Crossing::depth`], the mean distance at which it first meets a fibre
    /// (each step's `e^(−N) ΔN` the weight, `N` the count before the step; 0 when it crosses none).
    pub fn march(&self, origin: Vec3, dir: Vec3, max: f32) -> Crossing {
        let none = Crossing {
            count: 0.0,
            depth: 0.0,
        };
        if self.density.is_empty() {
            return none;
        }
        let size = self.cell * CELLS as f32;
        let (mut near, mut far) = (0.0f32, max);
        for a in 0..3 {
            if dir[a].abs() < 1e-12 {
                if origin[a] < self.min[a] || origin[a] > self.min[a] + size[a] {
                    return none;
                }
                continue;
            }
            let t0 = (self.min[a] - origin[a]) / dir[a];
            let t1 = (self.min[a] + size[a] - origin[a]) / dir[a];
            near = near.max(t0.min(t1));
            far = far.min(t0.max(t1));
        }
        if !(near.is_finite() && far.is_finite()) || far <= near {
            return none;
        }
        let steps = ((far - near) * dir.abs() / (self.cell * 0.5))
            .max_element()
            .ceil()
            .max(1.0) as usize;
        let dt = (far - near) / steps as f32;
        let (mut count, mut weight, mut depth) = (0.0f32, 0.0f32, 0.0f32);
        for j in 0..steps {
            let t = near + (j as f32 + 0.5) * dt;
            let Some(c) = self.cell_of(origin + dir * t) else {
                continue;
            };
            let step = self.density[c] * dt;
            let w = (-count).exp() * step;
            weight += w;
            depth += w * t;
            count += step;
        }
        Crossing {
            count,
            depth: if weight > 0.0 { depth / weight } else { 0.0 },
        }
    }
}

/// What a ray meets in a [`HairDensity`] ([`HairDensity::march`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Crossing {
    /// The mean number of fibres crossed.
    pub count: f32,
    /// The mean distance along the ray at which it first meets a fibre.
    pub depth: f32,
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Rows a side of [`bundle`], their spacing and the fibres' width.
    const BUNDLE: (usize, f32, f32) = (40, 0.01, 0.002);

    /// The density of a square bundle of [`BUNDLE`]'s parallel fibres along x, from x = 0 to 0.4, its rows
    /// from y, z = 0.
    fn bundle() -> HairDensity {
        let (k, s, w) = BUNDLE;
        let mut points = Vec::new();
        for i in 0..k {
            for j in 0..k {
                let (y, z) = (i as f32 * s, j as f32 * s);
                points.extend([Vec3::new(0.0, y, z), Vec3::new(0.4, y, z)]);
            }
        }
        HairDensity::from_strands(&points, (0..k * k).map(|n| (2 * n, 2)), |_| w)
    }

    /// A square bundle of parallel fibres along x, `k` a side spaced `s` apart, of width `w`: rays across it at
    /// right angles to the fibres cross `(π/4) k w / s` on average over their offsets (a ray crosses a row with
    /// chance `w / s`, and `π/4` is the mean over directions), within 4 % over rays spread across the bundle's
    /// inside (a cell holds a whole number of rows, so one column alone may be off by a row); stopped halfway,
    /// half of it; a ray that misses the box, or stops before it, or starts nowhere (NaN), crosses none.
    #[test]
    fn a_bundle_of_parallel_fibres_gives_its_count() {
        let (k, s, w) = BUNDLE;
        let grid = bundle();
        let expected = std::f32::consts::FRAC_PI_4 * k as f32 * w / s;
        let rays = 100;
        let mean = |max: f32| {
            (0..rays)
                .map(|r| {
                    let y = 0.05 + 0.29 * (r as f32 + 0.5) / rays as f32;
                    grid.crossed(Vec3::new(0.2, y, -1.0), Vec3::Z, max)
                })
                .sum::<f32>()
                / rays as f32
        };
        let across = mean(10.0);
        assert!(
            (across - expected).abs() <= 0.04 * expected,
            "{across} vs {expected}"
        );
        let half = mean(1.0 + 0.5 * k as f32 * s);
        assert!((half - 0.5 * expected).abs() <= 0.04 * expected, "{half}");
        assert_eq!(grid.crossed(Vec3::new(0.2, 0.2, -1.0), Vec3::Z, 0.5), 0.0);
        assert_eq!(grid.crossed(Vec3::new(0.2, 5.0, -1.0), Vec3::Z, 10.0), 0.0);
        assert_eq!(HairDensity::empty().crossed(Vec3::ZERO, Vec3::Z, 1.0), 0.0);
        assert_eq!(grid.crossed(Vec3::splat(f32::NAN), Vec3::Z, 10.0), 0.0);
    }

    /// Where a ray first meets the bundle of the test above, on average: rows `s` apart own a slab from half a
    /// row before the first, `k s` thick, of density `ρ = (π/4) w / s²` per unit length (a count of
    /// `(π/4) k w / s`), so a ray from outside meets it at `1/ρ (1 − (1 + ρ k s) e^(−ρ k s)) / (1 − e^(−ρ k s))`
    /// past its face: within half a cell, as far as the voxels smear the face, averaged over rays; a ray
    /// that crosses no fibre has depth 0.
    #[test]
    fn a_ray_meets_the_bundle_where_its_fibres_begin() {
        let (k, s, w) = BUNDLE;
        let grid = bundle();
        let rho = std::f32::consts::FRAC_PI_4 * w / (s * s);
        let thick = rho * k as f32 * s;
        let face = 1.0 - 0.5 * s;
        let expected = face + (1.0 - (1.0 + thick) * (-thick).exp()) / (1.0 - (-thick).exp()) / rho;
        let rays = 100;
        let depth = (0..rays)
            .map(|r| {
                let y = 0.05 + 0.29 * (r as f32 + 0.5) / rays as f32;
                grid.march(Vec3::new(0.2, y, -1.0), Vec3::Z, 10.0).depth
            })
            .sum::<f32>()
            / rays as f32;
        assert!(
            (depth - expected).abs() <= 0.5 * grid.cell.z,
            "{depth} vs {expected} (cell {})",
            grid.cell.z
        );
        assert_eq!(grid.march(Vec3::new(0.2, 5.0, -1.0), Vec3::Z, 10.0).depth, 0.0);
    }

    /// The grid's total is the strands' `(π/4) Σ w L` whatever the segments' lengths; non-finite points add
    /// nothing.
    #[test]
    fn the_density_integrates_to_the_fibres_area() {
        let points = vec![
            Vec3::ZERO,
            Vec3::new(0.1, 0.2, 0.0),
            Vec3::new(0.3, 0.2, 0.1),
            Vec3::new(f32::NAN, 0.0, 0.0),
            Vec3::new(0.0, 0.3, 0.3),
            Vec3::new(0.05, 0.31, 0.3),
        ];
        let grid =
            HairDensity::from_strands(&points, [(0, 4), (4, 2)].into_iter(), |k| 0.001 * (k + 1) as f32);
        let volume = grid.cell.x * grid.cell.y * grid.cell.z;
        let total: f32 = grid.density.iter().sum::<f32>() * volume;
        let seg = |a: usize, b: usize| points[a].distance(points[b]) * 0.001 * (a + b + 2) as f32 * 0.5;
        let expected = std::f32::consts::FRAC_PI_4 * (seg(0, 1) + seg(1, 2) + seg(4, 5));
        assert!(
            (total - expected).abs() <= 1e-4 * expected,
            "{total} vs {expected}"
        );
    }
}
