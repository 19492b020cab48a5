//! Scenes and rays shared by the unit tests of the structures, and the check they all pass: the same
//! answers as brute force.

use super::{Brute, Hit, MeshPrimitives, Primitives, TraversalStats};
use crate::geometry::TriangleMesh;
use crate::math::{Ray, Vec3};

/// xorshift32: deterministic, dependency-free.
pub struct Rng(pub u32);

impl Rng {
    pub fn f(&mut self) -> f32 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 17;
        self.0 ^= self.0 << 5;
        (self.0 >> 8) as f32 / (1u32 << 24) as f32
    }

    pub fn v(&mut self, lo: f32, hi: f32) -> Vec3 {
        Vec3::new(self.f(), self.f(), self.f()) * (hi - lo) + Vec3::splat(lo)
    }
}

pub fn mesh(tris: Vec<[Vec3; 3]>) -> TriangleMesh {
    TriangleMesh {
        positions: tris.iter().flatten().copied().collect(),
        indices: (0..tris.len() as u32)
            .map(|i| [3 * i, 3 * i + 1, 3 * i + 2])
            .collect(),
        normals: None,
        uvs: None,
    }
}

/// `n` small random triangles in the cube [-1, 1]^3.
pub fn soup(n: usize, seed: u32) -> TriangleMesh {
    let mut r = Rng(seed);
    mesh(
        (0..n)
            .map(|_| {
                let c = r.v(-1.0, 1.0);
                [c, c + r.v(-0.2, 0.2), c + r.v(-0.2, 0.2)]
            })
            .collect(),
    )
}

/// Rays from outside and inside the cube, some of them axis-aligned with `+0` and `-0` components.
pub fn rays(n: usize, seed: u32) -> Vec<Ray> {
    let mut r = Rng(seed);
    (0..n)
        .map(|k| {
            let o = if k % 2 == 0 {
                r.v(-3.0, 3.0)
            } else {
                r.v(-1.0, 1.0)
            };
            let mut d = r.v(-1.0, 1.0);
            if k % 5 == 0 {
                let axis = k / 5 % 3;
                let s = if k % 10 == 0 { 1.0 } else { -1.0 };
                d = Vec3::ZERO;
                d[axis] = s;
                // Toward the middle, so these rays meet something.
                let mut o2 = o;
                o2[axis] = -2.0 * s;
                return Ray::new(o2, d);
            }
            if k % 7 == 0 {
                d.x = -0.0;
            }
            Ray::new(o, d)
        })
        .collect()
}

/// Every ray gets the same closest hit (primitive and `t`; either primitive of an exact tie) and the
/// same any-hit answer from `intersect`/`occluded` as from brute force. Returns how many closest hits
/// there were, so that callers can make sure the check was not vacuous.
pub fn agrees_with_brute<P: Primitives>(
    prims: &P,
    rays: &[Ray],
    intersect: impl Fn(&Ray, f32, &mut TraversalStats) -> Option<Hit>,
    occluded: impl Fn(&Ray, f32, &mut TraversalStats) -> bool,
) -> usize {
    let brute = Brute::build(prims);
    let mut s = TraversalStats::default();
    let mut hits = 0;
    for ray in rays {
        for t_max in [f32::INFINITY, 1.5] {
            let want = brute.intersect(prims, ray, t_max, &mut s);
            let got = intersect(ray, t_max, &mut s);
            match (want, got) {
                (None, None) => {}
                (Some(w), Some(g)) => {
                    hits += 1;
                    assert_eq!(w.t, g.t, "t differs for {ray:?}: brute {w:?}, got {g:?}");
                    if w.prim != g.prim {
                        // A tie: the other primitive must report the very same t.
                        let other = prims.intersect(g.prim as usize, ray, f32::INFINITY);
                        assert_eq!(other.map(|h| h.t), Some(w.t), "{ray:?}");
                    }
                }
                _ => panic!("{ray:?} t_max {t_max}: brute {want:?}, got {got:?}"),
            }
            assert_eq!(
                brute.occluded(prims, ray, t_max, &mut s),
                occluded(ray, t_max, &mut s),
                "any-hit differs for {ray:?} t_max {t_max}"
            );
        }
    }
    hits
}

pub fn prims(m: &TriangleMesh) -> MeshPrimitives<'_> {
    MeshPrimitives::new(m)
}

/// The rays through the pixel centres of a `width x height` pinhole camera at `eye` looking at
/// `look_at` (y up) with a vertical field of view of `fov_degrees`, row by row.
pub fn pinhole_rays(
    eye: Vec3,
    look_at: Vec3,
    fov_degrees: f32,
    width: u32,
    height: u32,
) -> Vec<Ray> {
    let forward = (look_at - eye).normalize();
    let right = forward.cross(Vec3::Y).normalize();
    let up = right.cross(forward);
    let half_h = (0.5 * fov_degrees.to_radians()).tan();
    let half_w = half_h * width as f32 / height as f32;
    (0..height)
        .flat_map(|j| {
            (0..width).map(move |i| {
                let x = (2.0 * (i as f32 + 0.5) / width as f32 - 1.0) * half_w;
                let y = (1.0 - 2.0 * (j as f32 + 0.5) / height as f32) * half_h;
                Ray::new(eye, (forward + x * right + y * up).normalize())
            })
        })
        .collect()
}
