//! A BSP cell as a convex polytope: the root box cut by the planes on the path to the node, kept
//! as its faces (convex polygons, counter-clockwise seen from outside), in f64. The build needs
//! only surface areas: by Cauchy's formula a random line meeting a convex body meets a convex
//! body inside it with probability equal to the ratio of their surface areas, the geometric fact
//! behind the surface area heuristic (MacDonald & Booth 1990), and it holds for any convex cell,
//! not only boxes. The bounding boxes of two cells cut by an oblique plane overlap almost
//! entirely, so they would make every oblique plane look useless.

use glam::DVec3;

#[derive(Clone, Debug)]
pub(super) struct Polytope {
    faces: Vec<Vec<DVec3>>,
    /// The half-spaces `n . x <= d` whose intersection the cell is.
    planes: Vec<(DVec3, f64)>,
}

/// The part of one face on the lower side of a plane: its area, and the points where its boundary
/// leaves and re-enters the lower side (the face's edge on the cut, if it is cut).
struct FaceCut {
    below: f64,
    exit: Option<DVec3>,
    entry: Option<DVec3>,
}

impl Polytope {
    pub(super) fn from_box(min: DVec3, max: DVec3) -> Self {
        let corner = |k: usize| {
            DVec3::new(
                if k & 1 == 1 { max.x } else { min.x },
                if k & 2 == 2 { max.y } else { min.y },
                if k & 4 == 4 { max.z } else { min.z },
            )
        };
        let mut faces = Vec::with_capacity(6);
        for a in 0..3 {
            for upper in [false, true] {
                let pts: Vec<DVec3> = (0..8)
                    .filter(|k| (k >> a & 1 == 1) == upper)
                    .map(corner)
                    .collect();
                let mut normal = DVec3::ZERO;
                normal[a] = if upper { 1.0 } else { -1.0 };
                faces.push(counter_clockwise(pts, normal));
            }
        }
        let planes = (0..3)
            .flat_map(|a| {
                let mut e = DVec3::ZERO;
                e[a] = 1.0;
                [(-e, -min[a]), (e, max[a])]
            })
            .collect();
        Self { faces, planes }
    }

    /// The bounding box, rounded outward to f32.
    pub(super) fn bounds(&self) -> crate::math::Aabb {
        let (mut lo, mut hi) = (DVec3::INFINITY, DVec3::NEG_INFINITY);
        for p in self.faces.iter().flatten() {
            lo = lo.min(*p);
            hi = hi.max(*p);
        }
        let down = |x: f64| (x as f32).next_down();
        let up = |x: f64| (x as f32).next_up();
        crate::math::Aabb::new(
            crate::math::Vec3::new(down(lo.x), down(lo.y), down(lo.z)),
            crate::math::Vec3::new(up(hi.x), up(hi.y), up(hi.z)),
        )
    }

    pub(super) fn area(&self) -> f64 {
        self.faces.iter().map(|f| polygon_area(f)).sum()
    }

    /// The surface areas of the two parts `n . x <= d` and `n . x >= d`: each face's part on
    /// either side, plus the cut itself, the polygon whose edges are the faces' cut edges. Faces
    /// are oriented consistently, so those edges form one loop and their cross products sum to
    /// twice its vector area, with no need to order them.
    pub(super) fn split_areas(&self, n: DVec3, d: f64) -> (f64, f64) {
        let (mut below, mut above) = (0.0, 0.0);
        let mut cap = DVec3::ZERO;
        for f in &self.faces {
            let c = cut_face(f, n, d, None);
            below += c.below;
            above += (polygon_area(f) - c.below).max(0.0);
            if let (Some(x), Some(e)) = (c.exit, c.entry) {
                cap += x.cross(e);
            }
        }
        let cap = 0.5 * cap.length();
        (below + cap, above + cap)
    }

    /// The part `n . x <= d`.
    pub(super) fn clip(&self, n: DVec3, d: f64) -> Self {
        let mut faces = Vec::with_capacity(self.faces.len() + 1);
        let mut cut = Vec::new();
        for f in &self.faces {
            let mut part = Vec::with_capacity(f.len() + 1);
            let c = cut_face(f, n, d, Some(&mut part));
            cut.extend(c.exit);
            cut.extend(c.entry);
            if part.len() >= 3 && c.below > 0.0 {
                faces.push(part);
            }
        }
        if cut.len() >= 3 {
            let cap = counter_clockwise(cut, n);
            if polygon_area(&cap) > 0.0 {
                faces.push(cap);
            }
        }
        let mut planes = self.planes.clone();
        planes.push((n, d));
        Self { faces, planes }
    }

    /// Whether triangle `t` comes within `margin` of the cell (in the distance to each of its
    /// planes): the triangle clipped by every half-space, each moved out by `margin` (Sutherland
    /// & Hodgman 1974), is not empty.
    pub(super) fn meets_triangle(&self, t: [DVec3; 3], margin: f64) -> bool {
        let mut poly = t.to_vec();
        let mut next = Vec::with_capacity(poly.len() + 1);
        for &(n, d) in &self.planes {
            next.clear();
            let d = d + margin * n.length();
            for (i, &p) in poly.iter().enumerate() {
                let q = poly[(i + 1) % poly.len()];
                let (sp, sq) = (n.dot(p) - d, n.dot(q) - d);
                if sp <= 0.0 {
                    next.push(p);
                }
                if (sp <= 0.0) != (sq <= 0.0) {
                    next.push(p + (q - p) * (sp / (sp - sq)));
                }
            }
            if next.is_empty() {
                return false;
            }
            std::mem::swap(&mut poly, &mut next);
        }
        true
    }
}

/// Sutherland & Hodgman (1974) on one convex face against `n . x <= d`: the area of the part
/// kept, and where the boundary crosses the plane; `out`, if given, receives the part's vertices.
fn cut_face(f: &[DVec3], n: DVec3, d: f64, mut out: Option<&mut Vec<DVec3>>) -> FaceCut {
    let mut acc = DVec3::ZERO;
    let (mut first, mut prev) = (None::<DVec3>, None::<DVec3>);
    let mut emit = |x: DVec3| {
        if let Some(o) = out.as_deref_mut() {
            o.push(x);
        }
        match prev {
            Some(p) => acc += p.cross(x),
            None => first = Some(x),
        }
        prev = Some(x);
    };
    let (mut exit, mut entry) = (None, None);
    for (i, &p) in f.iter().enumerate() {
        let q = f[(i + 1) % f.len()];
        let (sp, sq) = (n.dot(p) - d, n.dot(q) - d);
        if sp <= 0.0 {
            emit(p);
        }
        if (sp <= 0.0) != (sq <= 0.0) {
            let x = p + (q - p) * (sp / (sp - sq));
            emit(x);
            if sp <= 0.0 {
                exit = Some(x);
            } else {
                entry = Some(x);
            }
        }
    }
    if let (Some(p), Some(f0)) = (prev, first) {
        acc += p.cross(f0);
    }
    FaceCut {
        below: 0.5 * acc.length(),
        exit,
        entry,
    }
}

/// The area of a planar polygon: half the length of its vector area, `sum p_i x p_(i+1)`.
fn polygon_area(f: &[DVec3]) -> f64 {
    let mut acc = DVec3::ZERO;
    for (i, p) in f.iter().enumerate() {
        acc += p.cross(f[(i + 1) % f.len()]);
    }
    0.5 * acc.length()
}

/// The points of a convex polygon in the plane normal to `n`, sorted counter-clockwise around
/// `n` (by angle about their centroid), with repeated points dropped.
fn counter_clockwise(mut pts: Vec<DVec3>, n: DVec3) -> Vec<DVec3> {
    let c = pts.iter().copied().sum::<DVec3>() / pts.len() as f64;
    let u = n.any_orthonormal_vector();
    let v = n.normalize().cross(u);
    let angle = |p: &DVec3| (*p - c).dot(v).atan2((*p - c).dot(u));
    pts.sort_by(|a, b| angle(a).total_cmp(&angle(b)));
    let scale = pts
        .iter()
        .map(|p| p.abs().max_element())
        .fold(0.0, f64::max);
    pts.dedup_by(|a, b| (*a - *b).abs().max_element() <= scale * 1e-14);
    if pts.len() > 1 && (pts[0] - pts[pts.len() - 1]).abs().max_element() <= scale * 1e-14 {
        pts.pop();
    }
    pts
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_cube_cut_by_planes_has_the_areas_of_its_parts() {
        let cube = Polytope::from_box(DVec3::ZERO, DVec3::ONE);
        assert!((cube.area() - 6.0).abs() < 1e-12);
        // Axis-aligned at a quarter: boxes of 0.25 and 0.75.
        let (b, a) = cube.split_areas(DVec3::X, 0.25);
        assert!((b - 2.0 * (0.25 + 0.25 + 1.0)).abs() < 1e-12, "{b}");
        assert!((a - 2.0 * (0.75 + 0.75 + 1.0)).abs() < 1e-12, "{a}");
        // The diagonal plane x + y = 1: two prisms on right triangles.
        let n = DVec3::new(1.0, 1.0, 0.0).normalize();
        let d = n.dot(DVec3::new(0.5, 0.5, 0.0));
        let (b, a) = cube.split_areas(n, d);
        // Each part: two triangles (0.5 each), two unit squares and the cut, 1 x sqrt(2).
        let want = 1.0 + 2.0 + 2f64.sqrt();
        assert!(
            (b - want).abs() < 1e-12 && (a - want).abs() < 1e-12,
            "{b} {a}"
        );
        // Clipping gives a polytope of the same area as predicted, and a plane missing the cell
        // leaves it whole on one side.
        let part = cube.clip(n, d);
        assert!((part.area() - want).abs() < 1e-12, "{}", part.area());
        let (b, a) = cube.split_areas(DVec3::Z, 2.0);
        assert!((b - 6.0).abs() < 1e-12 && a.abs() < 1e-12);
        // A corner cut off by a body diagonal plane: an equilateral cut of side sqrt(2) * 0.5.
        let n = DVec3::ONE.normalize();
        let corner = cube.clip(n, n.dot(DVec3::new(0.5, 0.0, 0.0)));
        let cut = 3f64.sqrt() / 4.0 * 0.5;
        let want = 3.0 * 0.125 + cut;
        assert!((corner.area() - want).abs() < 1e-12, "{}", corner.area());
        let (b, _) = cube.split_areas(n, n.dot(DVec3::new(0.5, 0.0, 0.0)));
        assert!((b - want).abs() < 1e-12);
        // Cutting the clipped part again agrees with its own split.
        let twice = corner.clip(-DVec3::Z, -0.1);
        let (_, above) = corner.split_areas(DVec3::Z, 0.1);
        assert!((twice.area() - above).abs() < 1e-12);
    }
}
