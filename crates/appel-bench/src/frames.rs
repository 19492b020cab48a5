//! The real-time measurement behind `appel bench --scene NAME --frames N`: render the same scene N
//! times, each frame from scratch (every ray traced again, a new film, nothing carried over), and
//! report the frame time, frames per second and the rays of one frame by kind. For the Monte Carlo
//! integrators (path, direct), [`bench_samples`] reports samples per second instead.

use appel::error::{Error, Result};
use appel::render::{render, RayCounts, RenderOptions};
use appel::scene::Scene;
use std::time::Instant;

/// What `N` frames of one scene took.
#[derive(Clone, Debug, serde::Serialize)]
pub struct FrameBench {
    pub scene: String,
    pub accel: String,
    pub width: u32,
    pub height: u32,
    pub spp: u32,
    pub max_depth: u32,
    pub threads: usize,
    pub frames: usize,
    /// Median wall-clock time of one frame, in milliseconds.
    pub frame_ms_median: f64,
    pub frame_ms_min: f64,
    pub frame_ms_max: f64,
    /// `1000 / frame_ms_median`.
    pub fps: f64,
    /// Rays of one frame (the same in every frame: checked).
    pub camera_rays: u64,
    pub shadow_rays: u64,
    pub reflection_rays: u64,
    pub refraction_rays: u64,
    pub rays_per_frame: u64,
    /// Rays of one frame divided by the median frame time.
    pub mrays_per_second: f64,
}

/// Renders `scene` `frames` times on `pool` and times every frame. `name` labels the result.
pub fn bench_frames(
    scene: &Scene,
    name: &str,
    frames: usize,
    pool: &rayon::ThreadPool,
) -> Result<FrameBench> {
    if frames == 0 {
        return Err(Error::Invalid("--frames must be at least 1".into()));
    }
    // A frame is its image: no AOVs, as in the viewer's colour frames.
    let options = RenderOptions {
        skip_aovs: true,
        ..Default::default()
    };
    let mut times = Vec::with_capacity(frames);
    let mut rays: Option<RayCounts> = None;
    for _ in 0..frames {
        let start = Instant::now();
        let (film, stats) = pool.install(|| render(scene, &options))?;
        times.push(start.elapsed().as_secs_f64() * 1e3);
        // The film is part of the frame's work; keep the optimizer from dropping any of it.
        std::hint::black_box(&film);
        match rays {
            None => rays = Some(stats.rays),
            Some(r) if r != stats.rays => {
                return Err(Error::Invalid(format!(
                    "frames traced different rays ({r:?}, then {:?}): the renderer is not deterministic",
                    stats.rays
                )))
            }
            Some(_) => {}
        }
    }
    let rays = rays.expect("at least one frame");
    times.sort_by(f64::total_cmp);
    let median = times[times.len() / 2];
    Ok(FrameBench {
        scene: name.to_string(),
        accel: scene.settings.accel.name().to_string(),
        width: scene.camera.width,
        height: scene.camera.height,
        spp: scene.settings.spp,
        max_depth: scene.settings.max_depth.max(0) as u32,
        threads: pool.current_num_threads(),
        frames,
        frame_ms_median: median,
        frame_ms_min: times[0],
        frame_ms_max: times[times.len() - 1],
        fps: 1e3 / median,
        camera_rays: rays.camera,
        shadow_rays: rays.shadow,
        reflection_rays: rays.reflection,
        refraction_rays: rays.refraction,
        rays_per_frame: rays.total(),
        mrays_per_second: rays.total() as f64 / median / 1e3,
    })
}

/// What `runs` renders of one path-traced (or directly lit) scene took.
#[derive(Clone, Debug, serde::Serialize)]
pub struct SampleBench {
    pub scene: String,
    pub integrator: String,
    pub accel: String,
    pub width: u32,
    pub height: u32,
    pub spp: u32,
    /// Mitsuba's convention: -1 is unlimited.
    pub max_depth: i32,
    pub threads: usize,
    pub runs: usize,
    /// Median wall-clock time of one whole render, in milliseconds.
    pub render_ms_median: f64,
    pub render_ms_min: f64,
    pub render_ms_max: f64,
    /// `width * height * spp / median render time`, in millions.
    pub msamples_per_second: f64,
    /// Rays of the median render by kind (paths are random, so renders may differ slightly).
    pub camera_rays: u64,
    pub shadow_rays: u64,
    pub reflection_rays: u64,
    pub refraction_rays: u64,
    pub rays_per_render: u64,
    pub rays_per_sample: f64,
    /// Rays of the median render divided by its time.
    pub mrays_per_second: f64,
}

/// Renders a path or direct `scene` `runs` times on `pool` at the scene's samples per pixel, and
/// reports samples per second from the median render time. `name` labels the result.
pub fn bench_samples(
    scene: &Scene,
    name: &str,
    runs: usize,
    pool: &rayon::ThreadPool,
) -> Result<SampleBench> {
    if runs == 0 {
        return Err(Error::Invalid("--frames must be at least 1".into()));
    }
    let integrator = match scene.settings.integrator {
        k if k.is_monte_carlo() => k.name(),
        other => {
            return Err(Error::Invalid(format!(
                "samples per second are measured for the Monte Carlo integrators, not {other}"
            )))
        }
    };
    // The samples of the image only: no AOVs, nor the pass of centre rays that finds them when
    // the samples are elsewhere in their pixels (Mitsuba's renders, compared with, have neither).
    let options = RenderOptions {
        skip_aovs: true,
        ..Default::default()
    };
    let mut renders = Vec::with_capacity(runs);
    for _ in 0..runs {
        let start = Instant::now();
        let (film, stats) = pool.install(|| render(scene, &options))?;
        let ms = start.elapsed().as_secs_f64() * 1e3;
        std::hint::black_box(&film);
        renders.push((ms, stats.rays, stats.spp));
    }
    renders.sort_by(|a, b| a.0.total_cmp(&b.0));
    let (median, rays, spp) = renders[renders.len() / 2];
    let samples = scene.camera.width as f64 * scene.camera.height as f64 * spp as f64;
    Ok(SampleBench {
        scene: name.to_string(),
        integrator: integrator.to_string(),
        accel: scene.settings.accel.name().to_string(),
        width: scene.camera.width,
        height: scene.camera.height,
        spp,
        max_depth: scene.settings.max_depth,
        threads: pool.current_num_threads(),
        runs,
        render_ms_median: median,
        render_ms_min: renders[0].0,
        render_ms_max: renders[renders.len() - 1].0,
        msamples_per_second: samples / median / 1e3,
        camera_rays: rays.camera,
        shadow_rays: rays.shadow,
        reflection_rays: rays.reflection,
        refraction_rays: rays.refraction,
        rays_per_render: rays.total(),
        rays_per_sample: rays.total() as f64 / samples.max(1.0),
        mrays_per_second: rays.total() as f64 / median / 1e3,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use appel::description::description_from_str;
    use appel::description::parse::Syntax;
    use appel::scene::builtin::builtin_scene;
    use appel::scene::IntegratorKind;
    use std::path::Path;

    fn whitted(w: u32, h: u32) -> Scene {
        let text = builtin_scene("whitted").unwrap();
        let mut d = description_from_str(text, Syntax::Toml, Path::new("whitted")).unwrap();
        (d.camera.width, d.camera.height) = (w, h);
        Scene::new(&d, Path::new(".")).unwrap()
    }

    #[test]
    fn frames_report_the_rays_of_one_render_and_fps_from_the_median() {
        let scene = whitted(64, 48);
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(2)
            .build()
            .unwrap();
        let (_, once) = pool.install(|| render(&scene, &RenderOptions::default()).unwrap());
        let b = bench_frames(&scene, "whitted", 5, &pool).unwrap();
        assert_eq!(b.frames, 5);
        assert_eq!((b.width, b.height, b.threads), (64, 48, 2));
        assert_eq!(b.camera_rays, 64 * 48);
        assert_eq!(b.shadow_rays, once.rays.shadow);
        assert_eq!(b.reflection_rays, once.rays.reflection);
        assert_eq!(b.refraction_rays, once.rays.refraction);
        assert!(b.shadow_rays > 0 && b.reflection_rays > 0 && b.refraction_rays > 0);
        assert_eq!(b.rays_per_frame, once.rays.total());
        assert!(b.frame_ms_min <= b.frame_ms_median && b.frame_ms_median <= b.frame_ms_max);
        assert!((b.fps * b.frame_ms_median - 1e3).abs() < 1e-6);
        assert!(bench_frames(&scene, "whitted", 0, &pool).is_err());
    }

    #[test]
    fn samples_per_second_count_every_pixel_and_sample() {
        let text = builtin_scene("whitted").unwrap();
        let mut d = description_from_str(text, Syntax::Toml, Path::new("whitted")).unwrap();
        (d.camera.width, d.camera.height) = (32, 24);
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(2)
            .build()
            .unwrap();
        let whitted = Scene::new(&d, Path::new(".")).unwrap();
        assert!(bench_samples(&whitted, "whitted", 1, &pool).is_err());
        d.render.integrator = IntegratorKind::Path;
        d.render.spp = 4;
        d.render.max_depth = 4;
        let scene = Scene::new(&d, Path::new(".")).unwrap();
        let b = bench_samples(&scene, "whitted", 3, &pool).unwrap();
        assert_eq!((b.integrator.as_str(), b.spp, b.runs), ("path", 4, 3));
        // One ray per sample: no pass of centre rays for the AOVs, which are skipped.
        assert_eq!(b.camera_rays, 32 * 24 * 4);
        assert!(b.shadow_rays > 0);
        assert!(b.render_ms_min <= b.render_ms_median && b.render_ms_median <= b.render_ms_max);
        let expected = 32.0 * 24.0 * 4.0 / b.render_ms_median / 1e3;
        assert!((b.msamples_per_second - expected).abs() < 1e-9);
        assert!(bench_samples(&scene, "whitted", 0, &pool).is_err());
    }
}
