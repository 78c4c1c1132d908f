//! The C ABI: opaque context handles, status codes, caller-owned flat arrays.
//!
//! Every function returns a [`PixgeoStatus`]; on failure the message is kept in the
//! context ([`pixgeo_context_last_error`]) or, for context creation, per thread
//! ([`pixgeo_create_error`]). No panic crosses the boundary: a panic becomes
//! [`PixgeoStatus::Panic`].
//!
//! Threads: a context may be used by one thread at a time (calls on it must not
//! overlap); different contexts may be used from different threads at once.
//!
//! The header `include/pixgeo.h` is generated from this file by cbindgen; a test
//! fails when the two drift apart.

use std::{
    cell::RefCell,
    ffi::{c_char, CString},
    panic::{catch_unwind, AssertUnwindSafe},
    ptr,
};

use glam::DVec2;

use crate::{
    algorithms::{
        delaunay,
        distances::{self, Answer},
        higher_order::{self, KNearestOptions},
        homothet::{self, HomothetAnswer, Region, Unit, DEFAULT_SIDE},
        settle::{self, SettleMethod, SettleOptions},
        sites::voronoi_sites,
        voronoi::{voronoi_bands, Accuracy, Speedup, VoronoiOptions},
    },
    geometry::{
        metric::Metric,
        site::{Shape, Site},
        Frame,
    },
    machine::{DeviceChoice, Machine, MachineOptions, PixelRect},
    Error,
};

/// Result of every call.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PixgeoStatus {
    Ok = 0,
    /// A pointer was null, a count zero, an option out of range, a coordinate
    /// not finite.
    InvalidArgument = 1,
    /// No Vulkan driver, or no device matching the request.
    NoDevice = 2,
    /// A Vulkan call or a memory allocation failed.
    DeviceError = 3,
    /// The validation layer reported a problem (only with validation on).
    ValidationError = 4,
    /// The picture is larger than pixgeo supports.
    TooLarge = 5,
    /// pixgeo panicked: a bug; the message says where.
    Panic = 6,
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
    /// A [`PixgeoDevice`]; other values are an invalid argument.
    pub device: u32,
    /// Enable the Khronos validation layer; any message fails the call.
    pub validation: bool,
}

/// How cones are drawn.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PixgeoAccuracy {
    /// Exact distance per pixel: every label is a nearest site.
    Exact = 0,
    /// Triangle fans: distances within `epsilon` (or `triangles` per cone).
    Fan = 1,
}

/// The distance function (thesis §3.6).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PixgeoMetric {
    /// The Euclidean norm (default).
    L2 = 0,
    L1 = 1,
    LInf = 2,
    /// L_p with `p = metric_p` > 0.
    Lp = 3,
    /// The polygonal distance whose unit ball is `polygon` around `kernel`
    /// (thesis §3.6.5); the polygon must be star-shaped around its kernel.
    Polygon = 4,
}

/// How far cones reach.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PixgeoSpeedup {
    /// A radius per site (default).
    Local = 0,
    /// The thesis's quadtree radius with minmax-checked retries.
    Quadtree = 1,
    /// Picture-wide cones.
    None = 2,
}

/// Options of [`pixgeo_voronoi`]; start from [`pixgeo_voronoi_options_default`].
/// Valid options have `polygon` pointing at `2 * polygon_count` doubles when the
/// metric is [`PixgeoMetric::Polygon`].
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct PixgeoVoronoiOptions {
    /// Picture size in pixels.
    pub width: u32,
    pub height: u32,
    /// Map the world rectangle `bbox = {xmin, ymin, xmax, ymax}` onto the picture
    /// (its aspect ratio must match the picture's to within a pixel); otherwise
    /// pixel (i, j) is centred at world point (i, j).
    pub use_bbox: bool,
    pub bbox: [f64; 4],
    /// The distance function, a [`PixgeoMetric`] (both accuracy modes take
    /// every metric). Enumerations are read as integers: a value outside the
    /// enumeration is an invalid argument.
    pub metric: u32,
    /// The exponent of [`PixgeoMetric::Lp`].
    pub metric_p: f64,
    /// The vertices `{x0, y0, x1, y1, ...}` of [`PixgeoMetric::Polygon`]'s unit
    /// ball, `polygon_count` of them, and its kernel point; read during the call.
    pub polygon: *const f64,
    pub polygon_count: usize,
    pub kernel: [f64; 2],
    /// A [`PixgeoAccuracy`].
    pub accuracy: u32,
    /// Distance error bound of fan mode, pixels.
    pub epsilon: f64,
    /// Triangles per fan cone; 0 = the fewest for `epsilon`.
    pub triangles: u32,
    /// A [`PixgeoSpeedup`].
    pub speedup: u32,
    /// Largest tile side in pixels; 0 = as large as the device allows.
    pub max_tile: u32,
    /// `{x0, y0, width, height}`: compute only this window of the picture's
    /// pixels (bit for bit the whole diagram's there), and write `width *
    /// height` values; a width of 0 means the whole picture. Point sites only.
    pub window: [u32; 4],
}

/// The shape of a [`PixgeoSite`].
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PixgeoSiteKind {
    /// `coords = {x, y}`.
    Point = 0,
    /// `coords = {x1, y1, x2, y2}`.
    Segment = 1,
    /// `coords = {cx, cy, radius}`.
    Circle = 2,
    /// `coords = {cx, cy, radius, start, end}`: counter-clockwise from angle
    /// `start` to `end` (radians).
    Arc = 3,
}

/// A site of any shape with weights (thesis §3.8–3.9): its weighted distance is
/// the distance to the shape divided by `multiplicative` (> 0) plus `additive`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PixgeoSite {
    /// A [`PixgeoSiteKind`].
    pub kind: u32,
    /// World coordinates, as [`PixgeoSiteKind`] lays them out; unused ones ignored.
    pub coords: [f64; 5],
    pub multiplicative: f64,
    pub additive: f64,
}

/// Two points, one of each set (indices into the sets as passed), and their exact
/// distance: the answer of the distance functions.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PixgeoPair {
    pub from: u32,
    pub to: u32,
    pub distance: f64,
}

/// The shape and picture of [`pixgeo_enclose`] and [`pixgeo_empty`].
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PixgeoHomothetOptions {
    /// The polygon's vertices `{x0, y0, x1, y1, ...}` around `kernel`, star-shaped
    /// around it; null for circles.
    pub polygon: *const f64,
    pub polygon_count: usize,
    pub kernel: [f64; 2],
    /// Picture side in pixels along the longer axis (0: 512).
    pub side: u32,
}

/// A homothet `centre + scale · Q`: the exact one, the picture's candidate, the
/// bound between them, and the gap left where a branch and bound decided.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PixgeoHomothet {
    pub centre: [f64; 2],
    pub scale: f64,
    pub pixel_centre: [f64; 2],
    pub pixel_scale: f64,
    pub pixel_bound: f64,
    pub tolerance: f64,
}

/// How [`pixgeo_settle`] counts the discs.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PixgeoSettleMethod {
    /// Row spans and prefix sums (default).
    Spans = 0,
    /// The thesis's discs, counted by stencil wrap-around and blending.
    Faithful = 1,
}

/// The answer of [`pixgeo_settle`].
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PixgeoSettle {
    /// The settle pixel (the first, row-major, of those tied) and the number of
    /// pixels a new site there would win.
    pub pixel_x: u32,
    pub pixel_y: u32,
    pub area: u32,
    /// How many pixels share the largest potential area.
    pub ties: u32,
    /// The refined position (world coordinates) and the exact area (world units)
    /// it wins; NaN unless the metric is L2.
    pub refined_x: f64,
    pub refined_y: f64,
    pub refined_area: f64,
}

impl From<Answer> for PixgeoPair {
    fn from(answer: Answer) -> Self {
        Self {
            from: answer.pair.from,
            to: answer.pair.to,
            distance: answer.pair.distance,
        }
    }
}

/// A pixel machine and the message of its last failed call.
pub struct PixgeoContext {
    machine: Machine,
    device_name: CString,
    last_error: CString,
}

thread_local! {
    static CREATE_ERROR: RefCell<CString> = RefCell::new(CString::default());
}

fn message(text: &str) -> CString {
    CString::new(text.replace('\0', " ")).unwrap_or_default()
}

fn status_of(error: &Error) -> PixgeoStatus {
    match error {
        Error::NoVulkan(_) | Error::NoDevice(_) => PixgeoStatus::NoDevice,
        Error::Vulkan { .. } | Error::Memory(_) => PixgeoStatus::DeviceError,
        Error::Validation(_) => PixgeoStatus::ValidationError,
        Error::PictureTooLarge { .. } => PixgeoStatus::TooLarge,
        Error::InvalidInput(_) | Error::Io { .. } | Error::Parse { .. } => {
            PixgeoStatus::InvalidArgument
        }
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
    // SAFETY: the caller passes a pointer from `pixgeo_context_create` that is not
    // used by another thread during this call (documented), or null.
    let Some(context) = (unsafe { ctx.as_mut() }) else {
        return PixgeoStatus::InvalidArgument;
    };
    let outcome = guarded(|| f(context));
    let (status, text) = match outcome {
        Ok(Ok(())) => (PixgeoStatus::Ok, String::new()),
        Ok(Err(e)) => e,
        Err(payload) => (PixgeoStatus::Panic, panic_text(payload)),
    };
    context.last_error = message(&text);
    status
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
    // SAFETY: `options` is null or valid (caller contract).
    let options = unsafe { options.as_ref() }.copied();
    let outcome = guarded(|| {
        let mut machine_options = MachineOptions::from_env();
        if let Some(o) = options {
            machine_options.validation = o.validation;
            match o.device {
                0 => {}
                1 => machine_options.device = DeviceChoice::Lavapipe,
                2 => machine_options.device = DeviceChoice::Gpu,
                other => {
                    return Err(Error::InvalidInput(format!(
                        "device {other} is not a PixgeoDevice (0 auto, 1 lavapipe, 2 gpu)"
                    )))
                }
            }
        }
        Machine::new(&machine_options)
    });
    let (status, text) = match outcome {
        Ok(Ok(machine)) => {
            let context = Box::new(PixgeoContext {
                device_name: message(machine.device_name()),
                machine,
                last_error: CString::default(),
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

/// Default Voronoi options for a `width` x `height` picture: Euclidean, exact,
/// local radii, no bounding box, tiles as large as the device allows.
#[no_mangle]
pub extern "C" fn pixgeo_voronoi_options_default(width: u32, height: u32) -> PixgeoVoronoiOptions {
    PixgeoVoronoiOptions {
        width,
        height,
        use_bbox: false,
        bbox: [0.0; 4],
        metric: PixgeoMetric::L2 as u32,
        metric_p: 2.0,
        polygon: ptr::null(),
        polygon_count: 0,
        kernel: [0.0; 2],
        accuracy: PixgeoAccuracy::Exact as u32,
        epsilon: 1.0,
        triangles: 0,
        speedup: PixgeoSpeedup::Local as u32,
        max_tile: 0,
        window: [0; 4],
    }
}

/// The Voronoi diagram of `count` point sites `xy = {x0, y0, x1, y1, ...}` (world
/// coordinates). Writes the nearest site's index per pixel to `labels` and, if
/// `distances` is not null, its distance (world units) to `distances`; both are
/// caller-owned arrays of `width * height` values (the window's, with one),
/// row-major (`[j * width + i]`).
/// `UINT32_MAX` marks a pixel with no site (never with the default options).
///
/// # Safety
/// `ctx` is a live context; `xy` holds `2 * count` doubles; `options` points to
/// valid options; `labels` (and `distances` unless null) have room for
/// `width * height` values.
#[no_mangle]
pub unsafe extern "C" fn pixgeo_voronoi(
    ctx: *mut PixgeoContext,
    xy: *const f64,
    count: usize,
    options: *const PixgeoVoronoiOptions,
    labels: *mut u32,
    distances: *mut f32,
) -> PixgeoStatus {
    with_context(ctx, |context| {
        if xy.is_null() || options.is_null() || labels.is_null() {
            return Err(invalid("xy, options and labels must not be null"));
        }
        // SAFETY: non-null and valid (caller contract).
        let o = unsafe { *options };
        let (frame, accuracy, speedup) = picture_of(&o)?;
        let metric = metric_of(&o)?;
        // SAFETY: `xy` holds `2 * count` doubles (caller contract).
        let sites = unsafe { points(xy, count) }?;
        let options = VoronoiOptions {
            frame,
            metric,
            accuracy,
            speedup,
            distances: !distances.is_null(),
            ties: false,
            max_tile: (o.max_tile > 0).then_some(o.max_tile),
            window: window_of(&o),
        };
        let window = options.window_rect().map_err(failed)?;
        let pixels = window.width as usize * window.height as usize;
        // SAFETY: caller-owned arrays of `width * height` values (caller contract).
        let labels = unsafe { std::slice::from_raw_parts_mut(labels, pixels) };
        let mut distances = (!distances.is_null())
            // SAFETY: as above.
            .then(|| unsafe { std::slice::from_raw_parts_mut(distances, pixels) });
        let width = window.width as usize;
        voronoi_bands(&context.machine, &sites, &options, |band| {
            let start = (band.y0 - window.y) as usize * width;
            labels[start..start + band.labels.len()].copy_from_slice(&band.labels);
            if let Some(d) = distances.as_mut() {
                d[start..start + band.distances.len()].copy_from_slice(&band.distances);
            }
            Ok(())
        })
        .map(|_| ())
        .map_err(failed)
    })
}

/// The Voronoi diagram of `count` sites of any shape and weight, like
/// [`pixgeo_voronoi`]: labels (and, unless null, weighted distances in world
/// units) of `width * height` pixels, row-major.
///
/// # Safety
/// `ctx` is a live context; `sites` holds `count` sites; `options` points to
/// valid options; `labels` (and `distances` unless null) have room for
/// `width * height` values.
#[no_mangle]
pub unsafe extern "C" fn pixgeo_voronoi_sites(
    ctx: *mut PixgeoContext,
    sites: *const PixgeoSite,
    count: usize,
    options: *const PixgeoVoronoiOptions,
    labels: *mut u32,
    distances: *mut f32,
) -> PixgeoStatus {
    with_context(ctx, |context| {
        if sites.is_null() || options.is_null() || labels.is_null() {
            return Err(invalid("sites, options and labels must not be null"));
        }
        // SAFETY: non-null and valid (caller contract).
        let o = unsafe { *options };
        let (frame, accuracy, speedup) = picture_of(&o)?;
        // SAFETY: `sites` holds `count` sites (caller contract).
        let given = unsafe { std::slice::from_raw_parts(sites, count) };
        let sites = sites_of(given)?;
        let options = VoronoiOptions {
            frame,
            metric: metric_of(&o)?,
            accuracy,
            speedup,
            distances: !distances.is_null(),
            ties: false,
            max_tile: (o.max_tile > 0).then_some(o.max_tile),
            window: window_of(&o),
        };
        let d = voronoi_sites(&context.machine, &sites, &options).map_err(failed)?;
        // SAFETY: caller-owned arrays of `width * height` values.
        unsafe { std::slice::from_raw_parts_mut(labels, d.labels.len()) }
            .copy_from_slice(&d.labels);
        if !distances.is_null() {
            // SAFETY: as above.
            unsafe { std::slice::from_raw_parts_mut(distances, d.distances.len()) }
                .copy_from_slice(&d.distances);
        }
        Ok(())
    })
}

/// The window of the options, if any (width 0: the whole picture).
fn window_of(o: &PixgeoVoronoiOptions) -> Option<PixelRect> {
    let [x, y, width, height] = o.window;
    (width > 0).then_some(PixelRect {
        x,
        y,
        width,
        height,
    })
}

/// The library's sites for the C ones.
fn sites_of(given: &[PixgeoSite]) -> Result<Vec<Site>, (PixgeoStatus, String)> {
    given
        .iter()
        .enumerate()
        .map(|(i, s)| {
            let c = s.coords;
            let shape = match s.kind {
                0 => Shape::Point(DVec2::new(c[0], c[1])),
                1 => Shape::Segment(DVec2::new(c[0], c[1]), DVec2::new(c[2], c[3])),
                2 => Shape::Circle {
                    center: DVec2::new(c[0], c[1]),
                    radius: c[2],
                },
                3 => Shape::Arc {
                    center: DVec2::new(c[0], c[1]),
                    radius: c[2],
                    start: c[3],
                    end: c[4],
                },
                other => {
                    return Err(invalid(format!(
                        "site {i}: kind {other} is not a PixgeoSiteKind (0 point, 1 segment, 2 circle, 3 arc)"
                    )))
                }
            };
            Ok(Site {
                shape,
                multiplicative: s.multiplicative,
                additive: s.additive,
            })
        })
        .collect()
}

/// The frame, accuracy and speedup that `options` describe.
fn picture_of(
    o: &PixgeoVoronoiOptions,
) -> Result<(Frame, Accuracy, Speedup), (PixgeoStatus, String)> {
    let frame = if o.use_bbox {
        Frame::with_bbox(o.width, Some(o.height), o.bbox)
    } else {
        Frame::pixels(o.width, o.height)
    }
    .map_err(failed)?;
    let accuracy = match o.accuracy {
        0 => Accuracy::Exact,
        1 => Accuracy::Fan {
            epsilon: o.epsilon,
            triangles: (o.triangles > 0).then_some(o.triangles),
        },
        other => {
            return Err(invalid(format!(
                "accuracy {other} is not a PixgeoAccuracy (0 exact, 1 fan)"
            )))
        }
    };
    let speedup = match o.speedup {
        0 => Speedup::Local,
        1 => Speedup::Quadtree,
        2 => Speedup::None,
        other => {
            return Err(invalid(format!(
                "speedup {other} is not a PixgeoSpeedup (0 local, 1 quadtree, 2 none)"
            )))
        }
    };
    Ok((frame, accuracy, speedup))
}

/// The distance function that `options` name.
fn metric_of(o: &PixgeoVoronoiOptions) -> Result<Metric, (PixgeoStatus, String)> {
    Ok(match o.metric {
        0 => Metric::L2,
        1 => Metric::L1,
        2 => Metric::LInf,
        3 => Metric::lp(o.metric_p).map_err(invalid)?,
        4 => {
            // SAFETY: `polygon` is null or holds `2 * polygon_count` doubles
            // (caller contract of every call taking options).
            let vertices = unsafe { points(o.polygon, o.polygon_count) }?;
            Metric::polygon(&vertices, DVec2::from(o.kernel)).map_err(invalid)?
        }
        other => {
            return Err(invalid(format!(
                "metric {other} is not a PixgeoMetric (0 L2, 1 L1, 2 L-infinity, 3 L_p, 4 polygon)"
            )))
        }
    })
}

/// `count` points from `xy = {x0, y0, x1, y1, ...}`.
///
/// # Safety
/// `xy` is null or holds `2 * count` doubles.
unsafe fn points(xy: *const f64, count: usize) -> Result<Vec<DVec2>, (PixgeoStatus, String)> {
    if xy.is_null() {
        return Err(invalid("a point array is null"));
    }
    let count2 = count
        .checked_mul(2)
        .ok_or_else(|| invalid("point count overflows"))?;
    // SAFETY: `xy` holds `2 * count` doubles (caller contract).
    let coords = unsafe { std::slice::from_raw_parts(xy, count2) };
    Ok(coords
        .chunks_exact(2)
        .map(|p| DVec2::new(p[0], p[1]))
        .collect())
}

/// Every pixel's `k` nearest sites in order (the degree 1..k diagrams, thesis
/// §3.7), equal distances counted with their multiplicity, ties by index. Writes
/// `width * height * k` values to `labels` and, unless null, `distances` (world
/// units): `[(j * width + i) * k + l]` is the (l+1)-th nearest site of pixel
/// (i, j); `UINT32_MAX` (and infinity) where fewer than l+1 sites exist. The
/// order-k diagram is each pixel's k labels as a set. `max_tile` must be 0 (the
/// picture is drawn whole).
///
/// # Safety
/// `ctx` is a live context; `xy` holds `2 * count` doubles; `options` points to
/// valid options; `labels` (and `distances` unless null) have room for
/// `width * height * k` values.
#[no_mangle]
pub unsafe extern "C" fn pixgeo_k_nearest(
    ctx: *mut PixgeoContext,
    xy: *const f64,
    count: usize,
    options: *const PixgeoVoronoiOptions,
    k: u32,
    labels: *mut u32,
    distances: *mut f32,
) -> PixgeoStatus {
    with_context(ctx, |context| {
        if options.is_null() || labels.is_null() {
            return Err(invalid("options and labels must not be null"));
        }
        // SAFETY: non-null and valid (caller contract).
        let o = unsafe { *options };
        if o.max_tile != 0 {
            return Err(invalid(
                "k nearest sites are drawn whole: max_tile must be 0",
            ));
        }
        let (frame, accuracy, speedup) = picture_of(&o)?;
        // SAFETY: `xy` holds `2 * count` doubles (caller contract).
        let sites = unsafe { points(xy, count) }?;
        let d = higher_order::k_nearest(
            &context.machine,
            &sites,
            &KNearestOptions {
                frame,
                k,
                metric: metric_of(&o)?,
                accuracy,
                speedup,
            },
        )
        .map_err(failed)?;
        // SAFETY: caller-owned arrays of `width * height * k` values.
        unsafe { std::slice::from_raw_parts_mut(labels, d.labels.len()) }
            .copy_from_slice(&d.labels);
        if !distances.is_null() {
            // SAFETY: as above.
            unsafe { std::slice::from_raw_parts_mut(distances, d.distances.len()) }
                .copy_from_slice(&d.distances);
        }
        Ok(())
    })
}

/// Every pixel's furthest site (thesis §3.7.1), like [`pixgeo_voronoi`]'s
/// outputs: `width * height` labels and, unless null, distances. Only the
/// picture's size, bounding box and metric of `options` apply.
///
/// # Safety
/// As [`pixgeo_voronoi`].
#[no_mangle]
pub unsafe extern "C" fn pixgeo_furthest(
    ctx: *mut PixgeoContext,
    xy: *const f64,
    count: usize,
    options: *const PixgeoVoronoiOptions,
    labels: *mut u32,
    distances: *mut f32,
) -> PixgeoStatus {
    with_context(ctx, |context| {
        if options.is_null() || labels.is_null() {
            return Err(invalid("options and labels must not be null"));
        }
        // SAFETY: non-null and valid (caller contract).
        let o = unsafe { &*options };
        let metric = metric_of(o)?;
        let (frame, _, _) = picture_of(o)?;
        // SAFETY: `xy` holds `2 * count` doubles (caller contract).
        let sites = unsafe { points(xy, count) }?;
        let f = higher_order::furthest(&context.machine, &sites, &frame, metric).map_err(failed)?;
        // SAFETY: caller-owned arrays of `width * height` values.
        unsafe { std::slice::from_raw_parts_mut(labels, f.labels.len()) }
            .copy_from_slice(&f.labels);
        if !distances.is_null() {
            // SAFETY: as above.
            unsafe { std::slice::from_raw_parts_mut(distances, f.distances.len()) }
                .copy_from_slice(&f.distances);
        }
        Ok(())
    })
}

/// Writes `answer` to `out`, which the caller guarantees is writable or null.
fn answer_into(out: *mut PixgeoPair, answer: Answer) -> Result<(), (PixgeoStatus, String)> {
    // SAFETY: null or writable (caller contract of the public functions).
    match unsafe { out.as_mut() } {
        Some(slot) => {
            *slot = answer.into();
            Ok(())
        }
        None => Err(invalid("the answer pointer is null")),
    }
}

/// The Hausdorff distance between point sets `a` and `b` (thesis §3.11.1), both
/// directed distances, exact: `*a_to_b` gets the point of `a` farthest from its
/// nearest point of `b` (`from` in `a`, `to` in `b`), `*b_to_a` the converse.
/// The Hausdorff distance is the larger of the two.
///
/// # Safety
/// `ctx` is a live context; `a` holds `2 * a_count` doubles, `b` `2 * b_count`;
/// `a_to_b` and `b_to_a` point to writable pairs.
#[no_mangle]
pub unsafe extern "C" fn pixgeo_hausdorff(
    ctx: *mut PixgeoContext,
    a: *const f64,
    a_count: usize,
    b: *const f64,
    b_count: usize,
    a_to_b: *mut PixgeoPair,
    b_to_a: *mut PixgeoPair,
) -> PixgeoStatus {
    with_context(ctx, |context| {
        // SAFETY: sizes as documented (caller contract).
        let (a, b) = unsafe { (points(a, a_count)?, points(b, b_count)?) };
        let h = distances::hausdorff(&context.machine, &a, &b, None).map_err(failed)?;
        answer_into(a_to_b, h.a_to_b)?;
        answer_into(b_to_a, h.b_to_a)
    })
}

/// The diameter of a point set: the two points farthest apart (thesis §3.11.2),
/// exact.
///
/// # Safety
/// `ctx` is a live context; `xy` holds `2 * count` doubles; `out` points to a
/// writable pair.
#[no_mangle]
pub unsafe extern "C" fn pixgeo_diameter(
    ctx: *mut PixgeoContext,
    xy: *const f64,
    count: usize,
    out: *mut PixgeoPair,
) -> PixgeoStatus {
    with_context(ctx, |context| {
        // SAFETY: size as documented (caller contract).
        let sites = unsafe { points(xy, count) }?;
        let d = distances::diameter(&context.machine, &sites, None).map_err(failed)?;
        answer_into(out, d)
    })
}

/// The largest distance between a point of `a` and a point of `b` (thesis
/// §3.11.3), exact; `from` indexes `a`, `to` indexes `b`.
///
/// # Safety
/// As [`pixgeo_hausdorff`], with one writable pair `out`.
#[no_mangle]
pub unsafe extern "C" fn pixgeo_max_distance(
    ctx: *mut PixgeoContext,
    a: *const f64,
    a_count: usize,
    b: *const f64,
    b_count: usize,
    out: *mut PixgeoPair,
) -> PixgeoStatus {
    with_context(ctx, |context| {
        // SAFETY: sizes as documented (caller contract).
        let (a, b) = unsafe { (points(a, a_count)?, points(b, b_count)?) };
        let d = distances::max_distance(&context.machine, &a, &b, None).map_err(failed)?;
        answer_into(out, d)
    })
}

/// The unit and picture side that homothet options describe.
///
/// # Safety
/// `options` is null or valid, its `polygon` null or holding `2 *
/// polygon_count` doubles.
unsafe fn homothet_options(
    options: *const PixgeoHomothetOptions,
) -> Result<(Unit, u32), (PixgeoStatus, String)> {
    // SAFETY: null or valid (caller contract).
    let Some(o) = (unsafe { options.as_ref() }) else {
        return Err(invalid("options must not be null"));
    };
    let unit = if o.polygon.is_null() {
        Unit::Circle
    } else {
        // SAFETY: as documented.
        let vertices = unsafe { points(o.polygon, o.polygon_count) }?;
        match Metric::polygon(&vertices, DVec2::from(o.kernel)).map_err(invalid)? {
            Metric::Polygon(g) => Unit::Polygon(g),
            _ => unreachable!("a polygon metric"),
        }
    };
    let side = if o.side == 0 { DEFAULT_SIDE } else { o.side };
    Ok((unit, side))
}

fn homothet_into(
    out: *mut PixgeoHomothet,
    answer: &HomothetAnswer,
) -> Result<(), (PixgeoStatus, String)> {
    // SAFETY: null or writable (caller contract of the public functions).
    let Some(slot) = (unsafe { out.as_mut() }) else {
        return Err(invalid("the answer pointer is null"));
    };
    *slot = PixgeoHomothet {
        centre: answer.exact.centre,
        scale: answer.exact.scale,
        pixel_centre: answer.pixel.centre,
        pixel_scale: answer.pixel.scale,
        pixel_bound: answer.pixel_bound,
        tolerance: answer.tolerance,
    };
    Ok(())
}

/// The smallest homothet of a circle or polygon (thesis ch. 4) holding every
/// one of the `count` sites (points, segments, circles, arcs; unweighted), or
/// with `k` > 0 at least `k` of them (points only, §4.4.1).
///
/// # Safety
/// `ctx` is a live context; `sites` holds `count` sites; `options` points to
/// valid options; `out` points to a writable answer.
#[no_mangle]
pub unsafe extern "C" fn pixgeo_enclose(
    ctx: *mut PixgeoContext,
    sites: *const PixgeoSite,
    count: usize,
    options: *const PixgeoHomothetOptions,
    k: usize,
    out: *mut PixgeoHomothet,
) -> PixgeoStatus {
    with_context(ctx, |context| {
        if sites.is_null() {
            return Err(invalid("sites must not be null"));
        }
        // SAFETY: as documented (caller contract).
        let (unit, side) = unsafe { homothet_options(options) }?;
        // SAFETY: `sites` holds `count` sites (caller contract).
        let given = sites_of(unsafe { std::slice::from_raw_parts(sites, count) })?;
        let answer =
            homothet::enclose_sites(&context.machine, &given, unit, k, side).map_err(failed)?;
        homothet_into(out, &answer)
    })
}

/// The largest homothet of a circle or polygon (thesis ch. 5) meeting none of
/// the `count` sites (points, segments, circles, arcs; multiplicative weights
/// scale the clearance each demands), its centre in the region: `ring_count`
/// rings of `ring_sizes[r]` points each, concatenated in `rings` as `{x0, y0,
/// ...}` (holes by even-odd; `ring_count` 0: the sites' bounding box). With
/// `inside`, the whole homothet stays inside the region.
///
/// # Safety
/// `ctx` is a live context; `sites` holds `count` sites; `rings` holds twice
/// the sum of the `ring_count` sizes in `ring_sizes` (both may be null when
/// `ring_count` is 0); `options` points to valid options; `out` points to a
/// writable answer.
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn pixgeo_empty(
    ctx: *mut PixgeoContext,
    sites: *const PixgeoSite,
    count: usize,
    rings: *const f64,
    ring_sizes: *const usize,
    ring_count: usize,
    inside: bool,
    options: *const PixgeoHomothetOptions,
    out: *mut PixgeoHomothet,
) -> PixgeoStatus {
    with_context(ctx, |context| {
        if sites.is_null() {
            return Err(invalid("sites must not be null"));
        }
        // SAFETY: as documented (caller contract).
        let (unit, side) = unsafe { homothet_options(options) }?;
        // SAFETY: `sites` holds `count` sites (caller contract).
        let given = sites_of(unsafe { std::slice::from_raw_parts(sites, count) })?;
        let mut region = Region::default();
        if ring_count > 0 {
            if ring_sizes.is_null() {
                return Err(invalid("ring_sizes must not be null"));
            }
            // SAFETY: `ring_sizes` holds `ring_count` sizes (caller contract).
            let sizes = unsafe { std::slice::from_raw_parts(ring_sizes, ring_count) };
            let total = sizes
                .iter()
                .try_fold(0usize, |a, n| a.checked_add(*n))
                .ok_or_else(|| invalid("ring sizes overflow"))?;
            // SAFETY: `rings` holds `2 * total` doubles (caller contract).
            let all = unsafe { points(rings, total) }?;
            let mut at = 0;
            for n in sizes {
                region.rings.push(all[at..at + n].to_vec());
                at += n;
            }
        }
        let answer =
            homothet::largest_empty_sites(&context.machine, &given, unit, &region, inside, side)
                .map_err(failed)?;
        homothet_into(out, &answer)
    })
}

/// The settle point (thesis §3.10): where a new site among the `count` sites
/// `xy` would win the most pixels, not counting pixels already nearest to one
/// of the `own_count` sites `own` (null when 0). The picture's size, bounding
/// box and metric come from `options`. Unless null, `area` receives the
/// potential-area map (`width * height` counts, row-major). With the L2 metric
/// the answer is refined to a real-valued position and its exact area.
///
/// # Safety
/// `ctx` is a live context; `xy` holds `2 * count` doubles, `own` `2 *
/// own_count` (or is null when `own_count` is 0); `options` points to valid
/// options; `area` is null or has room for `width * height` values; `out`
/// points to a writable answer.
#[no_mangle]
pub unsafe extern "C" fn pixgeo_settle(
    ctx: *mut PixgeoContext,
    xy: *const f64,
    count: usize,
    own: *const f64,
    own_count: usize,
    options: *const PixgeoVoronoiOptions,
    method: u32,
    area: *mut u32,
    out: *mut PixgeoSettle,
) -> PixgeoStatus {
    with_context(ctx, |context| {
        if options.is_null() || out.is_null() {
            return Err(invalid("options and out must not be null"));
        }
        // SAFETY: non-null and valid (caller contract).
        let o = unsafe { *options };
        let (frame, _, _) = picture_of(&o)?;
        let metric = metric_of(&o)?;
        // SAFETY: sizes as documented (caller contract).
        let rivals = unsafe { points(xy, count) }?;
        let own = if own_count == 0 {
            Vec::new()
        } else {
            // SAFETY: as above.
            unsafe { points(own, own_count) }?
        };
        let method = match method {
            0 => SettleMethod::Spans,
            1 => SettleMethod::Faithful,
            other => {
                return Err(invalid(format!(
                    "method {other} is not a PixgeoSettleMethod (0 spans, 1 faithful)"
                )))
            }
        };
        let options = SettleOptions {
            frame,
            metric,
            method,
        };
        let map =
            settle::potential_areas(&context.machine, &rivals, &own, &options, &mut |_, _| {})
                .map_err(failed)?;
        let refined = if metric == Metric::L2 {
            Some(settle::refine(&rivals, &own, &frame, &map.leaders(8)).map_err(failed)?)
        } else {
            None
        };
        if !area.is_null() {
            // SAFETY: caller-owned array of `width * height` values.
            unsafe { std::slice::from_raw_parts_mut(area, map.area.len()) }
                .copy_from_slice(&map.area);
        }
        let best = map.best[0];
        let world = refined.map(|r| frame.to_world(DVec2::from_array(r.position)));
        let answer = PixgeoSettle {
            pixel_x: (best % frame.width as usize) as u32,
            pixel_y: (best / frame.width as usize) as u32,
            area: map.best_area,
            ties: map.best.len() as u32,
            refined_x: world.map_or(f64::NAN, |p| p.x),
            refined_y: world.map_or(f64::NAN, |p| p.y),
            refined_area: refined.map_or(f64::NAN, |r| r.area / (frame.scale * frame.scale)),
        };
        // SAFETY: non-null and writable (caller contract).
        unsafe { *out = answer };
        Ok(())
    })
}

/// The Delaunay triangulation of the `count` points `xy` (`{x0, y0, x1, ...}`),
/// from their digital Voronoi diagram on a texture `grid` pixels along the
/// longer side of their bounding box (0: about one pixel per point). Writes
/// the counter-clockwise triangles as point indices, three per triangle, into
/// `triangles` and their number into `*triangle_count`; repeated points are in
/// no triangle, and `*duplicate_count` (unless null) receives how many there
/// were. Fewer than three distinct points, or all on one line, is an invalid
/// argument.
///
/// # Safety
/// `ctx` is a live context; `xy` holds `2 * count` doubles; `triangles` has
/// room for `6 * count` values (a triangulation has fewer than `2 * count`
/// triangles); `triangle_count` points to a writable `size_t`;
/// `duplicate_count` is null or does.
#[no_mangle]
pub unsafe extern "C" fn pixgeo_delaunay(
    ctx: *mut PixgeoContext,
    xy: *const f64,
    count: usize,
    grid: u32,
    triangles: *mut u32,
    triangle_count: *mut usize,
    duplicate_count: *mut usize,
) -> PixgeoStatus {
    with_context(ctx, |context| {
        if triangles.is_null() || triangle_count.is_null() {
            return Err(invalid("triangles and triangle_count must not be null"));
        }
        // SAFETY: `xy` holds `2 * count` doubles (caller contract).
        let given = unsafe { points(xy, count) }?;
        let options = delaunay::DelaunayOptions {
            grid: (grid > 0).then_some(grid),
            check: false,
        };
        let result = delaunay::delaunay(&context.machine, &given, &options).map_err(failed)?;
        let flat: Vec<u32> = result.triangles.iter().flatten().copied().collect();
        // SAFETY: room for `6 * count` values (caller contract); a
        // triangulation of n points has at most 2n - 5 triangles.
        unsafe { std::slice::from_raw_parts_mut(triangles, flat.len()) }.copy_from_slice(&flat);
        // SAFETY: writable (caller contract).
        unsafe { *triangle_count = result.triangles.len() };
        if !duplicate_count.is_null() {
            // SAFETY: writable when not null (caller contract).
            unsafe { *duplicate_count = result.duplicates.len() };
        }
        Ok(())
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_panic_in_a_call_becomes_its_message() {
        let payload = guarded(|| panic!("boom")).unwrap_err();
        let text = panic_text(payload);
        assert!(text.contains("boom") && text.contains("ffi.rs"), "{text}");
        assert!(!IN_CALL.get());
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
