//! The 2D scene: points, boxes, rays and the three kinds of object of the lecture's figures
//! (circles, segments, triangles), each with its bounds, its intersection with a ray, and the
//! side of a line it lies on.

use serde::Serialize;

#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct P2 {
    pub x: f64,
    pub y: f64,
}

impl P2 {
    pub const fn new(x: f64, y: f64) -> Self {
        Self { x, y }
    }
    pub fn plus(self, o: P2) -> P2 {
        P2::new(self.x + o.x, self.y + o.y)
    }
    pub fn minus(self, o: P2) -> P2 {
        P2::new(self.x - o.x, self.y - o.y)
    }
    pub fn scale(self, k: f64) -> P2 {
        P2::new(self.x * k, self.y * k)
    }
    pub fn dot(self, o: P2) -> f64 {
        self.x * o.x + self.y * o.y
    }
    /// The z component of the 3D cross product.
    pub fn cross(self, o: P2) -> f64 {
        self.x * o.y - self.y * o.x
    }
    pub fn get(self, axis: usize) -> f64 {
        if axis == 0 {
            self.x
        } else {
            self.y
        }
    }
}

/// An axis-aligned box.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Box2 {
    pub min: P2,
    pub max: P2,
}

impl Box2 {
    pub const EMPTY: Box2 = Box2 {
        min: P2::new(f64::INFINITY, f64::INFINITY),
        max: P2::new(f64::NEG_INFINITY, f64::NEG_INFINITY),
    };

    pub fn union(self, o: Box2) -> Box2 {
        Box2 {
            min: P2::new(self.min.x.min(o.min.x), self.min.y.min(o.min.y)),
            max: P2::new(self.max.x.max(o.max.x), self.max.y.max(o.max.y)),
        }
    }
    pub fn add_point(self, p: P2) -> Box2 {
        self.union(Box2 { min: p, max: p })
    }
    pub fn extent(self) -> P2 {
        self.max.minus(self.min)
    }
    pub fn centre(self) -> P2 {
        self.min.plus(self.max).scale(0.5)
    }
    /// In 2D a random line meets a convex region with probability proportional to its
    /// perimeter (Cauchy-Crofton), which therefore plays the part of the surface area in the SAH.
    pub fn perimeter(self) -> f64 {
        let e = self.extent();
        if e.x < 0.0 || e.y < 0.0 {
            0.0
        } else {
            2.0 * (e.x + e.y)
        }
    }
    pub fn overlaps(self, o: Box2) -> bool {
        self.min.x <= o.max.x
            && o.min.x <= self.max.x
            && self.min.y <= o.max.y
            && o.min.y <= self.max.y
    }
    pub fn corners(self) -> Vec<P2> {
        vec![
            self.min,
            P2::new(self.max.x, self.min.y),
            self.max,
            P2::new(self.min.x, self.max.y),
        ]
    }
    /// The slab test (Kay and Kajiya 1986): the interval `[t_enter, t_exit]` of the ray inside
    /// the box, clipped to `[t0, t1]`, or `None` if it misses.
    pub fn slab(self, ray: &Ray2, t0: f64, t1: f64) -> Option<(f64, f64)> {
        let (mut lo, mut hi) = (t0, t1);
        for axis in 0..2 {
            let inv = 1.0 / ray.d.get(axis);
            let mut a = (self.min.get(axis) - ray.o.get(axis)) * inv;
            let mut b = (self.max.get(axis) - ray.o.get(axis)) * inv;
            if a > b {
                std::mem::swap(&mut a, &mut b);
            }
            // NaN (a zero direction component on the slab's plane) leaves the bound as is.
            if a > lo {
                lo = a;
            }
            if b < hi {
                hi = b;
            }
        }
        (lo <= hi).then_some((lo, hi))
    }
}

/// A ray `o + t d` for `t >= 0`, `d` of unit length.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Ray2 {
    pub o: P2,
    pub d: P2,
}

impl Ray2 {
    /// The ray from `a` towards `b`; `None` if they coincide.
    pub fn through(a: P2, b: P2) -> Option<Ray2> {
        let d = b.minus(a);
        let len = d.dot(d).sqrt();
        (len > 1e-12).then(|| Ray2 {
            o: a,
            d: d.scale(1.0 / len),
        })
    }
    pub fn at(&self, t: f64) -> P2 {
        self.o.plus(self.d.scale(t))
    }
}

#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "lowercase")]
pub enum Shape {
    Circle { c: P2, r: f64 },
    Segment { a: P2, b: P2 },
    Triangle { a: P2, b: P2, c: P2 },
}

/// Which side of a line `n . p = d` an object lies on: it may reach either or both.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Sides {
    pub below: bool,
    pub above: bool,
}

impl Shape {
    pub fn bounds(&self) -> Box2 {
        match *self {
            Shape::Circle { c, r } => Box2 {
                min: P2::new(c.x - r, c.y - r),
                max: P2::new(c.x + r, c.y + r),
            },
            Shape::Segment { a, b } => Box2::EMPTY.add_point(a).add_point(b),
            Shape::Triangle { a, b, c } => Box2::EMPTY.add_point(a).add_point(b).add_point(c),
        }
    }

    pub fn centroid(&self) -> P2 {
        match *self {
            Shape::Circle { c, .. } => c,
            Shape::Segment { a, b } => a.plus(b).scale(0.5),
            Shape::Triangle { a, b, c } => a.plus(b).plus(c).scale(1.0 / 3.0),
        }
    }

    /// The nearest `t` in `[t0, t1]` where the ray meets the object's outline.
    pub fn intersect(&self, ray: &Ray2, t0: f64, t1: f64) -> Option<f64> {
        let ok = |t: f64| (t >= t0 && t <= t1).then_some(t);
        match *self {
            Shape::Circle { c, r } => {
                // |o + t d - c|^2 = r^2 with |d| = 1.
                let oc = ray.o.minus(c);
                let b = oc.dot(ray.d);
                let disc = b * b - (oc.dot(oc) - r * r);
                if disc < 0.0 {
                    return None;
                }
                let s = disc.sqrt();
                ok(-b - s).or_else(|| ok(-b + s))
            }
            Shape::Segment { a, b } => segment_hit(ray, a, b).and_then(ok),
            Shape::Triangle { a, b, c } => [(a, b), (b, c), (c, a)]
                .into_iter()
                .filter_map(|(p, q)| segment_hit(ray, p, q).and_then(ok))
                .min_by(f64::total_cmp),
        }
    }

    /// The sides of the line `n . p = d` the object reaches.
    pub fn sides(&self, n: P2, d: f64) -> Sides {
        let side_of = |pts: &[P2]| {
            let v: Vec<f64> = pts.iter().map(|p| n.dot(*p) - d).collect();
            Sides {
                below: v.iter().any(|&x| x < 0.0),
                above: v.iter().any(|&x| x >= 0.0),
            }
        };
        match *self {
            Shape::Circle { c, r } => {
                let s = (n.dot(c) - d) / n.dot(n).sqrt();
                Sides {
                    below: s - r < 0.0,
                    above: s + r >= 0.0,
                }
            }
            Shape::Segment { a, b } => side_of(&[a, b]),
            Shape::Triangle { a, b, c } => side_of(&[a, b, c]),
        }
    }
}

/// The ray's `t` at the segment `pq`, if it crosses it.
fn segment_hit(ray: &Ray2, p: P2, q: P2) -> Option<f64> {
    let e = q.minus(p);
    let denom = ray.d.cross(e);
    if denom.abs() < 1e-15 {
        return None;
    }
    let w = p.minus(ray.o);
    let t = w.cross(e) / denom;
    let u = w.cross(ray.d) / denom;
    ((0.0..=1.0).contains(&u) && t >= 0.0).then_some(t)
}

/// The nearest hit over every object, testing them all: the reference the structures must match.
pub fn brute_force(objects: &[Shape], ray: &Ray2) -> Option<(usize, f64)> {
    objects
        .iter()
        .enumerate()
        .filter_map(|(i, s)| s.intersect(ray, 0.0, f64::INFINITY).map(|t| (i, t)))
        .min_by(|a, b| a.1.total_cmp(&b.1))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_shape_is_hit_where_geometry_says() {
        let ray = Ray2::through(P2::new(0.0, 0.0), P2::new(1.0, 0.0)).unwrap();
        let c = Shape::Circle {
            c: P2::new(5.0, 0.0),
            r: 1.0,
        };
        assert!((c.intersect(&ray, 0.0, f64::INFINITY).unwrap() - 4.0).abs() < 1e-12);
        // From inside the circle the exit is the hit.
        assert!((c.intersect(&ray, 4.5, f64::INFINITY).unwrap() - 6.0).abs() < 1e-12);
        let s = Shape::Segment {
            a: P2::new(3.0, -1.0),
            b: P2::new(3.0, 1.0),
        };
        assert_eq!(s.intersect(&ray, 0.0, f64::INFINITY), Some(3.0));
        assert_eq!(s.intersect(&ray, 0.0, 2.0), None);
        let t = Shape::Triangle {
            a: P2::new(2.0, -1.0),
            b: P2::new(4.0, -1.0),
            c: P2::new(2.0, 1.0),
        };
        assert_eq!(t.intersect(&ray, 0.0, f64::INFINITY), Some(2.0));
        let miss = Shape::Segment {
            a: P2::new(3.0, 1.0),
            b: P2::new(3.0, 2.0),
        };
        assert_eq!(miss.intersect(&ray, 0.0, f64::INFINITY), None);
    }

    #[test]
    fn slab_interval_of_a_box() {
        let b = Box2 {
            min: P2::new(1.0, -1.0),
            max: P2::new(3.0, 1.0),
        };
        let ray = Ray2::through(P2::new(0.0, 0.0), P2::new(1.0, 0.0)).unwrap();
        assert_eq!(b.slab(&ray, 0.0, f64::INFINITY), Some((1.0, 3.0)));
        let up = Ray2::through(P2::new(0.0, 0.0), P2::new(0.0, 1.0)).unwrap();
        assert_eq!(b.slab(&up, 0.0, f64::INFINITY), None);
    }
}
