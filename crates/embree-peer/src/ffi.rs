//! The part of Embree 3's C API (`rtcore.h`, version 3.13) that the peer uses: the memory layout of
//! its ray structures and the functions, resolved from the shared library at run time so that Appel
//! builds and tests on machines without Embree.

use std::ffi::{c_char, c_int, c_uint, c_void};

pub type Device = *mut c_void;
pub type Scene = *mut c_void;
pub type Geometry = *mut c_void;

pub const INVALID_GEOMETRY_ID: c_uint = u32::MAX;
pub const GEOMETRY_TYPE_TRIANGLE: c_int = 0;
pub const BUFFER_TYPE_INDEX: c_int = 0;
pub const BUFFER_TYPE_VERTEX: c_int = 1;
/// `RTC_FORMAT_UINT3` and `RTC_FORMAT_FLOAT3` from `rtcore_common.h`.
pub const FORMAT_UINT3: c_int = 0x5003;
pub const FORMAT_FLOAT3: c_int = 0x9003;
pub const SCENE_FLAG_ROBUST: c_int = 1 << 2;
pub const DEVICE_PROPERTY_VERSION: c_int = 0;
pub const DEVICE_PROPERTY_NATIVE_RAY8_SUPPORTED: c_int = 33;
pub const INTERSECT_CONTEXT_FLAG_INCOHERENT: c_uint = 0;
pub const INTERSECT_CONTEXT_FLAG_COHERENT: c_uint = 1;

/// `RTCIntersectContext` as built with `RTC_MAX_INSTANCE_LEVEL_COUNT == 1` and no min-width, the
/// configuration of Debian's and Intel's binary packages.
#[repr(C)]
pub struct IntersectContext {
    pub flags: c_uint,
    pub filter: *const c_void,
    pub inst_id: [c_uint; 1],
}

impl IntersectContext {
    /// What `rtcInitIntersectContext` (an inline function in the header) does.
    pub fn new(coherent: bool) -> Self {
        Self {
            flags: if coherent {
                INTERSECT_CONTEXT_FLAG_COHERENT
            } else {
                INTERSECT_CONTEXT_FLAG_INCOHERENT
            },
            filter: std::ptr::null(),
            inst_id: [INVALID_GEOMETRY_ID],
        }
    }
}

#[repr(C, align(16))]
#[derive(Clone, Copy, Default)]
pub struct Ray1 {
    pub org: [f32; 3],
    pub tnear: f32,
    pub dir: [f32; 3],
    pub time: f32,
    pub tfar: f32,
    pub mask: c_uint,
    pub id: c_uint,
    pub flags: c_uint,
}

#[repr(C, align(16))]
#[derive(Clone, Copy, Default)]
pub struct Hit1 {
    pub ng: [f32; 3],
    pub u: f32,
    pub v: f32,
    pub prim_id: c_uint,
    pub geom_id: c_uint,
    pub inst_id: [c_uint; 1],
}

#[repr(C, align(16))]
#[derive(Clone, Copy, Default)]
pub struct RayHit1 {
    pub ray: Ray1,
    pub hit: Hit1,
}

/// `RTCRayHit8`: eight rays and hits in structure-of-arrays layout.
#[repr(C, align(32))]
#[derive(Clone, Copy, Default)]
pub struct RayHit8 {
    pub org: [[f32; 8]; 3],
    pub tnear: [f32; 8],
    pub dir: [[f32; 8]; 3],
    pub time: [f32; 8],
    pub tfar: [f32; 8],
    pub mask: [c_uint; 8],
    pub id: [c_uint; 8],
    pub flags: [c_uint; 8],
    pub ng: [[f32; 8]; 3],
    pub u: [f32; 8],
    pub v: [f32; 8],
    pub prim_id: [c_uint; 8],
    pub geom_id: [c_uint; 8],
    pub inst_id: [[c_uint; 8]; 1],
}

const _: () = assert!(std::mem::size_of::<RayHit1>() == 80);
const _: () = assert!(std::mem::size_of::<RayHit8>() == 20 * 32);

pub type MemoryMonitor = unsafe extern "C" fn(user: *mut c_void, bytes: isize, post: bool) -> bool;

/// The functions, looked up once when the library is loaded.
pub struct Api {
    pub new_device: unsafe extern "C" fn(*const c_char) -> Device,
    pub release_device: unsafe extern "C" fn(Device),
    pub get_device_error: unsafe extern "C" fn(Device) -> c_int,
    pub get_device_property: unsafe extern "C" fn(Device, c_int) -> isize,
    pub set_memory_monitor: unsafe extern "C" fn(Device, Option<MemoryMonitor>, *mut c_void),
    pub new_scene: unsafe extern "C" fn(Device) -> Scene,
    pub release_scene: unsafe extern "C" fn(Scene),
    pub set_scene_build_quality: unsafe extern "C" fn(Scene, c_int),
    pub set_scene_flags: unsafe extern "C" fn(Scene, c_int),
    pub commit_scene: unsafe extern "C" fn(Scene),
    pub new_geometry: unsafe extern "C" fn(Device, c_int) -> Geometry,
    pub release_geometry: unsafe extern "C" fn(Geometry),
    pub set_new_geometry_buffer:
        unsafe extern "C" fn(Geometry, c_int, c_uint, c_int, usize, usize) -> *mut c_void,
    pub set_geometry_build_quality: unsafe extern "C" fn(Geometry, c_int),
    pub commit_geometry: unsafe extern "C" fn(Geometry),
    pub attach_geometry: unsafe extern "C" fn(Scene, Geometry) -> c_uint,
    pub intersect1: unsafe extern "C" fn(Scene, *mut IntersectContext, *mut RayHit1),
    pub occluded1: unsafe extern "C" fn(Scene, *mut IntersectContext, *mut Ray1),
    pub intersect8: unsafe extern "C" fn(*const c_int, Scene, *mut IntersectContext, *mut RayHit8),
}

impl Api {
    /// Resolves every function.
    ///
    /// # Safety
    /// `lib` must be Embree 3: the signatures are taken on trust from its header.
    pub unsafe fn resolve(lib: &libloading::Library) -> Result<Self, libloading::Error> {
        macro_rules! sym {
            ($name:literal) => {
                *lib.get($name)?
            };
        }
        Ok(Self {
            new_device: sym!(b"rtcNewDevice\0"),
            release_device: sym!(b"rtcReleaseDevice\0"),
            get_device_error: sym!(b"rtcGetDeviceError\0"),
            get_device_property: sym!(b"rtcGetDeviceProperty\0"),
            set_memory_monitor: sym!(b"rtcSetDeviceMemoryMonitorFunction\0"),
            new_scene: sym!(b"rtcNewScene\0"),
            release_scene: sym!(b"rtcReleaseScene\0"),
            set_scene_build_quality: sym!(b"rtcSetSceneBuildQuality\0"),
            set_scene_flags: sym!(b"rtcSetSceneFlags\0"),
            commit_scene: sym!(b"rtcCommitScene\0"),
            new_geometry: sym!(b"rtcNewGeometry\0"),
            release_geometry: sym!(b"rtcReleaseGeometry\0"),
            set_new_geometry_buffer: sym!(b"rtcSetNewGeometryBuffer\0"),
            set_geometry_build_quality: sym!(b"rtcSetGeometryBuildQuality\0"),
            commit_geometry: sym!(b"rtcCommitGeometry\0"),
            attach_geometry: sym!(b"rtcAttachGeometry\0"),
            intersect1: sym!(b"rtcIntersect1\0"),
            occluded1: sym!(b"rtcOccluded1\0"),
            intersect8: sym!(b"rtcIntersect8\0"),
        })
    }
}
