//! `GET /api/lecture?scene=..&n=..&seed=..&structure=..&c=..&check=0|1&ray=x0,y0,x1,y1`: the
//! scene, the structure's build steps, the ray's traversal and every structure's counters on
//! the same ray, as JSON, all computed by `appel-lecture2d` (the page only draws).

use super::http::Request;
use appel_lecture2d::geometry::{brute_force, Ray2, P2};
use appel_lecture2d::{compare, scenes, Built, Params, STRUCTURES};
use serde_json::json;

/// Most objects a page may ask for (the builds are quadratic in places).
pub const MAX_OBJECTS: usize = 400;

pub fn answer(req: &Request) -> Result<String, String> {
    let (mut scene, mut n, mut seed, mut structure) = ("figures", 40usize, 1u64, "grid");
    let mut p = Params {
        grid_c: 1.0,
        grid_check: true,
    };
    let mut ray = None;
    for (k, v) in req.query_pairs() {
        let v = v.as_str();
        match k.as_str() {
            "scene" => {
                scene = *scenes::NAMES
                    .iter()
                    .find(|s| **s == v)
                    .ok_or_else(|| format!("scene: expected one of {}", scenes::NAMES.join(", ")))?
            }
            "structure" => {
                structure = *STRUCTURES.iter().find(|s| **s == v).ok_or_else(|| {
                    format!("structure: expected one of {}", STRUCTURES.join(", "))
                })?
            }
            "n" => {
                n = v
                    .parse()
                    .ok()
                    .filter(|&n| (1..=MAX_OBJECTS).contains(&n))
                    .ok_or(format!("n: expected 1 to {MAX_OBJECTS}"))?
            }
            "seed" => seed = v.parse().map_err(|_| "seed: expected a whole number")?,
            "c" => {
                p.grid_c = v
                    .parse()
                    .ok()
                    .filter(|c: &f64| (0.05..=16.0).contains(c))
                    .ok_or("c: expected 0.05 to 16")?
            }
            "check" => p.grid_check = v != "0",
            "ray" => {
                let x: Vec<f64> = v
                    .split(',')
                    .map(|s| s.parse::<f64>())
                    .collect::<Result<_, _>>()
                    .map_err(|_| "ray: expected x0,y0,x1,y1")?;
                let [x0, y0, x1, y1] = x[..] else {
                    return Err("ray: expected x0,y0,x1,y1".into());
                };
                if x.iter().any(|v| !v.is_finite() || v.abs() > 1e6) {
                    return Err("ray: expected finite coordinates".into());
                }
                ray = Ray2::through(P2::new(x0, y0), P2::new(x1, y1));
            }
            _ => return Err(format!("unknown parameter `{k}`")),
        }
    }
    let objects = scenes::scene(scene, n, seed);
    let built = Built::new(structure, &objects, p).expect("a known structure");
    let trace = ray.as_ref().map(|r| built.trace(&objects, r));
    let reference = ray.as_ref().and_then(|r| brute_force(&objects, r));
    Ok(json!({
        "world": appel_lecture2d::WORLD,
        "objects": objects,
        "structure": structure,
        "steps": built.steps(),
        "ray": ray,
        "trace": trace,
        "brute_force_hit": reference,
        "compare": compare(&objects, ray.as_ref(), p),
        "structures": STRUCTURES,
        "scenes": scenes::NAMES,
    })
    .to_string())
}
