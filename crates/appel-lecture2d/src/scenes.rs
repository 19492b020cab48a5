//! The 2D scenes of the lecture page, all inside [`super::WORLD`] and reproducible from a seed:
//! the lecture's figure (a few circles, segments and triangles), random and clustered sets, and
//! the teapot in a stadium (a small dense cluster in a large, nearly empty scene).

use super::geometry::{Ray2, Shape, P2};

pub const NAMES: &[&str] = &["figures", "random", "clustered", "stadium"];

/// SplitMix64 (Steele, Lea and Flood 2014): small, and the same sequence on every platform.
pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u64) -> Rng {
        Rng(seed ^ 0x853c_49e6_748f_ea9b)
    }
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }
    /// Uniform in [lo, hi).
    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// A small object of random kind and orientation around `c`, of size about `s`.
fn object_at(rng: &mut Rng, c: P2, s: f64) -> Shape {
    let angle = rng.range(0.0, std::f64::consts::TAU);
    let dir = |a: f64| P2::new(a.cos(), a.sin());
    match rng.next_u64() % 3 {
        0 => Shape::Circle {
            c,
            r: s * rng.range(0.3, 0.6),
        },
        1 => {
            let h = dir(angle).scale(s * 0.7);
            Shape::Segment {
                a: c.minus(h),
                b: c.plus(h),
            }
        }
        _ => Shape::Triangle {
            a: c.plus(dir(angle).scale(s * 0.6)),
            b: c.plus(dir(angle + 2.1).scale(s * 0.6)),
            c: c.plus(dir(angle + 4.2).scale(s * 0.6)),
        },
    }
}

/// The scene `name` with `n` objects (the figure has its own few).
pub fn scene(name: &str, n: usize, seed: u64) -> Vec<Shape> {
    let mut rng = Rng::new(seed);
    match name {
        "random" => (0..n)
            .map(|_| {
                let c = P2::new(rng.range(6.0, 94.0), rng.range(6.0, 94.0));
                let s = rng.range(2.0, 8.0);
                object_at(&mut rng, c, s)
            })
            .collect(),
        "clustered" => {
            let centres: Vec<P2> = (0..4)
                .map(|_| P2::new(rng.range(15.0, 85.0), rng.range(15.0, 85.0)))
                .collect();
            (0..n)
                .map(|i| {
                    let k = centres[i % centres.len()];
                    let c = P2::new(k.x + rng.range(-9.0, 9.0), k.y + rng.range(-9.0, 9.0));
                    let s = rng.range(1.5, 4.0);
                    object_at(&mut rng, c, s)
                })
                .collect()
        }
        "stadium" => {
            // The stadium: a ring of long segments around the field; the teapot: n tiny
            // objects within two units of one spot.
            let mut out: Vec<Shape> = (0..16)
                .map(|i| {
                    let a = |k: f64| std::f64::consts::TAU * k / 16.0;
                    let p = |k: f64| P2::new(50.0 + 46.0 * a(k).cos(), 50.0 + 46.0 * a(k).sin());
                    Shape::Segment {
                        a: p(i as f64),
                        b: p(i as f64 + 0.8),
                    }
                })
                .collect();
            let spot = P2::new(62.0, 41.0);
            out.extend((0..n.saturating_sub(16)).map(|_| {
                let c = P2::new(spot.x + rng.range(-2.0, 2.0), spot.y + rng.range(-2.0, 2.0));
                object_at(&mut rng, c, 0.4)
            }));
            out
        }
        _ => figures(),
    }
}

/// The lecture's figure: a handful of each kind of object, some large enough to span cells.
fn figures() -> Vec<Shape> {
    let p = P2::new;
    vec![
        Shape::Circle {
            c: p(20.0, 75.0),
            r: 8.0,
        },
        Shape::Circle {
            c: p(70.0, 80.0),
            r: 5.0,
        },
        Shape::Circle {
            c: p(45.0, 30.0),
            r: 3.0,
        },
        Shape::Circle {
            c: p(85.0, 20.0),
            r: 6.0,
        },
        Shape::Segment {
            a: p(10.0, 10.0),
            b: p(40.0, 55.0),
        },
        Shape::Segment {
            a: p(55.0, 60.0),
            b: p(90.0, 50.0),
        },
        Shape::Segment {
            a: p(60.0, 10.0),
            b: p(62.0, 40.0),
        },
        Shape::Triangle {
            a: p(30.0, 85.0),
            b: p(50.0, 95.0),
            c: p(45.0, 70.0),
        },
        Shape::Triangle {
            a: p(70.0, 30.0),
            b: p(80.0, 40.0),
            c: p(72.0, 45.0),
        },
        Shape::Triangle {
            a: p(15.0, 40.0),
            b: p(25.0, 42.0),
            c: p(18.0, 52.0),
        },
    ]
}

/// Rays from random points of the world in random directions (tests and counters).
pub fn random_rays(n: usize, seed: u64) -> Vec<Ray2> {
    let mut rng = Rng::new(seed);
    (0..n)
        .filter_map(|_| {
            let o = P2::new(rng.range(0.0, 100.0), rng.range(0.0, 100.0));
            let a = rng.range(0.0, std::f64::consts::TAU);
            Ray2::through(o, o.plus(P2::new(a.cos(), a.sin())))
        })
        .collect()
}
