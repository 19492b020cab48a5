use super::{AccelStats, Hit, NoOptions, Primitives, Structure, TraversalStats};
use crate::math::Ray;

/// Exhaustive intersection: every ray tests every primitive. The reference the others are checked
/// against, and the cost (#rays x #primitives) they exist to avoid.
#[derive(Clone, Debug, Default)]
pub struct Brute {
    count: usize,
}

impl Brute {
    pub fn build<P: Primitives>(prims: &P) -> Self {
        Self {
            count: prims.count(),
        }
    }

    pub fn intersect<P: Primitives>(
        &self,
        prims: &P,
        ray: &Ray,
        t_max: f32,
        stats: &mut TraversalStats,
    ) -> Option<Hit> {
        stats.rays += 1;
        stats.prim_tests += self.count as u64;
        let mut best: Option<Hit> = None;
        let mut t_max = t_max;
        for i in 0..self.count {
            if let Some(h) = prims.intersect_counted(i, ray, t_max, stats) {
                t_max = h.t;
                best = Some(Hit::new(i, h));
            }
        }
        best
    }

    pub fn occluded<P: Primitives>(
        &self,
        prims: &P,
        ray: &Ray,
        t_max: f32,
        stats: &mut TraversalStats,
    ) -> bool {
        stats.rays += 1;
        for i in 0..self.count {
            stats.prim_tests += 1;
            if prims.occluded_counted(i, ray, t_max, stats) {
                return true;
            }
        }
        false
    }

    pub fn stats(&self) -> AccelStats {
        AccelStats {
            name: Self::NAME,
            primitives: self.count,
            ..Default::default()
        }
    }
}

impl Structure for Brute {
    const NAME: &'static str = "brute";
    type Options = NoOptions;

    fn build<P: Primitives>(prims: &P, options: &NoOptions) -> Self {
        let _ = options;
        Brute::build(prims)
    }

    super::structure::forward_queries!(Brute);
}
