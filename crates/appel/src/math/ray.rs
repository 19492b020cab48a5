use glam::Vec3;

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
