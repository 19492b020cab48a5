//! MikkTSpace tangents (Mikkelsen 2008, "Simulation of wrinkled surfaces revisited") for glTF
//! primitives with a normal texture but no `TANGENT`, as glTF 2.0 (section 3.7.2.1) asks of
//! clients. Unlike a frame from dp/du, MikkTSpace's handedness w follows the uv layout, so
//! mirrored uv islands read the normal map's y the right way round.

use crate::geometry::TriangleMesh;
use glam::Vec4;

/// The mesh seen through `mikktspace::Geometry`, its usable faces only; tangents land per
/// vertex.
struct Mikk<'a> {
    mesh: &'a TriangleMesh,
    faces: Vec<usize>,
    normals: &'a [glam::Vec3],
    uvs: &'a [glam::Vec2],
    tangents: Vec<Vec4>,
}

impl Mikk<'_> {
    fn vertex(&self, face: usize, vert: usize) -> usize {
        self.mesh.indices[self.faces[face]][vert] as usize
    }
}

/// Faces MikkTSpace can take: three distinct vertices with finite attributes and a nonzero
/// area. The `mikktspace` crate indexes past its vertex hash table when every position it is
/// given is the same point (its grid then leaves the last cells empty), so degenerate input
/// is filtered here rather than handed over; those faces keep no tangent of their own.
fn usable_faces(mesh: &TriangleMesh, normals: &[glam::Vec3], uvs: &[glam::Vec2]) -> Vec<usize> {
    let finite =
        |v: usize| mesh.positions[v].is_finite() && normals[v].is_finite() && uvs[v].is_finite();
    (0..mesh.indices.len())
        .filter(|&f| {
            let [a, b, c] = mesh.indices[f].map(|i| i as usize);
            let distinct = a != b && b != c && a != c;
            let (pa, pb, pc) = (mesh.positions[a], mesh.positions[b], mesh.positions[c]);
            distinct
                && [a, b, c].into_iter().all(finite)
                && (pb - pa).cross(pc - pa).length_squared() > 0.0
        })
        .collect()
}

impl mikktspace::Geometry for Mikk<'_> {
    fn num_faces(&self) -> usize {
        self.faces.len()
    }
    fn num_vertices_of_face(&self, _face: usize) -> usize {
        3
    }
    fn position(&self, face: usize, vert: usize) -> [f32; 3] {
        self.mesh.positions[self.vertex(face, vert)].into()
    }
    fn normal(&self, face: usize, vert: usize) -> [f32; 3] {
        self.normals[self.vertex(face, vert)].into()
    }
    /// glTF's v points down the image; MikkTSpace (like Blender, which the glTF exporters
    /// compute tangents in) expects it up, hence 1 - v.
    fn tex_coord(&self, face: usize, vert: usize) -> [f32; 2] {
        let uv = self.uvs[self.vertex(face, vert)];
        [uv.x, 1.0 - uv.y]
    }
    fn set_tangent_encoded(&mut self, tangent: [f32; 4], face: usize, vert: usize) {
        let v = self.vertex(face, vert);
        self.tangents[v] = Vec4::from(tangent);
    }
}

/// Per-vertex MikkTSpace tangents (xyz, handedness in w) of `mesh`, or `None` when it lacks
/// normals or uvs or MikkTSpace gives up. Corners sharing a vertex share its tangent: glTF
/// splits vertices at uv seams, so corners of one vertex agree but for rounding.
pub fn mikktspace_tangents(mesh: &TriangleMesh) -> Option<Vec<Vec4>> {
    let (normals, uvs) = (mesh.normals.as_deref()?, mesh.uvs.as_deref()?);
    let faces = usable_faces(mesh, normals, uvs);
    if faces.is_empty() {
        return None;
    }
    let mut m = Mikk {
        mesh,
        faces,
        normals,
        uvs,
        tangents: vec![Vec4::new(1.0, 0.0, 0.0, 1.0); mesh.positions.len()],
    };
    if !mikktspace::generate_tangents(&mut m) {
        return None;
    }
    m.tangents
        .iter()
        .all(|t| t.is_finite())
        .then_some(m.tangents)
}
