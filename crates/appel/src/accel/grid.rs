//! Uniform grid (Fujimoto et al. 1986) traversed by 3D DDA (Amanatides & Woo 1987, "A fast voxel
//! traversal algorithm for ray tracing").
//!
//! About `density * N` cells, shaped to the aspect of the scene bounds; each primitive is listed in
//! every cell its bounds overlap and, where the primitive can tell ([`Primitives::clip_overlaps`], the
//! Akenine-Moller triangle/box test for triangles), that it really touches. Cells are stored in CSR
//! form: `offsets[c]..offsets[c + 1]` is cell `c`'s range of the flat `items` list.

use super::{test_primitive, AccelStats, BadOption, Hit, Primitives, Structure, TraversalStats};
use crate::math::{far_scale, Aabb, Ray, RayBox, Vec3};
use rayon::prelude::*;
use std::sync::atomic::{AtomicU32, Ordering};

/// `[render.grid]`.
#[derive(Clone, Copy, Debug, PartialEq, serde::Deserialize, serde::Serialize)]
#[serde(default, deny_unknown_fields)]
pub struct GridOptions {
    /// Cells per primitive (Cleary & Wyvill 1988 and pbrt-v1 use a few per primitive; 27 = 3^3 means
    /// about 3 cells per primitive along each axis of a cubical scene).
    pub density: f32,
    /// Upper bound on the total number of cells, which bounds the memory of the offsets array.
    pub max_cells: usize,
}

impl Default for GridOptions {
    fn default() -> Self {
        Self {
            density: 27.0,
            max_cells: 1 << 25,
        }
    }
}

#[derive(Clone, Debug, Default)]
pub struct Grid {
    bounds: Aabb,
    res: [u32; 3],
    cell: Vec3,
    inv_cell: Vec3,
    /// CSR: cell `c` holds `items[offsets[c]..offsets[c + 1]]`.
    offsets: Vec<u32>,
    items: Vec<u32>,
    primitives: usize,
}

/// Direct-mapped mailbox (Amanatides & Woo 1987 store a ray id per primitive; that is shared mutable
/// state, so each ray keeps its own small table of recently tested ids instead). A collision only
/// causes a repeated test, never a skipped one.
const MAILBOX: usize = 32;

impl Grid {
    pub fn build<P: Primitives>(prims: &P) -> Self {
        Self::build_with(prims, GridOptions::default())
    }

    pub fn build_with<P: Primitives>(prims: &P, opts: GridOptions) -> Self {
        let n = prims.count();
        let bounds: Vec<Aabb> = (0..n).into_par_iter().map(|i| prims.bounds(i)).collect();
        let scene = bounds.iter().fold(Aabb::EMPTY, |a, &b| a.union(b));
        if n == 0 || scene.is_empty() {
            return Self {
                bounds: Aabb::EMPTY,
                offsets: vec![0],
                primitives: n,
                ..Default::default()
            };
        }
        let e = scene.extent();
        let max_e = e.max_element();
        let target = (opts.density.max(0.0) as f64 * n as f64).clamp(1.0, opts.max_cells as f64);
        // Cells per unit length so that a cube of side max_e would hold `target` cells; flatter
        // bounds get proportionally fewer cells along their thin axes.
        let per_unit = if max_e > 0.0 {
            target.cbrt() / max_e as f64
        } else {
            0.0
        };
        let mut res = [0u32; 3];
        for a in 0..3 {
            res[a] = ((e[a] as f64 * per_unit).round() as u32).clamp(1, 4096);
        }
        // Rounding up axes can overshoot the cap; shrink the largest axis until it fits.
        while res.iter().map(|&r| r as usize).product::<usize>() > opts.max_cells.max(1) {
            let a = (0..3).max_by_key(|&a| res[a]).unwrap();
            res[a] = (res[a] * 7 / 8).max(1);
        }
        let cell = Vec3::new(
            e.x / res[0] as f32,
            e.y / res[1] as f32,
            e.z / res[2] as f32,
        );
        let inv_cell = Vec3::select(cell.cmpgt(Vec3::ZERO), cell.recip(), Vec3::ZERO);
        let mut g = Self {
            bounds: scene,
            res,
            cell,
            inv_cell,
            offsets: Vec::new(),
            items: Vec::new(),
            primitives: n,
        };
        // Primitives are inserted with a small margin, so that a ray whose DDA rounding puts a point
        // near a cell face into the neighbouring cell still finds the primitive there: a fraction of
        // a cell, plus a few ulps of the largest coordinate.
        let scale = scene.min.abs().max(scene.max.abs()).max_element();
        let margin = cell * 1e-3 + Vec3::splat(scale * 8.0 * f32::EPSILON);
        let cells = g.cell_count();
        let counts: Vec<AtomicU32> = (0..cells).map(|_| AtomicU32::new(0)).collect();
        (0..n).into_par_iter().for_each(|i| {
            g.for_each_cell(prims, i, &bounds[i], margin, |c| {
                counts[c].fetch_add(1, Ordering::Relaxed);
            })
        });
        let mut offsets = Vec::with_capacity(cells + 1);
        let mut total = 0u64;
        offsets.push(0u32);
        for c in &counts {
            total += c.load(Ordering::Relaxed) as u64;
            assert!(total < u32::MAX as u64, "grid has more than 2^32 entries");
            offsets.push(total as u32);
        }
        // Reuse the counters as insertion cursors.
        counts
            .par_iter()
            .zip(offsets.par_iter())
            .for_each(|(c, &o)| c.store(o, Ordering::Relaxed));
        let items: Vec<AtomicU32> = (0..total).map(|_| AtomicU32::new(0)).collect();
        (0..n).into_par_iter().for_each(|i| {
            g.for_each_cell(prims, i, &bounds[i], margin, |c| {
                let at = counts[c].fetch_add(1, Ordering::Relaxed);
                items[at as usize].store(i as u32, Ordering::Relaxed);
            })
        });
        let mut items: Vec<u32> = items.into_iter().map(AtomicU32::into_inner).collect();
        // Parallel insertion leaves each cell in arbitrary order; sorting makes the grid, and so exact
        // ties between primitives, deterministic.
        let mut rest: &mut [u32] = &mut items;
        let mut slices = Vec::with_capacity(cells);
        for w in offsets.windows(2) {
            let (a, b) = std::mem::take(&mut rest).split_at_mut((w[1] - w[0]) as usize);
            slices.push(a);
            rest = b;
        }
        slices.par_iter_mut().for_each(|s| s.sort_unstable());
        g.offsets = offsets;
        g.items = items;
        g
    }

    fn cell_count(&self) -> usize {
        self.res.iter().map(|&r| r as usize).product()
    }

    #[inline]
    fn cell_index(&self, c: [u32; 3]) -> usize {
        (c[2] as usize * self.res[1] as usize + c[1] as usize) * self.res[0] as usize
            + c[0] as usize
    }

    /// The cell coordinate of `x` on `axis`, clamped to the grid.
    #[inline]
    fn coord(&self, x: f32, axis: usize) -> u32 {
        let f = ((x - self.bounds.min[axis]) * self.inv_cell[axis]).floor();
        // `as` saturates, and maps NaN to 0.
        (f.max(0.0) as u32).min(self.res[axis] - 1)
    }

    fn cell_bounds(&self, c: [u32; 3]) -> Aabb {
        let lo = self.bounds.min + Vec3::new(c[0] as f32, c[1] as f32, c[2] as f32) * self.cell;
        Aabb::new(lo, lo + self.cell)
    }

    fn for_each_cell<P: Primitives>(
        &self,
        prims: &P,
        i: usize,
        b: &Aabb,
        margin: Vec3,
        mut f: impl FnMut(usize),
    ) {
        if b.is_empty() {
            return;
        }
        let lo: [u32; 3] = std::array::from_fn(|a| self.coord(b.min[a] - margin[a], a));
        let hi: [u32; 3] = std::array::from_fn(|a| self.coord(b.max[a] + margin[a], a));
        let whole = lo.iter().zip(&hi).all(|(l, h)| l == h);
        for z in lo[2]..=hi[2] {
            for y in lo[1]..=hi[1] {
                for x in lo[0]..=hi[0] {
                    let c = [x, y, z];
                    // A primitive inside one cell needs no overlap test.
                    let cb = self.cell_bounds(c);
                    let grown = Aabb::new(cb.min - margin, cb.max + margin);
                    if whole || prims.clip_overlaps(i, &grown) {
                        f(self.cell_index(c));
                    }
                }
            }
        }
    }

    /// Walks the cells the ray crosses, front to back.
    #[inline]
    fn traverse<P: Primitives, const ANY: bool>(
        &self,
        prims: &P,
        ray: &Ray,
        mut t_max: f32,
        stats: &mut TraversalStats,
    ) -> Option<Hit> {
        stats.rays += 1;
        if self.items.is_empty() {
            return None;
        }
        let rb = RayBox::new(ray);
        let (t0, _) =
            self.bounds
                .slab_intersect(ray, Vec3::from(rb.inv), t_max * far_scale())?;
        let p = ray.at(t0);
        let mut c: [u32; 3] = std::array::from_fn(|a| self.coord(p[a], a));
        // Per axis: the direction of stepping (0 for a zero component, which never steps), and the
        // index where the ray leaves the grid.
        let step: [i32; 3] = std::array::from_fn(|a| {
            if ray.dir[a] > 0.0 {
                1
            } else if ray.dir[a] < 0.0 {
                -1
            } else {
                0
            }
        });
        // The t at which the ray crosses the next cell face on each axis, recomputed from the face
        // position at every step rather than accumulated, so the error does not grow along the ray.
        let next = |c: u32, a: usize| -> f32 {
            match step[a] {
                0 => f32::INFINITY,
                s => {
                    let face = c + (s > 0) as u32;
                    let x = self.bounds.min[a] + face as f32 * self.cell[a];
                    (x - rb.o[a]) * rb.inv[a]
                }
            }
        };
        let mut t_next = [next(c[0], 0), next(c[1], 1), next(c[2], 2)];
        let mut mail = [u32::MAX; MAILBOX];
        let mut best = None;
        loop {
            stats.nodes_visited += 1;
            let cell = self.cell_index(c);
            let (lo, hi) = (self.offsets[cell] as usize, self.offsets[cell + 1] as usize);
            for &p in &self.items[lo..hi] {
                let slot = (p as usize).wrapping_mul(0x9E37_79B9) >> 27 & (MAILBOX - 1);
                if mail[slot] == p {
                    continue;
                }
                mail[slot] = p;
                stats.prim_tests += 1;
                if let Some(h) = test_primitive::<P, ANY>(prims, p as usize, ray, t_max, stats) {
                    best = Some(Hit::new(p as usize, h));
                    if ANY {
                        return best;
                    }
                    t_max = h.t;
                }
            }
            let a = if t_next[0] < t_next[1] {
                if t_next[0] < t_next[2] {
                    0
                } else {
                    2
                }
            } else if t_next[1] < t_next[2] {
                1
            } else {
                2
            };
            // A hit found in this cell may lie beyond it (the primitive reaches into later cells),
            // and a primitive in a later cell could then be nearer: the closest hit is final only
            // once it lies within the cells walked so far, i.e. before this cell's exit. Hits are
            // kept as candidates rather than discarded, which is what makes the mailbox correct: a
            // primitive tested once never needs testing again for this ray.
            if t_max <= t_next[a] {
                return best;
            }
            let nc = c[a] as i64 + step[a] as i64;
            if step[a] == 0 || nc < 0 || nc >= self.res[a] as i64 {
                return best;
            }
            c[a] = nc as u32;
            t_next[a] = next(c[a], a);
        }
    }

    #[inline]
    pub fn intersect<P: Primitives>(
        &self,
        prims: &P,
        ray: &Ray,
        t_max: f32,
        stats: &mut TraversalStats,
    ) -> Option<Hit> {
        self.traverse::<P, false>(prims, ray, t_max, stats)
    }

    #[inline]
    pub fn occluded<P: Primitives>(
        &self,
        prims: &P,
        ray: &Ray,
        t_max: f32,
        stats: &mut TraversalStats,
    ) -> bool {
        self.traverse::<P, true>(prims, ray, t_max, stats).is_some()
    }

    pub fn resolution(&self) -> [u32; 3] {
        self.res
    }

    pub fn stats(&self) -> AccelStats {
        let cells = self.offsets.len().saturating_sub(1);
        AccelStats {
            name: Self::NAME,
            primitives: self.primitives,
            bytes: (self.offsets.len() + self.items.len()) * std::mem::size_of::<u32>(),
            nodes: cells,
            leaves: self.offsets.windows(2).filter(|w| w[1] > w[0]).count(),
            depth: 0,
            ..Default::default()
        }
    }
}

impl Structure for Grid {
    const NAME: &'static str = "grid";
    type Options = GridOptions;

    fn check_options(o: &GridOptions) -> Result<(), BadOption> {
        if !(o.density.is_finite() && o.density > 0.0 && o.density <= 1e4) {
            return Err(BadOption::new(
                "density",
                format!(
                    "`density` (cells per primitive) must be in (0, 10000], got {}",
                    o.density
                ),
            ));
        }
        BadOption::check_range("max_cells", o.max_cells, 1, 1 << 28)
    }

    fn build<P: Primitives>(prims: &P, options: &GridOptions) -> Self {
        Grid::build_with(prims, *options)
    }

    super::structure::forward_queries!(Grid);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::accel::testutil::{agrees_with_brute, mesh, prims, rays, soup};

    fn check(m: &crate::geometry::TriangleMesh, opts: GridOptions) -> (Grid, usize) {
        let p = prims(m);
        let g = Grid::build_with(&p, opts);
        let hits = agrees_with_brute(
            &p,
            &rays(400, 13),
            |r, t, s| g.intersect(&p, r, t, s),
            |r, t, s| g.occluded(&p, r, t, s),
        );
        (g, hits)
    }

    #[test]
    fn agrees_with_brute_force_at_several_densities() {
        let m = soup(2000, 21);
        for density in [0.1, 1.0, 27.0, 100.0] {
            let (g, hits) = check(
                &m,
                GridOptions {
                    density,
                    ..Default::default()
                },
            );
            assert!(hits > 200, "{hits}");
            let cells = g.cell_count() as f32;
            assert!(cells <= 4.0 * density * 2000.0 + 8.0, "{density}: {cells}");
        }
    }

    #[test]
    fn cells_follow_the_aspect_of_the_bounds() {
        let mut m = soup(1000, 2);
        for p in &mut m.positions {
            p.x *= 4.0;
            p.z *= 0.0;
        }
        let (g, _) = check(&m, GridOptions::default());
        let [x, y, z] = g.resolution();
        assert_eq!(z, 1);
        assert!(x >= 3 * y && x <= 5 * y, "{x} {y}");
    }

    #[test]
    fn empty_single_and_coincident_inputs() {
        check(&mesh(vec![]), GridOptions::default());
        let t = [Vec3::ZERO, Vec3::X, Vec3::Y];
        check(&mesh(vec![t]), GridOptions::default());
        let (g, _) = check(&mesh(vec![t; 500]), GridOptions::default());
        assert!(g.items.len() >= 500);
        // All at one point.
        check(&mesh(vec![[Vec3::ONE; 3]; 50]), GridOptions::default());
    }

    #[test]
    fn clipping_keeps_a_diagonal_triangle_out_of_most_cells_its_bounds_cover() {
        let big = [
            Vec3::new(-1.0, -1.0, -1.0),
            Vec3::new(1.0, 1.0, -1.0),
            Vec3::new(1.0, 1.0, 1.0),
        ];
        let mut tris = vec![big];
        // Filler to make the grid fine.
        let filler = soup(300, 4);
        for t in 0..300 {
            tris.push(filler.vertices(t));
        }
        let m = mesh(tris);
        let (g, _) = check(&m, GridOptions::default());
        let in_cells = g.items.iter().filter(|&&p| p == 0).count();
        let covered = g.cell_count();
        assert!(
            (in_cells as f32) < 0.5 * covered as f32,
            "{in_cells} of {covered}"
        );
    }

    #[test]
    fn mailbox_tests_each_primitive_at_most_once() {
        // One triangle across the whole grid: a ray through every cell tests it once.
        let big = [
            Vec3::new(-1.0, -1.0, 0.0),
            Vec3::new(3.0, -1.0, 0.0),
            Vec3::new(-1.0, 3.0, 0.0),
        ];
        let filler = soup(200, 4);
        let mut tris: Vec<_> = (0..200).map(|t| filler.vertices(t)).collect();
        tris.insert(0, big);
        let m = mesh(tris);
        let p = prims(&m);
        let g = Grid::build(&p);
        let mut s = TraversalStats::default();
        let r = Ray::new(Vec3::new(-1.0, -1.0, 0.5), Vec3::new(1.0, 1.0, 0.001));
        g.intersect(&p, &r, f32::INFINITY, &mut s);
        let in_cells: usize = g.items.iter().filter(|&&q| q != 0).count() + 1;
        assert!(s.nodes_visited > 3);
        assert!((s.prim_tests as usize) < in_cells);
    }
}
