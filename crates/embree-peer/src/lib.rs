//! Intel Embree 3 as a peer: the same triangles and the same rays, traced in Appel's own process, so
//! that Appel's hits can be checked against Embree's and its speed measured beside it (`appel bench
//! --embree`). The library is loaded at run time (`libembree3.so.3`, or the file named by
//! `APPEL_EMBREE_LIB`), so Appel builds everywhere and the peer reports plainly when it is missing.

mod ffi;

use std::ffi::{c_int, c_void, CString};
use std::sync::atomic::{AtomicIsize, Ordering};
use std::sync::OnceLock;
use std::time::{Duration, Instant};

/// Why Embree could not be used.
#[derive(Debug, thiserror::Error)]
pub enum EmbreeError {
    #[error("cannot load Embree 3 ({0}); install it with `apt-get install libembree3-3` or name the library in APPEL_EMBREE_LIB")]
    Load(String),
    #[error("Embree call failed: {0}")]
    Call(&'static str),
    #[error("Embree indexes triangles and vertices with u32; got {0}")]
    TooLarge(usize),
}

/// Embree's build quality (`RTCBuildQuality`): `Medium` is its default.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum BuildQuality {
    Low,
    #[default]
    Medium,
    High,
}

impl BuildQuality {
    pub fn from_name(name: &str) -> Option<Self> {
        match name {
            "low" => Some(Self::Low),
            "medium" => Some(Self::Medium),
            "high" => Some(Self::High),
            _ => None,
        }
    }

    fn code(self) -> c_int {
        match self {
            Self::Low => 0,
            Self::Medium => 1,
            Self::High => 2,
        }
    }
}

/// A loaded Embree library and one device.
pub struct Embree {
    api: &'static ffi::Api,
    device: ffi::Device,
    /// Bytes Embree holds, kept by its memory-monitor callback (boxed: Embree keeps the pointer).
    memory: Box<AtomicIsize>,
}

/// The library, loaded once and never unloaded: TBB's worker threads outlive every device, and
/// unloading their code under them crashes the process at exit.
fn api() -> Result<&'static ffi::Api, EmbreeError> {
    static API: OnceLock<Result<(libloading::Library, ffi::Api), String>> = OnceLock::new();
    API.get_or_init(|| {
        let names: Vec<String> = match std::env::var("APPEL_EMBREE_LIB") {
            Ok(path) => vec![path],
            Err(_) => vec!["libembree3.so.3".into(), "libembree3.so".into()],
        };
        let mut errors = vec![];
        for name in &names {
            // SAFETY: loading Embree runs its (and TBB's) initialisers, which have no preconditions.
            match unsafe { libloading::Library::new(name) } {
                // SAFETY: the library is Embree 3 by name; the signatures are those of its header.
                Ok(lib) => {
                    return match unsafe { ffi::Api::resolve(&lib) } {
                        Ok(api) => Ok((lib, api)),
                        Err(e) => Err(format!("{name}: {e}")),
                    }
                }
                Err(e) => errors.push(e.to_string()),
            }
        }
        Err(errors.join("; "))
    })
    .as_ref()
    .map(|(_, api)| api)
    .map_err(|e| EmbreeError::Load(e.clone()))
}

// Embree's device is thread-safe (rtcore.h: all API calls on a device may come from any thread).
unsafe impl Send for Embree {}
unsafe impl Sync for Embree {}

unsafe extern "C" fn count_memory(user: *mut c_void, bytes: isize, _post: bool) -> bool {
    // SAFETY: `user` is the `AtomicIsize` boxed in `Embree`, which outlives the device.
    unsafe { &*(user as *const AtomicIsize) }.fetch_add(bytes, Ordering::Relaxed);
    true
}

impl Embree {
    /// Loads Embree 3 (once per process) and creates a device whose builds use `threads` threads
    /// (0: all cores).
    pub fn load(threads: usize) -> Result<Self, EmbreeError> {
        let api = api()?;
        let config = CString::new(if threads > 0 {
            format!("threads={threads}")
        } else {
            String::new()
        })
        .expect("no NUL in the config");
        // SAFETY: a valid C string; a null device is checked below.
        let device = unsafe { (api.new_device)(config.as_ptr()) };
        if device.is_null() {
            return Err(EmbreeError::Call("rtcNewDevice"));
        }
        let memory = Box::new(AtomicIsize::new(0));
        // SAFETY: the box lives as long as the device (both are dropped together, device first).
        unsafe {
            (api.set_memory_monitor)(
                device,
                Some(count_memory),
                &*memory as *const AtomicIsize as *mut c_void,
            )
        };
        Ok(Self {
            api,
            device,
            memory,
        })
    }

    /// Embree's version, e.g. `3.13.5`.
    pub fn version(&self) -> String {
        // SAFETY: a live device.
        let v =
            unsafe { (self.api.get_device_property)(self.device, ffi::DEVICE_PROPERTY_VERSION) };
        format!("{}.{}.{}", v / 10000, v / 100 % 100, v % 100)
    }

    /// Whether this build of Embree traces 8-ray packets natively (AVX).
    pub fn native_ray8(&self) -> bool {
        // SAFETY: a live device.
        unsafe {
            (self.api.get_device_property)(self.device, ffi::DEVICE_PROPERTY_NATIVE_RAY8_SUPPORTED)
                != 0
        }
    }

    /// Bytes Embree holds right now, as its memory monitor reports them.
    pub fn bytes_in_use(&self) -> usize {
        self.memory.load(Ordering::Relaxed).max(0) as usize
    }

    fn check(&self, what: &'static str) -> Result<(), EmbreeError> {
        // SAFETY: a live device.
        match unsafe { (self.api.get_device_error)(self.device) } {
            0 => Ok(()),
            _ => Err(EmbreeError::Call(what)),
        }
    }

    /// Copies a triangle mesh into Embree and builds its BVH. `robust` asks for Embree's watertight
    /// triangle test and robust traversal (`RTC_SCENE_FLAG_ROBUST`), closer to Appel's guarantee.
    pub fn triangle_scene(
        &self,
        positions: &[[f32; 3]],
        indices: &[[u32; 3]],
        quality: BuildQuality,
        robust: bool,
    ) -> Result<TriangleScene<'_>, EmbreeError> {
        let too_large = positions.len().max(indices.len());
        if too_large >= u32::MAX as usize {
            return Err(EmbreeError::TooLarge(too_large));
        }
        let api = &self.api;
        let before = self.bytes_in_use();
        // SAFETY: every pointer comes from Embree on this device and is checked for null; buffers are
        // written within the item counts Embree allocated them for.
        unsafe {
            let scene = (api.new_scene)(self.device);
            if scene.is_null() {
                return Err(EmbreeError::Call("rtcNewScene"));
            }
            let mut scene = TriangleScene {
                embree: self,
                scene,
                build_time: Duration::ZERO,
                bytes: 0,
            };
            (api.set_scene_build_quality)(scene.scene, quality.code());
            if robust {
                (api.set_scene_flags)(scene.scene, ffi::SCENE_FLAG_ROBUST);
            }
            let geom = (api.new_geometry)(self.device, ffi::GEOMETRY_TYPE_TRIANGLE);
            if geom.is_null() {
                return Err(EmbreeError::Call("rtcNewGeometry"));
            }
            (api.set_geometry_build_quality)(geom, quality.code());
            let vertices = (api.set_new_geometry_buffer)(
                geom,
                ffi::BUFFER_TYPE_VERTEX,
                0,
                ffi::FORMAT_FLOAT3,
                12,
                positions.len(),
            ) as *mut [f32; 3];
            let tris = (api.set_new_geometry_buffer)(
                geom,
                ffi::BUFFER_TYPE_INDEX,
                0,
                ffi::FORMAT_UINT3,
                12,
                indices.len(),
            ) as *mut [u32; 3];
            if vertices.is_null() || tris.is_null() {
                (api.release_geometry)(geom);
                return Err(EmbreeError::Call("rtcSetNewGeometryBuffer"));
            }
            std::ptr::copy_nonoverlapping(positions.as_ptr(), vertices, positions.len());
            std::ptr::copy_nonoverlapping(indices.as_ptr(), tris, indices.len());
            (api.commit_geometry)(geom);
            (api.attach_geometry)(scene.scene, geom);
            (api.release_geometry)(geom);
            self.check("building the geometry")?;
            let start = Instant::now();
            (api.commit_scene)(scene.scene);
            scene.build_time = start.elapsed();
            self.check("rtcCommitScene")?;
            scene.bytes = self.bytes_in_use().saturating_sub(before);
            Ok(scene)
        }
    }
}

impl Drop for Embree {
    fn drop(&mut self) {
        // SAFETY: every scene borrows the device, so none outlives it.
        unsafe { (self.api.release_device)(self.device) };
    }
}

/// A closest hit as Embree reports it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EmbreeHit {
    pub prim: u32,
    pub t: f32,
    pub u: f32,
    pub v: f32,
}

/// One committed Embree scene of one triangle mesh.
pub struct TriangleScene<'a> {
    embree: &'a Embree,
    scene: ffi::Scene,
    /// Time of `rtcCommitScene`, the BVH build.
    pub build_time: Duration,
    /// Bytes the scene holds: the copied mesh and the BVH.
    pub bytes: usize,
}

// A committed scene is read-only; Embree allows queries from any number of threads at once.
unsafe impl Send for TriangleScene<'_> {}
unsafe impl Sync for TriangleScene<'_> {}

/// Where every ray given to Embree starts. Appel's rays hold `t` in `(0, t_max]`: a hit at exactly
/// 0, which a ray leaving a surface can compute exactly (a field at y = 0), is not a hit. Embree's
/// interval is `[tnear, tfar]`, and its robust mode reports such hits at `t = 0`; the smallest
/// positive normal float closes that end as Appel does for any `t` a ray can reach (a subnormal
/// would be read as zero under the flush-to-zero mode Embree asks for).
const T_NEAR: f32 = f32::MIN_POSITIVE;

impl TriangleScene<'_> {
    fn ray(origin: [f32; 3], dir: [f32; 3], t_max: f32) -> ffi::Ray1 {
        ffi::Ray1 {
            org: origin,
            dir,
            tnear: T_NEAR,
            tfar: t_max,
            mask: u32::MAX,
            ..Default::default()
        }
    }

    /// Closest hit with `t` in `(0, t_max]` (`rtcIntersect1`).
    #[inline]
    pub fn intersect(&self, origin: [f32; 3], dir: [f32; 3], t_max: f32) -> Option<EmbreeHit> {
        let mut ctx = ffi::IntersectContext::new(false);
        let mut rh = ffi::RayHit1 {
            ray: Self::ray(origin, dir, t_max),
            hit: ffi::Hit1 {
                geom_id: ffi::INVALID_GEOMETRY_ID,
                ..Default::default()
            },
        };
        // SAFETY: a committed scene and properly aligned structures that live across the call.
        unsafe { (self.embree.api.intersect1)(self.scene, &mut ctx, &mut rh) };
        (rh.hit.geom_id != ffi::INVALID_GEOMETRY_ID).then_some(EmbreeHit {
            prim: rh.hit.prim_id,
            t: rh.ray.tfar,
            u: rh.hit.u,
            v: rh.hit.v,
        })
    }

    /// Whether anything lies on the ray with `t` in `(0, t_max]` (`rtcOccluded1`).
    #[inline]
    pub fn occluded(&self, origin: [f32; 3], dir: [f32; 3], t_max: f32) -> bool {
        let mut ctx = ffi::IntersectContext::new(false);
        let mut ray = Self::ray(origin, dir, t_max);
        // SAFETY: as in `intersect`.
        unsafe { (self.embree.api.occluded1)(self.scene, &mut ctx, &mut ray) };
        // Embree marks an occluded ray by setting tfar to -inf.
        ray.tfar < 0.0
    }

    /// Closest hits of up to eight rays traced as one packet (`rtcIntersect8`, coherent context).
    pub fn intersect8(&self, rays: &[([f32; 3], [f32; 3])], out: &mut [Option<EmbreeHit>]) {
        assert!(rays.len() <= 8 && out.len() >= rays.len());
        let mut p = ffi::RayHit8 {
            tnear: [T_NEAR; 8],
            tfar: [f32::INFINITY; 8],
            mask: [u32::MAX; 8],
            geom_id: [ffi::INVALID_GEOMETRY_ID; 8],
            ..Default::default()
        };
        let mut valid = [0 as c_int; 8];
        for (k, (o, d)) in rays.iter().enumerate() {
            valid[k] = -1;
            for a in 0..3 {
                p.org[a][k] = o[a];
                p.dir[a][k] = d[a];
            }
        }
        let mut ctx = ffi::IntersectContext::new(true);
        // SAFETY: a committed scene; `p` is 32-byte aligned as RTCRayHit8 requires.
        unsafe { (self.embree.api.intersect8)(valid.as_ptr(), self.scene, &mut ctx, &mut p) };
        for (k, slot) in out.iter_mut().enumerate().take(rays.len()) {
            *slot = (p.geom_id[k] != ffi::INVALID_GEOMETRY_ID).then_some(EmbreeHit {
                prim: p.prim_id[k],
                t: p.tfar[k],
                u: p.u[k],
                v: p.v[k],
            });
        }
    }
}

impl Drop for TriangleScene<'_> {
    fn drop(&mut self) {
        // SAFETY: the scene is released once, on a live device.
        unsafe { (self.embree.api.release_scene)(self.scene) };
    }
}
