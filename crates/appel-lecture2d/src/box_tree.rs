//! The traversal shared by the trees whose nodes are boxes (quadtree, BVH): front to back, the
//! children the ray meets visited in the order it enters them, a subtree skipped once the
//! nearest hit lies before its box.

use super::geometry::{Box2, Ray2, Shape};
use super::trace::{box_region, Trace, TraceStep, Tracer};

pub struct BoxNode {
    pub bounds: Box2,
    pub children: Vec<usize>,
    pub objects: Vec<usize>,
}

pub fn trace(nodes: &[BoxNode], objects: &[Shape], ray: &Ray2) -> Trace {
    let mut tr = Tracer::new(objects, *ray);
    if let Some(&root) = nodes.first().as_ref() {
        if let Some((a, b)) = root.bounds.slab(ray, 0.0, f64::INFINITY) {
            walk(nodes, 0, a, b, &mut tr);
        }
    }
    tr.finish()
}

fn walk(nodes: &[BoxNode], id: usize, t_enter: f64, t_exit: f64, tr: &mut Tracer) {
    let node = &nodes[id];
    tr.visit(id, box_region(node.bounds), t_enter, t_exit);
    for &k in &node.objects {
        tr.test(k);
    }
    let mut order: Vec<(f64, f64, usize)> = node
        .children
        .iter()
        .filter_map(|&c| {
            nodes[c]
                .bounds
                .slab(&tr.ray, 0.0, f64::INFINITY)
                .map(|(a, b)| (a, b, c))
        })
        .collect();
    order.sort_by(|x, y| x.0.total_cmp(&y.0));
    for (a, b, c) in order {
        // Strictly before: a hit on the box's edge may still be beaten inside it by nothing,
        // but an equal t elsewhere cannot be nearer.
        if tr.best_t() < a {
            tr.trace.steps.push(TraceStep::EarlyExit { t: tr.best_t() });
            return;
        }
        walk(nodes, c, a, b, tr);
    }
}
