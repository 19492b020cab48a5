//! Triangles paired with their neighbour in the primitive order, for the wide BVH to build over and
//! store as quads (`wide/quad_block.rs`), as Embree does for quad meshes: a mesh of quads gives the
//! builder half the records to sort and its leaves four vertices to store per two triangles.
//!
//! Primitive `i + 1` pairs with `i` when both are watertight-tested triangles and the second is
//! `(p0, p2, p3)` of the first's `(p0, p1, p2)`, bit for bit: the two halves of a quad
//! triangulated as a fan, which is what the OBJ and PLY loaders and the scene generators emit (or
//! the same two the other way round, flagged [`SWAP`]). The pair's block then tests each triangle
//! from its own three vertices in its own order, so the hits are exactly those of testing them
//! one by one.

use super::wide::{ID, PAIR, SWAP};
use crate::accel::Primitives;
use crate::math::{Aabb, Vec3};
use rayon::prelude::*;

/// The items a BVH over pairs is built over, in the primitives' order: each a primitive id, with
/// [`PAIR`] set where the item is that primitive and the next. `None` where pairing does not pay:
/// fewer than half of the triangles pair (a mesh made of triangles rather than quads), or too many
/// primitives for the flag bit and the lane numbering of the blocks.
pub(crate) fn pair_up<P: Primitives>(prims: &P) -> Option<Vec<u32>> {
    let n = prims.count();
    if n < 2 || n >= PAIR as usize / 4 {
        return None;
    }
    // A look at up to 1024 evenly spaced places first, so that a mesh of single triangles (most
    // meshes) costs no scan of all of them: in a mesh of quads one of any two neighbours pairs
    // with its successor, in a mesh of triangles almost none does. (Both neighbours: with an even
    // stride and a mesh starting at an odd primitive, one alone would always be a quad's second
    // half, as in the ecosystem's top level.)
    let stride = ((n - 1) / 1024).max(1);
    let sampled = (0..n - 1).step_by(stride);
    let sampled_pairs = sampled
        .clone()
        .filter(|&i| (i..(i + 2).min(n - 1)).any(|j| pairs_with_next(prims, j) != Pairing::None))
        .count();
    if 4 * sampled_pairs < sampled.len() {
        return None;
    }
    // Which primitives pair with their successor, in parallel; then the choice, in order: a
    // primitive already taken by its predecessor does not pair again.
    let with_next: Vec<Pairing> = (0..n - 1)
        .into_par_iter()
        .with_min_len(4096)
        .map(|i| pairs_with_next(prims, i))
        .collect();
    // Room for no pairs at all: the pages past the items written are never touched, so they cost
    // no resident memory.
    let mut items = Vec::with_capacity(n);
    let mut i = 0;
    while i < n {
        let with = if i + 1 < n {
            with_next[i]
        } else {
            Pairing::None
        };
        if with != Pairing::None {
            items.push(i as u32 | PAIR | if with == Pairing::Swapped { SWAP } else { 0 });
            i += 2;
        } else {
            items.push(i as u32);
            i += 1;
        }
    }
    // Each pair made one item of two primitives.
    let pairs = n - items.len();
    if 4 * pairs < n {
        return None;
    }
    Some(items)
}

/// The bounds of item `code` (see [`pair_up`]).
#[inline]
pub(crate) fn item_bounds<P: Primitives>(prims: &P, code: u32) -> Aabb {
    let id = (code & ID) as usize;
    let b = prims.bounds(id);
    if code & PAIR != 0 {
        b.union(prims.bounds(id + 1))
    } else {
        b
    }
}

/// How primitive `i` pairs with `i + 1`.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Pairing {
    None,
    /// `(p0, p1, p2)` then `(p0, p2, p3)`.
    InOrder,
    /// `(p0, p2, p3)` then `(p0, p1, p2)`.
    Swapped,
}

fn pairs_with_next<P: Primitives>(prims: &P, i: usize) -> Pairing {
    let same = |a: Vec3, b: Vec3| a.to_array().map(f32::to_bits) == b.to_array().map(f32::to_bits);
    match (
        prims.watertight_triangle(i),
        prims.watertight_triangle(i + 1),
    ) {
        (Some(a), Some(b)) if same(a[0], b[0]) && same(a[2], b[1]) => Pairing::InOrder,
        (Some(a), Some(b)) if same(a[0], b[0]) && same(a[1], b[2]) => Pairing::Swapped,
        _ => Pairing::None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::accel::testutil::{mesh, prims, soup};
    use crate::accel::MeshPrimitives;
    use crate::geometry::TriangleTest;

    fn quad(c: Vec3) -> [[Vec3; 3]; 2] {
        let [a, b, d] = [c + Vec3::X, c + Vec3::X + Vec3::Y, c + Vec3::Y];
        [[c, a, b], [c, b, d]]
    }

    #[test]
    fn fan_halves_pair_and_nothing_else_does() {
        // Two quads, then a triangle, then a quad whose second half is rotated (not the pattern),
        // then a quad.
        let mut tris: Vec<[Vec3; 3]> = Vec::new();
        tris.extend(quad(Vec3::ZERO));
        tris.extend(quad(Vec3::Z));
        tris.push([Vec3::ZERO, Vec3::X, Vec3::Z]);
        let [p, q] = quad(Vec3::Y);
        tris.extend([p, [q[1], q[2], q[0]]]);
        tris.extend(quad(-Vec3::Z));
        // The two halves the other way round.
        let [p, q] = quad(Vec3::X);
        tris.extend([q, p]);
        let m = mesh(tris);
        let items = pair_up(&prims(&m)).expect("four pairs among eleven triangles");
        assert_eq!(
            items,
            vec![PAIR, 2 | PAIR, 4, 5, 6, 7 | PAIR, 9 | PAIR | SWAP],
            "{:x?}",
            items
        );
        assert_eq!(
            item_bounds(&prims(&m), PAIR),
            Aabb::new(Vec3::ZERO, Vec3::new(1.0, 1.0, 0.0))
        );
        // Triangles tested otherwise than watertight never pair.
        let moller = MeshPrimitives {
            mesh: &m,
            test: TriangleTest::Moller,
        };
        assert_eq!(pair_up(&moller), None);
    }

    /// A mesh of quads after an odd number of other primitives (the ecosystem's top level: its
    /// instances and one rectangle, then the terrain) pairs, whatever the sampling stride.
    #[test]
    fn quads_after_an_odd_number_of_other_primitives_pair() {
        let mut tris: Vec<[Vec3; 3]> = vec![[Vec3::ZERO, Vec3::X, Vec3::Z]; 3];
        // 2,803 primitives: a sampling stride of 2, so every sampled primitive is a quad's
        // second half.
        for k in 0..1400 {
            tris.extend(quad(Vec3::new(k as f32 * 2.0, 0.0, 0.0)));
        }
        let m = mesh(tris);
        let items = pair_up(&prims(&m)).expect("the quads pair");
        assert_eq!(items.len(), 3 + 1400);
    }

    #[test]
    fn meshes_of_triangles_are_not_paired() {
        assert_eq!(pair_up(&prims(&soup(1000, 3))), None);
        assert_eq!(pair_up(&prims(&soup(1, 3))), None);
    }
}
