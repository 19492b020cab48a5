//! What a structure did while building and while tracing one ray, step by step, for the page to
//! replay: the build's splits, and the ray's visited cells or nodes, objects tested, mailbox hits
//! and early exit.

use super::geometry::{Box2, Ray2, Shape, P2};
use serde::Serialize;

/// One step of a build: a node (its region as a polygon), the split line drawn across it (none
/// for a leaf), and for SAH builds the cost of each candidate split along the chosen axis.
#[derive(Clone, Debug, Serialize)]
pub struct BuildStep {
    pub depth: u32,
    pub region: Vec<P2>,
    pub split: Option<[P2; 2]>,
    pub objects: usize,
    pub leaf: bool,
    /// Candidate positions and their costs (the SAH curve), with the one chosen.
    pub sah: Option<SahCurve>,
}

#[derive(Clone, Debug, Serialize)]
pub struct SahCurve {
    pub axis: usize,
    pub positions: Vec<f64>,
    pub costs: Vec<f64>,
    pub chosen: usize,
    /// The cost of not splitting (a leaf of all the node's objects).
    pub leaf_cost: f64,
}

#[derive(Clone, Debug, Serialize)]
#[serde(tag = "step", rename_all = "snake_case")]
pub enum TraceStep {
    /// A cell or node the ray enters, with the ray's interval inside it.
    Visit {
        id: usize,
        region: Vec<P2>,
        t_enter: f64,
        t_exit: f64,
    },
    /// An object tested: where it was hit (if it was).
    Test { object: usize, t: Option<f64> },
    /// An object already tested in an earlier cell: the mailbox (Amanatides and Woo 1987)
    /// skips it.
    Mailbox { object: usize },
    /// The nearest hit so far lies before the next cell or node: the traversal stops.
    EarlyExit { t: f64 },
    /// A hit accepted although it lies beyond the cell being visited (the grid's pitfall when
    /// hits are not checked against the cell).
    AcceptedOutsideCell { object: usize, t: f64, t_exit: f64 },
}

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub struct Counters {
    pub visited: usize,
    pub tests: usize,
    pub mailbox_hits: usize,
}

#[derive(Clone, Debug, Serialize)]
pub struct Trace {
    pub steps: Vec<TraceStep>,
    pub hit: Option<(usize, f64)>,
    pub counters: Counters,
}

/// Records a traversal: tests objects through a mailbox and keeps the nearest hit.
pub struct Tracer<'a> {
    pub objects: &'a [Shape],
    pub ray: Ray2,
    tested: Vec<bool>,
    /// Each tested object's hit, so that a mailbox skip still knows it.
    pub trace: Trace,
}

impl<'a> Tracer<'a> {
    pub fn new(objects: &'a [Shape], ray: Ray2) -> Self {
        Self {
            objects,
            ray,
            tested: vec![false; objects.len()],
            trace: Trace {
                steps: Vec::new(),
                hit: None,
                counters: Counters::default(),
            },
        }
    }

    pub fn visit(&mut self, id: usize, region: Vec<P2>, t_enter: f64, t_exit: f64) {
        self.trace.counters.visited += 1;
        self.trace.steps.push(TraceStep::Visit {
            id,
            region,
            t_enter,
            t_exit,
        });
    }

    /// Tests `object` unless the mailbox says it was; returns its hit when tested now.
    pub fn test(&mut self, object: usize) -> Option<f64> {
        if self.tested[object] {
            self.trace.counters.mailbox_hits += 1;
            self.trace.steps.push(TraceStep::Mailbox { object });
            return None;
        }
        self.tested[object] = true;
        self.trace.counters.tests += 1;
        let t = self.objects[object].intersect(&self.ray, 0.0, f64::INFINITY);
        self.trace.steps.push(TraceStep::Test { object, t });
        if let Some(t) = t {
            if self.trace.hit.is_none_or(|(_, best)| t < best) {
                self.trace.hit = Some((object, t));
            }
        }
        t
    }

    pub fn best_t(&self) -> f64 {
        self.trace.hit.map_or(f64::INFINITY, |h| h.1)
    }

    /// Stops if the nearest hit lies before `t_next`, where the next region begins.
    pub fn exit_before(&mut self, t_next: f64) -> bool {
        let best = self.best_t();
        if best <= t_next {
            self.trace.steps.push(TraceStep::EarlyExit { t: best });
            true
        } else {
            false
        }
    }

    pub fn finish(self) -> Trace {
        self.trace
    }
}

/// The leaf step of a region with `objects` objects.
pub fn leaf_step(depth: u32, region: Vec<P2>, objects: usize) -> BuildStep {
    BuildStep {
        depth,
        region,
        split: None,
        objects,
        leaf: true,
        sah: None,
    }
}

pub fn box_region(b: Box2) -> Vec<P2> {
    b.corners()
}
