//! Interpolated rasters and power diagrams: the bindings of
//! `pixgeo.natural_neighbor`, `pixgeo.power_diagram` and
//! `pixgeo.regular_triangulation`.

use numpy::{ndarray::Array2, IntoPyArray, PyArray1, PyArray2, PyReadonlyArray1, PyReadonlyArray2};
use pixgeo::{
    algorithms::{
        interpolate::{
            interpolate as interpolated, interpolate_points, InterpolateOptions, Method,
        },
        power::{power_diagram as diagram_of, regular_triangulation as triangulate, PowerOptions},
    },
    geometry::power::Weighted,
    machine::PixelRect,
};
use pyo3::prelude::*;

use crate::{frame, named, on_backend, on_cpu, points, raster, InternalError};

/// `values` interpolated at every pixel centre of the picture (or with
/// `window = (x0, y0, width, height)` of those pixels) by `method`; NaN where
/// it gives none.
#[pyfunction]
#[pyo3(signature = (sites, values, width, height, bbox, method, device, window=None))]
#[allow(clippy::too_many_arguments)]
pub fn interpolate<'py>(
    py: Python<'py>,
    sites: PyReadonlyArray2<'py, f64>,
    values: PyReadonlyArray1<'py, f64>,
    width: u32,
    height: u32,
    bbox: Option<[f64; 4]>,
    method: &str,
    device: Option<&str>,
    window: Option<[u32; 4]>,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let (sites, values) = (points(&sites)?, values.as_array().to_vec());
    let (f, method) = (frame(width, height, bbox)?, named::<Method>(method)?);
    let [x, y, w, h] = window.unwrap_or([0, 0, width, height]);
    let rect = PixelRect {
        x,
        y,
        width: w,
        height: h,
    };
    let answer = on_backend(py, device, method.need(), |b| {
        interpolated(
            b,
            &sites,
            &values,
            &InterpolateOptions::new(f, method).window(Some(rect)),
        )
    })?;
    raster(py, answer.values, h, w)
}

/// `values` interpolated at each of `at` (m, 2) by the exact or the linear
/// method.
#[pyfunction]
#[pyo3(signature = (sites, values, at, method, device))]
pub fn interpolate_at<'py>(
    py: Python<'py>,
    sites: PyReadonlyArray2<'py, f64>,
    values: PyReadonlyArray1<'py, f64>,
    at: PyReadonlyArray2<'py, f64>,
    method: &str,
    device: Option<&str>,
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    let (sites, values, at) = (points(&sites)?, values.as_array().to_vec(), points(&at)?);
    let method = named::<Method>(method)?;
    let answer = on_backend(py, device, method.need(), |b| {
        interpolate_points(b, &sites, &values, &at, method)
    })?;
    Ok(answer.values.into_pyarray(py))
}

/// `(points, weights)` as weighted sites.
pub(crate) fn weighted(
    points: &PyReadonlyArray2<'_, f64>,
    weights: &PyReadonlyArray1<'_, f64>,
) -> PyResult<Vec<Weighted>> {
    Ok(Weighted::zip(
        &crate::points(points)?,
        &weights.as_array().to_vec(),
    ))
}

type PowerTuple<'py> = (
    Bound<'py, PyArray2<u32>>,
    Bound<'py, PyArray2<f64>>,
    Bound<'py, PyArray2<u32>>,
    Vec<u32>,
);

/// Each pixel's site of least power (ties to the lower index), its power,
/// how many sites share it, and the hidden sites; with `window = (x0, y0, width, height)` only those
/// pixels.
#[pyfunction]
#[pyo3(signature = (sites, weights, width, height, bbox, window=None))]
pub fn power_diagram<'py>(
    py: Python<'py>,
    sites: PyReadonlyArray2<'py, f64>,
    weights: PyReadonlyArray1<'py, f64>,
    width: u32,
    height: u32,
    bbox: Option<[f64; 4]>,
    window: Option<[u32; 4]>,
) -> PyResult<PowerTuple<'py>> {
    let (sites, f) = (weighted(&sites, &weights)?, frame(width, height, bbox)?);
    let [x, y, w, h] = window.unwrap_or([0, 0, width, height]);
    let rect = PixelRect {
        x,
        y,
        width: w,
        height: h,
    };
    let options = PowerOptions::new(f).window(Some(rect));
    let d = on_cpu(py, || diagram_of(&sites, &options))?;
    Ok((
        raster(py, d.labels, h, w)?,
        raster(py, d.powers, h, w)?,
        raster(py, d.ties, h, w)?,
        d.regular.hidden,
    ))
}

/// Counter-clockwise triangles (m, 3) of the regular triangulation and the
/// hidden sites.
#[pyfunction]
#[pyo3(signature = (sites, weights))]
pub fn regular_triangulation<'py>(
    py: Python<'py>,
    sites: PyReadonlyArray2<'py, f64>,
    weights: PyReadonlyArray1<'py, f64>,
) -> PyResult<(Bound<'py, PyArray2<u32>>, Vec<u32>)> {
    let sites = weighted(&sites, &weights)?;
    let r = on_cpu(py, || triangulate(&sites))?;
    let flat: Vec<u32> = r.triangles.iter().flatten().copied().collect();
    let triangles = Array2::from_shape_vec((r.triangles.len(), 3), flat)
        .map_err(|e| InternalError::new_err(e.to_string()))?;
    Ok((triangles.into_pyarray(py), r.hidden))
}
