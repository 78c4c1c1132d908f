//! `pixgeo transform`: distance and feature transforms of a raster.

use std::path::{Path, PathBuf};

use anyhow::{bail, Result};
use clap::Args as ClapArgs;
use pixgeo::{
    algorithms::transform::{
        components, distance_transform, medial_axis, Pruning, Transform, TransformOptions,
        NO_COMPONENT,
    },
    geometry::metric::Metric,
};
use serde_json::json;

use crate::{
    envelope,
    input::{Placement, YAxis},
    progress::Progress,
    write::{
        geotiff::GeoReference,
        npy,
        output::{check_distinct, check_extension, extension_among},
        picture::{site_color, PngStream},
        raster,
    },
};

/// Distance and feature transforms of a raster: every pixel's distance to the
/// nearest feature pixel (the mask's non-zero pixels), and that pixel's (row,
/// column).
///
/// Exact under every metric. L2, L1, L∞ and L_p for p >= 1 separate into a
/// pass down the columns and one along the rows (Meijster et al. 2000) and
/// take any --sampling; polygon metrics and L_p for p < 1 grow the feature
/// pixels' Voronoi diagram (thesis §3.12) with equal sampling. Distances are
/// sqrt((SY dy)² + (SX dx)²) for L2, as SciPy's distance_transform_edt
/// computes them; infinite where the mask has no feature.
///
/// Examples:
///
///   pixgeo transform --mask examples/data/obstacles.png --distance d.npy --indices i.npy
///   pixgeo transform --mask mask.npy --metric l1 --sampling 2,1 --distance d.npy
///   pixgeo transform --mask roads.npy --bbox 500000,4000000,501000,4000800 --crs EPSG:32633 --distance d.tif
///   pixgeo transform --mask landcover.tif --values 11,12 --distance-units geo --max-distance 500 --distance d.tif
///
/// Rasters named `.tif` are GeoTIFFs placed where a GeoTIFF mask lies, or by
/// --bbox (the rectangle the mask covers; pixel coordinates without it),
/// --y-axis and --crs. Distances are in pixels, in sampled units with
/// --sampling, or in the georeferencing's units with --distance-units geo, as
/// gdal_proximity's -distunits.
#[derive(ClapArgs)]
#[command(verbatim_doc_comment)]
pub struct Args {
    /// The raster: a 2-D .npy array (any numeric or bool dtype), a PNG, or a
    /// GeoTIFF (its first band; the outputs lie where it lies); its non-zero
    /// pixels are the features. Row 0 is the array's first row, the picture's
    /// top row.
    #[arg(long, value_name = "FILE")]
    mask: PathBuf,
    /// The pixel values that are features, `V1,V2,...` (as gdal_proximity's
    /// -values), for a .npy or .tif mask; default: every value but 0.
    #[arg(
        long,
        value_name = "V1,V2,...",
        value_delimiter = ',',
        allow_hyphen_values = true
    )]
    values: Option<Vec<f64>>,
    /// Units of the distances: `pixel` (or --sampling's) or `geo`, the
    /// georeferencing's (a GeoTIFF mask's or --bbox's pixel size), as
    /// gdal_proximity's -distunits.
    #[arg(long, value_enum, default_value = "pixel")]
    distance_units: DistanceUnits,
    /// Pixels farther than this from every feature (in the distances' units)
    /// have none: distance inf, indices -1, component 4294967295, as
    /// gdal_proximity's -maxdist.
    #[arg(long, value_name = "DISTANCE", allow_hyphen_values = true)]
    max_distance: Option<f64>,
    /// Write the distances: float64, (rows, columns).
    #[arg(long, value_name = "FILE.npy|FILE.tif")]
    distance: Option<PathBuf>,
    /// Write each pixel's nearest feature pixel: int32, its row then its
    /// column, -1 where the mask has no feature; `.npy` (2, rows, columns)
    /// as SciPy lays them out, `.tif` two bands.
    #[arg(long, value_name = "FILE.npy|FILE.tif")]
    indices: Option<PathBuf>,
    /// Write the connected feature component (8-connected, numbered 0, 1, ...
    /// by its first pixel, row by row) each pixel is nearest to: uint32, (rows,
    /// columns), 4294967295 where the mask has no feature. The Voronoi diagram
    /// of the obstacles.
    #[arg(long, value_name = "FILE.npy|FILE.tif")]
    components: Option<PathBuf>,
    /// Write the medial axis of the free space (the pixels that are not
    /// features): bool, (rows, columns). A free pixel is on it when it and a
    /// neighbour have different nearest features, more than --prune apart and
    /// seen under more than --prune-angle, and it is the one of the two nearer
    /// their bisector (Hesselink and Roerdink's integer medial axis); those
    /// pixels are joined by a thinning that keeps each free region one piece
    /// with a loop around each hole (`.tif`: 0 and 1 bytes).
    #[arg(long, value_name = "FILE.npy|FILE.tif")]
    medial_axis: Option<PathBuf>,
    /// The least distance between two features, in sampled units, that makes
    /// an axis between them; smaller values keep the spurs that a boundary's
    /// pixel steps grow. A region whose features are all closer keeps the
    /// axis between its farthest-apart ones.
    #[arg(long, value_name = "LENGTH", default_value_t = Pruning::default().length, requires = "medial_axis")]
    prune: f64,
    /// The least angle, in degrees, under which two features seen from the
    /// pixels between them make an axis: a square corner's bisector is seen
    /// under 90°, a digital curve's notches under a few degrees.
    #[arg(long, value_name = "DEGREES", default_value_t = Pruning::default().angle, requires = "medial_axis")]
    prune_angle: f64,
    /// Draw a PNG: each pixel in the colour of the feature component it is
    /// nearest to, darker with the distance, and bands every tenth of the
    /// largest distance; the features black, and the medial axis white when
    /// --medial-axis is given.
    #[arg(short = 'o', long = "output", value_name = "PNG")]
    output: Option<PathBuf>,
    /// Distance function: `l2`, `l1`, `linf`, `lp:P` or `polygon:FILE` (see
    /// `pixgeo voronoi --help`).
    #[arg(long, default_value = "l2", value_parser = pixgeo_io::sites::parse_metric)]
    metric: Metric,
    /// Spacing of rows and of columns, `SY,SX` (or one for both), as SciPy's
    /// `sampling`.
    #[arg(long, value_name = "SY,SX", value_parser = parse_sampling)]
    sampling: Option<[f64; 2]>,
    #[command(flatten)]
    place: Placement,
    /// Print the answer as JSON.
    #[arg(long)]
    json: bool,
}

/// Units of `transform`'s distances.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
enum DistanceUnits {
    Pixel,
    Geo,
}

fn parse_sampling(text: &str) -> Result<[f64; 2], String> {
    let values: Vec<f64> = text
        .split(',')
        .map(|v| {
            v.trim()
                .parse::<f64>()
                .map_err(|_| format!("`{v}` is not a number"))
        })
        .collect::<Result<_, _>>()?;
    let sampling = match values[..] {
        [s] => [s, s],
        [sy, sx] => [sy, sx],
        _ => return Err("give SY,SX or one spacing for both".into()),
    };
    if sampling.iter().any(|s| !(s.is_finite() && *s > 0.0)) {
        return Err("spacings are finite numbers above 0".into());
    }
    Ok(sampling)
}

pub fn run(args: Args) -> Result<()> {
    let rasters = [
        ("--distance", &args.distance),
        ("--indices", &args.indices),
        ("--components", &args.components),
        ("--medial-axis", &args.medial_axis),
    ];
    let picture = [("-o", &args.output)];
    let outputs = rasters.iter().chain(&picture);
    if outputs.clone().all(|(_, path)| path.is_none()) && !args.json {
        bail!(
            "nothing to write: give --distance, --indices, --components or \
             --medial-axis (FILE.npy or FILE.tif), -o PNG or --json"
        );
    }
    for (flag, path) in rasters {
        if let Some(path) = path {
            raster::check_name(path, flag)?;
        }
    }
    if let Some(path) = &args.output {
        check_extension(path, "png", "pictures")?;
    }
    check_distinct(
        outputs
            .clone()
            .map(|(flag, path)| (*flag, path.as_deref()))
            .chain([("--mask", Some(args.mask.as_path()))]),
    )?;
    args.place.check_world_file()?;
    if let Some(d) = args.max_distance {
        if d.is_nan() || d < 0.0 {
            bail!("--max-distance {d}: give a distance of 0 or more");
        }
    }
    let source = crate::mask::read(&args.mask, args.values.as_deref())?;
    let mask = source.mask;
    let placed_by_mask = source.placed.is_some();
    let geo = placement(&args, source.placed, mask.width, mask.height)?;
    let geographic = geo.epsg.filter(|&c| {
        crate::write::geotiff::crs_kind(c) == Ok(crate::write::geotiff::CrsKind::Geographic)
    });
    if let (DistanceUnits::Geo, Some(code)) = (args.distance_units, geographic) {
        bail!(
            "--distance-units geo on EPSG:{code}, a geographic system, would give degrees of \
             longitude and latitude, not distances on the Earth, and pixgeo has no great-circle \
             transform: give --distance-units pixel, or a raster in a projected system"
        );
    }
    let sampling = match (args.distance_units, args.sampling) {
        (DistanceUnits::Pixel, sampling) => sampling.unwrap_or([1.0, 1.0]),
        (DistanceUnits::Geo, None) => [geo.pixel_height.abs(), geo.pixel_width],
        (DistanceUnits::Geo, Some(_)) => {
            bail!("--sampling sets the pixels' spacing and --distance-units geo takes it from the georeferencing: give one")
        }
    };
    let started = std::time::Instant::now();
    let progress = Progress::new("transform: rows", args.json);
    let options = TransformOptions::new()
        .metric(args.metric)
        .sampling(sampling)
        .control(progress.control());
    let t = distance_transform(&mask.features, mask.width, mask.height, &options)?;
    drop(progress);
    let transform_ms = started.elapsed().as_secs_f64() * 1e3;
    let mut axis = match &args.medial_axis {
        Some(_) => medial_axis(
            &t,
            &options,
            Pruning {
                length: args.prune,
                angle: args.prune_angle,
            },
        )?,
        None => Vec::new(),
    };
    let mut t = t;
    if let Some(reach) = args.max_distance {
        for p in 0..t.distances.len() {
            if t.distances[p] > reach {
                t.distances[p] = f64::INFINITY;
                t.feature_rows[p] = -1;
                t.feature_columns[p] = -1;
                if let Some(a) = axis.get_mut(p) {
                    *a = false;
                }
            }
        }
    }
    let size = [t.width, t.height, 1];
    if let Some(path) = &args.distance {
        raster::write(path, size, &t.distances, Some(&geo))?;
    }
    if let Some(path) = &args.indices {
        write_indices(path, &t, &geo)?;
    }
    if let Some(path) = &args.medial_axis {
        raster::write(path, size, &axis, Some(&geo))?;
    }
    let (labels, count) = components(&mask.features, mask.width as usize)?;
    let largest = t
        .distances
        .iter()
        .copied()
        .filter(|d| d.is_finite())
        .fold(0.0, f64::max);
    if args.components.is_some() || args.output.is_some() {
        let nearest = t.at_nearest(&labels, NO_COMPONENT);
        if let Some(path) = &args.components {
            raster::write(path, size, &nearest, Some(&geo))?;
        }
        if let Some(path) = &args.output {
            let shade = |d: f64| {
                let f = d / largest.max(f64::MIN_POSITIVE);
                let band = if (f * 10.0).fract() < 0.04 { 0.8 } else { 1.0 };
                (1.0 - 0.6 * f) * band
            };
            let on_axis = |p: usize| axis.get(p).copied().unwrap_or(false);
            let rgb: Vec<u8> = (0..nearest.len())
                .flat_map(|p| match (mask.features[p], nearest[p]) {
                    (true, _) => [0; 3],
                    (false, _) if on_axis(p) => [255; 3],
                    (false, NO_COMPONENT) => [255; 3],
                    (false, c) => site_color(c).map(|v| (v as f64 * shade(t.distances[p])) as u8),
                })
                .collect();
            let mut png = PngStream::create(path, t.width, t.height)?;
            png.write(&rgb)?;
            png.finish()?;
        }
    }
    crate::wrote(outputs.map(|(_, path)| path.as_deref()));
    args.place.write_world_file(&geo)?;
    let features = mask.features.iter().filter(|&&f| f).count();
    if args.json {
        let answer = json!({
            "width": t.width,
            "height": t.height,
            "features": features,
            "components": count,
            "metric": args.metric.to_string(),
            "sampling": sampling,
            "largest_distance": (features > 0).then_some(largest),
            "medial_axis_pixels": args.medial_axis.is_some().then(|| axis.iter().filter(|&&a| a).count()),
            "georeference": match placed_by_mask {
                true => describe(&geo, t.width, t.height),
                false => args.place.describe(t.width, t.height),
            },
            "stats": { "transform_ms": transform_ms },
        });
        envelope::print("transform", "cpu", None, &answer)?;
    } else if features == 0 {
        outln!(
            "{} x {} raster, no feature pixel: every distance is infinite",
            t.width,
            t.height
        );
    } else {
        outln!(
            "{} x {} raster, {features} feature pixels in {count} components: largest {} \
             distance {largest}",
            t.width,
            t.height,
            args.metric
        );
    }
    Ok(())
}

/// Where the rasters lie: where a GeoTIFF mask lies (which --bbox and
/// --y-axis may not contradict; --crs names its system if it names none), or
/// as --bbox, --y-axis and --crs place them.
fn placement(
    args: &Args,
    placed: Option<GeoReference>,
    width: u32,
    height: u32,
) -> Result<GeoReference> {
    let Some(mut geo) = placed else {
        return Ok(args.place.georeference(width, height));
    };
    if args.place.bbox.is_some() || args.place.y_axis.is_some() {
        bail!(
            "{} is placed by its own georeferencing: --bbox and --y-axis place masks that have none",
            args.mask.display()
        );
    }
    match (geo.epsg, args.place.crs) {
        (Some(own), Some(asked)) if own != asked => bail!(
            "{} is in EPSG:{own}, not the EPSG:{asked} of --crs",
            args.mask.display()
        ),
        (None, asked) => geo.epsg = asked,
        _ => {}
    }
    geo.cloud_optimized = args.place.cog;
    Ok(geo)
}

/// The box, the way y runs and the coordinate system of rasters placed by
/// a GeoTIFF mask's `geo`, for the JSON answer.
fn describe(geo: &GeoReference, width: u32, height: u32) -> serde_json::Value {
    let (x0, x1) = (geo.left, geo.left + geo.pixel_width * width as f64);
    let y1 = geo.top - geo.pixel_height * height as f64;
    json!({
        "bbox": [x0, geo.top.min(y1), x1, geo.top.max(y1)],
        "y_axis": if geo.pixel_height > 0.0 { YAxis::Up } else { YAxis::Down },
        "crs": crate::write::geotiff::crs_name(geo.epsg),
    })
}

/// Each pixel's nearest feature pixel, row then column: SciPy's (2, rows,
/// columns) in a `.npy`, two bands of a GeoTIFF.
fn write_indices(path: &Path, t: &Transform, geo: &GeoReference) -> Result<()> {
    if extension_among(path, &["npy"]).is_some() {
        let mut planes = t.feature_rows.clone();
        planes.extend_from_slice(&t.feature_columns);
        return Ok(npy::write(
            path,
            &[2, t.height as u64, t.width as u64],
            &planes,
        )?);
    }
    let pairs: Vec<i32> = t
        .feature_rows
        .iter()
        .zip(&t.feature_columns)
        .flat_map(|(&row, &column)| [row, column])
        .collect();
    Ok(raster::write(
        path,
        [t.width, t.height, 2],
        &pairs,
        Some(geo),
    )?)
}
