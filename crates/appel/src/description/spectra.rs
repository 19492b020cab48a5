//! Named optical constants, as Mitsuba 3 names them: the real IORs of dielectrics
//! (`src/render/ior.h`, after Hecht, "Optics", 4th edition: 0 to 20 °C, about 589 nm) and the
//! complex IORs `eta + i k` of conductors.
//!
//! Mitsuba's conductors are measured spectra (`data/ior/NAME.{eta,k}.spd`); in RGB mode it reduces
//! each spectrum to a linear sRGB colour when the scene loads. The table holds the colours its
//! `scalar_rgb` variant actually uses (read back with `mi.traverse` from
//! `{'type': 'conductor', 'material': NAME}` in Mitsuba 3.9.1), so renders agree channel for channel.

use crate::math::Vec3;

/// Mitsuba's named IORs, in its order.
const IORS: [(&str, f32); 23] = [
    ("vacuum", 1.0),
    ("helium", 1.000036),
    ("hydrogen", 1.000132),
    ("air", 1.000277),
    ("carbon dioxide", 1.00045),
    ("water", 1.3330),
    ("acetone", 1.36),
    ("ethanol", 1.361),
    ("carbon tetrachloride", 1.461),
    ("glycerol", 1.4729),
    ("benzene", 1.501),
    ("silicone oil", 1.52045),
    ("bromine", 1.661),
    ("water ice", 1.31),
    ("fused quartz", 1.458),
    ("pyrex", 1.470),
    ("acrylic glass", 1.49),
    ("polypropylene", 1.49),
    ("bk7", 1.5046),
    ("sodium chloride", 1.544),
    ("amber", 1.55),
    ("pet", 1.5750),
    ("diamond", 2.419),
];

/// The names [`ior`] accepts, for error messages.
pub const IOR_NAMES: [&str; 23] = [
    "vacuum",
    "helium",
    "hydrogen",
    "air",
    "carbon dioxide",
    "water",
    "acetone",
    "ethanol",
    "carbon tetrachloride",
    "glycerol",
    "benzene",
    "silicone oil",
    "bromine",
    "water ice",
    "fused quartz",
    "pyrex",
    "acrylic glass",
    "polypropylene",
    "bk7",
    "sodium chloride",
    "amber",
    "pet",
    "diamond",
];

/// The IOR of a named dielectric (case-insensitive, as Mitsuba lower-cases the name), or `None`.
pub fn ior(name: &str) -> Option<f32> {
    let lower = name.to_lowercase();
    IORS.iter().find(|(n, _)| *n == lower).map(|&(_, v)| v)
}

/// `eta` and `k` (linear RGB) of every conductor Mitsuba 3 ships, by its file name (case-sensitive:
/// Mitsuba opens `data/ior/NAME.eta.spd`). Some `k` channels are 0 where Mitsuba clamps a slightly
/// negative colour (dielectric-like materials such as MgO).
const CONDUCTORS: [(&str, [f32; 3], [f32; 3]); 71] = [
    (
        "Ag",
        [0.1552762, 0.116727956, 0.13838764],
        [4.8283544, 3.1222224, 2.1469011],
    ),
    (
        "Al",
        [1.6575009, 0.8804047, 0.52124447],
        [9.223811, 6.269502, 4.837004],
    ),
    (
        "AlAs",
        [3.605296, 3.2329378, 2.2163186],
        [0.0006794373, 0.0, 0.007512709],
    ),
    (
        "AlAs_palik",
        [3.605296, 3.2329378, 2.2163186],
        [0.0006794373, 0.0, 0.007512709],
    ),
    (
        "AlSb",
        [0.0, 4.1393747, 4.6692543],
        [0.0, 0.09400908, 1.30057],
    ),
    (
        "AlSb_palik",
        [0.0, 4.1393747, 4.6692543],
        [0.0, 0.09400908, 1.30057],
    ),
    (
        "Au",
        [0.14303598, 0.37530708, 1.4420453],
        [3.982997, 2.3855565, 1.6033592],
    ),
    (
        "Be",
        [4.1850123, 3.1850293, 2.7840612],
        [3.835466, 3.0101223, 2.868994],
    ),
    (
        "Be_palik",
        [4.1850123, 3.1850293, 2.7840612],
        [3.835466, 3.0101223, 2.868994],
    ),
    (
        "Cr",
        [4.3696675, 2.9165053, 1.6549046],
        [5.206547, 4.231306, 3.7546988],
    ),
    ("CsI", [2.1448996, 1.7023189, 1.6624272], [0.0, 0.0, 0.0]),
    (
        "CsI_palik",
        [2.1448996, 1.7023189, 1.6624272],
        [0.0, 0.0, 0.0],
    ),
    (
        "Cu",
        [0.20100547, 0.9237495, 1.1022154],
        [3.9132621, 2.4530451, 2.1420898],
    ),
    (
        "Cu2O",
        [3.5517726, 2.9498696, 2.7518754],
        [0.11420702, 0.19389686, 0.6061339],
    ),
    (
        "Cu2O_palik",
        [3.5517726, 2.9498696, 2.7518754],
        [0.11420702, 0.19389686, 0.6061339],
    ),
    (
        "CuO",
        [3.247541, 2.4478052, 2.2102196],
        [0.52108955, 0.57003075, 0.72217894],
    ),
    (
        "CuO_palik",
        [3.247541, 2.4478052, 2.2102196],
        [0.52108955, 0.57003075, 0.72217894],
    ),
    (
        "Cu_palik",
        [0.21322851, 0.9197154, 1.1024108],
        [3.9218733, 2.4573317, 2.136584],
    ),
    (
        "Hg",
        [2.3989387, 1.440028, 0.9095704],
        [6.327587, 4.371925, 3.4217637],
    ),
    (
        "HgTe",
        [4.77904, 3.2311962, 2.6599011],
        [1.6316127, 1.5808104, 1.7292874],
    ),
    (
        "HgTe_palik",
        [4.77904, 3.2311962, 2.6599011],
        [1.6316127, 1.5808104, 1.7292874],
    ),
    (
        "Hg_palik",
        [2.3989387, 1.440028, 0.9095704],
        [6.327587, 4.371925, 3.4217637],
    ),
    (
        "Ir",
        [3.0863, 2.0821905, 1.6179146],
        [5.592153, 4.067088, 3.267312],
    ),
    (
        "Ir_palik",
        [3.0863, 2.0821905, 1.6179146],
        [5.592153, 4.067088, 3.267312],
    ),
    (
        "K",
        [0.06404319, 0.046409767, 0.038184915],
        [2.1041996, 1.34894, 0.9131259],
    ),
    (
        "K_palik",
        [0.06404319, 0.046409767, 0.038184915],
        [2.1041996, 1.34894, 0.9131259],
    ),
    (
        "Li",
        [0.26579094, 0.19561832, 0.22094862],
        [3.540155, 2.3111234, 1.6686072],
    ),
    (
        "Li_palik",
        [0.26579094, 0.19561832, 0.22094862],
        [3.540155, 2.3111234, 1.6686072],
    ),
    (
        "MgO",
        [2.0895839, 1.6507235, 1.594879],
        [4.3326952e-12, 0.0, 2.4986457e-11],
    ),
    (
        "MgO_palik",
        [2.0895839, 1.6507235, 1.594879],
        [4.3326952e-12, 0.0, 2.4986457e-11],
    ),
    (
        "Mo",
        [4.483974, 3.5251307, 2.7763104],
        [4.1114373, 3.420827, 3.1506073],
    ),
    (
        "Mo_palik",
        [4.483974, 3.5251307, 2.7763104],
        [4.1114373, 3.420827, 3.1506073],
    ),
    (
        "Na_palik",
        [0.060269356, 0.056140948, 0.061988432],
        [3.1792734, 2.1124904, 1.5790411],
    ),
    (
        "Nb",
        [3.420074, 2.7900932, 2.3956294],
        [3.4413946, 2.7376661, 2.5797458],
    ),
    (
        "Nb_palik",
        [3.420074, 2.7900932, 2.3956294],
        [3.4413946, 2.7376661, 2.5797458],
    ),
    (
        "Ni_palik",
        [2.3673046, 1.6633731, 1.4670781],
        [4.4988117, 3.050153, 2.3454392],
    ),
    (
        "Rh",
        [2.5857935, 1.8602164, 1.5542634],
        [6.7822604, 4.702987, 3.976073],
    ),
    (
        "Rh_palik",
        [2.5857935, 1.8602164, 1.5542634],
        [6.7822604, 4.702987, 3.976073],
    ),
    (
        "Se",
        [4.0583115, 2.842935, 2.8208535],
        [0.75404954, 0.6384435, 0.52180755],
    ),
    (
        "Se-e",
        [5.722849, 4.165736, 4.0813384],
        [0.8711363, 1.1051575, 1.5653203],
    ),
    (
        "Se-e_palik",
        [5.722849, 4.165736, 4.0813384],
        [0.8711363, 1.1051575, 1.5653203],
    ),
    (
        "Se_palik",
        [4.0583115, 2.842935, 2.8208535],
        [0.75404954, 0.6384435, 0.52180755],
    ),
    (
        "SiC",
        [3.1723416, 2.5259717, 2.4793706],
        [7.5376636e-07, 0.0, 1.0192531e-05],
    ),
    (
        "SiC_palik",
        [3.1723416, 2.5259717, 2.4793706],
        [7.5376636e-07, 0.0, 1.0192531e-05],
    ),
    ("SnTe", [4.5242496, 1.981645, 1.2815913], [0.0, 0.0, 0.0]),
    (
        "SnTe_palik",
        [4.5242496, 1.981645, 1.2815913],
        [0.0, 0.0, 0.0],
    ),
    (
        "Ta",
        [2.062721, 2.3929389, 2.6279287],
        [2.4083598, 1.7414864, 1.9470278],
    ),
    (
        "Ta_palik",
        [2.062721, 2.3929389, 2.6279287],
        [2.4083598, 1.7414864, 1.9470278],
    ),
    (
        "Te",
        [7.3902335, 4.482105, 2.637106],
        [3.2560222, 3.5270588, 3.2920542],
    ),
    (
        "Te-e",
        [7.508907, 4.2964287, 2.3699877],
        [5.5839286, 4.947205, 3.9975922],
    ),
    (
        "Te-e_palik",
        [7.508907, 4.2964287, 2.3699877],
        [5.5839286, 4.947205, 3.9975922],
    ),
    (
        "Te_palik",
        [7.3902335, 4.482105, 2.637106],
        [3.2560222, 3.5270588, 3.2920542],
    ),
    ("ThF4", [1.8307136, 1.4422286, 1.3876476], [0.0, 0.0, 0.0]),
    (
        "ThF4_palik",
        [1.8307136, 1.4422286, 1.3876476],
        [0.0, 0.0, 0.0],
    ),
    (
        "TiC",
        [3.7005284, 2.8374221, 2.582287],
        [3.265635, 2.3515892, 2.1727905],
    ),
    (
        "TiC_palik",
        [3.7005284, 2.8374221, 2.582287],
        [3.265635, 2.3515892, 2.1727905],
    ),
    (
        "TiN",
        [1.6484497, 1.150516, 1.3798234],
        [3.368328, 1.9434981, 1.1020677],
    ),
    (
        "TiN_palik",
        [1.6484497, 1.150516, 1.3798234],
        [3.368328, 1.9434981, 1.1020677],
    ),
    (
        "TiO2",
        [3.45661, 2.8017359, 2.905175],
        [0.00010526484, 0.0, 0.0006528865],
    ),
    (
        "TiO2-e",
        [3.1065645, 2.5131683, 2.5824444],
        [2.9751605e-05, 0.0, 0.00018269809],
    ),
    (
        "TiO2-e_palik",
        [3.1065645, 2.5131683, 2.5824444],
        [2.9751605e-05, 0.0, 0.00018269809],
    ),
    (
        "TiO2_palik",
        [3.45661, 2.8017359, 2.905175],
        [0.00010526484, 0.0, 0.0006528865],
    ),
    (
        "VC",
        [3.657566, 2.752736, 2.532672],
        [3.0683007, 2.1986873, 1.9631927],
    ),
    (
        "VC_palik",
        [3.657566, 2.752736, 2.532672],
        [3.0683007, 2.1986873, 1.9631927],
    ),
    (
        "VN",
        [2.8656023, 2.119189, 1.9400911],
        [3.0322425, 2.0561156, 1.6163063],
    ),
    (
        "VN_palik",
        [2.8656023, 2.119189, 1.9400911],
        [3.0322425, 2.0561156, 1.6163063],
    ),
    (
        "V_palik",
        [4.277582, 3.5129488, 2.7610714],
        [3.4913008, 2.8894548, 3.111522],
    ),
    (
        "W",
        [4.3708167, 3.3002465, 2.9984074],
        [3.5006406, 2.604874, 2.2732332],
    ),
    (
        "a-C",
        [2.9440458, 2.2271364, 1.9681617],
        [0.8874649, 0.7992985, 0.81529],
    ),
    ("d-C", [2.7087197, 2.3188257, 2.2288976], [0.0, 0.0, 0.0]),
    (
        "d-C_palik",
        [2.7087197, 2.3188257, 2.2288976],
        [0.0, 0.0, 0.0],
    ),
];

/// The name of Mitsuba's default conductor: not a material but an ideal mirror, `eta = 0`,
/// `k = 1`, whose Fresnel reflectance is 1 at every angle.
pub const NO_CONDUCTOR: &str = "none";

/// The names [`conductor`] accepts, for error messages: [`NO_CONDUCTOR`], then Mitsuba's files.
pub const CONDUCTOR_NAMES: [&str; 72] = [
    "none",
    "Ag",
    "Al",
    "AlAs",
    "AlAs_palik",
    "AlSb",
    "AlSb_palik",
    "Au",
    "Be",
    "Be_palik",
    "Cr",
    "CsI",
    "CsI_palik",
    "Cu",
    "Cu2O",
    "Cu2O_palik",
    "CuO",
    "CuO_palik",
    "Cu_palik",
    "Hg",
    "HgTe",
    "HgTe_palik",
    "Hg_palik",
    "Ir",
    "Ir_palik",
    "K",
    "K_palik",
    "Li",
    "Li_palik",
    "MgO",
    "MgO_palik",
    "Mo",
    "Mo_palik",
    "Na_palik",
    "Nb",
    "Nb_palik",
    "Ni_palik",
    "Rh",
    "Rh_palik",
    "Se",
    "Se-e",
    "Se-e_palik",
    "Se_palik",
    "SiC",
    "SiC_palik",
    "SnTe",
    "SnTe_palik",
    "Ta",
    "Ta_palik",
    "Te",
    "Te-e",
    "Te-e_palik",
    "Te_palik",
    "ThF4",
    "ThF4_palik",
    "TiC",
    "TiC_palik",
    "TiN",
    "TiN_palik",
    "TiO2",
    "TiO2-e",
    "TiO2-e_palik",
    "TiO2_palik",
    "VC",
    "VC_palik",
    "VN",
    "VN_palik",
    "V_palik",
    "W",
    "a-C",
    "d-C",
    "d-C_palik",
];

/// `(eta, k)` of a named conductor, relative to vacuum, or `None` for a name Mitsuba does not know.
/// `"none"` is the ideal mirror (`eta = 0`, `k = 1`), Mitsuba's default `material`.
pub fn conductor(name: &str) -> Option<(Vec3, Vec3)> {
    if name == NO_CONDUCTOR {
        return Some((Vec3::ZERO, Vec3::ONE));
    }
    CONDUCTORS
        .iter()
        .find(|(n, _, _)| *n == name)
        .map(|&(_, eta, k)| (Vec3::from_array(eta), Vec3::from_array(k)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn named_iors() {
        assert_eq!(ior("bk7"), Some(1.5046));
        assert_eq!(ior("Water"), Some(1.333));
        assert_eq!(ior("carbon dioxide"), Some(1.00045));
        assert_eq!(ior("glass"), None);
        for name in IOR_NAMES {
            assert!(ior(name).is_some_and(|v| (1.0..2.5).contains(&v)), "{name}");
        }
        assert_eq!(IOR_NAMES.len(), IORS.len());
    }

    #[test]
    fn named_conductors() {
        // Mitsuba 3.9.1 scalar_rgb: conductor 'Au' has eta = [0.143036, 0.375307, 1.44205],
        // k = [3.983, 2.38556, 1.60336]; 'Cu' eta = [0.201005, 0.92375, 1.10222].
        let (eta, k) = conductor("Au").unwrap();
        assert!(
            (eta - Vec3::new(0.143_036, 0.375_307, 1.442_05))
                .abs()
                .max_element()
                < 1e-5
        );
        assert!(
            (k - Vec3::new(3.983, 2.385_56, 1.603_36))
                .abs()
                .max_element()
                < 1e-5
        );
        let (eta, _) = conductor("Cu").unwrap();
        assert!(
            (eta - Vec3::new(0.201_005, 0.923_75, 1.102_22))
                .abs()
                .max_element()
                < 1e-5
        );
        assert_eq!(conductor("none"), Some((Vec3::ZERO, Vec3::ONE)));
        assert_eq!(conductor("au"), None);
        for name in CONDUCTOR_NAMES {
            let (eta, k) = conductor(name).unwrap();
            assert!(
                eta.is_finite() && k.is_finite() && eta.min_element() >= 0.0,
                "{name}"
            );
            assert!(k.min_element() >= 0.0, "{name}");
        }
    }
}
