//! Where each entry of the converted description was written: the element that made it and its
//! parameters, under the description's keys (see `description::origins`).

use super::super::document::Object;
use crate::description::origins::Origin;

/// Description keys filled from a Mitsuba parameter of another name: `(key, parameter)`.
const RENAMED: &[(&str, &str)] = &[
    ("transform", "to_world"),
    ("color", "intensity"),
    ("color", "irradiance"),
    ("position", "to_world"),
    ("direction", "to_world"),
    ("look_at", "to_world"),
    ("up", "to_world"),
    ("eye", "to_world"),
    ("spp", "sample_count"),
];

/// The place of `o` and of its parameters (properties and named children), each also under the
/// description key it fills where that is named otherwise.
pub(super) fn origin_of(o: &Object) -> Origin {
    let mut parts: Vec<(String, crate::error::Location)> = o
        .props
        .iter()
        .map(|p| (p.name.clone(), p.loc.location()))
        .chain(
            o.children
                .iter()
                .filter_map(|c| Some((c.name.clone()?, c.loc.location()))),
        )
        .collect();
    for (key, name) in RENAMED {
        let has = |n: &str| parts.iter().any(|(p, _)| p == n);
        if has(key) {
            continue;
        }
        if let Some((_, at)) = parts.iter().find(|(p, _)| p == name) {
            let at = at.clone();
            parts.push((key.to_string(), at));
        }
    }
    Origin {
        at: o.loc.location(),
        parts,
    }
}
