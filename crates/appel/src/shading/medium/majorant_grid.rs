//! Local majorants: a coarse grid of bounds on a heterogeneous medium's extinction over its unit
//! cube, and the walk of a ray through its cells (pbrt-v4 section 11.4.3, `MajorantGrid` and
//! `DDAMajorantIterator`; the 3D DDA of Amanatides and Woo 1987). Delta and ratio tracking then
//! draw tentative collisions in each cell at that cell's own rate: in a cloud's empty corners
//! the rate is 0 and the walk skips them without a lookup, and in thin parts it takes fewer
//! null collisions than one global maximum would.
//!
//! Every cell holds the largest sample that the volume's lookup reads anywhere in the cell (the
//! trilinear stencil reaches half a sample beyond the cell's samples), so the cell's majorant
//! bounds every interpolated value in it. The bounds are widened by a thousandth of a sample
//! so that a point rounded across a cell's face stays under its cell's bound.

use super::volume::Grid;
use crate::math::{Ray, Vec3};
use glam::Mat4;

/// How many of the volume's samples a majorant cell spans along each axis (at most; grids
/// smaller than this get one cell along that axis). 4 samples make a 64^3 grid a 16^3 grid of
/// majorants, pbrt-v4's fixed resolution.
pub const SAMPLES_PER_CELL: usize = 4;

/// Widening of each cell's reach, in samples: see the module's comment.
const REACH_SLACK: f32 = 1e-3;

/// Each bound is raised by this factor so that the rounding of the interpolation's arithmetic
/// (a few units in the last place) never lifts a value above it.
const ROUNDING_SLACK: f32 = 1.0 + 1.0 / (1 << 20) as f32;

/// Bounds of the extinction over the cells of the unit cube, x fastest.
#[derive(Clone, Debug, PartialEq)]
pub struct MajorantGrid {
    pub resolution: [usize; 3],
    pub max: Vec<f32>,
}

impl MajorantGrid {
    /// One cell: a global majorant.
    pub fn global(max: f32) -> Self {
        MajorantGrid {
            resolution: [1, 1, 1],
            max: vec![max],
        }
    }

    /// The grid of `resolution` cells over `grid`'s samples, each bound multiplied by `scale`
    /// (the largest channel of the largest sample that the lookup reads in the cell).
    pub fn over(grid: &Grid, resolution: [usize; 3], scale: f32) -> Self {
        let resolution = resolution.map(|r| r.max(1));
        // Per axis: the samples that the lookups within each cell read.
        let reach: [Vec<(usize, usize)>; 3] = [0, 1, 2].map(|k| {
            let (n, cells) = (grid.resolution[k], resolution[k]);
            // Lookups are at `x * n - 1/2` (trilinear: that sample and the next) or at `x * n`
            // (nearest).
            let (offset, extra) = if grid.nearest { (0.0, 0) } else { (0.5, 1) };
            (0..cells)
                .map(|c| {
                    let x0 = c as f32 / cells as f32 * n as f32 - offset - REACH_SLACK;
                    let x1 = (c + 1) as f32 / cells as f32 * n as f32 - offset + REACH_SLACK;
                    let clamp = |i: f32| (i.max(0.0) as usize).min(n - 1);
                    (clamp(x0.floor()), clamp(x1.floor() + extra as f32))
                })
                .collect()
        });
        let [rx, ry, rz] = resolution;
        let mut max = Vec::with_capacity(rx * ry * rz);
        for &(z0, z1) in &reach[2] {
            for &(y0, y1) in &reach[1] {
                for &(x0, x1) in &reach[0] {
                    let mut m = 0.0f32;
                    for z in z0..=z1 {
                        for y in y0..=y1 {
                            for x in x0..=x1 {
                                m = m.max(grid.at([x, y, z]).max_element());
                            }
                        }
                    }
                    max.push(m * scale * ROUNDING_SLACK);
                }
            }
        }
        MajorantGrid { resolution, max }
    }

    /// The resolution for `grid`: [`SAMPLES_PER_CELL`] samples a cell.
    pub fn resolution_for(grid: &Grid) -> [usize; 3] {
        grid.resolution.map(|n| n.div_ceil(SAMPLES_PER_CELL))
    }

    /// The bound of cell `i`.
    #[inline]
    pub fn cell(&self, i: [usize; 3]) -> f32 {
        let [rx, ry, _] = self.resolution;
        self.max[(i[2] * ry + i[1]) * rx + i[0]]
    }

    /// The bound of the cell holding unit-cube point `p` (clamped to the cube).
    pub fn at(&self, p: Vec3) -> f32 {
        let i = [0, 1, 2].map(|k| {
            let r = self.resolution[k];
            ((p[k] * r as f32).max(0.0) as usize).min(r - 1)
        });
        self.cell(i)
    }

    /// The cells that `ray` crosses between `t0` and `t1` (the part of it inside the unit cube
    /// that `to_local` maps the world to), in order.
    pub fn walk(&self, to_local: &Mat4, ray: &Ray, t0: f32, t1: f32) -> Dda<'_> {
        let o = to_local.transform_point3(ray.origin);
        let d = to_local.transform_vector3(ray.dir);
        let start = o + d * t0;
        let mut dda = Dda {
            grid: self,
            t: t0,
            t_end: t1,
            cell: [0; 3],
            step: [0; 3],
            limit: [0; 3],
            next: [f32::INFINITY; 3],
            delta: [f32::INFINITY; 3],
        };
        for k in 0..3 {
            let r = self.resolution[k] as i32;
            let cell = ((start[k] * r as f32) as i32).clamp(0, r - 1);
            dda.cell[k] = cell;
            if d[k] > 0.0 {
                dda.step[k] = 1;
                dda.limit[k] = r;
                dda.next[k] = t0 + ((cell + 1) as f32 / r as f32 - start[k]) / d[k];
                dda.delta[k] = 1.0 / (d[k] * r as f32);
            } else if d[k] < 0.0 {
                dda.step[k] = -1;
                dda.limit[k] = -1;
                dda.next[k] = t0 + (cell as f32 / r as f32 - start[k]) / d[k];
                dda.delta[k] = -1.0 / (d[k] * r as f32);
            }
            // A ray parallel to the axis never crosses a face along it (`next` infinite).
        }
        dda
    }
}

/// A part `[t0, t1]` of a ray with one majorant (per channel).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MajorantSegment {
    pub t0: f32,
    pub t1: f32,
    pub majorant: Vec3,
}

/// A ray's walk through a [`MajorantGrid`]'s cells.
#[derive(Clone, Debug)]
pub struct Dda<'a> {
    grid: &'a MajorantGrid,
    t: f32,
    t_end: f32,
    cell: [i32; 3],
    step: [i32; 3],
    /// The cell index past the grid along each axis in the direction of travel.
    limit: [i32; 3],
    /// The ray parameter of the next face crossed along each axis.
    next: [f32; 3],
    /// The ray parameter between faces along each axis.
    delta: [f32; 3],
}

impl Iterator for Dda<'_> {
    type Item = MajorantSegment;

    #[inline]
    fn next(&mut self) -> Option<MajorantSegment> {
        if self.t >= self.t_end {
            return None;
        }
        let axis = if self.next[0] < self.next[1] {
            if self.next[0] < self.next[2] {
                0
            } else {
                2
            }
        } else if self.next[1] < self.next[2] {
            1
        } else {
            2
        };
        let majorant = Vec3::splat(self.grid.cell(self.cell.map(|c| c as usize)));
        self.cell[axis] += self.step[axis];
        // The last cell takes the rest of the range (where the box's ends and the faces' differ
        // by rounding), so that the segments always cover it.
        let exit = if self.cell[axis] == self.limit[axis] {
            self.t_end
        } else {
            self.next[axis].min(self.t_end)
        };
        let segment = MajorantSegment {
            t0: self.t,
            t1: exit,
            majorant,
        };
        self.t = exit;
        self.next[axis] += self.delta[axis];
        Some(segment)
    }
}

/// The majorant segments of a medium along a ray: one for a medium with one majorant, a grid's
/// walk for one with local majorants.
#[derive(Clone, Debug)]
pub enum Majorants<'a> {
    One(Option<MajorantSegment>),
    Grid(Dda<'a>),
}

impl Iterator for Majorants<'_> {
    type Item = MajorantSegment;

    #[inline]
    fn next(&mut self) -> Option<MajorantSegment> {
        match self {
            Majorants::One(s) => s.take(),
            Majorants::Grid(d) => d.next(),
        }
    }
}
