//! A city of box buildings whose walls are grids of recessed windows: every window is a frame of
//! four wall strips, four reveal faces and a pane set back into the wall (18 triangles), so the
//! sun's shadows in the reveals draw the windows without any texture.

use super::builder::MeshBuilder;
use crate::geometry::procedural::SplitMix64;
use crate::math::Vec3;

/// Width and height of one window cell of a facade, in metres.
const CELL_W: f32 = 3.0;
const CELL_H: f32 = 3.5;

/// One facade: a `w x h` rectangle from corner `o` along `right` and up, facing `right x up`.
fn facade(b: &mut MeshBuilder, o: Vec3, right: Vec3, w: f32, floors: u32, depth: f32) {
    let up = Vec3::Y;
    let inward = up.cross(right);
    let cols = ((w / CELL_W).floor() as u32).max(1);
    let cw = w / cols as f32;
    let (mx, my) = (0.22 * cw, 0.25 * CELL_H);
    for f in 0..floors {
        for c in 0..cols {
            let p = o + right * (c as f32 * cw) + up * (f as f32 * CELL_H);
            let at = |x: f32, y: f32| p + right * x + up * y;
            let (x0, x1, y0, y1) = (mx, cw - mx, my, CELL_H - 0.6 * my);
            // The wall around the window.
            b.quad(at(0.0, 0.0), at(cw, 0.0), at(cw, y0), at(0.0, y0));
            b.quad(at(0.0, y1), at(cw, y1), at(cw, CELL_H), at(0.0, CELL_H));
            b.quad(at(0.0, y0), at(x0, y0), at(x0, y1), at(0.0, y1));
            b.quad(at(x1, y0), at(cw, y0), at(cw, y1), at(x1, y1));
            // The reveal: four faces from the wall back to the pane.
            let d = inward * depth;
            b.quad(at(x0, y0), at(x0, y0) + d, at(x1, y0) + d, at(x1, y0));
            b.quad(at(x1, y1), at(x1, y1) + d, at(x0, y1) + d, at(x0, y1));
            b.quad(at(x0, y1), at(x0, y1) + d, at(x0, y0) + d, at(x0, y0));
            b.quad(at(x1, y0), at(x1, y0) + d, at(x1, y1) + d, at(x1, y1));
            b.quad(
                at(x0, y0) + d,
                at(x0, y1) + d,
                at(x1, y1) + d,
                at(x1, y0) + d,
            );
        }
    }
}

/// A building with its footprint's corner at `corner`, `w` along x and `d` along z.
fn building(b: &mut MeshBuilder, corner: Vec3, w: f32, d: f32, floors: u32) {
    let h = floors as f32 * CELL_H;
    let depth = 0.35;
    let (x0, z0) = (corner.x, corner.z);
    let (x1, z1) = (x0 + w, z0 + d);
    let y = corner.y;
    // Facades counter-clockwise seen from above, each facing out.
    facade(b, Vec3::new(x0, y, z1), Vec3::X, w, floors, depth);
    facade(b, Vec3::new(x1, y, z1), -Vec3::Z, d, floors, depth);
    facade(b, Vec3::new(x1, y, z0), -Vec3::X, w, floors, depth);
    facade(b, Vec3::new(x0, y, z0), Vec3::Z, d, floors, depth);
    b.quad(
        Vec3::new(x0, y + h, z1),
        Vec3::new(x1, y + h, z1),
        Vec3::new(x1, y + h, z0),
        Vec3::new(x0, y + h, z0),
    );
}

/// The side of one block (four lots) and the street between blocks, in metres.
pub const BLOCK: f32 = 60.0;
pub const STREET: f32 = 16.0;

/// Buildings in blocks spiralling out from the centre until at least `target` triangles are
/// built; towers are tallest in the middle. Returns the mesh and the city's half-width.
pub fn city(target: usize, seed: u64) -> (MeshBuilder, f32) {
    let mut rng = SplitMix64(seed);
    let mut b = MeshBuilder::default();
    let pitch = BLOCK + STREET;
    let mut extent = 0.0f32;
    // Square rings of blocks around the centre block.
    'rings: for ring in 0i32.. {
        let cells: Vec<(i32, i32)> = if ring == 0 {
            vec![(0, 0)]
        } else {
            (-ring..=ring)
                .flat_map(|i| (-ring..=ring).map(move |j| (i, j)))
                .filter(|&(i, j)| i.abs() == ring || j.abs() == ring)
                .collect()
        };
        for (i, j) in cells {
            let block = Vec3::new(
                i as f32 * pitch - 0.5 * BLOCK,
                0.0,
                j as f32 * pitch - 0.5 * BLOCK,
            );
            let centre = (i as f32).hypot(j as f32);
            for lot in 0..4 {
                let (lx, lz) = (
                    (lot % 2) as f32 * 0.5 * BLOCK,
                    (lot / 2) as f32 * 0.5 * BLOCK,
                );
                let w = 0.5 * BLOCK * (0.6 + 0.3 * rng.next_f32());
                let d = 0.5 * BLOCK * (0.6 + 0.3 * rng.next_f32());
                // Towers in the middle, low blocks at the edge.
                let tall = 25.0 + 90.0 / (1.0 + 0.4 * centre);
                let floors = (5.0 + tall * rng.next_f32().powi(2)) as u32;
                let inset = Vec3::new(0.5 * (0.5 * BLOCK - w), 0.0, 0.5 * (0.5 * BLOCK - d));
                building(&mut b, block + Vec3::new(lx, 0.0, lz) + inset, w, d, floors);
            }
            extent = extent.max((ring as f32 + 0.5) * pitch);
            if b.triangle_count() >= target {
                break 'rings;
            }
        }
    }
    (b, extent)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_small_city_reaches_its_target_with_outward_walls() {
        let (b, extent) = city(50_000, 1);
        assert!(b.triangle_count() >= 50_000);
        assert!(extent > 0.0);
        let m = b.into_mesh();
        for t in 0..m.triangle_count() {
            let [p0, p1, p2] = m.vertices(t);
            assert!((p1 - p0).cross(p2 - p0).length() > 1e-4, "triangle {t}");
        }
    }
}
