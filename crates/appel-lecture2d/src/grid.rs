//! The uniform grid, with the resolution heuristic cells = C x objects (the cells shaped like
//! the scene's box), traversed with the 2D form of the 3D DDA of Amanatides and Woo (1987).
//!
//! The pitfall: an object spanning several cells is tested in the first of them the ray visits,
//! and its hit may lie in a later cell, beyond another object's. Accepting it there returns a
//! first hit that is not the nearest; the nearest hit is only known once it lies inside the cell
//! being visited (`check_in_cell`).

use super::geometry::{Box2, Ray2, Shape, P2};
use super::trace::{box_region, BuildStep, Trace, TraceStep, Tracer};

pub struct Grid {
    pub bounds: Box2,
    pub nx: usize,
    pub ny: usize,
    /// Object indices of each cell, row-major from the cell at `bounds.min`.
    pub cells: Vec<Vec<usize>>,
    pub steps: Vec<BuildStep>,
}

impl Grid {
    pub fn build(objects: &[Shape], bounds: Box2, c: f64) -> Grid {
        let e = bounds.extent();
        let cells = (c * objects.len().max(1) as f64).clamp(1.0, 1e6);
        // nx * ny = cells with nx / ny = width / height: square-ish cells.
        let nx = ((cells * e.x / e.y).sqrt().round() as usize).clamp(1, 1000);
        let ny = ((cells * e.y / e.x).sqrt().round() as usize).clamp(1, 1000);
        let mut grid = Grid {
            bounds,
            nx,
            ny,
            cells: vec![Vec::new(); nx * ny],
            steps: Vec::new(),
        };
        // The build shown as its lines, then each object's cells.
        for i in 1..nx {
            let x = bounds.min.x + e.x * i as f64 / nx as f64;
            grid.steps.push(line_step(
                [P2::new(x, bounds.min.y), P2::new(x, bounds.max.y)],
                &bounds,
            ));
        }
        for j in 1..ny {
            let y = bounds.min.y + e.y * j as f64 / ny as f64;
            grid.steps.push(line_step(
                [P2::new(bounds.min.x, y), P2::new(bounds.max.x, y)],
                &bounds,
            ));
        }
        for (k, o) in objects.iter().enumerate() {
            let b = o.bounds();
            let (i0, j0) = grid.cell_of(b.min);
            let (i1, j1) = grid.cell_of(b.max);
            for j in j0..=j1 {
                for i in i0..=i1 {
                    grid.cells[j * nx + i].push(k);
                }
            }
        }
        for j in 0..ny {
            for i in 0..nx {
                let n = grid.cells[j * nx + i].len();
                if n > 0 {
                    grid.steps.push(super::trace::leaf_step(
                        0,
                        box_region(grid.cell_box(i, j)),
                        n,
                    ));
                }
            }
        }
        grid
    }

    fn cell_size(&self) -> P2 {
        let e = self.bounds.extent();
        P2::new(e.x / self.nx as f64, e.y / self.ny as f64)
    }

    /// The cell holding `p`, clamped to the grid.
    pub fn cell_of(&self, p: P2) -> (usize, usize) {
        let s = self.cell_size();
        let i = ((p.x - self.bounds.min.x) / s.x)
            .floor()
            .clamp(0.0, self.nx as f64 - 1.0);
        let j = ((p.y - self.bounds.min.y) / s.y)
            .floor()
            .clamp(0.0, self.ny as f64 - 1.0);
        (i as usize, j as usize)
    }

    pub fn cell_box(&self, i: usize, j: usize) -> Box2 {
        let s = self.cell_size();
        let min = P2::new(
            self.bounds.min.x + s.x * i as f64,
            self.bounds.min.y + s.y * j as f64,
        );
        Box2 {
            min,
            max: min.plus(s),
        }
    }

    /// Visits the cells along the ray in order. With `check_in_cell`, the traversal stops at the
    /// first cell whose exit lies beyond the nearest hit (correct); without, at the first cell
    /// where any object was hit, wherever the hit lies (the pitfall).
    pub fn trace(&self, objects: &[Shape], ray: &Ray2, check_in_cell: bool) -> Trace {
        let mut tr = Tracer::new(objects, *ray);
        let Some((t0, t1)) = self.bounds.slab(ray, 0.0, f64::INFINITY) else {
            return tr.finish();
        };
        let s = self.cell_size();
        let (mut i, mut j) = self.cell_of(ray.at(t0));
        // Per axis: the step, the t of the next cell boundary, and the t between boundaries.
        let axis = |d: f64, o: f64, min: f64, size: f64, cell: usize| -> (isize, f64, f64) {
            if d > 0.0 {
                let next = min + size * (cell + 1) as f64;
                (1, (next - o) / d, size / d)
            } else if d < 0.0 {
                let next = min + size * cell as f64;
                (-1, (next - o) / d, -size / d)
            } else {
                (0, f64::INFINITY, f64::INFINITY)
            }
        };
        let (sx, mut tx, dx) = axis(ray.d.x, ray.o.x, self.bounds.min.x, s.x, i);
        let (sy, mut ty, dy) = axis(ray.d.y, ray.o.y, self.bounds.min.y, s.y, j);
        let mut t_enter = t0;
        loop {
            let t_exit = tx.min(ty).min(t1);
            tr.visit(
                j * self.nx + i,
                box_region(self.cell_box(i, j)),
                t_enter,
                t_exit,
            );
            let mut any = false;
            for &k in &self.cells[j * self.nx + i] {
                if let Some(t) = tr.test(k) {
                    any = true;
                    if !check_in_cell && t > t_exit {
                        tr.trace.steps.push(TraceStep::AcceptedOutsideCell {
                            object: k,
                            t,
                            t_exit,
                        });
                    }
                }
            }
            if check_in_cell {
                if tr.exit_before(t_exit) {
                    break;
                }
            } else if any {
                // Take the first hit of this cell as the answer, without checking it is here.
                let best = tr.best_t();
                tr.trace.steps.push(TraceStep::EarlyExit { t: best });
                break;
            }
            if t_exit >= t1 {
                break;
            }
            if tx < ty {
                let n = i as isize + sx;
                if n < 0 || n >= self.nx as isize {
                    break;
                }
                i = n as usize;
                tx += dx;
            } else {
                let n = j as isize + sy;
                if n < 0 || n >= self.ny as isize {
                    break;
                }
                j = n as usize;
                ty += dy;
            }
            t_enter = t_exit;
        }
        tr.finish()
    }
}

fn line_step(line: [P2; 2], bounds: &Box2) -> BuildStep {
    BuildStep {
        depth: 0,
        region: box_region(*bounds),
        split: Some(line),
        objects: 0,
        leaf: false,
        sah: None,
    }
}

#[cfg(test)]
mod tests {
    use super::super::geometry::brute_force;
    use super::super::scenes::{random_rays, scene};
    use super::*;

    #[test]
    fn resolution_follows_c_times_objects() {
        let objects = scene("random", 50, 3);
        let g = Grid::build(&objects, super::super::WORLD, 2.0);
        assert_eq!(g.nx * g.ny, 100);
    }

    #[test]
    fn checked_grid_finds_the_brute_force_hit() {
        for (name, n) in [
            ("random", 40),
            ("clustered", 60),
            ("figures", 0),
            ("stadium", 80),
        ] {
            let objects = scene(name, n, 7);
            for c in [0.5, 1.0, 4.0] {
                let g = Grid::build(&objects, super::super::WORLD, c);
                for ray in random_rays(200, 11) {
                    let got = g.trace(&objects, &ray, true).hit;
                    assert_eq!(got, brute_force(&objects, &ray), "{name} C={c} {ray:?}");
                }
            }
        }
    }

    #[test]
    fn dda_visits_the_cells_a_ray_crosses_in_order() {
        // 4 x 4 cells of 25 units; a ray along y = 30 from x = 5 crosses row 1 left to right.
        let objects = vec![
            Shape::Circle {
                c: P2::new(90.0, 10.0),
                r: 1.0
            };
            16
        ];
        let g = Grid::build(&objects, super::super::WORLD, 1.0);
        assert_eq!((g.nx, g.ny), (4, 4));
        let ray = Ray2::through(P2::new(5.0, 30.0), P2::new(6.0, 30.0)).unwrap();
        let visited: Vec<usize> = g
            .trace(&objects, &ray, true)
            .steps
            .iter()
            .filter_map(|s| match s {
                TraceStep::Visit { id, .. } => Some(*id),
                _ => None,
            })
            .collect();
        assert_eq!(visited, [4, 5, 6, 7]);
        // A diagonal ray steps one axis at a time.
        let diag = Ray2::through(P2::new(1.0, 2.0), P2::new(2.0, 3.0)).unwrap();
        let cells: Vec<usize> = g
            .trace(&objects, &diag, true)
            .steps
            .iter()
            .filter_map(|s| match s {
                TraceStep::Visit { id, .. } => Some(*id),
                _ => None,
            })
            .collect();
        // y = x + 1 crosses y = 25 at x = 24, before x = 25: up first.
        assert_eq!(cells, [0, 4, 5, 9, 10, 14, 15]);
    }

    #[test]
    fn unchecked_grid_returns_a_far_hit_of_a_spanning_object() {
        // A long segment across the first cells, hit far along the ray, and a small circle
        // nearer: without the in-cell check the segment is taken in the first cell.
        let objects = vec![
            Shape::Segment {
                a: P2::new(5.0, 40.0),
                b: P2::new(60.0, 4.0),
            },
            Shape::Circle {
                c: P2::new(30.0, 10.0),
                r: 2.0,
            },
        ];
        let g = Grid::build(&objects, super::super::WORLD, 8.0);
        let ray = Ray2::through(P2::new(1.0, 10.0), P2::new(2.0, 10.0)).unwrap();
        let right = brute_force(&objects, &ray).unwrap();
        assert_eq!(right.0, 1);
        assert_eq!(g.trace(&objects, &ray, true).hit.unwrap().0, 1);
        let wrong = g.trace(&objects, &ray, false);
        assert_eq!(wrong.hit.unwrap().0, 0);
        assert!(wrong
            .steps
            .iter()
            .any(|s| matches!(s, TraceStep::AcceptedOutsideCell { object: 0, .. })));
    }
}
