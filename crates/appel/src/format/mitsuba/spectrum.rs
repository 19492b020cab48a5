//! Spectra to linear sRGB, as Mitsuba 3's RGB variants do when they read a `<spectrum>` of
//! `wavelength:value` pairs: the piecewise-linear spectrum is integrated against the CIE 1931
//! colour matching functions to XYZ (1000 evenly spaced samples over 360-830 nm), then taken to
//! linear sRGB (Rec. 709 primaries, D65 white). Reflectances and indices are seen under the D65
//! illuminant (so that a flat 1 is white); emission is integrated as it is.

/// First and last wavelength of the table, in nanometres.
const CIE_MIN: f64 = 360.0;
const CIE_MAX: f64 = 830.0;

/// Scales the matching functions so that a spectrum of 1 everywhere has luminance 1 (Mitsuba's
/// `MI_CIE_Y_NORMALIZATION`).
const CIE_Y_NORMALIZATION: f64 = 1.0 / 106.750_259_399_414_06;

/// Scales the D65 table so that D65 has luminance 1 (Mitsuba's `MI_CIE_D65_NORMALIZATION`).
const CIE_D65_NORMALIZATION: f64 = 1.0 / 98.99741751876255;

/// Samples of the integral.
const STEPS: usize = 1000;

/// XYZ to linear sRGB, the matrix Mitsuba's `xyz_to_srgb` uses.
const XYZ_TO_SRGB: [[f64; 3]; 3] = [
    [3.240479, -1.537150, -0.498535],
    [-0.969256, 1.875991, 0.041556],
    [0.055648, -0.204043, 1.057311],
];

/// The colour Mitsuba 3.9.1's scalar_rgb variant gives a uniform spectrum of 1 inside an emitter
/// (measured with its Python module: `<spectrum name="radiance" value="1"/>` in an area emitter).
/// It is the colour of the equal-energy illuminant, which is not white in sRGB; Mitsuba's value
/// differs from `pairs_to_rgb` of a flat spectrum by up to 4e-4, so it is kept as measured.
pub const UNIFORM_EMITTER_RGB: [f64; 3] = [1.20479393, 0.948291004, 0.908916056];

/// The CIE 1931 2-degree standard observer, x-bar, y-bar, z-bar from 360 nm to 830 nm in steps of
/// 5 nm (CIE 018:2019; the table Mitsuba 3 embeds in `src/core/spectrum.cpp`, read back here
/// through its Python module's `cie1931_xyz` at each sample, single precision).
#[rustfmt::skip]
const CIE_1931: [[f64; 3]; 95] = [
    [0.0001299, 3.91699996e-06, 0.000606100017],
    [0.000232100007, 6.96500001e-06, 0.001086],
    [0.000414899987, 1.23899999e-05, 0.00194600003],
    [0.000741600001, 2.202e-05, 0.003486],
    [0.00136800006, 3.89999987e-05, 0.00645000115],
    [0.00223600003, 6.39999998e-05, 0.0105499905],
    [0.00424299994, 0.000119999997, 0.0200500097],
    [0.00765000004, 0.000216999993, 0.0362100005],
    [0.0143100005, 0.000395999989, 0.0678500086],
    [0.0231899992, 0.000639999984, 0.110200003],
    [0.0435100012, 0.00121000002, 0.207399994],
    [0.0776299983, 0.00218000007, 0.371300012],
    [0.134379998, 0.00400000019, 0.645600021],
    [0.214770004, 0.00730000017, 1.0390501],
    [0.283899993, 0.0115999999, 1.38559997],
    [0.328500003, 0.0168399997, 1.62295997],
    [0.348280013, 0.023, 1.74705994],
    [0.348060012, 0.0297999997, 1.78260005],
    [0.336199999, 0.0379999988, 1.77210999],
    [0.318699986, 0.0480000004, 1.74409997],
    [0.290800005, 0.0599999987, 1.66919994],
    [0.251100004, 0.0738999993, 1.52810001],
    [0.195360005, 0.0909800008, 1.28763998],
    [0.142100006, 0.112599999, 1.04190004],
    [0.0956400037, 0.139019996, 0.812950075],
    [0.0579500087, 0.169300005, 0.61619997],
    [0.0320100002, 0.208020002, 0.46518001],
    [0.0147000002, 0.258599997, 0.353300005],
    [0.00490000006, 0.323000014, 0.272000015],
    [0.00240000011, 0.407299995, 0.212300003],
    [0.00930000003, 0.503000021, 0.158199996],
    [0.0291000009, 0.608200014, 0.111699998],
    [0.0632700026, 0.709999979, 0.0782499909],
    [0.1096, 0.793200016, 0.0572500117],
    [0.1655, 0.861999989, 0.0421600007],
    [0.225749895, 0.914850116, 0.02984],
    [0.290399998, 0.953999996, 0.0203000009],
    [0.359699994, 0.980300009, 0.0133999996],
    [0.433449894, 0.994950116, 0.00874999911],
    [0.512050092, 1.0, 0.00574999908],
    [0.594500005, 0.995000005, 0.00389999989],
    [0.67839998, 0.978600025, 0.00274999905],
    [0.762099981, 0.952000022, 0.00209999993],
    [0.842499971, 0.915400028, 0.00179999997],
    [0.916299999, 0.870000005, 0.00165000104],
    [0.978600025, 0.816299975, 0.00139999995],
    [1.02629995, 0.757000029, 0.00109999999],
    [1.05669999, 0.694899976, 0.00100000005],
    [1.06219995, 0.630999982, 0.00079999998],
    [1.04560006, 0.566799998, 0.000600000028],
    [1.00259995, 0.503000021, 0.000339999999],
    [0.938399971, 0.441199988, 0.000239999994],
    [0.854449928, 0.381000012, 0.000190000006],
    [0.751399994, 0.32100001, 9.99999975e-05],
    [0.642400026, 0.264999986, 4.99999915e-05],
    [0.541899979, 0.216999993, 2.99999992e-05],
    [0.447899997, 0.174999997, 1.99999995e-05],
    [0.360799998, 0.1382, 9.99999975e-06],
    [0.283499986, 0.107000001, 0.0],
    [0.218700007, 0.0816000029, 0.0],
    [0.164900005, 0.0610000007, 0.0],
    [0.121200003, 0.0445800014, 0.0],
    [0.0873999968, 0.0320000015, 0.0],
    [0.0636000037, 0.0231999997, 0.0],
    [0.046769999, 0.0170000009, 0.0],
    [0.0329000019, 0.0119200004, 0.0],
    [0.0227000006, 0.00820999965, 0.0],
    [0.0158399995, 0.00572300004, 0.0],
    [0.0113591598, 0.00410200004, 0.0],
    [0.00811091624, 0.00292899995, 0.0],
    [0.00579034584, 0.00209100009, 0.0],
    [0.00410945714, 0.00148400001, 0.0],
    [0.00289932708, 0.00104700006, 0.0],
    [0.00204918999, 0.000739999989, 0.0],
    [0.00143997103, 0.000520000001, 0.0],
    [0.00099994929, 0.000361100014, 0.0],
    [0.000690078596, 0.000249200006, 0.0],
    [0.000476021291, 0.000171899999, 0.0],
    [0.000332301104, 0.000119999997, 0.0],
    [0.000234826104, 8.47999981e-05, 0.0],
    [0.000166150494, 5.99999985e-05, 0.0],
    [0.000117413001, 4.23999991e-05, 0.0],
    [8.30752688e-05, 2.99999992e-05, 0.0],
    [5.87065188e-05, 2.11999995e-05, 0.0],
    [4.15099385e-05, 1.49899997e-05, 0.0],
    [2.93532594e-05, 1.05999998e-05, 0.0],
    [2.06738296e-05, 7.46570004e-06, 0.0],
    [1.45597696e-05, 5.25779978e-06, 0.0],
    [1.02539798e-05, 3.7028999e-06, 0.0],
    [7.22145614e-06, 2.60780007e-06, 0.0],
    [5.085868e-06, 1.83659995e-06, 0.0],
    [3.58165198e-06, 1.29340003e-06, 0.0],
    [2.52252494e-06, 9.10929998e-07, 0.0],
    [1.77650895e-06, 6.41529994e-07, 0.0],
    [1.25114104e-06, 4.51809996e-07, 0.0],
];

/// The CIE standard illuminant D65 at the same wavelengths, relative to 100 at 560 nm (CIE
/// 015:2018; as in Mitsuba 3's `include/mitsuba/core/spectrum.h`, `d65_table`).
#[rustfmt::skip]
const CIE_D65: [f64; 95] = [
    46.6383, 49.3637, 52.0891, 51.0323, 49.9755, 52.3118, 54.6482,
    68.7015, 82.7549, 87.1204, 91.486, 92.4589, 93.4318, 90.057,
    86.6823, 95.7736, 104.865, 110.936, 117.008, 117.41, 117.812,
    116.336, 114.861, 115.392, 115.923, 112.367, 108.811, 109.082,
    109.354, 108.578, 107.802, 106.296, 104.79, 106.239, 107.689,
    106.047, 104.405, 104.225, 104.046, 102.023, 100.0, 98.1671,
    96.3342, 96.0611, 95.788, 92.2368, 88.6856, 89.3459, 90.0062,
    89.8026, 89.5991, 88.6489, 87.6987, 85.4936, 83.2886, 83.4939,
    83.6992, 81.863, 80.0268, 80.1207, 80.2146, 81.2462, 82.2778,
    80.281, 78.2842, 74.0027, 69.7213, 70.6652, 71.6091, 72.979,
    74.349, 67.9765, 61.604, 65.7448, 69.8856, 72.4863, 75.087,
    69.3398, 63.5927, 55.0054, 46.4182, 56.6118, 66.8054, 65.0941,
    63.3828, 63.8434, 64.304, 61.8779, 59.4519, 55.7054, 51.959,
    54.6998, 57.4406, 58.8765, 60.3125,
];

/// Linear interpolation in a table over 360-830 nm; the index of the lower sample and the
/// weight of the upper one. None outside the table.
fn table_position(lambda: f64) -> Option<(usize, f64)> {
    if !(CIE_MIN..=CIE_MAX).contains(&lambda) {
        return None;
    }
    let t = (lambda - CIE_MIN) * ((CIE_1931.len() - 1) as f64 / (CIE_MAX - CIE_MIN));
    let i0 = (t as usize).min(CIE_1931.len() - 2);
    Some((i0, t - i0 as f64))
}

/// D65 at `lambda`, normalized to luminance 1; zero outside the table.
fn cie_d65(lambda: f64) -> f64 {
    table_position(lambda).map_or(0.0, |(i0, w1)| {
        ((1.0 - w1) * CIE_D65[i0] + w1 * CIE_D65[i0 + 1]) * CIE_D65_NORMALIZATION
    })
}

/// The colour matching functions at `lambda`, linearly interpolated; zero outside the table.
fn cie1931_xyz(lambda: f64) -> [f64; 3] {
    let Some((i0, w1)) = table_position(lambda) else {
        return [0.0; 3];
    };
    let (a, b) = (CIE_1931[i0], CIE_1931[i0 + 1]);
    [0, 1, 2].map(|c| (1.0 - w1) * a[c] + w1 * b[c])
}

pub fn xyz_to_srgb(xyz: [f64; 3]) -> [f64; 3] {
    XYZ_TO_SRGB.map(|row| row[0] * xyz[0] + row[1] * xyz[1] + row[2] * xyz[2])
}

/// How a spectrum is turned into a colour, by what it describes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SpectrumUse {
    /// A reflectance or other fraction: under D65, clamped to [0, 1].
    Reflectance,
    /// An index of refraction or absorption (`eta`, `k`, `int_ior`, `ext_ior`): under D65, only
    /// negative parts clamped.
    Unbounded,
    /// Emitted light (any spectrum inside an `<emitter>`): as it is, negative parts clamped.
    Emission,
}

impl SpectrumUse {
    /// Mitsuba's rule: inside an emitter, everything is emission; elsewhere the parameter names
    /// of indices are unbounded.
    pub fn of(within_emitter: bool, name: &str) -> SpectrumUse {
        if within_emitter {
            SpectrumUse::Emission
        } else if matches!(name, "eta" | "k" | "int_ior" | "ext_ior") {
            SpectrumUse::Unbounded
        } else {
            SpectrumUse::Reflectance
        }
    }
}

/// Linear sRGB of the spectrum through `(wavelength, value)` points (at least two, wavelengths
/// increasing; zero outside them).
pub fn pairs_to_rgb(pairs: &[(f64, f64)], use_: SpectrumUse) -> [f64; 3] {
    assert!(pairs.len() >= 2, "checked by the parser");
    let (first, last) = (pairs[0].0, pairs[pairs.len() - 1].0);
    let mut xyz = [0.0; 3];
    for i in 0..STEPS {
        let x = CIE_MIN + (i as f64 / (STEPS - 1) as f64) * (CIE_MAX - CIE_MIN);
        if x < first || x > last {
            continue;
        }
        // The last point whose wavelength is at most x, keeping one after it.
        let k = pairs
            .partition_point(|p| p.0 <= x)
            .clamp(1, pairs.len() - 1)
            - 1;
        let ((x0, y0), (x1, y1)) = (pairs[k], pairs[k + 1]);
        let weight = match use_ {
            SpectrumUse::Emission => CIE_Y_NORMALIZATION,
            _ => CIE_Y_NORMALIZATION * cie_d65(x),
        };
        let y = (x * y0 - x1 * y0 - x * y1 + x0 * y1) / (x0 - x1) * weight;
        let c = cie1931_xyz(x);
        for (acc, c) in xyz.iter_mut().zip(c) {
            *acc += c * y;
        }
    }
    let rgb = xyz_to_srgb(xyz.map(|v| v * (CIE_MAX - CIE_MIN) / STEPS as f64));
    if use_ == SpectrumUse::Reflectance {
        rgb.map(|v| v.clamp(0.0, 1.0))
    } else {
        rgb.map(|v| v.max(0.0))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: [f64; 3], b: [f64; 3], tol: f64) -> bool {
        a.iter()
            .zip(b)
            .all(|(x, y)| (x - y).abs() <= tol * y.abs().max(1.0))
    }

    // Expected values: Mitsuba 3.9.1, scalar_rgb, `mi.traverse` of the loaded scene.
    #[test]
    fn the_fragments_spectra_match_mitsuba() {
        let reflectance = [(400.0, 0.78), (500.0, 0.78), (600.0, 0.78), (700.0, 0.78)];
        let rgb = pairs_to_rgb(&reflectance, SpectrumUse::Reflectance);
        assert!(
            close(rgb, [0.77636677, 0.779810011, 0.77602911], 2e-6),
            "{rgb:?}"
        );
        let radiance = [(400.0, 0.0), (500.0, 8.0), (600.0, 15.6), (700.0, 18.4)];
        let rgb = pairs_to_rgb(&radiance, SpectrumUse::Emission);
        assert!(
            close(rgb, [20.7108364, 10.8546343, 2.77115202], 2e-6),
            "{rgb:?}"
        );
    }

    #[test]
    fn clamping_follows_boundedness() {
        // A flat spectrum of 2 over 400-700 nm under D65: (1.99068, 1.99951, 1.98982) before
        // clamping, which a reflectance gets and an index (Mitsuba's `eta`) does not.
        let flat = [(400.0, 2.0), (700.0, 2.0)];
        assert_eq!(
            pairs_to_rgb(&flat, SpectrumUse::Reflectance),
            [1.0, 1.0, 1.0]
        );
        let rgb = pairs_to_rgb(&flat, SpectrumUse::Unbounded);
        assert!(
            close(rgb, [1.99068403, 1.99951279, 1.98981822], 2e-6),
            "{rgb:?}"
        );
        // A negative part: (0.612954, -0.0468454, -0.722825) before clamping (Mitsuba's `k`).
        let rgb = pairs_to_rgb(&[(400.0, -1.0), (700.0, 1.0)], SpectrumUse::Unbounded);
        assert!(close(rgb, [0.612954438, 0.0, 0.0], 2e-6), "{rgb:?}");
        // Emission beyond the table is not seen: the equal-energy colour over 360-830 nm.
        let rgb = pairs_to_rgb(&[(300.0, 1.0), (900.0, 1.0)], SpectrumUse::Emission);
        assert!(
            close(rgb, [1.20488369, 0.94822818, 0.909266829], 2e-6),
            "{rgb:?}"
        );
    }

    #[test]
    fn the_use_follows_mitsubas_names() {
        assert_eq!(SpectrumUse::of(true, "eta"), SpectrumUse::Emission);
        assert_eq!(SpectrumUse::of(false, "int_ior"), SpectrumUse::Unbounded);
        assert_eq!(SpectrumUse::of(false, "k"), SpectrumUse::Unbounded);
        assert_eq!(
            SpectrumUse::of(false, "reflectance"),
            SpectrumUse::Reflectance
        );
        // A flat 1 over the whole table, seen under D65, is white (to the table's precision).
        let rgb = pairs_to_rgb(&[(360.0, 1.0), (830.0, 1.0)], SpectrumUse::Unbounded);
        // (Mitsuba's value printed to six digits.)
        assert!(close(rgb, [0.998983, 0.998872, 0.998802], 5e-6), "{rgb:?}");
    }

    #[test]
    fn the_table_is_interpolated_and_zero_outside() {
        assert_eq!(cie1931_xyz(359.0), [0.0; 3]);
        assert_eq!(cie1931_xyz(831.0), [0.0; 3]);
        assert_eq!(cie1931_xyz(560.0), CIE_1931[40]);
        let mid = cie1931_xyz(562.5);
        assert!(close(
            mid,
            [0, 1, 2].map(|c| 0.5 * (CIE_1931[40][c] + CIE_1931[41][c])),
            1e-12
        ));
    }
}
