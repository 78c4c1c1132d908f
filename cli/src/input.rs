//! The picture and the sites, as every picture-making command takes them.

use std::path::PathBuf;

use anyhow::{bail, Result};
use clap::{Args as ClapArgs, ValueEnum};
use glam::DVec2;
use pixgeo::geometry::{
    cell::Rect,
    metric::Metric,
    site::{Shape, Site},
    Frame,
};
use pixgeo_io::{
    samples::{read_samples, Samples},
    sites::{self, GeoJsonSources},
};

use crate::write::{
    geotiff::{crs_kind, crs_name, parse_crs, CrsKind, GeoReference, WORLD_FILE_EXTENSIONS},
    output::{check_extensions, claim, extension_among},
};

/// What the weights of `--weights` are.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Weights {
    /// Power weights `w`: a site's power at `p` is `|p − s|² − w`.
    Power,
}

/// The sites and the picture they are drawn on.
#[derive(ClapArgs)]
pub struct Input {
    /// Site file, read by its extension: `.csv`/`.txt` (`x,y` per line, or the
    /// columns a header names: `x`, `y` and the weights `m`, `a`), `.json`
    /// (`[[x, y], ...]` or `{"sites": [...]}`; `pixgeo voronoi` also reads
    /// `{"segment": [[x1, y1], [x2, y2]]}`, `{"circle": {"center": [x, y],
    /// "radius": r}}`, `{"arc": {"center": [x, y], "radius": r, "start": a0,
    /// "end": a1}}` and weights `"m"`, `"a"` on any site), `.geojson` (Point,
    /// MultiPoint, LineString, MultiLineString) or `.npy` (n×2 x, y; n×3 adds m;
    /// n×4 adds a). `-` reads CSV from stdin.
    #[arg(long, value_name = "FILE", conflicts_with = "random")]
    sites: Option<PathBuf>,

    /// Use N uniformly random sites over the picture instead of a file.
    #[arg(long, value_name = "N")]
    random: Option<usize>,

    /// Seed of --random.
    #[arg(long, default_value_t = 1)]
    seed: u64,

    /// Picture size in pixels: `N`, the longer side (a square picture, or with
    /// --bbox the other side follows the box's aspect ratio), or `WxH`.
    #[arg(long, value_name = "PIXELS", default_value = "1024", value_parser = parse_size)]
    size: (u32, Option<u32>),

    #[command(flatten)]
    place: Placement,

    /// Where a GeoJSON file's sites come from, once it is read.
    #[arg(skip)]
    sources: std::cell::OnceCell<GeoJsonSources>,
}

/// Where the rasters lie in the user's world: the flags of every command that
/// writes a raster.
#[derive(ClapArgs)]
pub struct Placement {
    /// World rectangle XMIN,YMIN,XMAX,YMAX the rasters and pictures cover.
    #[arg(long, value_name = "XMIN,YMIN,XMAX,YMAX", value_parser = parse_bbox, allow_hyphen_values = true)]
    pub bbox: Option<[f64; 4]>,

    /// Which way y runs in the rasters and pictures: `up` puts the largest y
    /// in row 0 (north-up, as maps and GIS tools show rasters), `down` the
    /// smallest (pixel coordinates). Default: up with --bbox, down without.
    #[arg(long, value_enum)]
    pub y_axis: Option<YAxis>,

    /// The coordinate system of the world coordinates, written into .tif
    /// rasters' GeoKeys: `EPSG:N`, an OGC URN, a WKT or PROJ string that
    /// names or matches an EPSG code, or a .prj file.
    #[arg(long, value_name = "CRS", value_parser = parse_crs)]
    pub crs: Option<u16>,

    /// Write a world file (`.tfw`, `.pgw`, `.pngw` or `.wld`: six lines from
    /// a pixel's centre to the world) that places the rasters and pictures.
    #[arg(long, value_name = "FILE")]
    pub world_file: Option<PathBuf>,

    /// Write .tif rasters cloud-optimised: overviews (nearest samples, each
    /// level half the last, down to one 256-pixel tile) and every directory
    /// before the tiles, as GDAL's COG driver lays them out.
    #[arg(long)]
    pub cog: bool,
}

impl Placement {
    /// Which way y runs: as asked, or up with --bbox and down without.
    pub fn y_axis(&self) -> YAxis {
        self.y_axis.unwrap_or(match self.bbox {
            Some(_) => YAxis::Up,
            None => YAxis::Down,
        })
    }

    /// Where a `width` x `height` raster covering the box lies (pixel
    /// coordinates, one unit a pixel, without --bbox).
    pub fn georeference(&self, width: u32, height: u32) -> GeoReference {
        let [x0, y0, x1, y1] = self.bbox.unwrap_or([0.0, 0.0, width as f64, height as f64]);
        let pixel_height = (y1 - y0) / height as f64;
        let (top, pixel_height) = match self.y_axis() {
            YAxis::Up => (y1, pixel_height),
            YAxis::Down => (y0, -pixel_height),
        };
        GeoReference {
            left: x0,
            top,
            pixel_width: (x1 - x0) / width as f64,
            pixel_height,
            epsg: self.crs,
            cloud_optimized: self.cog,
        }
    }

    /// The placement of a `width` x `height` raster as the JSON answers give it.
    pub fn describe(&self, width: u32, height: u32) -> serde_json::Value {
        serde_json::json!({
            "bbox": self.bbox.unwrap_or([0.0, 0.0, width as f64, height as f64]),
            "y_axis": self.y_axis(),
            "crs": crs_name(self.crs),
        })
    }

    /// Refuses a world file of another name, or one another output names,
    /// before any work.
    pub fn check_world_file(&self) -> Result<()> {
        if let Some(path) = &self.world_file {
            check_extensions(path, &WORLD_FILE_EXTENSIONS, "world files")?;
            claim(path, "--world-file")?;
        }
        Ok(())
    }

    /// Writes the world file of rasters placed by `geo`, if one was asked for.
    pub fn write_world_file(&self, geo: &GeoReference) -> Result<()> {
        if let Some(path) = &self.world_file {
            geo.write_world_file(path)?;
            crate::wrote([Some(path.as_path())]);
        }
        Ok(())
    }
}

/// Which way y runs down a raster's rows.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum YAxis {
    Up,
    Down,
}

/// Where the rasters lie in the user's world. With y up, pixgeo computes in
/// the world mirrored across the x axis (y to -y), whose frame puts the
/// largest y in row 0: distances are the same, and every raster path comes
/// out north-up with no flip of its own.
#[derive(Clone, Copy, Debug)]
pub struct World {
    /// The frame pixgeo computes in.
    pub frame: Frame,
    pub y_axis: YAxis,
    pub epsg: Option<u16>,
    /// The user's --bbox as given (the frame's rows round its height).
    pub bbox: Option<[f64; 4]>,
    /// GeoTIFFs cloud-optimised (--cog).
    pub cloud_optimized: bool,
}

impl World {
    /// The rectangle that vector answers are clipped to, in the computing
    /// world: the user's --bbox exactly as given, else the frame's pixels.
    pub fn clip_rect(&self) -> Rect {
        let f = &self.frame;
        match (self.bbox, self.y_axis) {
            (Some([x0, y0, x1, y1]), YAxis::Down) => Rect {
                lo: DVec2::new(x0, y0),
                hi: DVec2::new(x1, y1),
            },
            (Some([x0, y0, x1, y1]), YAxis::Up) => Rect {
                lo: DVec2::new(x0, 0.0 - y1),
                hi: DVec2::new(x1, 0.0 - y0),
            },
            (None, _) => Rect {
                lo: f.origin,
                hi: f.origin + DVec2::new(f.width as f64, f.height as f64) / f.scale,
            },
        }
    }

    /// Warns, on stderr, that `what` is measured on the longitude-latitude
    /// plane where the coordinate system is geographic.
    pub fn warn_if_geographic(&self, what: &str) {
        warn_if_geographic(self.epsg, what);
    }

    /// Whether the coordinate system is geographic (longitude, latitude).
    pub fn is_geographic(&self) -> bool {
        self.epsg
            .is_some_and(|c| crs_kind(c) == Ok(CrsKind::Geographic))
    }

    /// The user's point of a point of the computing world (and back: the
    /// mirror is its own inverse).
    pub fn to_user(self, p: DVec2) -> DVec2 {
        match self.y_axis {
            // 0 - y, not -y: no -0.0 in the answers.
            YAxis::Up => DVec2::new(p.x, 0.0 - p.y),
            YAxis::Down => p,
        }
    }

    /// The computing world's metric: a polygon mirrored with the world.
    pub fn metric(&self, metric: Metric) -> Metric {
        match self.y_axis {
            YAxis::Up => metric.mirrored_y(),
            YAxis::Down => metric,
        }
    }

    /// Where the rasters lie, for GeoTIFFs and world files.
    pub fn georeference(&self) -> GeoReference {
        self.georeference_from(0, 0)
    }

    /// Where a raster whose first pixel is the frame's pixel (`x`, `y`) lies:
    /// a window of the frame.
    pub fn georeference_from(&self, x: u32, y: u32) -> GeoReference {
        let f = &self.frame;
        let pixel = 1.0 / f.scale;
        let corner = self.to_user(f.origin + DVec2::new(x as f64, y as f64) * pixel);
        GeoReference {
            left: corner.x,
            top: corner.y,
            pixel_width: pixel,
            pixel_height: match self.y_axis {
                YAxis::Up => pixel,
                YAxis::Down => -pixel,
            },
            epsg: self.epsg,
            cloud_optimized: self.cloud_optimized,
        }
    }

    /// The user's rectangle XMIN,YMIN,XMAX,YMAX of the rasters.
    pub fn bbox(&self) -> [f64; 4] {
        let f = &self.frame;
        let far = f.origin + DVec2::new(f.width as f64, f.height as f64) / f.scale;
        let (a, b) = (self.to_user(f.origin), self.to_user(far));
        [a.x, a.y.min(b.y), b.x, a.y.max(b.y)]
    }
}

impl Input {
    /// Where the rasters lie and the (unweighted point) sites, in the
    /// computing world.
    pub fn world_and_sites(&self) -> Result<(World, Vec<DVec2>)> {
        let (world, general) = self.world_and_general_sites()?;
        let points = general
            .iter()
            .enumerate()
            .map(|(i, s)| match s.shape {
                Shape::Point(p) if s.is_plain_point() => Ok(p),
                _ => bail!("site {i}: this command takes unweighted points"),
            })
            .collect::<Result<_>>()?;
        Ok((world, points))
    }

    /// Where the rasters lie and the sites of every shape and weight, in the
    /// computing world.
    pub fn world_and_general_sites(&self) -> Result<(World, Vec<Site>)> {
        let frame = self.frame()?;
        let sites = match (&self.sites, self.random) {
            (Some(path), None) if extension_among(path, &["geojson"]).is_some() => {
                let (sites, sources) = sites::read_geojson_sources(path)?;
                // --crs names the system of a file whose crs pixgeo cannot
                // read; it may not contradict one it can.
                match (sources.crs.as_deref().map(geojson_crs), self.place.crs) {
                    (Some(Ok(code)), Some(asked)) if code != asked => bail!(
                        "{} is in EPSG:{code} (its crs member), not the EPSG:{asked} of --crs",
                        path.display()
                    ),
                    (Some(Err(e)), None) => bail!("{}: {e}", path.display()),
                    _ => {}
                }
                let _ = self.sources.set(sources);
                sites
            }
            (Some(path), None) => sites::read_general_sites(path)?,
            (None, Some(n)) if n > 0 => {
                pixgeo::memory::reserve_sites(n)?;
                frame
                    .random_points(n, self.seed)?
                    .into_iter()
                    .map(Site::point)
                    .collect()
            }
            (None, Some(_)) => bail!("--random needs at least one site"),
            _ => bail!("give the sites: --sites FILE or --random N"),
        };
        let y_axis = self.place.y_axis();
        let world = self.placed(frame);
        let sites = sites.into_iter().map(|s| match y_axis {
            YAxis::Up => s.mirrored_y(),
            YAxis::Down => s,
        });
        Ok((world, sites.collect()))
    }

    /// The picture --size and --bbox give, in the computing world (y down).
    fn frame(&self) -> Result<Frame> {
        let mut frame = self.unplaced_frame()?;
        if let (Some(b), YAxis::Up) = (self.place.bbox, self.place.y_axis()) {
            // Random sites fall inside the picture [`Self::placed`] keeps.
            frame.origin.y = b[3] - frame.height as f64 / frame.scale;
        }
        Ok(frame)
    }

    /// [`Self::frame`] with the box's bottom edge kept.
    fn unplaced_frame(&self) -> Result<Frame> {
        let (width, height) = self.size;
        Ok(match (self.place.bbox, height) {
            // A tall box: N is its height, the scale N pixels to its height,
            // and the width the whole pixels nearest its width (as a wide
            // box's height is).
            (Some(b), None) if b[3] - b[1] > b[2] - b[0] && b[2] > b[0] => {
                let scale = width as f64 / (b[3] - b[1]);
                let across = ((b[2] - b[0]) * scale).round().max(1.0) as u32;
                let checked = Frame::with_bbox(across, None, b)?;
                Frame {
                    width: across,
                    height: width,
                    scale,
                    ..checked
                }
            }
            (Some(b), _) => Frame::with_bbox(width, height, b)?,
            (None, _) => Frame::pixels(width, height.unwrap_or(width))?,
        })
    }

    /// The world whose computing frame is `frame`, with y running as
    /// --y-axis asks.
    fn placed(&self, frame: Frame) -> World {
        match self.place.y_axis() {
            YAxis::Down => self.world_of(frame),
            // North-up, the box's top edge is row 0's, as Python places it
            // (the first pixel's corner is the box's, down or up).
            YAxis::Up => {
                let top = match self.place.bbox {
                    Some(b) => b[3],
                    None => frame.origin.y + frame.height as f64 / frame.scale,
                };
                let origin = DVec2::new(frame.origin.x, 0.0 - top);
                self.world_of(Frame { origin, ..frame })
            }
        }
    }

    /// Where the rasters lie and the samples of --sites (their values from
    /// `column`), in the computing world.
    pub fn world_and_samples(&self, column: &str) -> Result<(World, Samples)> {
        let path = match (&self.sites, self.random) {
            (Some(path), None) => path,
            _ => bail!("give the samples and their values: --sites FILE"),
        };
        let mut samples = read_samples(path, column)?;
        if self.place.y_axis() == YAxis::Up {
            samples.points.iter_mut().for_each(|p| p.y = -p.y);
        }
        Ok((self.placed(self.frame()?), samples))
    }

    /// `--random N --seed S`, when the sites are drawn rather than read.
    pub fn random(&self) -> Option<(usize, u64)> {
        self.random.map(|n| (n, self.seed))
    }

    /// Whether y runs up (north-up rasters, y negated in the computing world).
    pub fn y_up(&self) -> bool {
        self.place.y_axis() == YAxis::Up
    }

    /// Whether the picture is the user's (--bbox), not fitted by the command.
    pub fn has_bbox(&self) -> bool {
        self.place.bbox.is_some()
    }

    /// The longer side of a picture the command fits to the sites itself.
    pub fn fitted_side(&self) -> Result<u32> {
        match self.size {
            (side, None) if side >= 2 => Ok(side),
            _ => bail!(
                "without --bbox this command fits its picture to the sites: give the \
                 longer side's pixels, one number of at least 2"
            ),
        }
    }

    /// The world whose computing frame is `frame`: in --crs's coordinate
    /// system, or a GeoJSON site file's.
    pub fn world_of(&self, frame: Frame) -> World {
        let from_file = self
            .sources()
            .and_then(|s| s.crs.as_deref())
            .and_then(|n| geojson_crs(n).ok());
        World {
            frame,
            y_axis: self.place.y_axis(),
            epsg: self.place.crs.or(from_file),
            bbox: self.place.bbox,
            cloud_optimized: self.place.cog,
        }
    }

    /// Where the sites of a GeoJSON site file come from, once it is read.
    pub fn sources(&self) -> Option<&GeoJsonSources> {
        self.sources.get()
    }

    /// [`Placement::check_world_file`].
    pub fn check_world_file(&self) -> Result<()> {
        self.place.check_world_file()
    }

    /// Writes the world file, if asked for, once the rasters are written:
    /// rasters whose first pixel is the frame's pixel `corner`.
    pub fn write_world_file(&self, world: &World, corner: (u32, u32)) -> Result<()> {
        self.place
            .write_world_file(&world.georeference_from(corner.0, corner.1))
    }
}

/// Point sites, for the commands that take points alone and size their own
/// picture: a file or random points.
#[derive(ClapArgs)]
pub struct Points {
    /// Sites, read by extension: `.csv`/`.txt` (`x,y` per line, optional header
    /// `x,y`), `.json` (`[[x, y], ...]`; `enclose` and `empty` also take
    /// segments, circles and arcs, as `voronoi` does), `.geojson` (Point,
    /// MultiPoint, LineString, MultiLineString) or `.npy` (n×2); `-` reads CSV
    /// from stdin.
    #[arg(long, value_name = "FILE", required_unless_present = "random")]
    sites: Option<PathBuf>,
    /// Use N uniformly random points in the square [0, 1000]² instead.
    #[arg(long, value_name = "N", conflicts_with = "sites")]
    random: Option<usize>,
    /// Seed of --random.
    #[arg(long, default_value_t = 1)]
    seed: u64,
}

impl Points {
    /// Unweighted points; other sites are an error.
    pub fn read(&self) -> Result<Vec<DVec2>> {
        match &self.sites {
            Some(path) => Ok(sites::read_sites(path)?),
            None => self.random(),
        }
    }

    /// Sites of every shape and weight.
    pub fn read_general(&self) -> Result<Vec<Site>> {
        match &self.sites {
            Some(path) => Ok(sites::read_general_sites(path)?),
            None => Ok(self.random()?.into_iter().map(Site::point).collect()),
        }
    }

    /// Points and the numbers of `column` (a CSV column, JSON key or GeoJSON
    /// property, an .npy's third column) from --sites.
    pub fn samples(&self, column: &str) -> Result<Samples> {
        match &self.sites {
            Some(path) => Ok(read_samples(path, column)?),
            None => bail!("give the points and their {column}: --sites FILE"),
        }
    }

    fn random(&self) -> Result<Vec<DVec2>> {
        match self.random {
            Some(n) if n > 0 => {
                pixgeo::memory::reserve_sites(n)?;
                Ok(Frame::pixels(1000, 1000)?.random_points(n, self.seed)?)
            }
            Some(_) => bail!("--random needs at least one point"),
            None => bail!("give the points: --sites FILE or --random N"),
        }
    }
}

/// An option read by its name, as the library and Python read it (`exact`,
/// `fan:12`, `quadtree`, `pixels`, ...).
pub fn named<T: std::str::FromStr<Err = pixgeo::Error>>(s: &str) -> Result<T, String> {
    s.parse().map_err(|e: pixgeo::Error| match e {
        pixgeo::Error::InvalidInput(why) => why.to_string(),
        other => other.to_string(),
    })
}

/// `--size` of the commands that fit their picture to the sites: the longer
/// side's pixels, 2 to 16384. `WxH` is refused by name, since the sites' box
/// sets the other side.
pub fn parse_side(s: &str) -> Result<u32, String> {
    if s.contains(['x', 'X']) {
        return Err(
            "this command fits its picture to the sites: give the longer side's pixels, one number"
                .into(),
        );
    }
    let side: u32 = s
        .trim()
        .parse()
        .map_err(|_| format!("`{s}` is not a pixel count"))?;
    if !(2..=16384).contains(&side) {
        return Err(format!("the picture side is 2 to 16384 pixels, not {side}"));
    }
    Ok(side)
}

fn parse_size(s: &str) -> Result<(u32, Option<u32>), String> {
    let parse = |t: &str| -> Result<u32, String> {
        let v: u32 = t
            .trim()
            .parse()
            .map_err(|_| format!("`{t}` is not a pixel count"))?;
        if v == 0 {
            return Err("picture sides must be at least 1 pixel".into());
        }
        Ok(v)
    };
    match s.split_once(['x', 'X']) {
        Some((w, h)) => Ok((parse(w)?, Some(parse(h)?))),
        None => Ok((parse(s)?, None)),
    }
}

fn parse_bbox(s: &str) -> Result<[f64; 4], String> {
    let v: Vec<f64> = s
        .split(',')
        .map(|t| {
            t.trim()
                .parse::<f64>()
                .map_err(|_| format!("`{t}` is not a number"))
        })
        .collect::<Result<_, _>>()?;
    let arr: [f64; 4] = v
        .try_into()
        .map_err(|_| "need four numbers XMIN,YMIN,XMAX,YMAX".to_string())?;
    if !arr.iter().all(|x| x.is_finite()) || arr[2] <= arr[0] || arr[3] <= arr[1] {
        return Err("need finite XMIN < XMAX and YMIN < YMAX".into());
    }
    Ok(arr)
}

/// Refuses arrays that cannot fit on their disk, before any work: a 100000²
/// label raster is 40 GB.
pub fn check_room(arrays: &[&std::path::Path], width: u32, height: u32) -> Result<()> {
    let each = width as u64 * height as u64 * 4 + 128;
    let needed = each * arrays.len() as u64;
    for path in arrays {
        let dir = match path.parent() {
            Some(d) if !d.as_os_str().is_empty() => d,
            _ => std::path::Path::new("."),
        };
        // A folder that cannot be asked is left to the write's own error.
        if let Ok(free) = fs4::available_space(dir) {
            if free < needed {
                bail!(
                    "{}: {width}x{height} arrays need {} and {} has {} free",
                    path.display(),
                    pixgeo::memory::amount(needed),
                    dir.display(),
                    pixgeo::memory::amount(free)
                );
            }
        }
    }
    Ok(())
}

/// Warns, on stderr, that `what` is measured on the longitude-latitude plane
/// where `epsg` names a geographic coordinate system.
pub fn warn_if_geographic(epsg: Option<u16>, what: &str) {
    if let Some(code) = epsg.filter(|&c| crs_kind(c) == Ok(CrsKind::Geographic)) {
        note!("warning: EPSG:{code} is geographic: {what} on the longitude-latitude plane, not on the Earth");
    }
}

/// The EPSG code a GeoJSON `crs` member names: `urn:ogc:def:crs:EPSG::N`
/// (as GDAL writes it), `EPSG:N`, or OGC's CRS84 (WGS 84 in longitude and
/// latitude, EPSG:4326 with GeoJSON's axis order).
pub fn geojson_crs(name: &str) -> Result<u16, String> {
    let upper = name.to_ascii_uppercase();
    if upper.ends_with(":CRS84") {
        return Ok(4326);
    }
    let code = upper
        .contains("EPSG")
        .then(|| upper.rsplit(':').next())
        .flatten()
        .and_then(|c| c.parse::<u16>().ok())
        .ok_or_else(|| format!("its crs {name:?} names no EPSG code: give --crs EPSG:N"))?;
    parse_crs(&format!("EPSG:{code}"))
}
