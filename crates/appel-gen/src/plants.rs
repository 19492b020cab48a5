//! Procedural plants, each in two parts (wood and foliage, so they take two materials): branching
//! trees after Honda's model as popularised by Prusinkiewicz & Lindenmayer ("The Algorithmic Beauty
//! of Plants", 1990, ch. 2: a parent branch, children at a branching angle, rotated by the golden
//! angle, shorter and thinner by fixed ratios), conifers with whorls of branches, bushes, ferns with
//! leaflets along arching fronds, flowers and grass tufts. Each species is a distinct mesh; leaves
//! are added until the species' triangle budget is spent.

use super::builder::MeshBuilder;
use appel::geometry::procedural::SplitMix64;
use appel::math::{orthonormal_basis, Vec3};

const GOLDEN_ANGLE: f32 = 2.399_963;
/// Leaves (or blades, leaflets) every plant gets even when its wood used up the budget.
const MIN_LEAVES: usize = 20;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    Broadleaf,
    Conifer,
    Bush,
    Fern,
    Flower,
    Grass,
}

impl Kind {
    pub fn name(self) -> &'static str {
        match self {
            Kind::Broadleaf => "broadleaf",
            Kind::Conifer => "conifer",
            Kind::Bush => "bush",
            Kind::Fern => "fern",
            Kind::Flower => "flower",
            Kind::Grass => "grass",
        }
    }
}

/// A plant's two meshes.
pub struct Plant {
    pub wood: MeshBuilder,
    pub foliage: MeshBuilder,
}

/// Where a leaf may grow: a point on a twig and the twig's direction there.
#[derive(Clone, Copy)]
struct Site {
    p: Vec3,
    dir: Vec3,
}

struct Shape {
    sides: u32,
    branch_angle: f32,
    children: u32,
    depth: u32,
    length_ratio: f32,
    leaf_length: f32,
    leaf_width: f32,
    leaf_segments: u32,
}

fn rotate_about(v: Vec3, axis: Vec3, angle: f32) -> Vec3 {
    glam::Quat::from_axis_angle(axis, angle) * v
}

/// One branch as a slightly curved tube; returns its points (for children to start from).
#[allow(clippy::too_many_arguments)]
fn branch(
    wood: &mut MeshBuilder,
    start: Vec3,
    dir: Vec3,
    length: f32,
    radius: f32,
    sides: u32,
    rise: f32,
    rng: &mut SplitMix64,
) -> Vec<(Vec3, Vec3)> {
    let segments = 5;
    let mut path = Vec::with_capacity(segments + 1);
    let mut radii = Vec::with_capacity(segments + 1);
    let mut p = start;
    let mut d = dir;
    let wobble = Vec3::new(rng.next_f32() - 0.5, 0.0, rng.next_f32() - 0.5) * 0.15;
    for k in 0..=segments {
        let t = k as f32 / segments as f32;
        path.push(p);
        radii.push(radius * (1.0 - 0.6 * t));
        // Branches bend towards the light (`rise` > 0) or sag (`rise` < 0).
        d = (d + Vec3::Y * rise + wobble).normalize();
        p += d * (length / segments as f32);
    }
    wood.tube(&path, &radii, sides);
    path.iter()
        .zip(path.iter().skip(1))
        .map(|(&a, &b)| (b, (b - a).normalize()))
        .collect()
}

#[allow(clippy::too_many_arguments)]
fn grow(
    wood: &mut MeshBuilder,
    sites: &mut Vec<Site>,
    s: &Shape,
    start: Vec3,
    dir: Vec3,
    length: f32,
    radius: f32,
    depth: u32,
    rng: &mut SplitMix64,
) {
    let sides = if depth + 1 >= s.depth { 3 } else { s.sides };
    let points = branch(wood, start, dir, length, radius, sides, 0.05, rng);
    if depth == s.depth {
        sites.extend(points.iter().skip(1).map(|&(p, dir)| Site { p, dir }));
        return;
    }
    let mut roll = rng.next_f32() * std::f32::consts::TAU;
    for c in 0..s.children {
        // Children start along the upper part of the parent and point away from it.
        let at = (points.len() - 1) * (c as usize + 2) / (s.children as usize + 1);
        let (p, d) = points[at.min(points.len() - 1)];
        let (u, _) = orthonormal_basis(d);
        roll += GOLDEN_ANGLE;
        let side = rotate_about(u, d, roll);
        let tilt = s.branch_angle * (0.8 + 0.4 * rng.next_f32());
        let child = rotate_about(d, side.cross(d).normalize_or(Vec3::X), tilt);
        let scale = s.length_ratio * (0.85 + 0.3 * rng.next_f32());
        grow(
            wood,
            sites,
            s,
            p,
            child,
            length * scale,
            radius * 0.55,
            depth + 1,
            rng,
        );
    }
}

/// Spends what is left of `budget` triangles on leaves spread over the sites.
fn leaves(
    foliage: &mut MeshBuilder,
    sites: &[Site],
    s: &Shape,
    budget: usize,
    rng: &mut SplitMix64,
) {
    let per_leaf = MeshBuilder::leaf_triangles(s.leaf_segments);
    // However small the budget, a plant keeps some foliage (and its mesh some triangles).
    let count = (budget / per_leaf).max(MIN_LEAVES);
    if sites.is_empty() {
        return;
    }
    for k in 0..count {
        let site = sites[k % sites.len()];
        let (u, _) = orthonormal_basis(site.dir);
        let around = rotate_about(u, site.dir, rng.next_f32() * std::f32::consts::TAU);
        // Leaves point outwards and upwards from their twig.
        let dir = (around + site.dir * 0.6 + Vec3::Y * 0.3).normalize();
        let side = dir.cross(Vec3::Y).normalize_or(Vec3::X);
        let jitter = site.dir * (0.5 * s.leaf_length * (rng.next_f32() - 0.5));
        let size = 0.75 + 0.5 * rng.next_f32();
        foliage.leaf(
            site.p + jitter,
            dir,
            side,
            s.leaf_length * size,
            s.leaf_width * size,
            0.25,
            s.leaf_segments,
        );
    }
}

fn tree(kind: Kind, budget: usize, rng: &mut SplitMix64) -> Plant {
    let mut wood;
    let mut sites = vec![];
    let mut r = |lo: f32, hi: f32| lo + (hi - lo) * rng.next_f32();
    let (shape, height, radius) = match kind {
        Kind::Broadleaf => (
            Shape {
                sides: 10,
                branch_angle: r(0.55, 0.85),
                children: 4,
                depth: 4,
                length_ratio: r(0.6, 0.72),
                leaf_length: r(0.12, 0.2),
                leaf_width: r(0.06, 0.12),
                leaf_segments: 4,
            },
            r(4.0, 6.0),
            r(0.25, 0.35),
        ),
        _ => (
            Shape {
                sides: 8,
                branch_angle: r(0.6, 0.9),
                children: 5,
                depth: 2,
                length_ratio: r(0.45, 0.6),
                leaf_length: r(0.18, 0.3),
                leaf_width: r(0.05, 0.09),
                leaf_segments: 3,
            },
            r(0.5, 0.8),
            r(0.03, 0.05),
        ),
    };
    let mut shape = shape;
    // Wood takes at most a third of the budget: small budgets get fewer levels of branches.
    let grown = rng.clone();
    loop {
        *rng = grown.clone();
        wood = MeshBuilder::default();
        sites.clear();
        if kind == Kind::Bush {
            // Several stems from the ground.
            for k in 0..7 {
                let a = k as f32 * GOLDEN_ANGLE;
                let dir = Vec3::new(0.45 * a.cos(), 1.0, 0.45 * a.sin()).normalize();
                grow(
                    &mut wood,
                    &mut sites,
                    &shape,
                    Vec3::ZERO,
                    dir,
                    height,
                    radius,
                    1,
                    rng,
                );
            }
        } else {
            grow(
                &mut wood,
                &mut sites,
                &shape,
                Vec3::ZERO,
                Vec3::Y,
                height,
                radius,
                0,
                rng,
            );
        }
        if wood.triangle_count() * 3 <= budget || shape.depth <= 1 {
            break;
        }
        shape.depth -= 1;
    }
    let mut foliage = MeshBuilder::default();
    let left = budget.saturating_sub(wood.triangle_count());
    leaves(&mut foliage, &sites, &shape, left, rng);
    Plant { wood, foliage }
}

fn conifer(budget: usize, rng: &mut SplitMix64) -> Plant {
    let mut wood = MeshBuilder::default();
    let height = 10.0 + 6.0 * rng.next_f32();
    let trunk: Vec<Vec3> = (0..=12)
        .map(|k| Vec3::Y * (height * k as f32 / 12.0))
        .collect();
    let radii: Vec<f32> = (0..=12).map(|k| 0.35 * (1.0 - k as f32 / 13.0)).collect();
    wood.tube(&trunk, &radii, 12);
    let whorls = 14 + (rng.next_u64() % 6) as usize;
    let per_whorl = 6 + (rng.next_u64() % 3) as usize;
    let droop = 0.15 + 0.2 * rng.next_f32();
    let mut sites = vec![];
    for w in 0..whorls {
        let t = 0.15 + 0.83 * w as f32 / whorls as f32;
        let reach = 3.2 * (1.0 - t).powf(0.9) + 0.3;
        for b in 0..per_whorl {
            let a = b as f32 / per_whorl as f32 * std::f32::consts::TAU + w as f32 * 0.7;
            let dir = Vec3::new(a.cos(), -droop, a.sin()).normalize();
            let pts = branch(
                &mut wood,
                Vec3::Y * (height * t),
                dir,
                reach,
                0.06,
                4,
                -0.02,
                rng,
            );
            sites.extend(pts.iter().map(|&(p, dir)| Site { p, dir }));
        }
    }
    // Needles: narrow, short, many.
    let shape = Shape {
        sides: 4,
        branch_angle: 0.0,
        children: 0,
        depth: 0,
        length_ratio: 0.0,
        leaf_length: 0.35,
        leaf_width: 0.05,
        leaf_segments: 2,
    };
    let mut foliage = MeshBuilder::default();
    let left = budget.saturating_sub(wood.triangle_count());
    leaves(&mut foliage, &sites, &shape, left, rng);
    Plant { wood, foliage }
}

fn fern(budget: usize, rng: &mut SplitMix64) -> Plant {
    let mut wood = MeshBuilder::default();
    let mut foliage = MeshBuilder::default();
    let fronds = 9 + (rng.next_u64() % 6) as usize;
    let frond_length = 0.9 + 0.4 * rng.next_f32();
    let arch = 0.25 + 0.15 * rng.next_f32();
    let mut sites = vec![];
    for f in 0..fronds {
        let a = f as f32 * GOLDEN_ANGLE;
        let out = Vec3::new(a.cos(), 0.0, a.sin());
        let pts: Vec<Vec3> = (0..=10)
            .map(|k| {
                let t = k as f32 / 10.0;
                out * (frond_length * t) + Vec3::Y * (frond_length * (0.9 * t - arch * 2.0 * t * t))
            })
            .collect();
        let radii: Vec<f32> = (0..=10).map(|k| 0.012 * (1.0 - k as f32 / 11.0)).collect();
        wood.tube(&pts, &radii, 4);
        for w in pts.windows(2) {
            sites.push(Site {
                p: w[0],
                dir: (w[1] - w[0]).normalize(),
            });
        }
    }
    // Leaflets in pairs, perpendicular to the frond, shorter towards its tip.
    let per_leaf = MeshBuilder::leaf_triangles(3);
    let count = (budget.saturating_sub(wood.triangle_count()) / per_leaf).max(MIN_LEAVES);
    for k in 0..count {
        let site = sites[k % sites.len()];
        let along = (k / sites.len()) as f32 / (count / sites.len()).max(1) as f32;
        let side = site.dir.cross(Vec3::Y).normalize_or(Vec3::X);
        let sign = if k % 2 == 0 { 1.0 } else { -1.0 };
        let base = site.p + site.dir * (0.1 * along * frond_length);
        let dir = (side * sign + site.dir * 0.3).normalize();
        let len = 0.18 * (1.0 - 0.6 * along) * (0.8 + 0.4 * rng.next_f32());
        foliage.leaf(base, dir, site.dir, len, 0.05, 0.1, 3);
    }
    Plant { wood, foliage }
}

fn flower(budget: usize, rng: &mut SplitMix64) -> Plant {
    // Wood: stems and green leaves; foliage: the petals, which take the flower's colour.
    let mut wood = MeshBuilder::default();
    let mut foliage = MeshBuilder::default();
    let heads = 5 + (rng.next_u64() % 5) as usize;
    let petals = 8 + (rng.next_u64() % 8) as u32;
    let per_head = (budget / heads).max(200);
    for h in 0..heads {
        let a = h as f32 * GOLDEN_ANGLE;
        let lean = Vec3::new(0.25 * a.cos(), 1.0, 0.25 * a.sin()).normalize();
        let height = 0.35 + 0.2 * rng.next_f32();
        let top = lean * height;
        let stem: Vec<Vec3> = (0..=6).map(|k| lean * (height * k as f32 / 6.0)).collect();
        wood.tube(&stem, &[0.006; 7], 5);
        for l in 0..3 {
            let b = a + l as f32 * 2.1;
            let dir = Vec3::new(b.cos(), 0.5, b.sin()).normalize();
            wood.leaf(
                lean * (0.05 + 0.06 * l as f32),
                dir,
                dir.cross(Vec3::Y).normalize(),
                0.12,
                0.04,
                0.3,
                4,
            );
        }
        // Petals: rings of them, as many rings as the budget allows.
        let per_petal = MeshBuilder::leaf_triangles(4);
        let rings = ((per_head.saturating_sub(200)) / (per_petal * petals as usize)).max(1);
        for ring in 0..rings {
            let up = 0.2 + 0.5 * ring as f32 / rings as f32;
            for p in 0..petals {
                let b = p as f32 / petals as f32 * std::f32::consts::TAU + ring as f32 * 0.37;
                let dir = Vec3::new(b.cos(), up, b.sin()).normalize();
                let side = dir.cross(Vec3::Y).normalize_or(Vec3::X);
                let size = 0.05 * (1.0 - 0.4 * ring as f32 / rings as f32);
                foliage.leaf(top, dir, side, size, 0.5 * size, 0.05, 4);
            }
        }
    }
    Plant { wood, foliage }
}

fn grass(budget: usize, rng: &mut SplitMix64) -> Plant {
    // A few stiff seed stalks as the wood; the blades are the foliage.
    let mut wood = MeshBuilder::default();
    for k in 0..3 {
        let a = k as f32 * 2.1 + rng.next_f32();
        let lean = Vec3::new(0.2 * a.cos(), 1.0, 0.2 * a.sin()).normalize();
        let stalk: Vec<Vec3> = (0..=4).map(|i| lean * (0.55 * i as f32 / 4.0)).collect();
        wood.tube(&stalk, &[0.004; 5], 3);
    }
    let mut foliage = MeshBuilder::default();
    let per_blade = MeshBuilder::leaf_triangles(6);
    let blades = (budget.saturating_sub(wood.triangle_count()) / per_blade).max(MIN_LEAVES);
    for _ in 0..blades {
        let a = rng.next_f32() * std::f32::consts::TAU;
        let r = 0.08 * rng.next_f32().sqrt();
        let base = Vec3::new(r * a.cos(), 0.0, r * a.sin());
        let out = Vec3::new(a.cos(), 0.0, a.sin());
        let dir = (Vec3::Y * 3.0 + out * (0.5 + rng.next_f32())).normalize();
        let side = dir.cross(out).normalize_or(Vec3::X);
        let len = 0.25 + 0.25 * rng.next_f32();
        foliage.leaf(base, dir, side, len, 0.012, 0.35, 6);
    }
    Plant { wood, foliage }
}

/// A plant of `kind` with about `budget` triangles (more only for budgets too small for its wood
/// and a few leaves), shaped by `seed`.
pub fn plant(kind: Kind, budget: usize, seed: u64) -> Plant {
    let mut rng = SplitMix64(seed);
    match kind {
        Kind::Broadleaf | Kind::Bush => tree(kind, budget, &mut rng),
        Kind::Conifer => conifer(budget, &mut rng),
        Kind::Fern => fern(budget, &mut rng),
        Kind::Flower => flower(budget, &mut rng),
        Kind::Grass => grass(budget, &mut rng),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_kind_spends_most_of_its_budget_and_is_deterministic() {
        for kind in [
            Kind::Broadleaf,
            Kind::Conifer,
            Kind::Bush,
            Kind::Fern,
            Kind::Flower,
            Kind::Grass,
        ] {
            let p = plant(kind, 20_000, 5);
            let n = p.wood.triangle_count() + p.foliage.triangle_count();
            assert!(n > 10_000 && n <= 20_500, "{}: {n}", kind.name());
            assert!(p.foliage.triangle_count() > 0);
            let q = plant(kind, 20_000, 5);
            assert_eq!(p.foliage.positions, q.foliage.positions);
        }
    }
}
