//! The path tracer's wavefront (`path` traces a row's samples together where the scene allows it)
//! against its scalar loop, one sample after the other, on the Bitterli Cornell box and on a scene
//! of spheres, glass and a point light: the same image bit for bit with the same seed, and the
//! same image in expectation with different seeds (a z-test per pixel block).

use appel::description::FilterDesc;
use appel::render::filter::Filter;
use appel::render::path::PathTracer;
use appel::render::render_loop::{render_loop, Passes};
use appel::render::sampler::{IndependentSampler, Sampler};
use appel::render::{
    Film, FilmSample, Integrator, PixelAov, PixelIntegrator, RenderOptions, RenderStats,
    TraceContext,
};
use appel::scene::{RenderSettings, Scene};
use std::path::Path;

/// The path tracer with the trait's default row method: [`PathTracer::sample`] pixel by pixel,
/// the scalar loop.
struct OneByOne(PathTracer);

impl Integrator for OneByOne {
    const NAME: &'static str = "path";

    fn from_settings(s: &RenderSettings) -> appel::error::Result<Self> {
        PathTracer::from_settings(s).map(OneByOne)
    }

    /// The render loop with the scene's own seed and sample count and the independent sampler.
    fn render(
        &self,
        scene: &Scene,
        options: &RenderOptions,
    ) -> appel::error::Result<(Film, RenderStats)> {
        let passes = Passes {
            filter: Filter::new(&scene.settings.filter),
            spp: scene.settings.spp,
        };
        let sampler = IndependentSampler::new(scene.settings.seed);
        render_loop(scene, self, &sampler, &passes, options)
    }
}

impl PixelIntegrator for OneByOne {
    fn sample<S: Sampler>(
        &self,
        scene: &Scene,
        x: u32,
        y: u32,
        sampler: &mut S,
        aov: Option<&mut PixelAov>,
        ctx: &mut TraceContext,
    ) -> FilmSample {
        self.0.sample(scene, x, y, sampler, aov, ctx)
    }
}

fn render_as<I: PixelIntegrator>(scene: &Scene, integrator: &I, seed: u64, spp: u32) -> Film {
    let passes = Passes {
        filter: Filter::new(&scene.settings.filter),
        spp,
    };
    let sampler = IndependentSampler::new(seed);
    render_loop(
        scene,
        integrator,
        &sampler,
        &passes,
        &RenderOptions::default(),
    )
    .unwrap()
    .0
}

fn bits(f: &Film) -> Vec<[u32; 3]> {
    f.rgb
        .iter()
        .chain(&f.variance)
        .map(|c| c.to_array().map(f32::to_bits))
        .collect()
}

/// Blocks of 4x4 pixels of two independent renders agree within the z-test's bound: the largest
/// |z| of a block's mean over all blocks and channels stays below 4.5 (about 1 in 150,000 for one
/// normal variate; a few hundred are tested).
fn assert_agree(a: &Film, b: &Film, what: &str) {
    let (w, h) = (a.width as usize, a.height as usize);
    let mut worst = 0.0f64;
    let mut lit = 0;
    for by in 0..h / 4 {
        for bx in 0..w / 4 {
            for c in 0..3 {
                let (mut ma, mut mb, mut va, mut vb) = (0.0, 0.0, 0.0, 0.0);
                for y in by * 4..by * 4 + 4 {
                    for x in bx * 4..bx * 4 + 4 {
                        let i = y * w + x;
                        ma += a.rgb[i][c] as f64 / 16.0;
                        mb += b.rgb[i][c] as f64 / 16.0;
                        va += a.variance[i][c] as f64 / 256.0;
                        vb += b.variance[i][c] as f64 / 256.0;
                    }
                }
                if va + vb > 0.0 {
                    worst = worst.max((ma - mb).abs() / (va + vb).sqrt());
                    lit += 1;
                } else {
                    assert_eq!(ma, mb, "{what}: a noiseless block differs");
                }
            }
        }
    }
    assert!(lit > 100, "{what}: {lit} blocks lit");
    assert!(worst < 4.5, "{what}: worst |z| {worst}");
}

fn check(scene: &Scene, spp: u32, what: &str) {
    let path = PathTracer::from_settings(&scene.settings).unwrap();
    let one = OneByOne(path);
    let wave = render_as(scene, &path, 7, spp);
    assert!(wave.rgb.iter().any(|c| c.max_element() > 0.0));
    assert_eq!(bits(&wave), bits(&render_as(scene, &one, 7, spp)), "{what}");
    assert_agree(&wave, &render_as(scene, &one, 8, spp), what);
}

#[test]
#[cfg_attr(not(shared_data), ignore = "needs ../shared/data")]
fn the_wavefront_renders_the_scalar_loops_cornell_box() {
    let xml = appel_testdata::path("bitterli-scenes/cornell-box/mitsuba/scene_v3.xml");
    let loaded = appel::format::load(&xml, &Default::default()).unwrap();
    let mut d = loaded.description;
    d.camera.width = 64;
    d.camera.height = 64;
    // The scene's tent filter: samples splatted into their neighbours, the same bits.
    let scene = Scene::new(&d, &loaded.base_dir).unwrap();
    let path = PathTracer::from_settings(&scene.settings).unwrap();
    let (wave, one) = (
        render_as(&scene, &path, 3, 2),
        render_as(&scene, &OneByOne(path), 3, 2),
    );
    assert_eq!(bits(&wave), bits(&one));
    // The box filter keeps the pixels independent for the z-test.
    d.render.filter = FilterDesc::Box { radius: 0.5 };
    let scene = Scene::new(&d, &loaded.base_dir).unwrap();
    check(&scene, 16, "Cornell box");
}

/// Delta lobes, a rough plastic, an area light and a point light, under the box filter, a row
/// narrower than the wave and an image width that is not a multiple of it.
#[test]
fn the_wavefront_renders_the_scalar_loops_spheres() {
    let toml = "[camera]\neye = [0.0, 0.0, 4.0]\nlook_at = [0.0, 0.0, 0.0]\nwidth = 44\nheight = 36\n\
         fov = 40\n[render]\nintegrator = \"path\"\nmax_depth = 8\nspp = 32\n\
         filter = { type = \"box\" }\n\n\
         [materials.glass]\ntype = \"dielectric\"\n[materials.red]\ntype = \"roughplastic\"\n\
         diffuse_reflectance = [0.6, 0.1, 0.1]\n[materials.white]\ntype = \"diffuse\"\n\n\
         [[shape]]\ntype = \"sphere\"\ncenter = [-0.6, 0.0, 0.0]\nradius = 0.5\nmaterial = \"glass\"\n\
         [[shape]]\ntype = \"sphere\"\ncenter = [0.6, 0.0, 0.0]\nradius = 0.5\nmaterial = \"red\"\n\
         [[shape]]\ntype = \"sphere\"\ncenter = [0.0, -101.0, 0.0]\nradius = 100.0\nmaterial = \"white\"\n\
         [[shape]]\ntype = \"rectangle\"\ntransform = { translate = [0.0, 2.0, 0.0], rotate = { axis = [1.0, 0.0, 0.0], degrees = 90.0 } }\n\
         emitter = { radiance = 5.0 }\n\
         [[light]]\ntype = \"point\"\nposition = [0.0, 1.0, 2.0]\nintensity = 3.0\n";
    let d = appel::description::description_from_str(
        toml,
        appel::description::parse::Syntax::Toml,
        Path::new("spheres.toml"),
    )
    .unwrap();
    let scene = Scene::new(&d, Path::new(".")).unwrap();
    check(&scene, 32, "spheres");
}
