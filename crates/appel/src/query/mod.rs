//! Geometry queries answered with the ray-tracing machinery: is a point inside a closed mesh?

mod inside;

pub use inside::InsideTester;
