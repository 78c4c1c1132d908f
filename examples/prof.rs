use std::time::Instant;
use pixgeo::{algorithms::homothet::*, geometry::Frame, io::sites::random_sites, Machine};
fn main() {
    let m = Machine::from_env().unwrap();
    let frame = Frame::pixels(1000, 1000).unwrap();
    let s = random_sites(100000, 100000, &frame);
    let mut v = Vec::new();
    for _ in 0..7 {
        let t = Instant::now();
        let a = largest_empty(&m, &s, Unit::Circle, &Region::default(), 1024).unwrap();
        v.push(t.elapsed().as_secs_f64()*1e3);
        assert!((a.exact.scale - 6.5890478160464205).abs() < 1e-9);
    }
    v.sort_by(f64::total_cmp);
    eprintln!("empty median {:.1} min {:.1}", v[3], v[0]);
}
