//! The ecosystem: a terrain with a lake, and twenty plant species scattered over it in patches,
//! each species one pair of meshes (wood and foliage) placed many times.

use super::noise::fbm;
use super::plants::{plant, Kind};
use super::terrain::Terrain;
use super::{GenOptions, GenReport};
use appel::error::{Error, Result};
use appel::geometry::procedural::SplitMix64;
use appel::io::placements::placement_line;
use appel::output::{write_atomically, write_ply};
use glam::{Mat4, Quat, Vec3};
use std::fmt::Write as _;
use std::path::Path;

/// One species: what it is, its triangle budget and how many are placed at density 1.
#[derive(Clone, Copy, Debug)]
pub struct Species {
    pub name: &'static str,
    pub kind: Kind,
    pub triangles: usize,
    pub count: usize,
    pub wood: [f32; 3],
    pub foliage: [f32; 3],
}

const fn sp(
    name: &'static str,
    kind: Kind,
    triangles: usize,
    count: usize,
    wood: [f32; 3],
    foliage: [f32; 3],
) -> Species {
    Species {
        name,
        kind,
        triangles,
        count,
        wood,
        foliage,
    }
}

const BARK: [f32; 3] = [0.32, 0.22, 0.14];
const PALE_BARK: [f32; 3] = [0.75, 0.72, 0.66];
const STEM: [f32; 3] = [0.2, 0.45, 0.12];

/// The species at detail 1: 9.9 million triangles of plants.
pub fn species_list() -> Vec<Species> {
    use Kind::*;
    vec![
        sp("oak", Broadleaf, 1_000_000, 90, BARK, [0.16, 0.36, 0.08]),
        sp("beech", Broadleaf, 950_000, 90, BARK, [0.24, 0.46, 0.1]),
        sp("maple", Broadleaf, 900_000, 80, BARK, [0.8, 0.32, 0.06]),
        sp(
            "birch",
            Broadleaf,
            800_000,
            90,
            PALE_BARK,
            [0.45, 0.58, 0.14],
        ),
        sp("linden", Broadleaf, 850_000, 70, BARK, [0.3, 0.5, 0.12]),
        sp("ash", Broadleaf, 750_000, 70, BARK, [0.62, 0.58, 0.12]),
        sp("spruce", Conifer, 1_000_000, 90, BARK, [0.07, 0.22, 0.1]),
        sp("pine", Conifer, 900_000, 90, BARK, [0.12, 0.28, 0.1]),
        sp("fir", Conifer, 800_000, 80, BARK, [0.05, 0.2, 0.14]),
        sp("hazel", Bush, 500_000, 300, BARK, [0.28, 0.48, 0.1]),
        sp("holly", Bush, 400_000, 300, BARK, [0.06, 0.26, 0.06]),
        sp("elder", Bush, 300_000, 300, BARK, [0.35, 0.5, 0.16]),
        sp("bracken", Fern, 300_000, 1500, STEM, [0.3, 0.52, 0.1]),
        sp("ladyfern", Fern, 200_000, 1500, STEM, [0.36, 0.6, 0.16]),
        sp("hartstongue", Fern, 120_000, 1500, STEM, [0.2, 0.45, 0.12]),
        sp("poppy", Flower, 50_000, 3000, STEM, [0.85, 0.1, 0.05]),
        sp("daisy", Flower, 30_000, 3000, STEM, [0.95, 0.95, 0.9]),
        sp("bluebell", Flower, 20_000, 3000, STEM, [0.35, 0.3, 0.85]),
        sp(
            "meadowgrass",
            Grass,
            20_000,
            25_000,
            STEM,
            [0.4, 0.58, 0.16],
        ),
        sp("fescue", Grass, 12_000, 25_000, STEM, [0.55, 0.6, 0.24]),
    ]
}

/// Side of the terrain in metres, and its grid at detail 1 (2 * 2299^2 = 10.6M triangles).
const SIZE: f32 = 300.0;
const GRID: f64 = 2300.0;

fn write_text(path: &Path, text: &str) -> Result<()> {
    write_atomically(path, |out| {
        use std::io::Write;
        out.write_all(text.as_bytes())
            .map_err(|e| Error::io(path, e))
    })
}

fn material(name: &str, color: [f32; 3], extra: &str) -> String {
    format!(
        "[materials.{name}]\ncolor = [{}, {}, {}]\nambient = 0.35\ndiffuse = 0.8\n{extra}\n",
        color[0], color[1], color[2]
    )
}

/// Writes the ecosystem into `dir`. `step` hears about each step before it starts, and stops the
/// generator by returning an error (Ctrl-C); the scene file is written last, so a stopped run
/// leaves no scene, and every file is written whole or not at all.
pub fn ecosystem(
    dir: &Path,
    options: &GenOptions,
    step: &dyn Fn(&str) -> Result<()>,
) -> Result<GenReport> {
    let seed = options.seed;
    let n = ((GRID * options.detail.sqrt()) as usize).max(16);
    step(&format!("terrain: {n} x {n} heights"))?;
    let terrain = Terrain::new(n, SIZE, seed);
    let mut report = GenReport {
        files: vec!["ecosystem.toml".into(), "terrain.ply".into()],
        ..Default::default()
    };
    {
        let mesh = terrain.mesh().into_mesh();
        report.unique_triangles += mesh.triangle_count() as u64;
        report.instanced_triangles += mesh.triangle_count() as u64;
        write_ply(&dir.join("terrain.ply"), &[(0, &mesh)])?;
    }
    // The lakes fill the lowest tenth of the ground.
    let mut sample: Vec<f32> = terrain.heights.iter().step_by(97).copied().collect();
    sample.sort_by(f32::total_cmp);
    let water = sample[sample.len() / 10];
    // The camera stands on the highest ground near one corner, looking across the middle.
    let eye = (0..400)
        .map(|k| {
            let x = (-0.45 + 0.25 * (k % 20) as f32 / 19.0) * SIZE;
            let z = (0.15 + 0.3 * (k / 20) as f32 / 19.0) * SIZE;
            Vec3::new(x, terrain.height(x, z) + 2.2, z)
        })
        .max_by(|a, b| a.y.total_cmp(&b.y))
        .unwrap_or(Vec3::Y);
    // It looks towards the nearest lake, so that reflections show.
    let look = (0..1600)
        .map(|k| {
            let x = (-0.3 + 0.6 * (k % 40) as f32 / 39.0) * SIZE;
            let z = (-0.3 + 0.6 * (k / 40) as f32 / 39.0) * SIZE;
            Vec3::new(x, terrain.height(x, z), z)
        })
        .filter(|p| p.y < water)
        .min_by(|a, b| {
            let d = |p: &Vec3| (p.x - eye.x).hypot(p.z - eye.z);
            d(a).total_cmp(&d(b))
        })
        .map_or(Vec3::new(0.0, water, 0.0), |p| {
            Vec3::new(p.x, water + 3.0, p.z)
        });

    let mut scene = format!(
        "# `appel gen ecosystem --seed {seed} --density {} --detail {}`\n\
         [camera]\neye = [{}, {}, {}]\nlook_at = [{}, {}, {}]\nfov = 55.0\nwidth = 1920\nheight = 1080\n\n\
         [render]\nintegrator = \"whitted\"\nmax_depth = 3\n\n\
         [environment]\nbackground = [0.6, 0.75, 0.95]\nambient = [0.45, 0.5, 0.55]\n\n",
        options.density, options.detail, eye.x, eye.y, eye.z, look.x, look.y, look.z
    );
    scene += &material("ground", [0.33, 0.3, 0.17], "");
    scene += &material(
        "water",
        [0.06, 0.12, 0.14],
        "reflection = 0.6\nspecular = 0.3\nshininess = 200.0",
    );
    let mut meshes = String::new();
    let mut instances = String::new();
    for (k, s) in species_list().iter().enumerate() {
        let species_seed = seed.wrapping_mul(1000).wrapping_add(k as u64);
        let budget = ((s.triangles as f64 * options.detail) as usize).max(300);
        let p = plant(s.kind, budget, species_seed);
        let count = (s.count as f64 * options.density).round() as usize;
        let placements = scatter(&terrain, water, s, count, species_seed, eye);
        let per_plant = (p.wood.triangle_count() + p.foliage.triangle_count()) as u64;
        step(&format!(
            "{}: {} triangles, {} placements",
            s.name,
            per_plant,
            placements.len()
        ))?;
        report.unique_triangles += per_plant;
        report.instanced_triangles += per_plant * placements.len() as u64;
        report.instances += 2 * placements.len() as u64;
        let list: String = placements.iter().map(placement_line).collect();
        write_text(&dir.join(format!("{}.txt", s.name)), &list)?;
        for (part, mesh, color) in [("wood", p.wood, s.wood), ("foliage", p.foliage, s.foliage)] {
            let name = format!("{}-{part}", s.name);
            write_ply(&dir.join(format!("{name}.ply")), &[(0, &mesh.into_mesh())])?;
            scene += &material(&name, color, "");
            writeln!(
                meshes,
                "[meshes.{name}]\nfile = \"{name}.ply\"\nmaterial = \"{name}\"\n"
            )
            .unwrap();
            writeln!(
                instances,
                "[[instance]]\nmesh = \"{name}\"\nplacements = \"{}.txt\"\n",
                s.name
            )
            .unwrap();
            report.files.push(format!("{name}.ply"));
        }
        report.files.push(format!("{}.txt", s.name));
    }
    scene += &format!(
        "[[shape]]\ntype = \"mesh\"\nfile = \"terrain.ply\"\nmaterial = \"ground\"\n\n\
         [[shape]]\ntype = \"plane\"\npoint = [0.0, {water}, 0.0]\nnormal = [0.0, 1.0, 0.0]\nsize = [{SIZE}, {SIZE}]\nmaterial = \"water\"\n\n"
    );
    scene += &meshes;
    scene += &instances;
    scene += "[[light]]\ntype = \"directional\"\ndirection = [0.7, -0.5, 0.25]\ncolor = [1.0, 0.95, 0.85]\nintensity = 1.0\n";
    step("writing ecosystem.toml")?;
    write_text(&dir.join("ecosystem.toml"), &scene)?;
    Ok(report)
}

/// Placements of one species: uniform over the terrain, kept where the species' own patch noise
/// is high (so species grow in stands), never in the lake or within a few metres of the camera.
fn scatter(
    terrain: &Terrain,
    water: f32,
    s: &Species,
    count: usize,
    seed: u64,
    eye: Vec3,
) -> Vec<Mat4> {
    let mut rng = SplitMix64(seed ^ 0x5ca7_7e12);
    let mut out = Vec::with_capacity(count);
    let half = 0.5 * SIZE * 0.98;
    let (lo, hi) = match s.kind {
        Kind::Broadleaf | Kind::Conifer => (0.8, 1.25),
        _ => (0.7, 1.3),
    };
    let mut tries = 0;
    while out.len() < count && tries < 50 * count + 100 {
        tries += 1;
        let x = (2.0 * rng.next_f32() - 1.0) * half;
        let z = (2.0 * rng.next_f32() - 1.0) * half;
        let patch = fbm(x / 35.0, z / 35.0, 3, seed);
        let keep = rng.next_f32();
        let y = terrain.height(x, z);
        let near_eye = (x - eye.x).hypot(z - eye.z) < 6.0;
        if patch < 0.45 || keep > 2.0 * (patch - 0.45) + 0.2 || y < water + 0.3 || near_eye {
            continue;
        }
        let scale = lo + (hi - lo) * rng.next_f32();
        let yaw = rng.next_f32() * std::f32::consts::TAU;
        let tilt_axis =
            Vec3::new(rng.next_f32() - 0.5, 0.0, rng.next_f32() - 0.5).normalize_or(Vec3::X);
        let tilt = 0.08 * rng.next_f32();
        let rotation = Quat::from_axis_angle(tilt_axis, tilt) * Quat::from_rotation_y(yaw);
        // Sunk a little so that no root floats above a slope.
        let base = Vec3::new(x, y - 0.08 * scale, z);
        out.push(Mat4::from_scale_rotation_translation(
            Vec3::splat(scale),
            rotation,
            base,
        ));
    }
    out
}
