//! The sample types a GeoTIFF holds, and the value each uses for "none".

/// A sample type a GeoTIFF holds.
pub trait Sample: Copy + Send + Sync {
    /// TIFF's SampleFormat: 1 unsigned, 2 signed, 3 floating point.
    const FORMAT: u16;
    /// Bytes per sample.
    const BYTES: usize;
    /// The value pixgeo writes where a pixel has none (GDAL_NODATA): "no
    /// site" labels, pixels no feature reaches.
    const NODATA: Option<&'static str>;
    fn put(self, out: &mut Vec<u8>);
}

impl Sample for u8 {
    const FORMAT: u16 = 1;
    const BYTES: usize = 1;
    const NODATA: Option<&'static str> = None;
    fn put(self, out: &mut Vec<u8>) {
        out.push(self);
    }
}

/// A bool raster (a medial axis, a mask) is a byte raster of 0 and 1.
impl Sample for bool {
    const FORMAT: u16 = 1;
    const BYTES: usize = 1;
    const NODATA: Option<&'static str> = None;
    fn put(self, out: &mut Vec<u8>) {
        out.push(u8::from(self));
    }
}

impl Sample for i32 {
    const FORMAT: u16 = 2;
    const BYTES: usize = 4;
    const NODATA: Option<&'static str> = Some("-1");
    fn put(self, out: &mut Vec<u8>) {
        out.extend_from_slice(&self.to_le_bytes());
    }
}

impl Sample for u32 {
    const FORMAT: u16 = 1;
    const BYTES: usize = 4;
    const NODATA: Option<&'static str> = Some("4294967295");
    fn put(self, out: &mut Vec<u8>) {
        out.extend_from_slice(&self.to_le_bytes());
    }
}

impl Sample for f32 {
    const FORMAT: u16 = 3;
    const BYTES: usize = 4;
    const NODATA: Option<&'static str> = Some("inf");
    fn put(self, out: &mut Vec<u8>) {
        out.extend_from_slice(&self.to_le_bytes());
    }
}

impl Sample for f64 {
    const FORMAT: u16 = 3;
    const BYTES: usize = 8;
    const NODATA: Option<&'static str> = Some("inf");
    fn put(self, out: &mut Vec<u8>) {
        out.extend_from_slice(&self.to_le_bytes());
    }
}
