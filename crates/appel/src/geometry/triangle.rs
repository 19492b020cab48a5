//! Ray-triangle intersection: the watertight test of Woop, Benthin and Wald (2013) and the
//! Moller-Trumbore test (1997). Both return `t` and the barycentrics `(u, v)` of vertices 1 and 2.

use super::PrimHit;
use crate::math::{gamma, Ray, Vec3};

/// Which ray-triangle test meshes use (`render.triangle`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum TriangleTest {
    /// Woop et al. 2013: no ray slips between triangles sharing an edge or a vertex.
    #[default]
    Watertight,
    /// Moller & Trumbore 1997: the classic, faster to set up, but rays can slip through shared edges.
    Moller,
}

impl TriangleTest {
    /// The names `render.triangle` and `appel bench --triangle` take, in the order of [`Self::ALL`].
    pub const NAMES: &'static [&'static str] = &["watertight", "moller"];
    pub const ALL: [TriangleTest; 2] = [TriangleTest::Watertight, TriangleTest::Moller];

    pub fn from_name(name: &str) -> Option<Self> {
        Self::NAMES
            .iter()
            .position(|&n| n == name)
            .map(|i| Self::ALL[i])
    }

    pub fn name(self) -> &'static str {
        Self::NAMES[self as usize]
    }

    #[inline]
    pub fn intersect(self, ray: &Ray, t_max: f32, p0: Vec3, p1: Vec3, p2: Vec3) -> Option<PrimHit> {
        match self {
            TriangleTest::Watertight => watertight(ray, t_max, p0, p1, p2),
            TriangleTest::Moller => moller_trumbore(ray, t_max, p0, p1, p2),
        }
    }
}

/// Woop, Benthin, Wald 2013, "Watertight Ray/Triangle Intersection", as laid out in pbrt-v4 section
/// 6.5.3: translate the vertices to the ray origin, permute so the ray direction's largest component is
/// z, shear so the ray points down +z, then evaluate the 2D edge functions. Edge functions that are
/// exactly zero are re-evaluated in f64, so a ray through a shared edge is inside exactly one of the
/// two triangles' closed regions. The final `t` is accepted only if it is positive by more than its
/// error bound (pbrt-v4 eq. 6.34 onwards).
#[inline]
pub fn watertight(ray: &Ray, t_max: f32, p0: Vec3, p1: Vec3, p2: Vec3) -> Option<PrimHit> {
    let d = ray.dir;
    let [kx, ky, kz] = watertight_axes(d);
    if d[kz] == 0.0 {
        return None;
    }
    let permute = |v: Vec3| Vec3::new(v[kx], v[ky], v[kz]);
    let d = permute(d);
    let mut p0t = permute(p0 - ray.origin);
    let mut p1t = permute(p1 - ray.origin);
    let mut p2t = permute(p2 - ray.origin);

    let sx = -d.x / d.z;
    let sy = -d.y / d.z;
    let sz = 1.0 / d.z;
    p0t.x += sx * p0t.z;
    p0t.y += sy * p0t.z;
    p1t.x += sx * p1t.z;
    p1t.y += sy * p1t.z;
    p2t.x += sx * p2t.z;
    p2t.y += sy * p2t.z;

    let mut e0 = p1t.x * p2t.y - p1t.y * p2t.x;
    let mut e1 = p2t.x * p0t.y - p2t.y * p0t.x;
    let mut e2 = p0t.x * p1t.y - p0t.y * p1t.x;
    if e0 == 0.0 || e1 == 0.0 || e2 == 0.0 {
        let (p0x, p0y) = (p0t.x as f64, p0t.y as f64);
        let (p1x, p1y) = (p1t.x as f64, p1t.y as f64);
        let (p2x, p2y) = (p2t.x as f64, p2t.y as f64);
        e0 = (p1x * p2y - p1y * p2x) as f32;
        e1 = (p2x * p0y - p2y * p0x) as f32;
        e2 = (p0x * p1y - p0y * p1x) as f32;
    }
    p0t.z *= sz;
    p1t.z *= sz;
    p2t.z *= sz;
    watertight_finish(
        [p0t.x, p1t.x, p2t.x],
        [p0t.y, p1t.y, p2t.y],
        [p0t.z, p1t.z, p2t.z],
        [e0, e1, e2],
        t_max,
        ray.dir[kz].abs(),
    )
}

/// The axes in [`watertight`]'s order: `kz` that of the largest direction component (ties
/// broken as the comparisons below break them), then `kx` and `ky` its cyclic successors, which keep the triangle's winding (pbrt-v4 section 6.5.3).
#[inline(always)]
fn watertight_axes(d: Vec3) -> [usize; 3] {
    let ad = d.abs();
    let kz = if ad.x > ad.y {
        if ad.x > ad.z {
            0
        } else {
            2
        }
    } else if ad.y > ad.z {
        1
    } else {
        2
    };
    let kx = if kz == 2 { 0 } else { kz + 1 };
    let ky = if kx == 2 { 0 } else { kx + 1 };
    [kx, ky, kz]
}

/// What [`watertight`] computes of the ray alone, with its operations: the axes
/// ([`watertight_axes`]), the origin in their order, and the shear `(-d[kx] / d[kz], -d[ky] /
/// d[kz], 1 / d[kz])`. The SIMD filters take it once per ray, so that each lane then repeats the
/// scalar test's remaining operations exactly.
#[inline(always)]
pub(crate) fn watertight_shear(ray: &Ray) -> ([usize; 3], [f32; 3], [f32; 3]) {
    let k @ [kx, ky, kz] = watertight_axes(ray.dir);
    let (o, d) = (ray.origin, ray.dir);
    (
        k,
        [o[kx], o[ky], o[kz]],
        [-d[kx] / d[kz], -d[ky] / d[kz], 1.0 / d[kz]],
    )
}

/// One lane of the SIMD triangle filters written out in scalar (their portable fallbacks), from
/// the ray's [`watertight_shear`] and the lane's vertices `v[k][axis]`: [`watertight`]'s operations
/// in its order up to the range of `t`. Returns whether the lane may hit in `(0, t_max)` (a lane is
/// dropped only where [`watertight`] certainly misses), and the sheared `x` and `y` and scaled `z`
/// of the three vertices and the edge functions, the values [`watertight_finish`] takes.
#[inline(always)]
pub(crate) fn watertight_filter_lane(
    (k, o, s): ([usize; 3], [f32; 3], [f32; 3]),
    v: [[f32; 3]; 3],
    t_max: f32,
) -> (bool, [f32; 12]) {
    let vert = |p: [f32; 3]| {
        let z = p[k[2]] - o[2];
        (p[k[0]] - o[0] + s[0] * z, p[k[1]] - o[1] + s[1] * z, z)
    };
    let (x0, y0, z0) = vert(v[0]);
    let (x1, y1, z1) = vert(v[1]);
    let (x2, y2, z2) = vert(v[2]);
    let e0 = x1 * y2 - y1 * x2;
    let e1 = x2 * y0 - y2 * x0;
    let e2 = x0 * y1 - y0 * x1;
    let any_zero = e0 == 0.0 || e1 == 0.0 || e2 == 0.0;
    let outside = (e0 < 0.0 || e1 < 0.0 || e2 < 0.0) && (e0 > 0.0 || e1 > 0.0 || e2 > 0.0);
    let det = e0 + e1 + e2;
    let (z0, z1, z2) = (z0 * s[2], z1 * s[2], z2 * s[2]);
    let t_scaled = e0 * z0 + e1 * z1 + e2 * z2;
    let loose = t_max * det * (1.0 + 4.0 * f32::EPSILON);
    let reject_t = det == 0.0
        || (det < 0.0 && (t_scaled >= 0.0 || t_scaled < loose))
        || (det > 0.0 && (t_scaled <= 0.0 || t_scaled > loose));
    (
        any_zero || !(outside || reject_t),
        [x0, x1, x2, y0, y1, y2, z0, z1, z2, e0, e1, e2],
    )
}

/// The rest of [`watertight`] from the translated, permuted and sheared vertices (`z` already
/// scaled by the shear's `sz`), the edge functions, and `dz_abs`, the magnitude of the ray
/// direction's largest component (`1 / |sz|`): the inside test, the determinant, the range of `t`
/// and its error bound. SIMD filters that compute those values lane by lane with the same
/// operations finish here, so their hits are bit for bit the scalar test's.
#[inline]
pub(crate) fn watertight_finish(
    x: [f32; 3],
    y: [f32; 3],
    z: [f32; 3],
    [e0, e1, e2]: [f32; 3],
    t_max: f32,
    dz_abs: f32,
) -> Option<PrimHit> {
    if (e0 < 0.0 || e1 < 0.0 || e2 < 0.0) && (e0 > 0.0 || e1 > 0.0 || e2 > 0.0) {
        return None;
    }
    let det = e0 + e1 + e2;
    if det == 0.0 || !det.is_finite() {
        // Degenerate triangle, or a ray in its plane: never a hit. Edge functions that overflow
        // (vertices near f32's range) give an infinite or NaN determinant, which would make `t`
        // NaN.
        return None;
    }

    let t_scaled = e0 * z[0] + e1 * z[1] + e2 * z[2];
    // Early out before the division, loosened by a few ulps: `t_scaled` against `t_max * det` is
    // rounded differently from `t` against `t_max`, and the exact test on `t` below must decide, so
    // that whether a hit is reported never depends on the rounding of `t_max * det` (an
    // acceleration structure calls this with other `t_max` values than brute force does).
    let loose = t_max * det * (1.0 + 4.0 * f32::EPSILON);
    if det < 0.0 && (t_scaled >= 0.0 || t_scaled < loose) {
        return None;
    }
    if det > 0.0 && (t_scaled <= 0.0 || t_scaled > loose) {
        return None;
    }
    let inv_det = 1.0 / det;
    let b1 = e1 * inv_det;
    let b2 = e2 * inv_det;
    let t = t_scaled * inv_det;
    if t >= t_max {
        return None;
    }

    // Conservative check that t is positive by more than its rounding error.
    let max_zt = Vec3::from(z).abs().max_element();
    let delta_z = gamma(3) * max_zt;
    let max_xt = Vec3::from(x).abs().max_element();
    let max_yt = Vec3::from(y).abs().max_element();
    // The shear's rounding (the x and y error terms) grows with the vertices' z before it is
    // divided by the direction's z: |sx|, |sy| <= 1 because z is the largest component, so the
    // shear adds at most |z|. pbrt-v4 uses the z after the division, which is the same for a unit
    // direction up to a factor of sqrt(3) but wrong by |d| for others: 10^4 times too large for the
    // short directions of rays taken into a 10^4-times scaled instance (rejecting every hit), and
    // too small for the long, unnormalized shadow rays of a 10^4-times scaled scene.
    let max_z_unscaled = max_zt * dz_abs * (1.0 + 2.0 * f32::EPSILON);
    let delta_x = gamma(5) * (max_xt + max_z_unscaled);
    let delta_y = gamma(5) * (max_yt + max_z_unscaled);
    let delta_e = 2.0 * (gamma(2) * max_xt * max_yt + delta_y * max_xt + delta_x * max_yt);
    let max_e = Vec3::new(e0, e1, e2).abs().max_element();
    let delta_t =
        3.0 * (gamma(3) * max_e * max_zt + delta_e * max_zt + delta_z * max_e) * inv_det.abs();
    if t <= delta_t {
        return None;
    }
    Some(PrimHit {
        t,
        u: b1,
        v: b2,
        sub: 0,
    })
}

/// Moller & Trumbore 1997, "Fast, Minimum Storage Ray/Triangle Intersection".
#[inline]
pub fn moller_trumbore(ray: &Ray, t_max: f32, p0: Vec3, p1: Vec3, p2: Vec3) -> Option<PrimHit> {
    let [p0, e1, e2] = moller_edges([p0, p1, p2]);
    moller_trumbore_edges(ray, t_max, p0, e1, e2)
}

/// A triangle as [`moller_trumbore_edges`] takes it: `p0`, `e1 = p1 - p0` and `e2 = p2 - p0`,
/// what Embree's `Triangle4` stores. A degenerate triangle (`e1 x e2` exactly zero) gets zero
/// edges, which every ray misses: the determinant is zero, or NaN (and so is `u`) for a direction
/// with an infinite component.
#[inline]
pub fn moller_edges([p0, p1, p2]: [Vec3; 3]) -> [Vec3; 3] {
    let (e1, e2) = (p1 - p0, p2 - p0);
    if cross(e1, e2) == Vec3::ZERO {
        [p0, Vec3::ZERO, Vec3::ZERO]
    } else {
        [p0, e1, e2]
    }
}

/// [`moller_trumbore`] from a vertex and the two edges leaving it ([`moller_edges`]): the reference
/// the wide BVH's Moller-Trumbore blocks compute lane by lane, operation for operation (no fused
/// multiply-adds), so their hits are this function's bit for bit.
///
/// Division-free until the hit, as Embree's default test is (Wald et al. 2014): the unscaled
/// `U = tvec . pvec`, `V = d . qvec` and `T = e2 . qvec`, their signs flipped with the
/// determinant's, are compared with `|det|` (see [`moller_decide`]), and only a triangle that
/// passes pays for the one division. The values of a hit are those of dividing first
/// (`U * (1 / det)` and `U' * (1 / |det|)` are the same float), but the decisions are taken before
/// rounding by the division, so a ray within an ulp or so of an edge, or with `t` next to `t_max`,
/// may be decided the other way than by `u = U / det` tested against `[0, 1]` (a test in
/// `geometry::triangle` bounds how often).
#[inline]
pub fn moller_trumbore_edges(
    ray: &Ray,
    t_max: f32,
    p0: Vec3,
    e1: Vec3,
    e2: Vec3,
) -> Option<PrimHit> {
    let pvec = cross(ray.dir, e2);
    let det = dot(e1, pvec);
    let tvec = ray.origin - p0;
    let (sign, abs_det) = sign_and_abs(det);
    let u = flip(dot(tvec, pvec), sign);
    // The test most triangles fail; it is implied by `moller_decide`'s (`U' + V' <= |det|` with
    // `V' >= 0` bounds `U'`), so leaving early changes no answer.
    if !(0.0..=abs_det).contains(&u) {
        return None;
    }
    let qvec = cross(tvec, e1);
    let v = flip(dot(ray.dir, qvec), sign);
    let t = flip(dot(e2, qvec), sign);
    moller_decide(abs_det, u, v, t, t_max)
}

/// What [`moller_trumbore_edges`] computes before deciding, without its early exit: `|det|` and
/// `U`, `V`, `T` with the determinant's sign flipped into them, by the same operations (for the
/// one-lane-at-a-time fallback of the SIMD blocks).
#[inline(always)]
pub(crate) fn moller_values(ray: &Ray, p0: Vec3, e1: Vec3, e2: Vec3) -> [f32; 4] {
    let pvec = cross(ray.dir, e2);
    let det = dot(e1, pvec);
    let tvec = ray.origin - p0;
    let qvec = cross(tvec, e1);
    let (sign, abs_det) = sign_and_abs(det);
    [
        abs_det,
        flip(dot(tvec, pvec), sign),
        flip(dot(ray.dir, qvec), sign),
        flip(dot(e2, qvec), sign),
    ]
}

/// The determinant's sign bit and its magnitude.
#[inline(always)]
fn sign_and_abs(det: f32) -> (u32, f32) {
    let sign = det.to_bits() & 0x8000_0000;
    (sign, f32::from_bits(det.to_bits() ^ sign))
}

/// `x` with its sign bit flipped where `sign` is set (exact).
#[inline(always)]
fn flip(x: f32, sign: u32) -> f32 {
    f32::from_bits(x.to_bits() ^ sign)
}

/// The decision of [`moller_trumbore_edges`] from `|det|` and the sign-flipped `U`, `V`, `T`: a
/// hit when `det != 0`, `U' >= 0`, `V' >= 0`, `U' + V' <= |det|` and `T' <= |det| t_max`, and the
/// distance `t = T' (1 / |det|)` lies in `(0, t_max)`; then `u = U' (1 / |det|)`, `v` likewise.
/// NaN anywhere is a miss. The checks before the division are the ones a SIMD filter can make
/// exactly; the check of `t` after it keeps every hit strictly inside `(0, t_max)`.
#[inline(always)]
pub(crate) fn moller_decide(abs_det: f32, u: f32, v: f32, t: f32, t_max: f32) -> Option<PrimHit> {
    if !(abs_det != 0.0 && u >= 0.0 && v >= 0.0 && u + v <= abs_det && t <= abs_det * t_max) {
        return None;
    }
    let inv = 1.0 / abs_det;
    let t = t * inv;
    if !(t > 0.0 && t < t_max) {
        return None;
    }
    Some(PrimHit {
        t,
        u: u * inv,
        v: v * inv,
        sub: 0,
    })
}

/// The cross product written out, in the order the SIMD blocks repeat it.
#[inline(always)]
fn cross(a: Vec3, b: Vec3) -> Vec3 {
    Vec3::new(
        a.y * b.z - b.y * a.z,
        a.z * b.x - b.z * a.x,
        a.x * b.y - b.x * a.y,
    )
}

/// The dot product written out, summed left to right as the SIMD blocks sum it.
#[inline(always)]
fn dot(a: Vec3, b: Vec3) -> f32 {
    a.x * b.x + a.y * b.y + a.z * b.z
}

#[cfg(test)]
mod tests {
    use super::*;

    const TRI: [Vec3; 3] = [
        Vec3::new(0.0, 0.0, 0.0),
        Vec3::new(1.0, 0.0, 0.0),
        Vec3::new(0.0, 1.0, 0.0),
    ];

    fn both(ray: &Ray, t_max: f32) -> [Option<PrimHit>; 2] {
        [TriangleTest::Watertight, TriangleTest::Moller]
            .map(|m| m.intersect(ray, t_max, TRI[0], TRI[1], TRI[2]))
    }

    #[test]
    fn names_round_trip_and_watertight_is_the_default() {
        for t in TriangleTest::ALL {
            assert_eq!(TriangleTest::from_name(t.name()), Some(t));
        }
        assert_eq!(TriangleTest::from_name("moeller"), None);
        assert_eq!(TriangleTest::default().name(), "watertight");
    }

    #[test]
    fn hit_inside_gives_t_and_barycentrics() {
        let r = Ray::new(Vec3::new(0.25, 0.5, -2.0), Vec3::Z);
        for h in both(&r, f32::INFINITY) {
            let h = h.unwrap();
            assert!((h.t - 2.0).abs() < 1e-6);
            assert!((h.u - 0.25).abs() < 1e-6 && (h.v - 0.5).abs() < 1e-6);
        }
    }

    #[test]
    fn both_windings_are_hit() {
        let r = Ray::new(Vec3::new(0.25, 0.25, 2.0), -Vec3::Z);
        for h in both(&r, f32::INFINITY) {
            assert!((h.unwrap().t - 2.0).abs() < 1e-6);
        }
    }

    #[test]
    fn outside_behind_and_beyond_t_max_miss() {
        let outside = Ray::new(Vec3::new(0.75, 0.75, -1.0), Vec3::Z);
        let behind = Ray::new(Vec3::new(0.2, 0.2, 1.0), Vec3::Z);
        let far = Ray::new(Vec3::new(0.2, 0.2, -3.0), Vec3::Z);
        for r in [outside, behind] {
            assert_eq!(both(&r, f32::INFINITY), [None, None]);
        }
        assert_eq!(both(&far, 2.5), [None, None]);
    }

    /// Edge functions that overflow f32 once made the determinant NaN, and a NaN `t` passed every
    /// range check: such a triangle must be a miss, not a hit at NaN.
    #[test]
    fn overflowing_edge_functions_are_a_miss_not_a_nan_hit() {
        let c = Vec3::new(2e31, 0.0, 0.0);
        let s = 2e30;
        let (p0, p1, p2) = (
            c,
            c + Vec3::new(0.5, 1.0, 0.0) * s,
            c + Vec3::new(0.0, 0.3, 1.0) * s,
        );
        let r = Ray::new(Vec3::new(-0.2, -0.3, 0.7), Vec3::new(-1.0, -0.1, -0.8));
        assert_eq!(watertight(&r, f32::INFINITY, p0, p1, p2), None);
        let toward = Ray::new(Vec3::ZERO, (p0 + p1 + p2) / 3.0);
        if let Some(h) = watertight(&toward, f32::INFINITY, p0, p1, p2) {
            assert!(h.t.is_finite());
        }
    }

    /// Moller-Trumbore as first written: divide, then test `u`, `v` and `t` against `[0, 1]`
    /// and `(0, t_max)`.
    fn moller_dividing_first(ray: &Ray, t_max: f32, p: [Vec3; 3]) -> Option<PrimHit> {
        let [p0, e1, e2] = moller_edges(p);
        let pvec = cross(ray.dir, e2);
        let det = dot(e1, pvec);
        if det == 0.0 {
            return None;
        }
        let inv = 1.0 / det;
        let tvec = ray.origin - p0;
        let u = dot(tvec, pvec) * inv;
        let qvec = cross(tvec, e1);
        let v = dot(ray.dir, qvec) * inv;
        let t = dot(e2, qvec) * inv;
        let inside = (0.0..=1.0).contains(&u) && v >= 0.0 && u + v <= 1.0;
        (inside && t > 0.0 && t < t_max).then_some(PrimHit { t, u, v, sub: 0 })
    }

    /// The division-free test decides as dividing first does but on rays within a few ulps of an
    /// edge or of `t_max`, and its hits carry the same values bit for bit. Rays aimed at edges
    /// (where the two differ at all) and at random points, with finite and infinite `t_max`.
    #[test]
    fn division_free_moller_decides_as_dividing_first_but_at_edges() {
        let mut rng = crate::accel::testutil::Rng(9);
        let mut next = || rng.f();
        // Per kind of ray (aimed at an edge, aimed at random): hits, and decisions that differ.
        let (mut hits, mut differ) = ([0usize; 2], [0usize; 2]);
        for i in 0..200_000 {
            let mut p = || Vec3::new(next(), next(), next()) * 2.0 - Vec3::ONE;
            let tri = [p(), p(), p()];
            let origin = p() * 3.0;
            // Toward a point of an edge (a = b: a vertex) or inside.
            let (a, b) = (tri[i % 3], tri[(i + 1 + i / 3 % 2) % 3]);
            let jitter = p() * 0.5;
            let w = next();
            let target = if i % 4 == 0 {
                (tri[0] + tri[1] + tri[2]) / 3.0 + jitter
            } else {
                a + (b - a) * w
            };
            let ray = Ray::new(origin, target - origin);
            let t_max = if i % 5 == 0 { 1.0 } else { f32::INFINITY };
            let new = moller_trumbore(&ray, t_max, tri[0], tri[1], tri[2]);
            let old = moller_dividing_first(&ray, t_max, tri);
            let kind = (i % 4 == 0) as usize;
            hits[kind] += new.is_some() as usize;
            match (new, old) {
                (Some(n), Some(o)) => assert_eq!(n, o, "ray {i}"),
                (None, None) => {}
                (Some(h), None) | (None, Some(h)) => {
                    differ[kind] += 1;
                    // Decided at an edge or at `t_max`: within a few ulps of one.
                    let near = |x: f32| x.abs() < 1e-6;
                    let edge = near(h.u) || near(h.v) || near(1.0 - h.u - h.v);
                    assert!(edge || near(h.t - t_max), "ray {i}: {h:?}");
                }
            }
        }
        assert!(hits[0] > 50_000 && hits[1] > 5_000, "{hits:?}");
        // Aimed at edges, a few percent of the hits differ (about 3%); aimed at random, almost none.
        assert!(differ[0] < hits[0] / 10, "{differ:?} of {hits:?}");
        assert!(differ[1] <= hits[1] / 5_000, "{differ:?} of {hits:?}");
    }

    #[test]
    fn degenerate_triangles_are_never_hit() {
        let r = Ray::new(Vec3::new(0.0, 0.0, -1.0), Vec3::Z);
        let collinear = [Vec3::ZERO, Vec3::X, 2.0 * Vec3::X];
        let point = [Vec3::ZERO; 3];
        for m in [TriangleTest::Watertight, TriangleTest::Moller] {
            for t in [collinear, point] {
                assert!(m.intersect(&r, f32::INFINITY, t[0], t[1], t[2]).is_none());
            }
            // A ray lying in the triangle's plane.
            let inplane = Ray::new(Vec3::new(-1.0, 0.2, 0.0), Vec3::X);
            assert!(m
                .intersect(&inplane, f32::INFINITY, TRI[0], TRI[1], TRI[2])
                .is_none());
        }
    }

    #[test]
    fn watertight_ray_through_shared_edge_hits_a_quad() {
        // Two triangles sharing the diagonal of the unit square.
        let a = [Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0)];
        let b = [Vec3::ZERO, Vec3::new(1.0, 1.0, 0.0), Vec3::Y];
        for i in 0..1000 {
            let s = i as f32 / 999.0;
            let r = Ray::new(
                Vec3::new(s, s, -1.0),
                Vec3::new(0.01 * (s - 0.5), 0.0, 1.0).normalize(),
            );
            let target = Vec3::new(s, s, 0.0);
            let r = Ray::new(r.origin, (target - r.origin).normalize());
            let hit_a = watertight(&r, f32::INFINITY, a[0], a[1], a[2]);
            let hit_b = watertight(&r, f32::INFINITY, b[0], b[1], b[2]);
            assert!(
                hit_a.is_some() || hit_b.is_some(),
                "slipped through at s={s}"
            );
        }
    }
}
