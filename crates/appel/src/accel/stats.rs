use std::time::Duration;

/// What a built structure costs.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct AccelStats {
    pub name: &'static str,
    pub primitives: usize,
    pub build_time: Duration,
    /// Bytes held by the structure itself (nodes, index arrays, cells), not the primitives.
    pub bytes: usize,
    /// Interior nodes, or cells for a grid.
    pub nodes: usize,
    pub leaves: usize,
    pub depth: usize,
    /// Surface area heuristic cost of the tree, where defined.
    pub sah_cost: Option<f64>,
}

/// What traversal did, summed over rays: divide by `rays` for the per-ray means.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct TraversalStats {
    pub rays: u64,
    /// Nodes (or grid cells) visited.
    pub nodes_visited: u64,
    /// Ray-primitive intersection tests.
    pub prim_tests: u64,
    /// Queries of instances' own structures (a ray reaching a mesh instance is traced through its
    /// prototype's structure), with their nodes visited and primitive tests: counted apart, so
    /// that the means above stay those of the scene's structure.
    pub instance_queries: u64,
    pub instance_nodes_visited: u64,
    pub instance_prim_tests: u64,
}

impl TraversalStats {
    pub fn merge(&mut self, o: &TraversalStats) {
        self.rays += o.rays;
        self.nodes_visited += o.nodes_visited;
        self.prim_tests += o.prim_tests;
        self.instance_queries += o.instance_queries;
        self.instance_nodes_visited += o.instance_nodes_visited;
        self.instance_prim_tests += o.instance_prim_tests;
    }

    /// Adds a query of an instance's structure, whose own statistics are `inner`.
    pub fn add_instance_query(&mut self, inner: &TraversalStats) {
        self.instance_queries += inner.rays;
        self.instance_nodes_visited += inner.nodes_visited;
        self.instance_prim_tests += inner.prim_tests;
    }
}
