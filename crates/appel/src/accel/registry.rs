//! The one list of acceleration structures. Everything that enumerates structures is generated from
//! it: the modules, [`super::AccelKind`] and its names, [`super::AccelOptions`], the [`super::Accel`]
//! enum and its per-ray matches, and the scene file's `[render.NAME]` tables
//! (`description::RenderDesc`) with their validation.

/// Calls macro `$then!` with every structure as `Variant(module::Type)`: `accel/module` holds the
/// structure, `Type` implements [`super::Structure`], and `module` is its name (`render.accel =
/// "module"`, `--accel module`, `[render.module]`). Adding a structure is its folder and one line
/// here. The order is the order of [`super::AccelKind::NAMES`].
macro_rules! for_each_structure {
    ($then:ident) => {
        $then! {
            Brute(brute::Brute),
            Grid(grid::Grid),
            KdTree(kdtree::KdTree),
            Bvh(bvh::Bvh),
            Octree(octree::Octree),
            Bsp(bsp::Bsp),
        }
    };
}
pub(crate) use for_each_structure;

/// The items of `accel` generated from the list (invoked in `accel/mod.rs`, so that the modules
/// are its children).
macro_rules! define_structures {
    ($($Variant:ident($module:ident::$Type:ident)),* $(,)?) => {
        $(pub mod $module;)*
        $(pub use $module::$Type;)*

        $(const _: () = assert!(
            structure::same_name(<$Type as Structure>::NAME, stringify!($module)),
            concat!("`", stringify!($Type), "::NAME` must be its module's name")
        );)*

        /// The structures a user can choose by name (`render.accel`, `--accel`).
        #[derive(Clone, Copy, Debug, PartialEq, Eq)]
        pub enum AccelKind {
            $($Variant,)*
        }

        impl AccelKind {
            /// Every kind, in the registry's order.
            pub const ALL: &'static [AccelKind] = &[$(AccelKind::$Variant,)*];
            pub const NAMES: &'static [&'static str] = &[$(<$Type as Structure>::NAME,)*];

            pub fn from_name(name: &str) -> Option<Self> {
                Self::ALL.iter().copied().find(|k| k.name() == name)
            }

            pub fn name(self) -> &'static str {
                match self {
                    $(AccelKind::$Variant => <$Type as Structure>::NAME,)*
                }
            }
        }

        /// Build parameters of every structure, each under its name; [`Accel::build_with`] uses
        /// the ones of the kind it builds.
        #[derive(Clone, Copy, Debug, Default, PartialEq)]
        pub struct AccelOptions {
            $(pub $module: <$Type as Structure>::Options,)*
        }

        /// A built acceleration structure: one match per ray, then the structure's own code,
        /// monomorphised and inlined (no dynamic dispatch).
        #[derive(Clone, Debug)]
        pub enum Accel {
            $($Variant($Type),)*
        }

        impl Accel {
            pub fn build_with<P: Primitives>(kind: AccelKind, prims: &P, o: &AccelOptions) -> Self {
                match kind {
                    $(AccelKind::$Variant => Accel::$Variant(<$Type as Structure>::build(prims, &o.$module)),)*
                }
            }

            pub fn kind(&self) -> AccelKind {
                match self {
                    $(Accel::$Variant(_) => AccelKind::$Variant,)*
                }
            }

            #[inline(always)]
            pub fn intersect<P: Primitives>(
                &self,
                prims: &P,
                ray: &Ray,
                t_max: f32,
                stats: &mut TraversalStats,
            ) -> Option<Hit> {
                match self {
                    $(Accel::$Variant(a) => Structure::intersect(a, prims, ray, t_max, stats),)*
                }
            }

            #[inline(always)]
            pub fn occluded<P: Primitives>(
                &self,
                prims: &P,
                ray: &Ray,
                t_max: f32,
                stats: &mut TraversalStats,
            ) -> bool {
                match self {
                    $(Accel::$Variant(a) => Structure::occluded(a, prims, ray, t_max, stats),)*
                }
            }

            /// See [`Structure::single_leaf`]: decided at the build, so asked at every ray.
            #[inline(always)]
            pub fn single_leaf(&self) -> Option<usize> {
                match self {
                    $(Accel::$Variant(a) => Structure::single_leaf(a),)*
                }
            }

            /// Whether [`Self::intersect_packet`] traces packets together (rather than ray by ray).
            pub fn has_packets(&self) -> bool {
                match self {
                    $(Accel::$Variant(a) => Structure::has_packets(a),)*
                }
            }

            /// Closest hits of up to [`bvh::PACKET`] rays, `out[i]` for `rays[i]`: the hits of
            /// [`Self::intersect`] on each ray. The 8-wide BVH traverses coherent packets together;
            /// other structures go ray by ray.
            pub fn intersect_packet<P: Primitives>(
                &self,
                prims: &P,
                rays: &[Ray],
                t_max: f32,
                out: &mut [Option<Hit>],
                stats: &mut TraversalStats,
            ) {
                match self {
                    $(Accel::$Variant(a) => Structure::intersect_packet(a, prims, rays, t_max, out, stats),)*
                }
            }

            /// Refits the structure to `prims`, the primitives it was built over after they moved
            /// (same count, same ids), and returns its SAH cost afterwards; `None` for structures
            /// that cannot be refitted (only the BVH can: the others' cells and planes are fixed by
            /// the build) and must be built again.
            pub fn refit<P: Primitives>(&mut self, prims: &P) -> Option<f64> {
                match self {
                    $(Accel::$Variant(a) => Structure::refit(a, prims),)*
                }
            }

            /// The SAH cost of a refittable structure as it stands (see [`Bvh::current_sah_cost`]).
            pub fn current_sah_cost(&self) -> Option<f64> {
                match self {
                    $(Accel::$Variant(a) => Structure::current_sah_cost(a),)*
                }
            }

            pub fn stats(&self) -> AccelStats {
                match self {
                    $(Accel::$Variant(a) => Structure::stats(a),)*
                }
            }
        }
    };
}
pub(crate) use define_structures;
