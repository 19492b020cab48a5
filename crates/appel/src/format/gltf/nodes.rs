//! The node hierarchy of a glTF file's scene, walked once: each node with its world transform,
//! in traversal order (depth first, children in the order they are listed).

use crate::error::{Error, Location, Result};
use ::gltf::{Document, Node};
use glam::Mat4;
use std::path::Path;

/// Deeper hierarchies are refused, as the mesh reader refuses them: real files are a few levels
/// deep, and the walk recurses.
const MAX_DEPTH: usize = 256;

/// A node of the scene and where it stands in the world.
pub struct Placed<'a> {
    pub node: Node<'a>,
    pub world: Mat4,
}

/// Every node of the scene the file shows ([`crate::io::gltf::scene_roots`]), each with its world
/// transform: its local transform (`matrix`, or `translation * rotation * scale`) after its
/// parent's (glTF 2.0 section 3.5.3). A node that is its own ancestor is an error: the hierarchy
/// must be a set of disjoint trees, and the `gltf` crate's validation does not check it.
/// `text` is the file's JSON (of a `.gltf`), to place a cycle at its line.
pub fn placed_nodes<'a>(
    document: &'a Document,
    path: &Path,
    text: Option<&str>,
) -> Result<Vec<Placed<'a>>> {
    let mut walk = Walk {
        path,
        text,
        on_path: vec![false; document.nodes().len()],
        ancestors: vec![],
        out: vec![],
    };
    for root in crate::io::gltf::scene_roots(document) {
        walk.node(root, Mat4::IDENTITY)?;
    }
    Ok(walk.out)
}

struct Walk<'a, 'p> {
    path: &'p Path,
    text: Option<&'p str>,
    /// Whether each node is on the path from the root to the node being walked.
    on_path: Vec<bool>,
    ancestors: Vec<usize>,
    out: Vec<Placed<'a>>,
}

impl<'a> Walk<'a, '_> {
    /// An error at the file, or at the line of `json_path` in it.
    fn err(&self, json_path: &str, message: String) -> Error {
        let line = self
            .text
            .and_then(|t| crate::io::json_path::line_of(t, json_path));
        let at = match line {
            Some(line) => Location::line(self.path, line, None),
            None => Location::file(self.path),
        };
        Error::input(at, message)
    }

    fn node(&mut self, node: Node<'a>, parent: Mat4) -> Result<()> {
        let i = node.index();
        if self.on_path[i] {
            let chain: Vec<String> = self
                .ancestors
                .iter()
                .skip_while(|&&a| a != i)
                .chain(std::iter::once(&i))
                .map(usize::to_string)
                .collect();
            let parent = self.ancestors.last().copied().unwrap_or(i);
            return Err(self.err(
                &format!("nodes[{parent}].children"),
                format!(
                    "node {i} is its own ancestor (nodes {}): a node hierarchy must be a tree",
                    chain.join(" -> ")
                ),
            ));
        }
        if self.ancestors.len() >= MAX_DEPTH {
            return Err(self.err(
                &format!("nodes[{i}]"),
                format!("node {i}: the node hierarchy is deeper than {MAX_DEPTH} levels"),
            ));
        }
        let world = parent * Mat4::from_cols_array_2d(&node.transform().matrix());
        if !world.is_finite() {
            return Err(self.err(
                &format!("nodes[{i}]"),
                format!("node {i}: its transform is not finite"),
            ));
        }
        self.on_path[i] = true;
        self.ancestors.push(i);
        let children: Vec<Node<'a>> = node.children().collect();
        self.out.push(Placed { node, world });
        for child in children {
            self.node(child, world)?;
        }
        self.ancestors.pop();
        self.on_path[i] = false;
        Ok(())
    }
}
