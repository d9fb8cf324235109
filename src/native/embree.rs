//! Safe handles over Embree 3: a device, scenes that must be committed
//! before they can be traced (a typestate: [`Scene`] builds, [`CommittedScene`]
//! traces), and an error callback that turns Embree's errors into Rust errors.
//!
//! Things this wrapper does so no caller has to know them
//! (`shared/native-notes.md` has the measurements behind each):
//! - triangle data is copied into buffers Embree allocates, because Embree
//!   reads past the end of shared buffers with SSE loads;
//! - scenes are built with `RTC_SCENE_FLAG_ROBUST` (rays aimed at shared
//!   edges of a gem otherwise leak through);
//! - every ray gets `mask = u32::MAX` (masks are compiled into Debian's build);
//! - rays live in a 16-byte aligned `RTCRayHit` on the stack;
//! - flush-to-zero and denormals-are-zero are set on every thread that
//!   traces, as Embree's documentation advises, the first time it traces;
//! - the error callback does not fire for a failed `rtcNewDevice`, so
//!   `rtcGetDeviceError(NULL)` is checked after creation.

use spar_sys::embree as sys;
use std::cell::Cell;
use std::ffi::{c_char, c_void, CStr, CString};
use std::ptr::NonNull;
use std::sync::{Arc, Mutex};

/// An error reported by Embree, through its callback or its error codes.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("Embree: {message} ({code})")]
pub struct EmbreeError {
    /// Embree's error code name, e.g. `RTC_ERROR_INVALID_ARGUMENT`.
    pub code: String,
    /// Embree's message, or what spar was doing when the code was set.
    pub message: String,
}

impl EmbreeError {
    fn from_code(code: sys::RTCError, message: impl Into<String>) -> EmbreeError {
        EmbreeError {
            code: format!("{code:?}"),
            message: message.into(),
        }
    }
}

/// Where the error callback records the first error since the last check.
/// It lives in a `Box` owned by the device so its address is stable.
#[derive(Default)]
struct ErrorSlot {
    first: Mutex<Option<EmbreeError>>,
}

/// Called by Embree, possibly from its own threads, on every error.
unsafe extern "C" fn error_callback(
    user: *mut c_void,
    code: sys::RTCError,
    message: *const c_char,
) {
    // SAFETY: `user` is the `ErrorSlot` registered in `Device::new`, which
    // outlives the device (it is dropped after `rtcReleaseDevice`).
    let slot = unsafe { &*(user as *const ErrorSlot) };
    let message = if message.is_null() {
        String::from("(no message)")
    } else {
        // SAFETY: Embree passes a NUL-terminated string valid for the call.
        unsafe { CStr::from_ptr(message) }
            .to_string_lossy()
            .into_owned()
    };
    if let Ok(mut first) = slot.first.lock() {
        first.get_or_insert(EmbreeError::from_code(code, message));
    }
}

struct DeviceInner {
    raw: NonNull<sys::RTCDeviceTy>,
    errors: Box<ErrorSlot>,
}

// SAFETY: Embree devices are thread-safe: the API may be called on one
// device from many threads (Embree 3 API docs, "rtcNewDevice"). The error
// slot is behind a Mutex.
unsafe impl Send for DeviceInner {}
// SAFETY: as above; shared references only reach thread-safe Embree calls.
unsafe impl Sync for DeviceInner {}

impl Drop for DeviceInner {
    fn drop(&mut self) {
        // SAFETY: `raw` came from `rtcNewDevice` and is released once, here;
        // every scene holds an `Arc<DeviceInner>`, so none outlives it.
        unsafe { sys::rtcReleaseDevice(self.raw.as_ptr()) };
    }
}

impl DeviceInner {
    /// Returns (and clears) the first error since the last call, from the
    /// callback or, failing that, from Embree's per-device error code.
    fn check(&self, what: &str) -> Result<(), EmbreeError> {
        // Reading the code also clears it, so read it even when the callback
        // already recorded the error (whose message is the better one).
        // SAFETY: `raw` is a live device.
        let code = unsafe { sys::rtcGetDeviceError(self.raw.as_ptr()) };
        if let Some(e) = self.errors.first.lock().ok().and_then(|mut f| f.take()) {
            return Err(e);
        }
        match code {
            sys::RTCError::RTC_ERROR_NONE => Ok(()),
            code => Err(EmbreeError::from_code(code, what)),
        }
    }
}

/// An Embree device. Cheap to clone (a reference count).
#[derive(Clone)]
pub struct Device {
    inner: Arc<DeviceInner>,
}

impl Device {
    /// Creates a device from an Embree configuration string such as
    /// `"threads=2"` or `"isa=sse4.2"`. Embree ignores keys it does not
    /// know, silently.
    pub fn new(config: &str) -> Result<Device, EmbreeError> {
        let config = CString::new(config).map_err(|_| EmbreeError {
            code: "RTC_ERROR_INVALID_ARGUMENT".into(),
            message: "device configuration contains a NUL byte".into(),
        })?;
        // SAFETY: `config` is a valid NUL-terminated string for the call.
        let raw = unsafe { sys::rtcNewDevice(config.as_ptr()) };
        let Some(raw) = NonNull::new(raw) else {
            // The callback cannot fire for a device that does not exist;
            // the error sits in the thread's NULL-device slot.
            // SAFETY: NULL asks for the error of the failed device creation.
            let code = unsafe { sys::rtcGetDeviceError(std::ptr::null_mut()) };
            return Err(EmbreeError::from_code(code, "rtcNewDevice failed"));
        };
        let errors = Box::<ErrorSlot>::default();
        let inner = DeviceInner { raw, errors };
        // SAFETY: the device is live; the user pointer is the boxed slot,
        // whose address is stable and which lives as long as the device.
        unsafe {
            sys::rtcSetDeviceErrorFunction(
                raw.as_ptr(),
                Some(error_callback),
                &*inner.errors as *const ErrorSlot as *mut c_void,
            )
        };
        inner.check("rtcSetDeviceErrorFunction")?;
        Ok(Device {
            inner: Arc::new(inner),
        })
    }

    /// An empty scene to add geometry to.
    pub fn new_scene(&self) -> Result<Scene, EmbreeError> {
        // SAFETY: the device is live.
        let raw = unsafe { sys::rtcNewScene(self.inner.raw.as_ptr()) };
        let raw = NonNull::new(raw).ok_or_else(|| {
            self.inner.check("rtcNewScene").err().unwrap_or_else(|| {
                EmbreeError::from_code(
                    sys::RTCError::RTC_ERROR_UNKNOWN,
                    "rtcNewScene returned NULL",
                )
            })
        })?;
        let scene = SceneHandle {
            raw,
            device: self.inner.clone(),
        };
        // SAFETY: `raw` is a live scene of this device.
        unsafe {
            sys::rtcSetSceneFlags(raw.as_ptr(), sys::RTCSceneFlags::RTC_SCENE_FLAG_ROBUST);
            sys::rtcSetSceneBuildQuality(
                raw.as_ptr(),
                sys::RTCBuildQuality::RTC_BUILD_QUALITY_HIGH,
            );
        }
        self.inner.check("setting scene flags")?;
        Ok(Scene {
            handle: scene,
            geometries: 0,
        })
    }
}

/// Owns one reference to an `RTCScene` and keeps its device alive.
struct SceneHandle {
    raw: NonNull<sys::RTCSceneTy>,
    device: Arc<DeviceInner>,
}

// SAFETY: a scene handle may be moved between threads; Embree scenes carry no
// thread affinity.
unsafe impl Send for SceneHandle {}
// SAFETY: shared access is only used for `rtcIntersect1` on a committed
// scene, which Embree documents as thread-safe (each call brings its own
// intersect context).
unsafe impl Sync for SceneHandle {}

impl Drop for SceneHandle {
    fn drop(&mut self) {
        // SAFETY: `raw` came from `rtcNewScene` and is released once; the
        // device outlives it through the Arc held here.
        unsafe { sys::rtcReleaseScene(self.raw.as_ptr()) };
    }
}

/// A scene being built: geometry can be added; it cannot be traced until
/// [`Scene::commit`] turns it into a [`CommittedScene`].
pub struct Scene {
    handle: SceneHandle,
    geometries: u32,
}

impl Scene {
    /// Copies a triangle mesh into Embree-allocated buffers and attaches it.
    /// Returns its geometry id (0, 1, 2, … in the order of attachment).
    /// Indices must be in range (the caller validates; Embree does not).
    pub fn add_triangles(
        &mut self,
        vertices: &[[f32; 3]],
        triangles: &[[u32; 3]],
    ) -> Result<u32, EmbreeError> {
        if let Some(bad) = triangles
            .iter()
            .flatten()
            .find(|&&i| i as usize >= vertices.len())
        {
            return Err(EmbreeError {
                code: "RTC_ERROR_INVALID_ARGUMENT".into(),
                message: format!(
                    "triangle index {bad} out of range for {} vertices",
                    vertices.len()
                ),
            });
        }
        let device = &self.handle.device;
        // SAFETY: the device is live.
        let geometry = unsafe {
            sys::rtcNewGeometry(
                device.raw.as_ptr(),
                sys::RTCGeometryType::RTC_GEOMETRY_TYPE_TRIANGLE,
            )
        };
        let geometry = NonNull::new(geometry).ok_or_else(|| {
            device.check("rtcNewGeometry").err().unwrap_or_else(|| {
                EmbreeError::from_code(
                    sys::RTCError::RTC_ERROR_UNKNOWN,
                    "rtcNewGeometry returned NULL",
                )
            })
        })?;
        // Release our reference on every path; the scene keeps its own once
        // attached.
        struct GeometryGuard(NonNull<sys::RTCGeometryTy>);
        impl Drop for GeometryGuard {
            fn drop(&mut self) {
                // SAFETY: the guard owns the one reference from rtcNewGeometry.
                unsafe { sys::rtcReleaseGeometry(self.0.as_ptr()) };
            }
        }
        let guard = GeometryGuard(geometry);

        // SAFETY: the geometry is live; Embree allocates a buffer of
        // `vertices.len()` items of 12 bytes (plus its own padding) and
        // returns a pointer to it, or NULL on failure.
        let vbuf = unsafe {
            sys::rtcSetNewGeometryBuffer(
                guard.0.as_ptr(),
                sys::RTCBufferType::RTC_BUFFER_TYPE_VERTEX,
                0,
                sys::RTCFormat::RTC_FORMAT_FLOAT3,
                std::mem::size_of::<[f32; 3]>(),
                vertices.len(),
            )
        } as *mut [f32; 3];
        // SAFETY: as above, for the index buffer of 3 × u32 per triangle.
        let ibuf = unsafe {
            sys::rtcSetNewGeometryBuffer(
                guard.0.as_ptr(),
                sys::RTCBufferType::RTC_BUFFER_TYPE_INDEX,
                0,
                sys::RTCFormat::RTC_FORMAT_UINT3,
                std::mem::size_of::<[u32; 3]>(),
                triangles.len(),
            )
        } as *mut [u32; 3];
        device.check("allocating geometry buffers")?;
        if (vbuf.is_null() && !vertices.is_empty()) || (ibuf.is_null() && !triangles.is_empty()) {
            return Err(EmbreeError::from_code(
                sys::RTCError::RTC_ERROR_OUT_OF_MEMORY,
                "rtcSetNewGeometryBuffer returned NULL",
            ));
        }
        // SAFETY: Embree returned buffers of exactly these item counts and
        // strides (4-byte aligned, as [f32; 3] and [u32; 3] need); the source
        // slices do not overlap Embree's memory.
        unsafe {
            if !vertices.is_empty() {
                std::ptr::copy_nonoverlapping(vertices.as_ptr(), vbuf, vertices.len());
            }
            if !triangles.is_empty() {
                std::ptr::copy_nonoverlapping(triangles.as_ptr(), ibuf, triangles.len());
            }
        }
        // SAFETY: the geometry is live and its buffers are filled.
        unsafe { sys::rtcCommitGeometry(guard.0.as_ptr()) };
        // SAFETY: scene and geometry belong to the same device.
        let id = unsafe { sys::rtcAttachGeometry(self.handle.raw.as_ptr(), guard.0.as_ptr()) };
        device.check("attaching geometry")?;
        debug_assert_eq!(id, self.geometries);
        self.geometries += 1;
        Ok(id)
    }

    /// Builds the acceleration structure. Only a committed scene can be
    /// traced.
    pub fn commit(self) -> Result<CommittedScene, EmbreeError> {
        // SAFETY: the scene is live and no other thread uses it while
        // committing (we own it by value).
        unsafe { sys::rtcCommitScene(self.handle.raw.as_ptr()) };
        self.handle.device.check("rtcCommitScene")?;
        Ok(CommittedScene {
            handle: self.handle,
        })
    }
}

/// A ray for Embree, in the scene's (f32) space.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RayF32 {
    pub origin: [f32; 3],
    pub dir: [f32; 3],
    pub tnear: f32,
    pub tfar: f32,
}

/// Embree's answer for a hit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HitF32 {
    pub t: f32,
    pub geom: u32,
    pub prim: u32,
    pub u: f32,
    pub v: f32,
    /// Unnormalized geometric normal, (v1 − v0) × (v2 − v0) per Embree's
    /// convention for triangles.
    pub ng: [f32; 3],
}

/// A committed scene: immutable, traceable from many threads at once.
pub struct CommittedScene {
    handle: SceneHandle,
}

thread_local! {
    static DENORMALS_OFF: Cell<bool> = const { Cell::new(false) };
}

/// Sets flush-to-zero and denormals-are-zero on the calling thread, as
/// Embree's documentation advises for every thread that traces. Idempotent
/// and cheap after the first call on a thread.
pub fn set_denormal_flags_for_this_thread() {
    DENORMALS_OFF.with(|done| {
        if !done.get() {
            set_ftz_daz();
            done.set(true);
        }
    });
}

#[cfg(target_arch = "x86_64")]
fn set_ftz_daz() {
    // MXCSR bit 15 is flush-to-zero, bit 6 denormals-are-zero.
    const FTZ_DAZ: u32 = (1 << 15) | (1 << 6);
    let mut csr: u32 = 0;
    // SAFETY: stmxcsr/ldmxcsr read and write the SSE control register of
    // this thread only; every x86_64 CPU has them; setting FTZ/DAZ changes
    // rounding of denormals, not memory.
    unsafe {
        std::arch::asm!("stmxcsr [{}]", in(reg) &mut csr, options(nostack));
        csr |= FTZ_DAZ;
        std::arch::asm!("ldmxcsr [{}]", in(reg) &csr, options(nostack));
    }
}

#[cfg(not(target_arch = "x86_64"))]
fn set_ftz_daz() {}

impl CommittedScene {
    /// Closest hit of a ray, both faces counted, or `None`.
    #[inline]
    pub fn intersect(&self, ray: &RayF32) -> Option<HitF32> {
        set_denormal_flags_for_this_thread();
        let mut context = sys::rtc_init_intersect_context();
        let mut rayhit = sys::RTCRayHit {
            ray: sys::RTCRay {
                org_x: ray.origin[0],
                org_y: ray.origin[1],
                org_z: ray.origin[2],
                tnear: ray.tnear,
                dir_x: ray.dir[0],
                dir_y: ray.dir[1],
                dir_z: ray.dir[2],
                time: 0.0,
                tfar: ray.tfar,
                mask: u32::MAX,
                id: 0,
                flags: 0,
            },
            hit: sys::RTCHit {
                geomID: sys::RTC_INVALID_GEOMETRY_ID,
                primID: sys::RTC_INVALID_GEOMETRY_ID,
                instID: [sys::RTC_INVALID_GEOMETRY_ID; 1],
                ..Default::default()
            },
        };
        // SAFETY: the scene is committed (typestate) and Embree allows
        // concurrent rtcIntersect1 calls on it; `context` and `rayhit` are
        // this call's own, and `RTCRayHit` is 16-byte aligned by its type.
        unsafe { sys::rtcIntersect1(self.handle.raw.as_ptr(), &mut context, &mut rayhit) };
        let hit = rayhit.hit;
        if hit.geomID == sys::RTC_INVALID_GEOMETRY_ID {
            return None;
        }
        Some(HitF32 {
            t: rayhit.ray.tfar,
            geom: hit.geomID,
            prim: hit.primID,
            u: hit.u,
            v: hit.v,
            ng: [hit.Ng_x, hit.Ng_y, hit.Ng_z],
        })
    }

    /// Any error Embree reported since the last check (for example from a
    /// trace with invalid arguments).
    pub fn check(&self) -> Result<(), EmbreeError> {
        self.handle.device.check("tracing")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn device_and_empty_scene() {
        let device = Device::new("verbose=0").unwrap();
        let scene = device.new_scene().unwrap().commit().unwrap();
        let ray = RayF32 {
            origin: [0.0; 3],
            dir: [0.0, 0.0, 1.0],
            tnear: 0.0,
            tfar: f32::INFINITY,
        };
        assert_eq!(scene.intersect(&ray), None);
    }

    #[test]
    fn unknown_configuration_is_accepted_silently() {
        // Embree 3.13 ignores keys and values it does not know (native-notes):
        // this is why spar validates `--isa` itself before it gets here.
        assert!(Device::new("isa=no-such-isa,no-such-key=1").is_ok());
        assert!(Device::new("bad\0config").is_err());
    }

    #[test]
    fn embree_errors_reach_rust_through_the_callback() {
        let device = Device::new("").unwrap();
        // A scene committed twice is fine; an invalid argument is not:
        // rtcSetNewGeometryBuffer with a stride that is not a multiple of 4.
        // SAFETY (test): the device is live; creating and releasing a
        // geometry with a bad buffer only sets an error.
        unsafe {
            let g = sys::rtcNewGeometry(
                device.inner.raw.as_ptr(),
                sys::RTCGeometryType::RTC_GEOMETRY_TYPE_TRIANGLE,
            );
            sys::rtcSetNewGeometryBuffer(
                g,
                sys::RTCBufferType::RTC_BUFFER_TYPE_VERTEX,
                0,
                sys::RTCFormat::RTC_FORMAT_FLOAT3,
                3,
                4,
            );
            sys::rtcReleaseGeometry(g);
        }
        let err = device.inner.check("test").unwrap_err();
        assert_eq!(err.code, "RTC_ERROR_INVALID_OPERATION");
        // The message is Embree's own text from the callback, not ours.
        assert_ne!(err.message, "test");
        // Checking clears the error.
        assert!(device.inner.check("again").is_ok());
    }
}
