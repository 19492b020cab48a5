//! The trees that cut space with lines (kd-tree: axis-parallel; BSP: any direction): a node's
//! region is a convex polygon, cut by its line `n . p = d` into the part below (`n . p < d`) and
//! the part above. Traversal is the classic recursive one: the near side over `[t_min, t_split]`,
//! then the far side over `[t_split, t_max]` unless a hit was found before `t_split`.

use super::geometry::{Ray2, Shape, P2};
use super::trace::{leaf_step, BuildStep, SahCurve, Trace, Tracer};

pub struct SplitNode {
    pub region: Vec<P2>,
    /// `(n, d)` and the children below and above; `None` for a leaf.
    pub split: Option<(P2, f64, usize, usize)>,
    pub objects: Vec<usize>,
}

/// A node's choice: a line and, for SAH builds, the curve it came from; `None` makes a leaf.
pub type Choice = Option<(P2, f64, Option<SahCurve>)>;

/// Picks a node's line from the objects, the node's region and the objects inside it, and depth.
pub type Chooser<'a> = &'a dyn Fn(&[Shape], &[P2], &[usize], u32) -> Choice;

pub struct SplitTree {
    pub nodes: Vec<SplitNode>,
    pub steps: Vec<BuildStep>,
}

pub const MAX_DEPTH: u32 = 12;

impl SplitTree {
    /// Builds by asking `choose` for each node's line, given the region and its objects.
    pub fn build(objects: &[Shape], region: Vec<P2>, choose: Chooser) -> SplitTree {
        let mut t = SplitTree {
            nodes: Vec::new(),
            steps: Vec::new(),
        };
        t.node(objects, region, (0..objects.len()).collect(), 0, choose);
        t
    }

    fn node(
        &mut self,
        objects: &[Shape],
        region: Vec<P2>,
        inside: Vec<usize>,
        depth: u32,
        choose: Chooser,
    ) -> usize {
        let id = self.nodes.len();
        self.nodes.push(SplitNode {
            region: region.clone(),
            split: None,
            objects: Vec::new(),
        });
        let choice = if depth >= MAX_DEPTH || inside.len() <= 1 {
            None
        } else {
            choose(objects, &region, &inside, depth)
        };
        let Some((n, d, sah)) = choice else {
            self.steps.push(leaf_step(depth, region, inside.len()));
            self.nodes[id].objects = inside;
            return id;
        };
        let below = clip(&region, n, d, false);
        let above = clip(&region, n, d, true);
        self.steps.push(BuildStep {
            depth,
            region: region.clone(),
            split: chord(&region, n, d),
            objects: inside.len(),
            leaf: false,
            sah,
        });
        let (mut lo, mut hi) = (Vec::new(), Vec::new());
        for &k in &inside {
            let s = objects[k].sides(n, d);
            if s.below {
                lo.push(k);
            }
            if s.above {
                hi.push(k);
            }
        }
        let a = self.node(objects, below, lo, depth + 1, choose);
        let b = self.node(objects, above, hi, depth + 1, choose);
        self.nodes[id].split = Some((n, d, a, b));
        id
    }

    pub fn trace(&self, objects: &[Shape], ray: &Ray2, t0: f64, t1: f64) -> Trace {
        let mut tr = Tracer::new(objects, *ray);
        if !self.nodes.is_empty() {
            self.walk(0, t0, t1, &mut tr);
        }
        tr.finish()
    }

    /// Returns true once the traversal is over (a hit before the rest).
    fn walk(&self, id: usize, tmin: f64, tmax: f64, tr: &mut Tracer) -> bool {
        let node = &self.nodes[id];
        let Some((n, d, below, above)) = node.split else {
            tr.visit(id, node.region.clone(), tmin, tmax);
            for &k in &node.objects {
                tr.test(k);
            }
            return tr.exit_before(tmax);
        };
        let ray = tr.ray;
        let denom = n.dot(ray.d);
        let start = n.dot(ray.at(tmin)) - d;
        // The side the ray starts on (on the line: the side it heads to).
        let start_below = start < 0.0 || (start == 0.0 && denom < 0.0);
        let (near, far) = if start_below {
            (below, above)
        } else {
            (above, below)
        };
        if denom == 0.0 {
            return self.walk(near, tmin, tmax, tr);
        }
        let t_split = (d - n.dot(ray.o)) / denom;
        if t_split >= tmax || t_split <= tmin {
            // The line is crossed outside this interval: only one side is entered.
            return self.walk(near, tmin, tmax, tr);
        }
        if self.walk(near, tmin, t_split, tr) {
            return true;
        }
        self.walk(far, t_split, tmax, tr)
    }
}

/// The part of a convex polygon above (or below) the line (Sutherland and Hodgman 1974).
pub fn clip(poly: &[P2], n: P2, d: f64, keep_above: bool) -> Vec<P2> {
    let side = |p: P2| {
        let s = n.dot(p) - d;
        if keep_above {
            s
        } else {
            -s
        }
    };
    let mut out = Vec::new();
    for i in 0..poly.len() {
        let (p, q) = (poly[i], poly[(i + 1) % poly.len()]);
        let (sp, sq) = (side(p), side(q));
        if sp >= 0.0 {
            out.push(p);
        }
        if (sp >= 0.0) != (sq >= 0.0) {
            let t = sp / (sp - sq);
            out.push(p.plus(q.minus(p).scale(t)));
        }
    }
    out
}

/// The segment of the line inside the convex polygon, for drawing the split.
fn chord(poly: &[P2], n: P2, d: f64) -> Option<[P2; 2]> {
    let mut pts = Vec::new();
    for i in 0..poly.len() {
        let (p, q) = (poly[i], poly[(i + 1) % poly.len()]);
        let (sp, sq) = (n.dot(p) - d, n.dot(q) - d);
        if (sp < 0.0) != (sq < 0.0) {
            pts.push(p.plus(q.minus(p).scale(sp / (sp - sq))));
        } else if sp == 0.0 {
            pts.push(p);
        }
    }
    (pts.len() >= 2).then(|| [pts[0], pts[pts.len() - 1]])
}
