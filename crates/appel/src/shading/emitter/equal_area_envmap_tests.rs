use super::super::chi2_sphere::{assert_fits, Rng, Spec};
use super::super::equal_area::square_to_sphere;
use super::super::{EmitterPlugin, EnvMap};
use super::*;

/// A sky with a smooth gradient, a bright sun and a dark ground, in an emitter frame whose pole
/// is +z (a lat-long map's pole is +y: `latlong` below turns its directions).
fn sky(d: Vec3) -> Vec3 {
    let sun = Vec3::new(0.4, 0.3, 0.8).normalize();
    let glow = 40.0 * d.dot(sun).max(0.0).powf(60.0);
    let up = d.z.max(0.0);
    Vec3::new(0.2 + up + glow, 0.3 + 0.8 * up + glow, 0.5 + 0.6 * up + 0.9 * glow)
        * if d.z < -0.1 { 0.2 } else { 1.0 }
}

/// The sky sampled at the centre of each texel of an `n` by `n` equal-area map.
fn equal_area_bitmap(n: u32) -> Bitmap {
    let mut data = Vec::new();
    for y in 0..n {
        for x in 0..n {
            let p = Vec2::new((x as f32 + 0.5) / n as f32, (y as f32 + 0.5) / n as f32);
            data.extend(sky(square_to_sphere(p)).to_array());
        }
    }
    Bitmap {
        width: n,
        height: n,
        channels: 3,
        data,
    }
}

/// The same sky as a Mitsuba lat-long map of `w` by `h` samples: row j at θ = π j / (h - 1)
/// from the map's +y pole, column i at u = (i + 1/2) / w with direction
/// (sin φ sin θ, cos θ, -cos φ sin θ), φ = 2π u.
fn latlong_bitmap(w: u32, h: u32) -> Bitmap {
    let mut data = Vec::new();
    for j in 0..h {
        let theta = PI * j as f32 / (h - 1) as f32;
        for i in 0..w {
            let phi = 2.0 * PI * (i as f32 + 0.5) / w as f32;
            let local = Vec3::new(
                phi.sin() * theta.sin(),
                theta.cos(),
                -phi.cos() * theta.sin(),
            );
            data.extend(sky(latlong_to_sky(local)).to_array());
        }
    }
    Bitmap {
        width: w,
        height: h,
        channels: 3,
        data,
    }
}

/// A lat-long map's frame (pole +y) to the sky's (pole +z): a quarter turn about x.
fn latlong_to_sky(d: Vec3) -> Vec3 {
    Vec3::new(d.x, -d.z, d.y)
}

/// The lat-long emitter's `to_world` that shows its map as the sky's frame shows the sky.
fn latlong_to_world() -> Mat4 {
    Mat4::from_mat3(Mat3::from_cols(
        latlong_to_sky(Vec3::X),
        latlong_to_sky(Vec3::Y),
        latlong_to_sky(Vec3::Z),
    ))
}

#[test]
fn sampling_fits_its_density_and_weights_are_radiance_over_density() {
    let e = EqualAreaEnvMap::new(&equal_area_bitmap(64), Mat4::from_rotation_x(0.3), 1.5).unwrap();
    assert_fits(
        "equalareaenvmap",
        &Spec {
            k: 64,
            depth: 0,
            ..Spec::sphere(300_000)
        },
        |u| EmitterPlugin::sample_li(&e, Vec3::ZERO, u).map(|s| s.wi),
        |wi| EmitterPlugin::pdf_li(&e, Vec3::ZERO, wi, Vec3::ZERO, Vec3::ZERO),
        1.0,
        0.01,
    );
    let mut rng = Rng::new(5);
    for _ in 0..2000 {
        let s = e.sample_li(rng.vec2()).unwrap();
        let pdf = e.pdf_li(s.wi);
        assert!((pdf / s.pdf - 1.0).abs() < 1e-3, "{pdf} vs {}", s.pdf);
        let w = e.radiance(s.wi) / pdf;
        assert!((w - s.weight).abs().max_element() <= 2e-3 * w.max_element() + 1e-6);
    }
}

/// The same sky stored both ways gives the same light: the radiance along directions away from
/// the sun's edge, the total power, and the irradiance of a surface facing each axis (a Monte
/// Carlo estimate drawn from each emitter's own sampling, which tests the densities too).
#[test]
fn agrees_with_a_latitude_longitude_map_of_the_same_sky() {
    let octa = EqualAreaEnvMap::new(&equal_area_bitmap(256), Mat4::IDENTITY, 1.0).unwrap();
    let latlong = EnvMap::new(&latlong_bitmap(512, 257), latlong_to_world(), 1.0).unwrap();
    let mut rng = Rng::new(17);
    for _ in 0..2000 {
        let d = square_to_sphere(rng.vec2());
        let exact = sky(d);
        // Nearest texel against bilinear: both within a texel of the smooth parts of the sky.
        let sun = Vec3::new(0.4, 0.3, 0.8).normalize();
        if d.dot(sun) > 0.9 || (d.z + 0.1).abs() < 0.03 {
            continue;
        }
        for (name, got) in [("octahedral", octa.radiance(d)), ("lat-long", latlong.radiance(d))] {
            assert!(
                (got - exact).abs().max_element() < 0.03 * exact.max_element(),
                "{name} at {d}: {got} vs {exact}"
            );
        }
    }
    let (po, pl) = (octa.power(), latlong.power());
    assert!((po / pl - Vec3::ONE).abs().max_element() < 0.01, "{po} vs {pl}");

    let irradiance = |sample: &dyn Fn(Vec2) -> Option<EmitterSample>, n: Vec3| {
        let mut rng = Rng::new(23);
        let (mut sum, mut sum2, count) = (0.0f64, 0.0f64, 200_000);
        for _ in 0..count {
            if let Some(s) = sample(rng.vec2()) {
                let x = (s.weight.x * s.wi.dot(n).max(0.0)) as f64;
                sum += x;
                sum2 += x * x;
            }
        }
        let mean = sum / count as f64;
        (mean, ((sum2 / count as f64 - mean * mean) / count as f64).sqrt())
    };
    for n in [Vec3::Z, -Vec3::Z, Vec3::X, Vec3::Y] {
        let (eo, so) = irradiance(&|u| octa.sample_li(u), n);
        let (el, sl) = irradiance(&|u| latlong.sample_li(u), n);
        let tolerance = 4.0 * (so * so + sl * sl).sqrt() + 0.01 * el;
        assert!((eo - el).abs() < tolerance, "{n}: {eo} ± {so} vs {el} ± {sl}");
    }
}

#[test]
fn a_uniform_map_has_the_constant_power_and_density() {
    let bitmap = Bitmap {
        width: 4,
        height: 4,
        channels: 1,
        data: vec![2.0; 16],
    };
    let mut e = EqualAreaEnvMap::new(&bitmap, Mat4::IDENTITY, 1.5).unwrap();
    let mut c = super::super::ConstantEnvironment::new(Vec3::splat(3.0));
    EmitterPlugin::set_scene_bounds(&mut e, Vec3::ONE, 2.0);
    EmitterPlugin::set_scene_bounds(&mut c, Vec3::ONE, 2.0);
    let (pe, pc) = (EmitterPlugin::power(&e), EmitterPlugin::power(&c));
    assert!((pe / pc - Vec3::ONE).abs().max_element() < 1e-5, "{pe} vs {pc}");
    let pdf = e.pdf_li(Vec3::new(0.3, -0.4, 0.5).normalize());
    assert!((pdf * 4.0 * PI - 1.0).abs() < 1e-4, "{pdf}");
}

#[test]
fn a_map_that_is_not_square_is_an_error() {
    let bitmap = Bitmap {
        width: 8,
        height: 4,
        channels: 3,
        data: vec![1.0; 96],
    };
    let err = EqualAreaEnvMap::new(&bitmap, Mat4::IDENTITY, 1.0).unwrap_err();
    assert!(err.contains("8x4") && err.contains("square"), "{err}");
}
