//! Mitsuba's `mesh_attribute` texture: a mesh's named values per vertex (interpolated with the
//! hit's barycentric coordinates) or per triangle, read where a ray hits the mesh.

use super::luminance;
use crate::description::loaded_mesh::MeshAttribute;
use glam::Vec3;

/// The attributes of one mesh.
pub type MeshAttributes = [MeshAttribute];

/// A hit on a mesh with attributes: its triangle, the triangle's vertices and the barycentric
/// weights of the hit point.
#[derive(Clone, Copy, Debug)]
pub struct AttributePoint<'a> {
    pub attributes: &'a MeshAttributes,
    pub triangle: u32,
    pub vertices: [u32; 3],
    pub barycentrics: [f32; 3],
}

impl AttributePoint<'_> {
    fn channels(&self, name: &str) -> Option<(&MeshAttribute, [f32; 4])> {
        let a = self.attributes.iter().find(|a| a.name == name)?;
        let c = a.channels;
        let mut v = [0.0f32; 4];
        if a.per_face {
            let base = self.triangle as usize * c;
            for (k, x) in v.iter_mut().enumerate().take(c.min(4)) {
                *x = a.data[base + k];
            }
        } else {
            for (&vi, &b) in self.vertices.iter().zip(&self.barycentrics) {
                let base = vi as usize * c;
                for (k, x) in v.iter_mut().enumerate().take(c.min(4)) {
                    *x += b * a.data[base + k];
                }
            }
        }
        Some((a, v))
    }

    /// The attribute as RGB: one channel as grey, else its first three (a missing third is 0).
    pub fn value(&self, name: &str) -> Option<Vec3> {
        let (a, v) = self.channels(name)?;
        Some(if a.channels == 1 {
            Vec3::splat(v[0])
        } else {
            Vec3::new(v[0], v[1], v[2])
        })
    }

    /// The attribute as one number: its value, or the luminance of a colour.
    pub fn value_1(&self, name: &str) -> Option<f32> {
        let (a, v) = self.channels(name)?;
        Some(if a.channels == 1 {
            v[0]
        } else {
            luminance(Vec3::new(v[0], v[1], v[2]))
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn vertex_values_interpolate_and_face_values_do_not() {
        let attributes = [
            MeshAttribute {
                name: "vertex_color".into(),
                per_face: false,
                channels: 3,
                data: vec![1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 9.0, 9.0, 9.0],
            },
            MeshAttribute {
                name: "face_weight".into(),
                per_face: true,
                channels: 1,
                data: vec![0.25, 0.75],
            },
        ];
        let p = AttributePoint {
            attributes: &attributes,
            triangle: 1,
            vertices: [0, 1, 2],
            barycentrics: [0.5, 0.3, 0.2],
        };
        assert_eq!(p.value("vertex_color"), Some(Vec3::new(0.5, 0.3, 0.2)));
        assert_eq!(p.value("face_weight"), Some(Vec3::splat(0.75)));
        assert_eq!(p.value_1("face_weight"), Some(0.75));
        assert!(
            (p.value_1("vertex_color").unwrap() - luminance(Vec3::new(0.5, 0.3, 0.2))).abs() < 1e-7
        );
        assert_eq!(p.value("face_color"), None);
    }
}
