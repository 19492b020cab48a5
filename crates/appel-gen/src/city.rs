//! A city of box buildings whose walls are grids of recessed windows: every window is a frame of
//! four wall strips, four reveal faces and a pane set back into the wall (18 triangles), so the
//! sun's shadows in the reveals draw the windows without any texture.

use super::builder::MeshBuilder;
use appel::geometry::procedural::SplitMix64;
use appel::math::Vec3;

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
            let (x0, x1, y0, y1) = (mx, cw - mx, my, CELL_H - 0.6 * my);
            // Sixteen shared corners: the cell's outline at the heights of the window's sill and
            // head, the window's opening in the wall, and the pane set back by `depth`.
            let mut v = |x: f32, y: f32, back: bool| {
                let d = if back { inward * depth } else { Vec3::ZERO };
                b.vertex(p + right * x + up * y + d)
            };
            let [o00, o10, o01, o11] = [
                v(0.0, 0.0, false),
                v(cw, 0.0, false),
                v(0.0, CELL_H, false),
                v(cw, CELL_H, false),
            ];
            let [l0, r0, l1, r1] = [
                v(0.0, y0, false),
                v(cw, y0, false),
                v(0.0, y1, false),
                v(cw, y1, false),
            ];
            let [w00, w10, w01, w11] = [
                v(x0, y0, false),
                v(x1, y0, false),
                v(x0, y1, false),
                v(x1, y1, false),
            ];
            let [p00, p10, p01, p11] = [
                v(x0, y0, true),
                v(x1, y0, true),
                v(x0, y1, true),
                v(x1, y1, true),
            ];
            // The wall around the window.
            b.quad_indices(o00, o10, r0, l0);
            b.quad_indices(l1, r1, o11, o01);
            b.quad_indices(l0, w00, w01, l1);
            b.quad_indices(w10, r0, r1, w11);
            // The reveal: four faces from the wall back to the pane, and the pane.
            b.quad_indices(w00, p00, p10, w10);
            b.quad_indices(w11, p11, p01, w01);
            b.quad_indices(w01, p01, p00, w00);
            b.quad_indices(w10, p10, p11, w11);
            b.quad_indices(p00, p01, p11, p10);
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
