//! Geometry queries answered with the ray-tracing machinery and beside it: is a point inside a
//! closed mesh, which point of a mesh is nearest, the winding number.

mod closest;
mod inside;
mod winding;

pub use closest::{closest_on_triangle, Closest, ClosestPoint};
pub use inside::InsideTester;
pub use winding::winding_number;
