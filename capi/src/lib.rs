//! The C ABI: opaque context handles, status codes, caller-owned flat arrays.
//!
//! Every function returns a [`PixgeoStatus`]; on failure the message is kept in the
//! context ([`pixgeo_context_last_error`]) or, for context creation, per thread
//! ([`pixgeo_create_error`]). No panic crosses the boundary: a panic becomes
//! [`PixgeoStatus::Panic`].
//!
//! Every options struct starts with `struct_size`, which its `*_default()`
//! sets: a library reads only the fields the caller's header knew of, so
//! structs can grow without breaking programs built against an older header.
//!
//! Threads: a context may be used by one thread at a time (calls on it must not
//! overlap; one that does is refused with [`PixgeoStatus::Busy`]); different
//! contexts may be used from different threads at once.
//!
//! The header `capi/include/pixgeo.h` is generated from these files by cbindgen; a
//! test fails when the two drift apart.

// The C boundary: the workspace denies unsafe code, and this crate allows it,
// each block with a `// SAFETY:` note.
#![allow(unsafe_code)]

use std::{
    cell::RefCell,
    ffi::{c_char, CString},
    panic::{catch_unwind, AssertUnwindSafe},
    ptr,
};

use pixgeo::{
    machine::{DeviceChoice, Machine, MachineOptions},
    Backend, Error, Need,
};

mod delaunay;
mod diagrams;
mod distances;
mod flooding;
mod homothets;
mod interpolate;
mod lloyd;
mod options;
mod power;
mod settle;
mod shapes;
mod transform;

pub use delaunay::*;
pub use diagrams::*;
pub use distances::*;
pub use flooding::*;
pub use homothets::*;
pub use interpolate::*;
pub use lloyd::*;
pub use options::*;
pub use power::*;
pub use settle::*;
pub use shapes::*;
pub use transform::*;

/// Result of every call.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PixgeoStatus {
    Ok = 0,
    /// A pointer was null, a count zero, an option out of range, a coordinate
    /// not finite.
    InvalidArgument = 1,
    /// No Vulkan driver, no device matching the request, or a device without
    /// a feature the call needs.
    NoDevice = 2,
    /// A Vulkan call or a memory allocation failed.
    DeviceError = 3,
    /// The validation layer reported a problem (only with validation on).
    ValidationError = 4,
    /// The picture is larger than pixgeo supports.
    TooLarge = 5,
    /// pixgeo panicked: a bug; the message says where.
    Panic = 6,
    /// A band callback returned non-zero, which stopped the call.
    Stopped = 7,
    /// An output array's capacity is smaller than the answer; the answer's
    /// sizes were written, so the call can be repeated with room enough.
    BufferTooSmall = 8,
    /// pixgeo broke one of its own invariants, or a machine was misused: a
    /// bug; the message says which.
    Internal = 9,
    /// The context was in a call on another thread; nothing was done.
    Busy = 10,
    /// [`pixgeo_context_cancel`] stopped the call.
    Cancelled = 11,
    /// The call would hold more memory than the process can have; nothing was
    /// done.
    NoMemory = 12,
}

/// A short, fixed description of a [`PixgeoStatus`], such as "invalid
/// argument" (values that are none give "unknown status"); the
/// failed call's own message is [`pixgeo_context_last_error`]. Never null;
/// valid for the life of the program.
#[no_mangle]
pub extern "C" fn pixgeo_status_string(status: i32) -> *const c_char {
    // An integer, not the enum: a C caller may pass any value.
    let text: &'static std::ffi::CStr = match status {
        0 => c"ok",
        1 => c"invalid argument",
        2 => c"no Vulkan device",
        3 => c"device error",
        4 => c"validation error",
        5 => c"picture too large",
        6 => c"pixgeo panicked (a bug)",
        7 => c"stopped by the callback",
        8 => c"buffer too small",
        9 => c"internal error (a bug)",
        10 => c"context busy in another thread",
        11 => c"cancelled",
        12 => c"not enough memory",
        _ => c"unknown status",
    };
    text.as_ptr()
}

/// Which device a context uses.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PixgeoDevice {
    /// `PIXGEO_DEVICE` if set, else a GPU if present, else lavapipe.
    Auto = 0,
    /// Mesa's software Vulkan device (lavapipe).
    Lavapipe = 1,
    /// A hardware GPU.
    Gpu = 2,
}

/// Options of [`pixgeo_context_create`].
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct PixgeoContextOptions {
    /// `sizeof(PixgeoContextOptions)`, set by [`pixgeo_context_options_default`].
    pub struct_size: u32,
    /// A [`PixgeoDevice`]; other values are an invalid argument.
    pub device: u32,
    /// Enable the Khronos validation layer; any message fails the call.
    pub validation: bool,
    /// Null, or a device named as `PIXGEO_DEVICE` and the command line's
    /// `--device` name one (`auto`, `lavapipe`, `gpu`, an index, or part of a
    /// device's name), in place of `device`; `cpu` makes a context without
    /// Vulkan, whose calls with a CPU algorithm answer as a device's would
    /// and whose drawings return `PIXGEO_STATUS_NO_DEVICE`. With `auto` and
    /// no Vulkan driver, the context is such a CPU one (its device name
    /// says why). Read during the call.
    pub device_name: *const c_char,
    /// Keep compiled pipelines in a file between processes (true by default):
    /// in `PIXGEO_CACHE_DIR`, else `$XDG_CACHE_HOME/pixgeo` or
    /// `~/.cache/pixgeo`, one file per device and driver, written after calls
    /// that made new pipelines. False keeps them for the context's life only
    /// and writes no file.
    pub pipeline_cache: bool,
}

/// A pixel machine and the message of its last failed call. One thread at a
/// time may call with a context: a call while another thread's call on it is
/// running returns `PIXGEO_STATUS_BUSY`. Different contexts may be used from
/// different threads at once.
pub struct PixgeoContext {
    /// The device's machine; `None`: the context computes on the CPU
    /// (`device_name` is `cpu`, or no Vulkan driver or device was there).
    machine: Option<Machine>,
    /// The choice the context was made with.
    options: MachineOptions,
    device_name: CString,
    last_error: CString,
    /// A call is running on the context.
    busy: std::sync::atomic::AtomicBool,
    /// Set by [`pixgeo_context_cancel`] from any thread; cleared when a call
    /// returns.
    cancel: std::sync::Arc<std::sync::atomic::AtomicBool>,
}

impl PixgeoContext {
    /// Where a call with `need` runs, by the core's one rule
    /// ([`Backend::choose`]) over this context's choice and backend.
    fn backend_for(&self, need: Need) -> Result<Backend<'_>, (PixgeoStatus, String)> {
        if Backend::cpu_first(&self.options, need).map_err(failed)? {
            return Ok(Backend::Cpu);
        }
        match (&self.machine, need) {
            (Some(machine), _) => Ok(Backend::Device(machine)),
            (None, Need::Drawing(what)) => Err(failed(Error::Unsupported(format!(
                "{what}: it is drawn by a Vulkan device, and this context has none ({})",
                self.device_name.to_string_lossy()
            )))),
            (None, _) => Ok(Backend::Cpu),
        }
    }

    /// The machine of a call drawn on a device alone.
    fn machine(&self, what: &'static str) -> Result<&Machine, (PixgeoStatus, String)> {
        let backend = self.backend_for(Need::Drawing(what))?;
        backend.device_for(what).map_err(failed)
    }
}

thread_local! {
    static CREATE_ERROR: RefCell<CString> = RefCell::new(CString::default());
}

fn message(text: &str) -> CString {
    CString::new(text.replace('\0', " ")).unwrap_or_default()
}

fn status_of(error: &Error) -> PixgeoStatus {
    match error {
        Error::NoVulkan(_) | Error::NoDevice(_) | Error::Unsupported(_) => PixgeoStatus::NoDevice,
        Error::Vulkan { .. } | Error::Memory(_) => PixgeoStatus::DeviceError,
        Error::Validation(_) => PixgeoStatus::ValidationError,
        Error::PictureTooLarge { .. } => PixgeoStatus::TooLarge,
        Error::InvalidInput(_) | Error::Io { .. } | Error::Parse { .. } => {
            PixgeoStatus::InvalidArgument
        }
        Error::Internal(_) | Error::Usage(_) => PixgeoStatus::Internal,
        Error::Cancelled => PixgeoStatus::Cancelled,
        Error::HostMemory { .. } => PixgeoStatus::NoMemory,
        // Kinds added later are errors pixgeo did not expect to reach C.
        _ => PixgeoStatus::Internal,
    }
}

thread_local! {
    /// Whether this thread is inside a call from C, and where its last panic
    /// happened.
    static IN_CALL: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
    static PANIC_AT: RefCell<String> = const { RefCell::new(String::new()) };
}

/// Runs a call from C: a panic comes back as `Err`, and the host's stderr gets
/// no message or backtrace from it (the message goes to the error string).
/// Panics outside calls from C still reach the hook that was there before.
fn guarded<T>(f: impl FnOnce() -> T) -> std::thread::Result<T> {
    static QUIET_HOOK: std::sync::Once = std::sync::Once::new();
    QUIET_HOOK.call_once(|| {
        let previous = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            if IN_CALL.get() {
                let at = info.location().map(|l| l.to_string()).unwrap_or_default();
                PANIC_AT.with_borrow_mut(|p| *p = at);
            } else {
                previous(info);
            }
        }));
    });
    let outer = IN_CALL.replace(true);
    let outcome = catch_unwind(AssertUnwindSafe(f));
    IN_CALL.set(outer);
    outcome
}

fn panic_text(payload: Box<dyn std::any::Any + Send>) -> String {
    let what = payload
        .downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "unknown panic".into());
    let at = PANIC_AT.with_borrow(|p| p.clone());
    format!("pixgeo panicked (a bug, please report it) at {at}: {what}")
}

/// Runs `f` on the context, recording its error message there.
fn with_context(
    ctx: *mut PixgeoContext,
    f: impl FnOnce(&mut PixgeoContext) -> Result<(), (PixgeoStatus, String)>,
) -> PixgeoStatus {
    use std::sync::atomic::Ordering;
    // SAFETY: the caller passes a pointer from `pixgeo_context_create`, or null.
    // Only the atomic flag is touched until it says no other call is running.
    let Some(shared) = (unsafe { ctx.as_ref() }) else {
        return PixgeoStatus::InvalidArgument;
    };
    if shared
        .busy
        .compare_exchange(false, true, Ordering::Acquire, Ordering::Relaxed)
        .is_err()
    {
        return PixgeoStatus::Busy;
    }
    // SAFETY: this call holds the flag, so no other call uses the context.
    let context = unsafe { &mut *ctx };
    let cancel = context.cancel.clone();
    let outcome = pixgeo::Control::new()
        .cancel(cancel)
        .run(|| guarded(|| f(context)));
    let (status, text) = match outcome {
        Ok(Ok(())) => (PixgeoStatus::Ok, String::new()),
        Ok(Err(e)) => e,
        Err(payload) => (PixgeoStatus::Panic, panic_text(payload)),
    };
    context.last_error = message(&text);
    context.cancel.store(false, Ordering::Relaxed);
    context.busy.store(false, Ordering::Release);
    status
}

/// Cancels the call running on `ctx`, from any thread: it stops at its next
/// submission to the device or its next look at the flag on the CPU (the
/// distance transform, the CPU's diagrams, the sweep) and returns
/// `PIXGEO_STATUS_CANCELLED`. With no
/// call running, the next call on `ctx` is cancelled. Null is ignored.
///
/// # Safety
/// `ctx` is null or a context from [`pixgeo_context_create`] not yet destroyed.
#[no_mangle]
pub unsafe extern "C" fn pixgeo_context_cancel(ctx: *const PixgeoContext) {
    if ctx.is_null() {
        return;
    }
    // SAFETY: the caller passes a live context; only its flag is read, through
    // a pointer to that field (a call may hold the rest), and no call
    // replaces the flag.
    let cancel = unsafe { &*ptr::addr_of!((*ctx).cancel) };
    cancel.store(true, std::sync::atomic::Ordering::Relaxed);
}

fn invalid(text: impl Into<String>) -> (PixgeoStatus, String) {
    (PixgeoStatus::InvalidArgument, text.into())
}

fn failed(error: Error) -> (PixgeoStatus, String) {
    (status_of(&error), error.to_string())
}

/// Creates a context on the device `options` asks for (null: `PIXGEO_DEVICE` and
/// `PIXGEO_VALIDATION` from the environment). On success `*out` holds the context,
/// to be released with [`pixgeo_context_destroy`]; on failure `*out` is null and
/// [`pixgeo_create_error`] says why.
///
/// # Safety
/// `options` is null or points to a valid `PixgeoContextOptions`; `out` points to
/// writable storage for one pointer.
#[no_mangle]
pub unsafe extern "C" fn pixgeo_context_create(
    options: *const PixgeoContextOptions,
    out: *mut *mut PixgeoContext,
) -> PixgeoStatus {
    if out.is_null() {
        return PixgeoStatus::InvalidArgument;
    }
    // SAFETY: `out` is non-null and writable (caller contract).
    unsafe { *out = ptr::null_mut() };
    let outcome = guarded(|| {
        let mut machine_options = MachineOptions::from_env();
        if !options.is_null() {
            // SAFETY: non-null and valid (caller contract).
            let o = unsafe { read_options(options, "pixgeo_context_options_default") }
                .map_err(|(_, text)| Error::malformed(text))?;
            machine_options.validation = o.validation;
            if !o.pipeline_cache {
                machine_options.pipeline_cache = None;
            }
            match o.device {
                0 => {}
                1 => machine_options.device = DeviceChoice::Lavapipe,
                2 => machine_options.device = DeviceChoice::Gpu,
                other => {
                    return Err(Error::malformed(format!(
                        "device {other} is not a PixgeoDevice (0 auto, 1 lavapipe, 2 gpu)"
                    )))
                }
            }
            if !o.device_name.is_null() {
                // SAFETY: a NUL-terminated string when not null (caller contract).
                let name = unsafe { std::ffi::CStr::from_ptr(o.device_name) };
                let name = name
                    .to_str()
                    .map_err(|_| Error::malformed("device_name is not UTF-8".into()))?;
                machine_options.device = DeviceChoice::parse(name);
            }
        }
        let chosen = Backend::choose(&machine_options, Need::DeviceIfAny)?;
        Ok((chosen, machine_options))
    });
    let (status, text) = match outcome {
        Ok(Ok((chosen, options))) => {
            let cancel = match &chosen.machine {
                Some(machine) => machine.cancel_flag(),
                None => Default::default(),
            };
            let name = match &chosen.fallback {
                Some(why) => format!("cpu ({why})"),
                None => chosen.backend().name().to_string(),
            };
            let context = Box::new(PixgeoContext {
                device_name: message(&name),
                cancel,
                machine: chosen.machine,
                options,
                last_error: CString::default(),
                busy: Default::default(),
            });
            // SAFETY: as above.
            unsafe { *out = Box::into_raw(context) };
            (PixgeoStatus::Ok, String::new())
        }
        Ok(Err(e)) => (status_of(&e), e.to_string()),
        Err(payload) => (PixgeoStatus::Panic, panic_text(payload)),
    };
    CREATE_ERROR.with(|c| *c.borrow_mut() = message(&text));
    status
}

/// The library's version, `MAJOR.MINOR.PATCH`; the header's
/// `PIXGEO_VERSION_*` are the version it was generated with.
pub const PIXGEO_VERSION_MAJOR: u32 = 0;
pub const PIXGEO_VERSION_MINOR: u32 = 1;
pub const PIXGEO_VERSION_PATCH: u32 = 0;

/// The version of the library loaded, as `"MAJOR.MINOR.PATCH"`: compare it
/// with the header's `PIXGEO_VERSION_*` to catch a mismatched install. A
/// static string; do not free it.
#[no_mangle]
pub extern "C" fn pixgeo_version() -> *const c_char {
    concat!(env!("CARGO_PKG_VERSION"), "\0").as_ptr().cast()
}

/// Why the last [`pixgeo_context_create`] on this thread failed ("" if it did
/// not). Valid until the next create call on this thread.
#[no_mangle]
pub extern "C" fn pixgeo_create_error() -> *const c_char {
    CREATE_ERROR.with(|c| c.borrow().as_ptr())
}

/// Options that choose the device as `PIXGEO_DEVICE` would (auto), without
/// validation.
#[no_mangle]
pub extern "C" fn pixgeo_context_options_default() -> PixgeoContextOptions {
    PixgeoContextOptions {
        struct_size: struct_size::<PixgeoContextOptions>(),
        device: PixgeoDevice::Auto as u32,
        validation: false,
        device_name: ptr::null(),
        pipeline_cache: true,
    }
}

/// Releases a context and every device object it holds. Null is ignored.
///
/// # Safety
/// `ctx` is null or a context from [`pixgeo_context_create`] not yet destroyed and
/// not in use by another thread.
#[no_mangle]
pub unsafe extern "C" fn pixgeo_context_destroy(ctx: *mut PixgeoContext) {
    if !ctx.is_null() {
        // SAFETY: the pointer came from `Box::into_raw` in `pixgeo_context_create`
        // and is destroyed once (caller contract).
        let context = unsafe { Box::from_raw(ctx) };
        let _ = guarded(move || drop(context));
    }
}

/// The message of the last failed call on `ctx` ("" after a successful call).
/// Valid until the next call on `ctx`.
///
/// # Safety
/// `ctx` is null or a live context.
#[no_mangle]
pub unsafe extern "C" fn pixgeo_context_last_error(ctx: *const PixgeoContext) -> *const c_char {
    // SAFETY: null or live (caller contract).
    match unsafe { ctx.as_ref() } {
        Some(c) => c.last_error.as_ptr(),
        None => c"null context".as_ptr(),
    }
}

/// The name of the context's device. Valid as long as the context.
///
/// # Safety
/// `ctx` is null or a live context.
#[no_mangle]
pub unsafe extern "C" fn pixgeo_context_device_name(ctx: *const PixgeoContext) -> *const c_char {
    // SAFETY: null or live (caller contract).
    match unsafe { ctx.as_ref() } {
        Some(c) => c.device_name.as_ptr(),
        None => c"null context".as_ptr(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_panic_in_a_call_becomes_its_message() {
        let payload = guarded(|| panic!("boom")).unwrap_err();
        let text = panic_text(payload);
        assert!(
            text.contains("boom") && text.contains("capi/src/"),
            "{text}"
        );
        assert!(!IN_CALL.get());
    }

    /// A context on the default device.
    fn context() -> *mut PixgeoContext {
        let mut ctx = ptr::null_mut();
        // SAFETY: null options and a writable pointer.
        let status = unsafe { pixgeo_context_create(ptr::null(), &mut ctx) };
        assert_eq!(status, PixgeoStatus::Ok);
        ctx
    }

    /// The triangle of three points on `ctx`: a quick call.
    fn triangulate(ctx: *mut PixgeoContext) -> PixgeoStatus {
        let xy = [0.0, 0.0, 1.0, 0.0, 0.0, 1.0];
        let (mut triangles, mut count) = ([0u32; 3], 0usize);
        // SAFETY: a context from the caller, three points, room for one
        // triangle.
        let status = unsafe {
            crate::pixgeo_delaunay(
                ctx,
                xy.as_ptr(),
                3,
                0,
                triangles.as_mut_ptr(),
                1,
                &mut count,
                ptr::null_mut(),
            )
        };
        assert!(status != PixgeoStatus::Ok || count == 1);
        status
    }

    #[test]
    fn a_context_in_a_call_on_another_thread_is_busy() {
        use std::sync::atomic::Ordering;
        let ctx = context();
        // SAFETY: live; only its flag is touched, as a running call would.
        let busy = unsafe { &(*ctx).busy };
        busy.store(true, Ordering::SeqCst);
        assert_eq!(triangulate(ctx), PixgeoStatus::Busy);
        busy.store(false, Ordering::SeqCst);
        assert_eq!(triangulate(ctx), PixgeoStatus::Ok);
        // SAFETY: made above, released once.
        unsafe { pixgeo_context_destroy(ctx) };
    }

    #[test]
    fn a_cancelled_call_stops_and_the_next_runs() {
        let ctx = context();
        let (w, h) = (3000u32, 3000u32);
        let settle = move |ctx: *mut PixgeoContext| {
            let xy = [10.0, 10.0, 2900.0, 2500.0];
            let options = crate::options::pixgeo_voronoi_options_default(w, h);
            let mut area = vec![0u32; (w * h) as usize];
            // SAFETY: zeroes are a valid answer to overwrite.
            let mut out: crate::settle::PixgeoSettle = unsafe { std::mem::zeroed() };
            // SAFETY: a live context, two points, an area of w × h.
            unsafe {
                crate::settle::pixgeo_settle(
                    ctx,
                    xy.as_ptr(),
                    2,
                    ptr::null(),
                    0,
                    &options,
                    0,
                    area.as_mut_ptr(),
                    &mut out,
                )
            }
        };
        // A cancel from another thread stops the running call.
        let address = ctx as usize;
        let running = std::thread::spawn(move || settle(address as *mut PixgeoContext));
        std::thread::sleep(std::time::Duration::from_millis(300));
        let asked = std::time::Instant::now();
        // SAFETY: live; cancelling touches only the flag.
        unsafe { pixgeo_context_cancel(ctx) };
        assert_eq!(running.join().unwrap(), PixgeoStatus::Cancelled);
        // Well before the whole count would end (tens of seconds here).
        assert!(asked.elapsed().as_secs_f64() < 5.0);
        // The flag is cleared: the context works again.
        let status = triangulate(ctx);
        assert_eq!(status, PixgeoStatus::Ok);
        // SAFETY: made above, released once.
        unsafe { pixgeo_context_destroy(ctx) };
    }

    #[test]
    fn the_header_says_the_default_side_the_calls_use() {
        let side = pixgeo::Frame::DEFAULT_SIDE;
        let header = include_str!("../include/pixgeo.h");
        assert_eq!(header.matches(&format!("(0: {side})")).count(), 2);
        let ctx = context();
        let xy = [0.0, 0.0, 10.0, 0.0, 10.0, 10.0, 0.0, 10.0];
        let options = crate::shapes::pixgeo_alpha_options_default();
        assert_eq!(options.side, 0);
        let mut out = crate::shapes::PixgeoAlphaHull::default();
        // SAFETY: a live context, four points, no pixels or boundary asked for.
        let status = unsafe {
            crate::shapes::pixgeo_alpha_hull(
                ctx,
                xy.as_ptr(),
                4,
                &options,
                &mut out,
                ptr::null_mut(),
                0,
                ptr::null_mut(),
                0,
            )
        };
        assert_eq!(status, PixgeoStatus::Ok);
        assert_eq!(out.width.max(out.height), side);
        // SAFETY: made above, released once.
        unsafe { pixgeo_context_destroy(ctx) };
    }

    #[test]
    fn a_cancel_reaches_work_on_the_cpu() {
        let ctx = context();
        let options = crate::options::pixgeo_voronoi_options_default(64, 64);
        let mut mask = [0u8; 64 * 64];
        mask[0] = 1;
        let mut distances = [0.0f64; 64 * 64];
        let transform = |distances: &mut [f64]| {
            // SAFETY: a live context, a 64 × 64 mask and room for its distances.
            unsafe {
                crate::transform::pixgeo_distance_transform(
                    ctx,
                    mask.as_ptr(),
                    &options,
                    ptr::null(),
                    distances.as_mut_ptr(),
                    ptr::null_mut(),
                    ptr::null_mut(),
                )
            }
        };
        // Cancelled before it starts: the transform, on the CPU alone, looks
        // at the context's flag.
        // SAFETY: live; cancelling touches only the flag.
        unsafe { pixgeo_context_cancel(ctx) };
        assert_eq!(transform(&mut distances), PixgeoStatus::Cancelled);
        assert_eq!(transform(&mut distances), PixgeoStatus::Ok);
        assert_eq!(distances[64 + 1], 2f64.sqrt());
        // SAFETY: made above, released once.
        unsafe { pixgeo_context_destroy(ctx) };
    }

    #[test]
    fn counts_no_array_can_hold_are_refused() {
        let ctx = context();
        let xy = [0.0; 4];
        let options = crate::options::pixgeo_voronoi_options_default(4, 4);
        let mut labels = [0u32; 16];
        for count in [1usize << 62, u32::MAX as usize] {
            // SAFETY: the count is refused before the array is read.
            let status = unsafe {
                crate::diagrams::pixgeo_voronoi(
                    ctx,
                    xy.as_ptr(),
                    count,
                    &options,
                    labels.as_mut_ptr(),
                    ptr::null_mut(),
                )
            };
            assert_eq!(status, PixgeoStatus::InvalidArgument);
            // SAFETY: a live context's message.
            let text = unsafe { std::ffi::CStr::from_ptr(pixgeo_context_last_error(ctx)) };
            assert!(text.to_str().unwrap().contains("2^32"), "{text:?}");
        }
        // SAFETY: made above, released once.
        unsafe { pixgeo_context_destroy(ctx) };
    }

    #[test]
    fn the_header_version_is_the_crate_version() {
        let header =
            format!("{PIXGEO_VERSION_MAJOR}.{PIXGEO_VERSION_MINOR}.{PIXGEO_VERSION_PATCH}");
        assert_eq!(header, env!("CARGO_PKG_VERSION"));
        // SAFETY: a static NUL-terminated string.
        let loaded = unsafe { std::ffi::CStr::from_ptr(pixgeo_version()) };
        assert_eq!(loaded.to_str().unwrap(), header);
    }
}
