use glam::{DVec3, Vec3};

/// A ray `origin + t * dir`. `dir` need not be unit length (shadow rays towards a point light span
/// `t` in `[0, 1)`), but camera, reflected and refracted rays are normalized so that `t` is a distance.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray {
    pub origin: Vec3,
    pub dir: Vec3,
}

impl Ray {
    pub fn new(origin: Vec3, dir: Vec3) -> Self {
        Self { origin, dir }
    }

    pub fn at(&self, t: f32) -> Vec3 {
        self.origin + t * self.dir
    }
}

/// A ray in f64, with `|dir|^2`: what the f64 solves of spheres and planes start from. A leaf of
/// several such primitives converts its ray once instead of once per test; the conversions are
/// exact, so every test computes what it would from the f32 ray.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RayF64 {
    pub origin: DVec3,
    pub dir: DVec3,
    pub dir_length_squared: f64,
}

impl RayF64 {
    #[inline]
    pub fn new(ray: &Ray) -> Self {
        let dir = ray.dir.as_dvec3();
        Self {
            origin: ray.origin.as_dvec3(),
            dir,
            dir_length_squared: dir.length_squared(),
        }
    }
}
