//! `--cells FILE.geojson` and `-o FILE.svg`: a diagram's cells as vector
//! art. The Euclidean diagram of points has exact cells, from the Delaunay
//! triangulation, and the power diagram from the regular triangulation;
//! every other diagram's cells are traced from its label raster, to half a
//! pixel.

use std::path::Path;

use anyhow::Result;
use glam::DVec2;
use pixgeo::{
    algorithms::{
        cells::{voronoi_cells, Cells, CellsOptions},
        power::Regular,
        trace::trace_regions,
    },
    geometry::power::Weighted,
    Backend,
};
use pixgeo_io::sites::GeoJsonSources;
use serde_json::{json, Map, Value};

use crate::{
    input::World,
    progress::Progress,
    write::{
        picture::site_color,
        vector::{write_geojson, write_svg, Feature, Polygons},
    },
};

/// Where the cells come from.
pub enum Source<'a> {
    /// The exact cells of point sites under L2.
    Exact {
        backend: &'a Backend<'a>,
        sites: &'a [DVec2],
    },
    /// The exact power cells of weighted sites, from their regular
    /// triangulation.
    Power {
        regular: &'a Regular,
        sites: &'a [Weighted],
    },
    /// The regions of a label raster covering the frame; `describe` gives a
    /// label's properties.
    Traced {
        labels: &'a [u32],
        describe: &'a dyn Fn(u32) -> Map<String, Value>,
    },
}

/// Where the vector outputs go.
#[derive(Clone, Copy)]
pub struct Outputs<'a> {
    pub geojson: Option<&'a Path>,
    pub svg: Option<&'a Path>,
    /// A `--json` answer: no progress bar beside it.
    pub json: bool,
    /// Where a GeoJSON site file's sites come from: each cell carries its
    /// site's feature index and properties.
    pub sources: Option<&'a GeoJsonSources>,
}

impl Outputs<'_> {
    pub fn any(&self) -> bool {
        self.geojson.is_some() || self.svg.is_some()
    }
}

/// Writes the cells of `source` to `outputs`; `sites` are the dots of the
/// SVG, in the computing world.
pub fn write(outputs: Outputs, world: &World, source: Source, sites: &[DVec2]) -> Result<()> {
    if !outputs.any() {
        return Ok(());
    }
    let frame = &world.frame;
    // Three coordinate systems: the computing world, the user's (GeoJSON),
    // and the picture's (SVG: pixel (0, 0) from (0, 0) to (1, 1)).
    let picture = |p: DVec2| frame.to_pixel(p) + DVec2::splat(0.5);
    let dots: Vec<DVec2> = sites.iter().map(|&p| picture(p)).collect();
    match source {
        Source::Exact { backend, sites } => {
            let progress = Progress::new("cells", outputs.json);
            let options = CellsOptions::new(world.clip_rect()).control(progress.control());
            let cells = voronoi_cells(backend, sites, &options)?;
            emit_exact(outputs, world, &dots, &cells, None)
        }
        Source::Power { regular, sites } => {
            let progress = Progress::new("cells", outputs.json);
            let options = CellsOptions::new(world.clip_rect()).control(progress.control());
            let cells = regular.cells(sites, &options)?;
            emit_exact(
                outputs,
                world,
                &dots,
                &cells,
                Some((sites, &regular.hidden)),
            )
        }
        Source::Traced { labels, describe } => {
            let (features, shapes): (Vec<Feature>, Vec<_>) =
                trace_regions(labels, frame.width, u32::MAX)
                    .into_iter()
                    .map(|region| {
                        let corners: Polygons = region
                            .polygons
                            .iter()
                            .map(|rings| {
                                rings
                                    .iter()
                                    .map(|r| {
                                        r.iter()
                                            .map(|&(x, y)| DVec2::new(x as f64, y as f64))
                                            .collect()
                                    })
                                    .collect()
                            })
                            .collect();
                        let user = map(&corners, |c| {
                            world.to_user(frame.to_world(c - DVec2::splat(0.5)))
                        });
                        let mut properties = describe(region.label);
                        if let Some(site) = properties.get("site").and_then(Value::as_u64) {
                            let mut merged = sourced(outputs.sources, site as usize);
                            merged.append(&mut properties);
                            properties = merged;
                        }
                        properties.insert("accuracy".into(), json!("raster: within half a pixel"));
                        let feature = Feature {
                            polygons: user,
                            properties,
                        };
                        (feature, (corners, site_color(region.label)))
                    })
                    .unzip();
            emit(outputs, world, &dots, features, || shapes)
        }
    }
}

/// Writes exact cells, one feature per site; `power`, the weighted sites of
/// power cells and the hidden ones.
fn emit_exact(
    outputs: Outputs,
    world: &World,
    dots: &[DVec2],
    cells: &Cells,
    power: Option<(&[Weighted], &[u32])>,
) -> Result<()> {
    let frame = &world.frame;
    let picture = |p: DVec2| frame.to_pixel(p) + DVec2::splat(0.5);
    let same_as: std::collections::HashMap<u32, u32> =
        cells.duplicates.iter().map(|&[r, f]| (r, f)).collect();
    let polygons = |i: usize| -> Polygons {
        match &cells.polygons[i] {
            ring if ring.is_empty() => Vec::new(),
            ring => vec![vec![ring.clone()]],
        }
    };
    let n = cells.polygons.len();
    // Features one at a time: a million repeats of a site are a million
    // features, never held at once.
    let features = (0..n).map(|i| {
        let mut properties = sourced(outputs.sources, i);
        properties.insert("site".into(), json!(i));
        if let Some((sites, hidden)) = power {
            properties.insert("weight".into(), json!(sites[i].weight));
            let is_hidden = hidden.binary_search(&(i as u32)).is_ok();
            properties.insert("hidden".into(), json!(is_hidden));
        }
        properties.insert("area".into(), json!(cells.area(i)));
        if let Some(f) = same_as.get(&(i as u32)) {
            properties.insert("same_as".into(), json!(f));
        }
        properties.insert("accuracy".into(), json!("exact"));
        Feature {
            polygons: map(&polygons(i), |p| world.to_user(p)),
            properties,
        }
    });
    // A repeated site's cell is drawn once, for the first.
    let shapes = || {
        (0..n)
            .map(|i| {
                let drawn = match same_as.contains_key(&(i as u32)) {
                    true => Vec::new(),
                    false => map(&polygons(i), picture),
                };
                (drawn, site_color(i as u32))
            })
            .collect()
    };
    emit(outputs, world, dots, features, shapes)
}

/// The properties of site `i`'s input feature and its index, `feature`, for
/// the answer's own properties to go after (and over).
fn sourced(sources: Option<&GeoJsonSources>, i: usize) -> Map<String, Value> {
    let Some(sources) = sources else {
        return Map::new();
    };
    let feature = sources.feature_of_site[i] as usize;
    let mut properties = sources.properties[feature].clone();
    properties.insert("feature".into(), json!(feature));
    properties
}

/// Writes the features and the shapes (made only for an SVG) to `outputs`.
fn emit(
    outputs: Outputs,
    world: &World,
    dots: &[DVec2],
    features: impl IntoIterator<Item = Feature>,
    shapes: impl FnOnce() -> Vec<(Polygons, [u8; 3])>,
) -> Result<()> {
    if let Some(path) = outputs.geojson {
        write_geojson(path, features, world.epsg)?;
    }
    if let Some(path) = outputs.svg {
        let frame = &world.frame;
        write_svg(path, frame.width, frame.height, &shapes(), dots)?;
    }
    Ok(())
}

fn map(polygons: &Polygons, f: impl Fn(DVec2) -> DVec2) -> Polygons {
    polygons
        .iter()
        .map(|rings| {
            rings
                .iter()
                .map(|r| r.iter().map(|&p| f(p)).collect())
                .collect()
        })
        .collect()
}

/// A site's properties: its index.
pub fn site(label: u32) -> Map<String, Value> {
    let mut m = Map::new();
    m.insert("site".into(), json!(label));
    m
}
