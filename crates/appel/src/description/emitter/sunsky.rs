//! Mitsuba 3's `sunsky`: Hosek and Wilkie's sky with a solar disk.

use super::{unit, EmitterParams};
use crate::description::param_error::{finite, non_negative, ParamError};
use crate::description::{TransformDesc, Vec3f};
use serde::{Deserialize, Serialize};

/// Sky and sun of Hosek and Wilkie's model around the scene, in a frame whose +z is the zenith
/// and +x north, turned into the scene by `transform`. The sun stands along `sun_direction`
/// (world space), or where it is seen from `latitude`/`longitude` (degrees) at the local time
/// `year`-`month`-`day` `hour`:`minute`:`second` in `timezone` (hours ahead of UTC); without
/// either, at Mitsuba's default place and time (see [`SunSkyDesc::sun`]).
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct SunSkyDesc {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sun_direction: Option<Vec3f>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub latitude: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub longitude: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub timezone: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub year: Option<i64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub month: Option<i64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub day: Option<i64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub hour: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub minute: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub second: Option<f64>,
    /// Atmospheric turbidity in [1, 10] (3: a clear temperate sky).
    #[serde(default = "default_turbidity")]
    pub turbidity: f32,
    /// Ground albedo in [0, 1] per channel.
    #[serde(default = "default_albedo")]
    pub albedo: Vec3f,
    #[serde(default = "unit")]
    pub sun_scale: f32,
    #[serde(default = "unit")]
    pub sky_scale: f32,
    /// The sun's angular diameter in degrees, in (0, 180); its irradiance stays the same.
    #[serde(default = "default_sun_aperture")]
    pub sun_aperture: f32,
    /// The limb-darkened solar disk instead of a uniform one.
    #[serde(default)]
    pub complex_sun: bool,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub transform: Option<TransformDesc>,
}

fn default_turbidity() -> f32 {
    3.0
}
fn default_albedo() -> Vec3f {
    [0.3; 3]
}
/// The real sun's angular diameter in degrees, as Mitsuba's `sunsky` takes it.
fn default_sun_aperture() -> f32 {
    0.5358
}

/// Where the sun stands: along a world-space direction, or where it is seen from a place at a
/// time.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SunPlaceDesc {
    Direction(Vec3f),
    Time(SunTime),
}

/// A place and a local time (Mitsuba's `sunsky` location and date parameters). The sun's
/// position at it is computed by shading (`shading::emitter::sunsky`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SunTime {
    /// Degrees north.
    pub latitude: f64,
    /// Degrees east.
    pub longitude: f64,
    /// Hours ahead of UTC.
    pub timezone: f64,
    pub year: i64,
    pub month: i64,
    pub day: i64,
    pub hour: f64,
    pub minute: f64,
    pub second: f64,
}

impl SunSkyDesc {
    /// The sun's place with Mitsuba's defaults for what is not given: Tokyo (35.6894° N,
    /// 139.6917° E, UTC+9), 2010-07-10 15:00:00.
    pub fn sun(&self) -> SunPlaceDesc {
        match self.sun_direction {
            Some(d) => SunPlaceDesc::Direction(d),
            None => SunPlaceDesc::Time(SunTime {
                latitude: self.latitude.unwrap_or(35.6894),
                longitude: self.longitude.unwrap_or(139.6917),
                timezone: self.timezone.unwrap_or(9.0),
                year: self.year.unwrap_or(2010),
                month: self.month.unwrap_or(7),
                day: self.day.unwrap_or(10),
                hour: self.hour.unwrap_or(15.0),
                minute: self.minute.unwrap_or(0.0),
                second: self.second.unwrap_or(0.0),
            }),
        }
    }

    /// The keys of the place and time, with whether each is given.
    fn place_and_time(&self) -> [(&'static str, bool); 9] {
        [
            ("latitude", self.latitude.is_some()),
            ("longitude", self.longitude.is_some()),
            ("timezone", self.timezone.is_some()),
            ("year", self.year.is_some()),
            ("month", self.month.is_some()),
            ("day", self.day.is_some()),
            ("hour", self.hour.is_some()),
            ("minute", self.minute.is_some()),
            ("second", self.second.is_some()),
        ]
    }
}

fn outside<T: std::fmt::Display>(key: &'static str, range: &str, v: T) -> ParamError {
    ParamError::new(key, format!("`{key}` must lie in {range}, got {v}"))
}

impl EmitterParams for SunSkyDesc {
    const NAME: &'static str = "sunsky";

    fn check(&self) -> Result<(), ParamError> {
        if let Some(d) = &self.sun_direction {
            finite("sun_direction", d)?;
            if d.iter().all(|&x| x == 0.0) {
                return Err(ParamError::new(
                    "sun_direction",
                    "`sun_direction` must not be zero",
                ));
            }
            if let Some((k, _)) = self.place_and_time().into_iter().find(|(_, given)| *given) {
                return Err(ParamError::new(
                    k,
                    format!("give `sun_direction` or a place and time, not both (`{k}`)"),
                ));
            }
        }
        for (k, v) in [
            ("latitude", self.latitude),
            ("longitude", self.longitude),
            ("timezone", self.timezone),
            ("hour", self.hour),
            ("minute", self.minute),
            ("second", self.second),
        ] {
            if let Some(v) = v.filter(|v| !v.is_finite()) {
                return Err(ParamError::new(k, format!("`{k}` must be finite, got {v}")));
            }
        }
        if let Some(l) = self.latitude.filter(|l| !(-90.0..=90.0).contains(l)) {
            return Err(outside("latitude", "[-90, 90]", l));
        }
        if let Some(m) = self.month.filter(|m| !(1..=12).contains(m)) {
            return Err(outside("month", "[1, 12]", m));
        }
        if let Some(d) = self.day.filter(|d| !(1..=31).contains(d)) {
            return Err(outside("day", "[1, 31]", d));
        }
        if !(1.0..=10.0).contains(&self.turbidity) {
            return Err(outside("turbidity", "[1, 10]", self.turbidity));
        }
        non_negative("albedo", &self.albedo)?;
        if self.albedo.iter().any(|&a| a > 1.0) {
            return Err(outside("albedo", "[0, 1]", format!("{:?}", self.albedo)));
        }
        non_negative("sun_scale", &[self.sun_scale])?;
        non_negative("sky_scale", &[self.sky_scale])?;
        let aperture = self.sun_aperture;
        if !(aperture > 0.0 && aperture < 180.0) {
            return Err(outside("sun_aperture", "(0, 180) degrees", aperture));
        }
        Ok(())
    }

    fn transform(&self) -> Option<&TransformDesc> {
        self.transform.as_ref()
    }
}
