//! `pixgeo._pixgeo`: the thin native layer under the `pixgeo` Python package.
//! Arrays arrive already checked for shape and dtype by `pixgeo/__init__.py`;
//! pixgeo checks the values. The GIL is released while pixgeo works.

use std::{
    borrow::Cow,
    sync::{
        atomic::{AtomicBool, Ordering},
        mpsc::RecvTimeoutError,
        Arc, Mutex, OnceLock,
    },
    time::Duration,
};

use glam::DVec2;
use numpy::{
    ndarray::{Array2, Array3},
    IntoPyArray, PyArray1, PyArray2, PyArray3, PyReadonlyArray1, PyReadonlyArray2,
};
use pixgeo::{
    algorithms::{
        alpha_hull::{self, AlphaMethod, AlphaOptions},
        area::{self, AreaOptions, Extreme},
        delaunay::{delaunay as triangulate, DelaunayOptions},
        distances::{self, Pair},
        great_circle::great_circle_grid,
        higher_order::{self, KNearestOptions},
        homothet::{self, EmptyOptions, EncloseOptions, HomothetAnswer, Region, Unit},
        lloyd::{lloyd as lloyd_iterations, LloydOptions},
        settle::{potential_areas, refine, SettleOptions},
        transform::{
            distance_transform as transform_of, distances_only, medial_axis as axis_of, Pruning,
            Transform, TransformOptions,
        },
        voronoi::{self as diagram, Accuracy, Method as VoronoiMethod, VoronoiOptions},
    },
    geometry::{
        metric::Metric,
        site::{Shape, Site},
        Frame,
    },
    machine::{DeviceChoice, PixelRect},
    Backend, Error, Machine, MachineOptions, Need,
};
use pyo3::{
    create_exception,
    exceptions::{PyOSError, PyRuntimeError, PyValueError},
    prelude::*,
    types::PyDict,
};

mod cells;
mod fields;

create_exception!(
    _pixgeo,
    NoDeviceError,
    PyRuntimeError,
    "No Vulkan driver, no device matching the request, or a device without a feature the call needs."
);
create_exception!(
    _pixgeo,
    DeviceError,
    PyRuntimeError,
    "A Vulkan call or a device memory allocation failed, or the validation layer reported a problem."
);
create_exception!(
    _pixgeo,
    InternalError,
    PyRuntimeError,
    "pixgeo broke one of its own invariants: a bug, to be reported with the input."
);

/// A device's machine, and the flag that cancels the call using it.
struct Device {
    machine: Mutex<Machine>,
    cancel: Arc<AtomicBool>,
}

type Shared = Arc<Device>;

/// The machine options for `device` (else `PIXGEO_DEVICE`).
fn options(device: Option<&str>) -> MachineOptions {
    let mut options = MachineOptions::from_env();
    if let Some(d) = device {
        options.device = DeviceChoice::parse(d);
    }
    options
}

/// One machine per device name, made on first use and shared; a mutex keeps
/// one call at a time on each. A failed start is not kept.
fn machine(device: Option<&str>) -> pixgeo::Result<Shared> {
    static MACHINES: OnceLock<Mutex<Vec<(String, Shared)>>> = OnceLock::new();
    let key = device.unwrap_or("").to_string();
    let mut machines = MACHINES
        .get_or_init(Default::default)
        .lock()
        .unwrap_or_else(|e| e.into_inner());
    if let Some((_, m)) = machines.iter().find(|(k, _)| *k == key) {
        return Ok(m.clone());
    }
    let machine = Machine::new(&options(device))?;
    let m = Arc::new(Device {
        cancel: machine.cancel_flag(),
        machine: Mutex::new(machine),
    });
    machines.push((key, m.clone()));
    Ok(m)
}

/// Runs `work` where the core's one rule ([`Backend::choose`]) puts work
/// with `need`: the CPU, or the device's shared machine, [`interruptible`]
/// by its cancel flag. Falling back to the CPU (no Vulkan driver) warns.
fn on_backend<T: Send>(
    py: Python<'_>,
    device: Option<&str>,
    need: Need,
    work: impl FnOnce(&Backend) -> pixgeo::Result<T> + Send,
) -> PyResult<T> {
    let options = options(device);
    if Backend::cpu_first(&options, need).map_err(to_py)? {
        return on_cpu(py, || work(&Backend::Cpu));
    }
    let shared = match py.detach(|| machine(device)) {
        Ok(shared) => shared,
        Err(e) => {
            // A fallback is to the CPU, or an error.
            let chosen = Backend::instead_of_device(&options, need, e).map_err(to_py)?;
            if let Some(why) = &chosen.fallback {
                let warning = py.get_type::<pyo3::exceptions::PyRuntimeWarning>();
                PyErr::warn(py, &warning, &std::ffi::CString::new(why.as_str())?, 1)?;
            }
            return on_cpu(py, || work(&Backend::Cpu));
        }
    };
    interruptible(py, &shared.cancel, || match shared.machine.lock() {
        Ok(machine) => work(&Backend::Device(&machine)).map_err(to_py),
        Err(_) => Err(PyRuntimeError::new_err("a pixgeo call panicked")),
    })
}

/// Runs `work` on the device's machine ([`on_backend`] for a drawing).
fn on_machine<T: Send>(
    py: Python<'_>,
    device: Option<&str>,
    work: impl FnOnce(&Machine) -> pixgeo::Result<T> + Send,
) -> PyResult<T> {
    let need = Need::Drawing("this call");
    on_backend(py, device, need, |b| work(b.device_for("this call")?))
}

/// [`interruptible`] work on the CPU alone, with a flag of its own.
fn on_cpu<T: Send>(py: Python<'_>, work: impl FnOnce() -> pixgeo::Result<T> + Send) -> PyResult<T> {
    let cancel = Arc::new(AtomicBool::new(false));
    interruptible(py, &cancel, || work().map_err(to_py))
}

/// Runs `work` in a thread of its own within `cancel` (its CPU steps look at
/// it), with the GIL released. The caller's thread looks for signals every
/// 50 ms meanwhile: on Ctrl-C it sets `cancel`, waits for the work to stop and
/// raises `KeyboardInterrupt`.
fn interruptible<T: Send>(
    py: Python<'_>,
    cancel: &Arc<AtomicBool>,
    work: impl FnOnce() -> PyResult<T> + Send,
) -> PyResult<T> {
    let (done, mut finished) = std::sync::mpsc::channel::<()>();
    std::thread::scope(|scope| {
        let worker = scope.spawn(|| {
            let result = pixgeo::Control::new().cancel(cancel.clone()).run(work);
            drop(done);
            result
        });
        let panicked = |_| PyRuntimeError::new_err("a pixgeo call panicked");
        loop {
            // The receiver goes into the detached closure and back.
            let (waited, receiver) =
                py.detach(move || (finished.recv_timeout(Duration::from_millis(50)), finished));
            finished = receiver;
            if !matches!(waited, Err(RecvTimeoutError::Timeout)) {
                return py.detach(|| worker.join()).map_err(panicked)?;
            }
            if let Err(interrupt) = py.check_signals() {
                cancel.store(true, Ordering::Relaxed);
                let _ = py.detach(|| worker.join());
                cancel.store(false, Ordering::Relaxed);
                return Err(interrupt);
            }
        }
    })
}

/// Each kind of error as its exception: bad input a `ValueError` with
/// pixgeo's message and its `reason` (`kind`, and `index` or `needed` and
/// `given` where the kind has them), a file an `OSError` (its errno's subclass, such as
/// `FileNotFoundError`), the device's failures the `RuntimeError` subclasses
/// above.
fn to_py(e: Error) -> PyErr {
    let text = e.to_string();
    match e {
        Error::InvalidInput(why) => {
            let err = PyValueError::new_err(text);
            Python::attach(|py| {
                let reason = PyDict::new(py);
                let _ = reason.set_item("kind", why.kind());
                for (name, number) in why.numbers() {
                    let _ = reason.set_item(name, number);
                }
                let _ = err.value(py).setattr("reason", reason);
            });
            err
        }
        Error::PictureTooLarge { .. } | Error::Parse { .. } => PyValueError::new_err(text),
        Error::Io { path, cause } => PyOSError::new_err((
            cause.raw_os_error().unwrap_or(0),
            cause.to_string(),
            path.display().to_string(),
        )),
        Error::NoVulkan(_) | Error::NoDevice(_) | Error::Unsupported(_) => {
            NoDeviceError::new_err(text)
        }
        Error::Vulkan { .. } | Error::Memory(_) | Error::Validation(_) => {
            DeviceError::new_err(text)
        }
        Error::Internal(_) | Error::Usage(_) => InternalError::new_err(text),
        Error::HostMemory { .. } => pyo3::exceptions::PyMemoryError::new_err(text),
        _ => PyRuntimeError::new_err(text),
    }
}

/// The rows of an (n, 2) array as points, once the work on n sites has its
/// memory (a `MemoryError` otherwise).
fn points(a: &PyReadonlyArray2<'_, f64>) -> PyResult<Vec<DVec2>> {
    let a = a.as_array();
    pixgeo::memory::reserve_sites(a.nrows()).map_err(to_py)?;
    Ok(a.rows()
        .into_iter()
        .map(|r| DVec2::new(r[0], r[1]))
        .collect())
}

fn frame(width: u32, height: u32, bbox: Option<[f64; 4]>) -> PyResult<Frame> {
    match bbox {
        None => Frame::pixels(width, height),
        Some(b) => Frame::with_bbox(width, Some(height), b),
    }
    .map_err(to_py)
}

fn metric(text: &str) -> PyResult<Metric> {
    pixgeo_io::sites::parse_metric(text).map_err(PyValueError::new_err)
}

/// An option by its name, as the command line reads it.
fn named<T: std::str::FromStr<Err = pixgeo::Error>>(text: &str) -> PyResult<T> {
    text.parse().map_err(to_py)
}

/// (width, height, origin x, origin y, pixels per world unit).
type FrameTuple = (u32, u32, f64, f64, f64);

fn frame_tuple(f: &Frame) -> FrameTuple {
    (f.width, f.height, f.origin.x, f.origin.y, f.scale)
}

fn raster<T: numpy::Element>(
    py: Python<'_>,
    values: Vec<T>,
    height: u32,
    width: u32,
) -> PyResult<Bound<'_, PyArray2<T>>> {
    let a = Array2::from_shape_vec((height as usize, width as usize), values)
        .map_err(|e| InternalError::new_err(e.to_string()))?;
    Ok(a.into_pyarray(py))
}

type Rasters<'py> = (
    Bound<'py, PyArray2<u32>>,
    Bound<'py, PyArray2<f32>>,
    FrameTuple,
);

type Levels<'py> = (
    Bound<'py, PyArray3<u32>>,
    Bound<'py, PyArray3<f32>>,
    FrameTuple,
);

/// Triangles (m, 3) and repeated points (dropped, kept).
type Triangulation<'py> = (Bound<'py, PyArray2<u32>>, Bound<'py, PyArray2<u32>>);

/// Distances (H, W), and the (row, column) planes (2, H, W) of each pixel's
/// nearest feature.
type Transformed<'py> = (Bound<'py, PyArray2<f64>>, Option<Bound<'py, PyArray3<i32>>>);

/// A (H, W) `features` raster's width and height, and the transform's
/// options.
fn transform_input(
    features: &numpy::PyReadonlyArray2<'_, bool>,
    sampling: [f64; 2],
    metric_name: &str,
) -> PyResult<([u32; 2], TransformOptions)> {
    let (h, w) = features.as_array().dim();
    let side = |n: usize| {
        u32::try_from(n).map_err(|_| PyValueError::new_err(format!("a side of {n} is too long")))
    };
    let options = TransformOptions::new()
        .metric(metric(metric_name)?)
        .sampling(sampling);
    Ok(([side(w)?, side(h)?], options))
}

/// A raster's values row-major: borrowed where they lie so already.
fn row_major<'a>(features: &'a numpy::PyReadonlyArray2<'_, bool>) -> Cow<'a, [bool]> {
    match features.as_slice() {
        Ok(contiguous) => Cow::Borrowed(contiguous),
        Err(_) => Cow::Owned(features.as_array().iter().copied().collect()),
    }
}

/// The transform of a (H, W) `features` raster, with its options.
fn transform(
    py: Python<'_>,
    features: numpy::PyReadonlyArray2<'_, bool>,
    sampling: [f64; 2],
    metric_name: &str,
) -> PyResult<(Transform, TransformOptions)> {
    let ([width, height], options) = transform_input(&features, sampling, metric_name)?;
    let mask = row_major(&features);
    let t = on_cpu(py, || transform_of(&mask, width, height, &options))?;
    Ok((t, options))
}

/// Distances (H, W) to the nearest `features` pixel and, with `indices`,
/// its (row, column) (2, H, W): -1 and infinity where there is no feature.
#[pyfunction]
#[pyo3(signature = (features, sampling, metric_name, indices=true))]
fn distance_transform<'py>(
    py: Python<'py>,
    features: numpy::PyReadonlyArray2<'py, bool>,
    sampling: [f64; 2],
    metric_name: &str,
    indices: bool,
) -> PyResult<Transformed<'py>> {
    if !indices {
        let ([width, height], options) = transform_input(&features, sampling, metric_name)?;
        let mask = row_major(&features);
        let d = on_cpu(py, || distances_only(&mask, width, height, &options))?;
        return Ok((raster(py, d, height, width)?, None));
    }
    let (t, _) = transform(py, features, sampling, metric_name)?;
    let (h, w) = (t.height as usize, t.width as usize);
    let distances = raster(py, t.distances, t.height, t.width)?;
    let mut planes = t.feature_rows;
    planes.extend_from_slice(&t.feature_columns);
    let indices = Array3::from_shape_vec((2, h, w), planes)
        .map_err(|e| InternalError::new_err(e.to_string()))?;
    Ok((distances, Some(indices.into_pyarray(py))))
}

/// A medial axis (H, W) and the distances (H, W).
type Axis<'py> = (Bound<'py, PyArray2<bool>>, Bound<'py, PyArray2<f64>>);

/// The medial axis (H, W) of the pixels that are not `features`, pruned by
/// `length` and `angle`, and the distances (H, W).
#[pyfunction]
#[pyo3(signature = (features, sampling, metric_name, length, angle))]
fn medial_axis<'py>(
    py: Python<'py>,
    features: numpy::PyReadonlyArray2<'py, bool>,
    sampling: [f64; 2],
    metric_name: &str,
    length: f64,
    angle: f64,
) -> PyResult<Axis<'py>> {
    let (t, options) = transform(py, features, sampling, metric_name)?;
    let axis = on_cpu(py, || axis_of(&t, &options, Pruning { length, angle }))?;
    Ok((
        raster(py, axis, t.height, t.width)?,
        raster(py, t.distances, t.height, t.width)?,
    ))
}

/// The frame of a `width` x `height` picture, without drawing anything.
#[pyfunction]
#[pyo3(signature = (width, height, bbox))]
fn frame_of(width: u32, height: u32, bbox: Option<[f64; 4]>) -> PyResult<FrameTuple> {
    Ok(frame_tuple(&frame(width, height, bbox)?))
}

/// The diagram, or with `window = (x0, y0, width, height)` only those pixels of
/// it, bit for bit.
#[pyfunction]
#[pyo3(signature = (sites, width, height, bbox, metric_name, mode, device, window=None, method="auto"))]
#[allow(clippy::too_many_arguments)]
fn voronoi<'py>(
    py: Python<'py>,
    sites: PyReadonlyArray2<'py, f64>,
    width: u32,
    height: u32,
    bbox: Option<[f64; 4]>,
    metric_name: &str,
    mode: &str,
    device: Option<&str>,
    window: Option<[u32; 4]>,
    method: &str,
) -> PyResult<Rasters<'py>> {
    let sites = points(&sites)?;
    let mut options = VoronoiOptions::exact(frame(width, height, bbox)?);
    options.metric = metric(metric_name)?;
    options.accuracy = named::<Accuracy>(mode)?;
    options.method = named::<VoronoiMethod>(method)?;
    options.window = window.map(|[x, y, width, height]| PixelRect {
        x,
        y,
        width,
        height,
    });
    // Without a GPU, the grid needs no Vulkan device, whose start would
    // cost more than the diagram.
    let need = if options.on_cpu_alone() {
        Need::CpuUnlessGpu
    } else {
        Need::Drawing("this diagram's options (cones, fans or another metric)")
    };
    let d = on_backend(py, device, need, |backend| {
        diagram::voronoi(backend, &sites, &options)
    })?;
    Ok((
        raster(py, d.labels, d.height, d.width)?,
        raster(py, d.distances, d.height, d.width)?,
        frame_tuple(&options.frame),
    ))
}

/// The diagram of points weighted by `weights` rows (m, a): distances divided
/// by m, then a added (thesis §3.8).
#[pyfunction]
#[pyo3(signature = (sites, weights, width, height, bbox, metric_name, mode, device))]
#[allow(clippy::too_many_arguments)]
fn voronoi_weighted<'py>(
    py: Python<'py>,
    sites: PyReadonlyArray2<'py, f64>,
    weights: PyReadonlyArray2<'py, f64>,
    width: u32,
    height: u32,
    bbox: Option<[f64; 4]>,
    metric_name: &str,
    mode: &str,
    device: Option<&str>,
) -> PyResult<Rasters<'py>> {
    let sites: Vec<Site> = points(&sites)?
        .into_iter()
        .zip(points(&weights)?)
        .map(|(p, w)| Site {
            multiplicative: w.x,
            additive: w.y,
            ..Site::point(p)
        })
        .collect();
    let mut options = VoronoiOptions::exact(frame(width, height, bbox)?);
    options.metric = metric(metric_name)?;
    options.accuracy = named::<Accuracy>(mode)?;
    let need = match options.accuracy {
        Accuracy::Exact => Need::DeviceIfAny,
        _ => Need::Drawing("the fans of weighted sites"),
    };
    let d = on_backend(py, device, need, |backend| {
        pixgeo::algorithms::voronoi::voronoi(backend, &sites, &options)
    })?;
    Ok((
        raster(py, d.labels, d.height, d.width)?,
        raster(py, d.distances, d.height, d.width)?,
        frame_tuple(&options.frame),
    ))
}

/// Pixel classes, the frame, the boundary sites and the method used.
type Hull<'py> = (Bound<'py, PyArray2<u8>>, FrameTuple, Vec<u32>, String);

/// The α-hull on a picture fitted to it: pixel classes, the frame, the
/// boundary sites (hull method and α = 0) and the method used.
#[pyfunction]
#[pyo3(signature = (p, alpha, side, method, device))]
fn alpha_hull_of<'py>(
    py: Python<'py>,
    p: PyReadonlyArray2<'py, f64>,
    alpha: f64,
    side: u32,
    method: &str,
    device: Option<&str>,
) -> PyResult<Hull<'py>> {
    let p = points(&p)?;
    let method: AlphaMethod = named(method)?;
    let h = on_machine(py, device, |m| {
        alpha_hull::alpha_hull(m, &p, &AlphaOptions::new(alpha).method(method).side(side))
    })?;
    let f = (h.width, h.height, h.origin[0], h.origin[1], h.scale);
    Ok((
        raster(py, h.pixels, h.height, h.width)?,
        f,
        h.boundary_sites,
        h.method.to_string(),
    ))
}

/// The map, its frame, its largest value and the refined point.
type SettleMap<'py> = (
    Bound<'py, PyArray2<u32>>,
    FrameTuple,
    u32,
    Option<(f64, f64, f64)>,
);

/// The potential-area map of a new site among `rivals` (not counting what
/// `own` stores hold), its largest value, and under L2 the exact settle point
/// refined from the best pixels: (x, y, area) in world units.
#[pyfunction]
#[pyo3(signature = (rivals, own, width, height, bbox, metric_name, refine_from, device))]
#[allow(clippy::too_many_arguments)]
fn settle<'py>(
    py: Python<'py>,
    rivals: PyReadonlyArray2<'py, f64>,
    own: PyReadonlyArray2<'py, f64>,
    width: u32,
    height: u32,
    bbox: Option<[f64; 4]>,
    metric_name: &str,
    refine_from: usize,
    device: Option<&str>,
) -> PyResult<SettleMap<'py>> {
    let (rivals, own) = (points(&rivals)?, points(&own)?);
    let options = SettleOptions::new(frame(width, height, bbox)?).metric(metric(metric_name)?);
    let f = options.frame;
    let map = on_backend(py, device, Need::DeviceIfAny, |backend| {
        potential_areas(backend, &rivals, &own, &options)
    })?;
    let refined = if options.metric == Metric::L2 && refine_from > 0 {
        let r = on_cpu(py, || refine(&rivals, &own, &f, &map.leaders(refine_from)))?;
        let at = f.to_world(DVec2::from(r.position));
        Some((at.x, at.y, r.area / (f.scale * f.scale)))
    } else {
        None
    };
    Ok((
        raster(py, map.area, map.height, map.width)?,
        frame_tuple(&f),
        map.best_area,
        refined,
    ))
}

/// Where Lloyd's iterations leave the sites, every pixel's nearest of
/// them, the frame, each iteration's (energy, largest move), the final
/// energy, whether they converged and how many sites own no weight.
type LloydTuple<'py> = (
    Bound<'py, PyArray2<f64>>,
    Bound<'py, PyArray2<u32>>,
    FrameTuple,
    Vec<(f64, f64)>,
    f64,
    bool,
    usize,
);

/// Lloyd's iterations from `sites` on the picture, over `density` (rows of
/// the picture) or uniformly; on the CPU pixel algorithms for `cpu`.
#[pyfunction]
#[pyo3(signature = (sites, width, height, bbox, iterations, tolerance, density, device))]
#[allow(clippy::too_many_arguments)]
fn lloyd<'py>(
    py: Python<'py>,
    sites: PyReadonlyArray2<'py, f64>,
    width: u32,
    height: u32,
    bbox: Option<[f64; 4]>,
    iterations: u32,
    tolerance: Option<f64>,
    density: Option<PyReadonlyArray2<'py, f64>>,
    device: Option<&str>,
) -> PyResult<LloydTuple<'py>> {
    let sites = points(&sites)?;
    let f = frame(width, height, bbox)?;
    let mut options = LloydOptions::new(f).iterations(iterations);
    if let Some(t) = tolerance {
        options = options.tolerance(t);
    }
    let density = match &density {
        Some(d) => {
            let d = d.as_array();
            if d.shape() != [height as usize, width as usize] {
                return Err(PyValueError::new_err(format!(
                    "density has shape {:?}, the picture ({height}, {width})",
                    d.shape()
                )));
            }
            Some(d.iter().copied().collect::<Vec<f64>>())
        }
        None => None,
    };
    let answer = on_backend(py, device, Need::DeviceIfAny, |backend| {
        lloyd_iterations(backend, &sites, density.as_deref(), &options)
    })?;
    let flat: Vec<f64> = answer.sites.iter().flat_map(|p| [p.x, p.y]).collect();
    let points = Array2::from_shape_vec((answer.sites.len(), 2), flat)
        .map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
    Ok((
        points.into_pyarray(py),
        raster(py, answer.labels, height, width)?,
        frame_tuple(&f),
        answer
            .steps
            .iter()
            .map(|s| (s.energy, s.largest_move))
            .collect(),
        answer.energy,
        answer.converged,
        answer.idle,
    ))
}

#[pyfunction]
#[pyo3(signature = (sites, width, height, k, bbox, metric_name, mode, device))]
#[allow(clippy::too_many_arguments)]
fn k_nearest<'py>(
    py: Python<'py>,
    sites: PyReadonlyArray2<'py, f64>,
    width: u32,
    height: u32,
    k: u32,
    bbox: Option<[f64; 4]>,
    metric_name: &str,
    mode: &str,
    device: Option<&str>,
) -> PyResult<Levels<'py>> {
    let sites = points(&sites)?;
    let options = KNearestOptions::exact(frame(width, height, bbox)?, k)
        .metric(metric(metric_name)?)
        .accuracy(named::<Accuracy>(mode)?);
    let need = match options.accuracy {
        Accuracy::Exact => Need::DeviceIfAny,
        _ => Need::Drawing("the fast mode's fans"),
    };
    let d = on_backend(py, device, need, |backend| {
        higher_order::k_nearest(backend, &sites, &options)
    })?;
    let shape = (d.height as usize, d.width as usize, d.k as usize);
    let wrong = |e: numpy::ndarray::ShapeError| InternalError::new_err(e.to_string());
    Ok((
        Array3::from_shape_vec(shape, d.labels)
            .map_err(wrong)?
            .into_pyarray(py),
        Array3::from_shape_vec(shape, d.distances)
            .map_err(wrong)?
            .into_pyarray(py),
        frame_tuple(&options.frame),
    ))
}

#[pyfunction]
#[pyo3(signature = (sites, width, height, bbox, metric_name, device))]
fn furthest<'py>(
    py: Python<'py>,
    sites: PyReadonlyArray2<'py, f64>,
    width: u32,
    height: u32,
    bbox: Option<[f64; 4]>,
    metric_name: &str,
    device: Option<&str>,
) -> PyResult<Rasters<'py>> {
    let sites = points(&sites)?;
    let f = frame(width, height, bbox)?;
    let m = metric(metric_name)?;
    let d = on_backend(py, device, Need::CpuUnlessGpu, |backend| {
        higher_order::furthest(backend, &sites, &f, m)
    })?;
    Ok((
        raster(py, d.labels, d.height, d.width)?,
        raster(py, d.distances, d.height, d.width)?,
        frame_tuple(&f),
    ))
}

/// Counter-clockwise triangles (m, 3) and the repeated points (dropped, kept).
#[pyfunction]
#[pyo3(signature = (points, device))]
fn delaunay<'py>(
    py: Python<'py>,
    points: PyReadonlyArray2<'py, f64>,
    device: Option<&str>,
) -> PyResult<Triangulation<'py>> {
    let p = self::points(&points)?;
    let options = DelaunayOptions::default();
    let d = on_backend(py, device, Need::CpuUnlessGpu, |b| {
        triangulate(b, &p, &options)
    })?;
    let triangles = Array2::from_shape_vec(
        (d.triangles.len(), 3),
        d.triangles.iter().flatten().copied().collect(),
    )
    .map_err(|e| InternalError::new_err(e.to_string()))?;
    let duplicates = Array2::from_shape_vec(
        (d.duplicates.len(), 2),
        d.duplicates.iter().flatten().copied().collect(),
    )
    .map_err(|e| InternalError::new_err(e.to_string()))?;
    Ok((triangles.into_pyarray(py), duplicates.into_pyarray(py)))
}

/// The triangle of `simplices` (m, 3) over `points` holding each query of
/// `xi` (q, 2), exactly: -1 outside the hull.
#[pyfunction]
fn find_simplex<'py>(
    py: Python<'py>,
    points: PyReadonlyArray2<'py, f64>,
    simplices: PyReadonlyArray2<'py, u32>,
    xi: PyReadonlyArray2<'py, f64>,
) -> PyResult<Bound<'py, PyArray1<i64>>> {
    let (p, q) = (self::points(&points)?, self::points(&xi)?);
    let triangles: Vec<[u32; 3]> = simplices
        .as_array()
        .rows()
        .into_iter()
        .map(|r| [r[0], r[1], r[2]])
        .collect();
    let found = on_cpu(py, || {
        pixgeo::algorithms::locate::locate(&p, &triangles, &q)
    })?;
    let indices: Vec<i64> = found
        .into_iter()
        .map(|t| {
            if t == pixgeo::algorithms::locate::OUTSIDE {
                -1
            } else {
                t as i64
            }
        })
        .collect();
    Ok(indices.into_pyarray(py))
}

/// Whether EPSG's coordinate system `code` is geographic.
#[pyfunction]
fn is_geographic(code: u16) -> PyResult<bool> {
    pixgeo_io::crs::is_geographic(code).map_err(PyValueError::new_err)
}

/// The EPSG code of a coordinate system (`EPSG:N`, an OGC URN, WKT, PROJ, a
/// .prj file), as the command line's `--crs` reads it.
#[pyfunction]
fn epsg_code(text: &str) -> PyResult<u16> {
    pixgeo_io::crs::parse_crs(text).map_err(PyValueError::new_err)
}

/// Labels, distances (metres), the count of pixels left equidistant and of
/// those the device's filter left to the host, and the device's name.
type GreatCircleTuple<'py> = (
    Bound<'py, PyArray1<u32>>,
    Bound<'py, PyArray1<f64>>,
    usize,
    usize,
    String,
);

/// Each pixel's nearest site by great circle on the Earth's mean sphere and
/// the distance in metres, for the grid of longitudes `lons` (columns) and
/// latitudes `lats` (rows): on a Vulkan device as a filter, or on the CPU
/// for `cpu`, and by default where there is no GPU.
#[pyfunction]
#[pyo3(signature = (sites, lons, lats, device=None))]
fn great_circle<'py>(
    py: Python<'py>,
    sites: PyReadonlyArray2<'py, f64>,
    lons: PyReadonlyArray1<'py, f64>,
    lats: PyReadonlyArray1<'py, f64>,
    device: Option<&str>,
) -> PyResult<GreatCircleTuple<'py>> {
    let sites = points(&sites)?;
    let (lons, lats) = (lons.as_slice()?.to_vec(), lats.as_slice()?.to_vec());
    let (answer, name) = on_backend(py, device, Need::CpuUnlessGpu, |backend| {
        let answer = great_circle_grid(backend, &sites, &lons, &lats, &Default::default())?;
        Ok((answer, backend.name().to_string()))
    })?;
    Ok((
        answer.labels.into_pyarray(py),
        answer.distances.into_pyarray(py),
        answer.equidistant,
        answer.decided_on_host,
        name,
    ))
}

/// The `pixgeo` command line run on `args` (its name first), with the GIL
/// released; returns its exit status.
#[pyfunction]
fn cli(py: Python<'_>, args: Vec<std::ffi::OsString>) -> i32 {
    py.detach(|| pixgeo_cli::main_with(args))
}

/// (distance, index in the first set, index in the second).
type PairTuple = (f64, u32, u32);

fn pair(p: Pair) -> PairTuple {
    (p.distance, p.from, p.to)
}

/// The Hausdorff distance, then each directed answer; `method` "pixels",
/// "grid" or None (the faster on the device).
#[pyfunction]
#[pyo3(signature = (a, b, device, method))]
fn hausdorff<'py>(
    py: Python<'py>,
    a: PyReadonlyArray2<'py, f64>,
    b: PyReadonlyArray2<'py, f64>,
    device: Option<&str>,
    method: Option<&str>,
) -> PyResult<(f64, PairTuple, PairTuple)> {
    let (a, b) = (points(&a)?, points(&b)?);
    let method = match method {
        None => None,
        Some("pixels") => Some(distances::Method::Pixels),
        Some("grid") => Some(distances::Method::Grid),
        Some(other) => {
            return Err(PyValueError::new_err(format!(
                "method must be 'pixels', 'grid' or None, not {other:?}"
            )))
        }
    };
    let need = match method {
        Some(distances::Method::Pixels) => Need::Drawing("the pixels method of Hausdorff"),
        _ => Need::CpuUnlessGpu,
    };
    let h = on_backend(py, device, need, |backend| {
        let method = method.unwrap_or_else(|| distances::Method::for_backend(backend));
        distances::hausdorff(
            backend,
            &a,
            &b,
            &distances::HausdorffOptions::default().method(Some(method)),
        )
    })?;
    Ok((h.distance, pair(h.a_to_b.pair), pair(h.b_to_a.pair)))
}

#[pyfunction]
#[pyo3(signature = (p, device))]
fn diameter<'py>(
    py: Python<'py>,
    p: PyReadonlyArray2<'py, f64>,
    device: Option<&str>,
) -> PyResult<PairTuple> {
    let p = points(&p)?;
    let d = on_machine(py, device, |m| distances::diameter(m, &p, None))?;
    Ok(pair(d.pair))
}

/// (centre x, centre y, radius, the sites on the circle).
type Circle = (f64, f64, f64, Vec<u32>);

fn circle(h: HomothetAnswer) -> Circle {
    let e = h.exact;
    (e.centre[0], e.centre[1], e.scale, e.sites)
}

#[pyfunction]
#[pyo3(signature = (p, device))]
fn enclosing_circle<'py>(
    py: Python<'py>,
    p: PyReadonlyArray2<'py, f64>,
    device: Option<&str>,
) -> PyResult<Circle> {
    let p = points(&p)?;
    let h = on_backend(py, device, Need::CpuUnlessGpu, |b| {
        homothet::enclose(b, &p, &EncloseOptions::new(Unit::Circle))
    })?;
    Ok(circle(h))
}

/// The largest circle free of the points and the segments (rows x0, y0, x1,
/// y1), its centre in `region`'s rings (even-odd) or, with none, the sites'
/// bounding box; with `inside`, the whole circle inside the region.
#[pyfunction]
#[pyo3(signature = (p, segments, region, inside, device))]
fn largest_empty_circle<'py>(
    py: Python<'py>,
    p: PyReadonlyArray2<'py, f64>,
    segments: PyReadonlyArray2<'py, f64>,
    region: Vec<PyReadonlyArray2<'py, f64>>,
    inside: bool,
    device: Option<&str>,
) -> PyResult<Circle> {
    let p = points(&p)?;
    let segments = segments.as_array();
    let region = Region {
        rings: region.iter().map(points).collect::<PyResult<_>>()?,
    };
    let options = EmptyOptions::new(Unit::Circle)
        .region(region)
        .inside(inside);
    let h = on_machine(py, device, |m| {
        if segments.nrows() == 0 {
            return homothet::largest_empty(m, &p, &options);
        }
        let sites: Vec<Site> = p
            .iter()
            .map(|&q| Site::point(q))
            .chain(segments.rows().into_iter().map(|r| {
                Site::new(Shape::Segment(
                    DVec2::new(r[0], r[1]),
                    DVec2::new(r[2], r[3]),
                ))
            }))
            .collect();
        homothet::largest_empty(m, &sites, &options)
    })?;
    Ok(circle(h))
}

/// The smallest or largest triangle (3 vertices) or quadrangle (4) by the
/// exact rotational sweep: (vertex indices counter-clockwise, area).
#[pyfunction]
#[pyo3(signature = (p, corners, largest))]
fn extremal_polygon<'py>(
    py: Python<'py>,
    p: PyReadonlyArray2<'py, f64>,
    corners: u32,
    largest: bool,
) -> PyResult<(Bound<'py, PyArray1<u32>>, f64)> {
    let p = points(&p)?;
    let extreme = if largest {
        Extreme::Largest
    } else {
        Extreme::Smallest
    };
    let answer = on_cpu(py, || match corners {
        3 => area::extremal_triangle(&Backend::Cpu, &p, &AreaOptions::new(extreme)),
        _ => area::extremal_quadrangle(&Backend::Cpu, &p, &AreaOptions::new(extreme)),
    })?;
    Ok((answer.sites.into_pyarray(py), answer.area))
}

#[pymodule]
fn _pixgeo(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("NoDeviceError", m.py().get_type::<NoDeviceError>())?;
    m.add("DeviceError", m.py().get_type::<DeviceError>())?;
    m.add("InternalError", m.py().get_type::<InternalError>())?;
    m.add_function(wrap_pyfunction!(frame_of, m)?)?;
    m.add_function(wrap_pyfunction!(distance_transform, m)?)?;
    m.add_function(wrap_pyfunction!(medial_axis, m)?)?;
    m.add_function(wrap_pyfunction!(voronoi, m)?)?;
    m.add_function(wrap_pyfunction!(voronoi_weighted, m)?)?;
    m.add_function(wrap_pyfunction!(alpha_hull_of, m)?)?;
    m.add_function(wrap_pyfunction!(settle, m)?)?;
    m.add_function(wrap_pyfunction!(lloyd, m)?)?;
    m.add_function(wrap_pyfunction!(k_nearest, m)?)?;
    m.add_function(wrap_pyfunction!(furthest, m)?)?;
    m.add_function(wrap_pyfunction!(delaunay, m)?)?;
    m.add_function(wrap_pyfunction!(find_simplex, m)?)?;
    m.add_function(wrap_pyfunction!(cells::voronoi_cells, m)?)?;
    m.add_function(wrap_pyfunction!(cli, m)?)?;
    m.add_function(wrap_pyfunction!(is_geographic, m)?)?;
    m.add_function(wrap_pyfunction!(epsg_code, m)?)?;
    m.add_function(wrap_pyfunction!(great_circle, m)?)?;
    m.add(
        "EARTH_RADIUS",
        pixgeo::algorithms::great_circle::EARTH_RADIUS,
    )?;
    m.add_function(wrap_pyfunction!(hausdorff, m)?)?;
    m.add_function(wrap_pyfunction!(fields::interpolate, m)?)?;
    m.add_function(wrap_pyfunction!(fields::interpolate_at, m)?)?;
    m.add_function(wrap_pyfunction!(fields::power_diagram, m)?)?;
    m.add_function(wrap_pyfunction!(fields::regular_triangulation, m)?)?;
    m.add_function(wrap_pyfunction!(cells::power_cells, m)?)?;
    m.add_function(wrap_pyfunction!(diameter, m)?)?;
    m.add_function(wrap_pyfunction!(enclosing_circle, m)?)?;
    m.add_function(wrap_pyfunction!(largest_empty_circle, m)?)?;
    m.add_function(wrap_pyfunction!(extremal_polygon, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
