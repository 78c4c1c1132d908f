//! Exact vector cells: the bindings of `pixgeo.voronoi_cells` and
//! `pixgeo.power_cells`.

use glam::DVec2;
use numpy::{ndarray::Array2, IntoPyArray, PyArray2, PyReadonlyArray1, PyReadonlyArray2};
use pixgeo::{
    algorithms::{
        cells::voronoi_cells as cells_of,
        cells::{Cells, CellsOptions},
        power::regular_triangulation,
    },
    geometry::cell::Rect,
};
use pyo3::prelude::*;

use pixgeo::Need;

use crate::{fields::weighted, on_backend, on_cpu, points, InternalError};

/// Each site's cell's corners, and the repeated sites (Voronoi) or the
/// hidden ones (power).
type CellsTuple<'py, T> = (Vec<Bound<'py, PyArray2<f64>>>, T);

/// Each site's exact Voronoi cell clipped to `bbox`, its corners (k, 2)
/// counter-clockwise (none where the cell misses the box), and the repeated
/// sites (repeat, first).
#[pyfunction]
#[pyo3(signature = (points, bbox, device))]
pub fn voronoi_cells<'py>(
    py: Python<'py>,
    points: PyReadonlyArray2<'py, f64>,
    bbox: [f64; 4],
    device: Option<&str>,
) -> PyResult<CellsTuple<'py, Bound<'py, PyArray2<u32>>>> {
    let p = self::points(&points)?;
    let cells = on_backend(py, device, Need::DeviceIfAny, |b| {
        cells_of(b, &p, &options(bbox))
    })?;
    let duplicates = Array2::from_shape_vec(
        (cells.duplicates.len(), 2),
        cells.duplicates.iter().flatten().copied().collect(),
    )
    .map_err(|e| InternalError::new_err(e.to_string()))?;
    Ok((corners(py, &cells)?, duplicates.into_pyarray(py)))
}

/// Each site's exact power cell clipped to `bbox`, as [`voronoi_cells`]
/// gives them (none for a hidden site), and the hidden sites.
#[pyfunction]
#[pyo3(signature = (points, weights, bbox))]
pub fn power_cells<'py>(
    py: Python<'py>,
    points: PyReadonlyArray2<'py, f64>,
    weights: PyReadonlyArray1<'py, f64>,
    bbox: [f64; 4],
) -> PyResult<CellsTuple<'py, Vec<u32>>> {
    let sites = weighted(&points, &weights)?;
    let (cells, hidden) = on_cpu(py, || {
        let regular = regular_triangulation(&sites)?;
        let cells = regular.cells(&sites, &options(bbox))?;
        Ok((cells, regular.hidden))
    })?;
    Ok((corners(py, &cells)?, hidden))
}

fn options(bbox: [f64; 4]) -> CellsOptions {
    CellsOptions::new(Rect {
        lo: DVec2::new(bbox[0], bbox[1]),
        hi: DVec2::new(bbox[2], bbox[3]),
    })
}

/// Each cell's corners as an array (k, 2).
fn corners<'py>(py: Python<'py>, cells: &Cells) -> PyResult<Vec<Bound<'py, PyArray2<f64>>>> {
    cells
        .polygons
        .iter()
        .map(|ring| {
            let corners = Array2::from_shape_vec(
                (ring.len(), 2),
                ring.iter().flat_map(|c| [c.x, c.y]).collect(),
            )
            .map_err(|e| InternalError::new_err(e.to_string()))?;
            Ok(corners.into_pyarray(py))
        })
        .collect()
}
