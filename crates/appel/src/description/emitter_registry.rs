//! The one list of emitters. Everything that enumerates emitters is generated from it: the runtime
//! enum `shading::emitter::Emitter` with its per-call match (`shading/emitter/mod.rs`, which checks
//! at compile time that each type's `EmitterPlugin::NAME` is its name here), the plugin modules,
//! and the names the formats list in their errors ([`EMITTER_NAMES`], [`is_light`]).

/// Calls macro `$then!` with every emitter as `Variant { name, runtime, light }`:
/// - `name`: its name (`[[light]] type`, Mitsuba's plugin name);
/// - `runtime`: the type in `shading/emitter/` (`module::Type`) that implements
///   `EmitterPlugin`;
/// - `light`: `[Desc]`, its parameters' struct in `description/emitter/` (implementing
///   [`super::EmitterParams`]) when it is a `[[light]]` of its own (a variant of
///   [`super::LightDesc`]); `[]` for a surface's `emitter`.
///
/// Adding an emitter is its runtime file, its parameters' file, one line here, the scene's
/// construction of it (`scene_build/emitters.rs`) and the format mappings that name it.
/// `$then` may be given leading tokens to carry (`$then!(tokens)`).
macro_rules! for_each_emitter {
    ($then:ident $(($($carry:tt)*))?) => {
        $then! {
            $($($carry)*)?
            Point { name: point, runtime: point::PointLight, light: [PointDesc] },
            Spot { name: spot, runtime: spot::SpotLight, light: [SpotDesc] },
            Projector { name: projector, runtime: projector::Projector, light: [ProjectorDesc] },
            Directional { name: directional, runtime: directional::DirectionalLight, light: [DirectionalDesc] },
            Area { name: area, runtime: area::AreaEmitter, light: [] },
            Constant { name: constant, runtime: constant::ConstantEnvironment, light: [ConstantDesc] },
            EnvMap { name: envmap, runtime: envmap::EnvMap, light: [EnvMapDesc] },
            EqualAreaEnvMap { name: equalareaenvmap, runtime: equal_area_envmap::EqualAreaEnvMap, light: [EqualAreaEnvMapDesc] },
            SunSky { name: sunsky, runtime: sunsky::SunSky, light: [SunSkyDesc] },
        }
    };
}
pub(crate) use for_each_emitter;

macro_rules! define_emitter_names {
    ($($Variant:ident { name: $name:ident, runtime: $module:ident::$Type:ident, light: [$($Desc:ident)?] }),* $(,)?) => {
        /// Every emitter's name, in the registry's order.
        pub const EMITTER_NAMES: &[&str] = &[$(stringify!($name),)*];

        /// Whether `name` is an emitter of its own (`[[light]]`), rather than a surface's.
        pub fn is_light(name: &str) -> bool {
            match name {
                $(stringify!($name) => !<[&str]>::is_empty(&[$(stringify!($Desc))?]),)*
                _ => false,
            }
        }
    };
}
for_each_emitter!(define_emitter_names);

/// The names of the `[[light]]` emitters, comma-separated, for error messages.
pub fn light_names() -> String {
    EMITTER_NAMES
        .iter()
        .copied()
        .filter(|n| is_light(n))
        .collect::<Vec<_>>()
        .join(", ")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::description::LightDesc;

    /// `[[light]] type` accepts exactly the registry's lights (serde lists its variants in the
    /// error for an unknown one).
    #[test]
    fn the_light_table_names_the_registrys_lights() {
        let e = toml::from_str::<LightDesc>("type = \"nope\"")
            .unwrap_err()
            .to_string();
        let listed: Vec<String> = e
            .split("expected one of ")
            .nth(1)
            .expect("serde lists the variants")
            .split(',')
            .map(|s| s.trim().trim_matches('`').to_string())
            .filter(|s| !s.is_empty())
            .collect();
        let mut listed: Vec<&str> = listed
            .iter()
            .map(|s| s.lines().next().unwrap().trim_matches('`'))
            .collect();
        listed.sort();
        let mut lights: Vec<&str> = EMITTER_NAMES
            .iter()
            .copied()
            .filter(|n| is_light(n))
            .collect();
        lights.sort();
        assert_eq!(listed, lights, "{e}");
    }
}
