use pixgeo::{algorithms::voronoi::*, geometry::Frame, io::sites::random_sites, Machine};
use std::time::Instant;
fn main() {
    let m = Machine::from_env().unwrap();
    let frame = Frame::pixels(1024, 1024).unwrap();
    let n: usize = std::env::args().nth(1).unwrap().parse().unwrap();
    let exact = std::env::args().nth(2).as_deref() != Some("fan");
    let sites = random_sites(n, 1, &frame);
    let acc = if exact {
        Accuracy::Exact
    } else {
        Accuracy::FAN
    };
    for _ in 0..5 {
        let t = Instant::now();
        let d = voronoi(
            &m,
            &sites,
            &VoronoiOptions {
                frame,
                accuracy: acc,
                speedup: Speedup::Local,
            },
        )
        .unwrap();
        let mut w = vec![0f32; n];
        for (l, dist) in d.labels.iter().zip(&d.distances) {
            let e = &mut w[*l as usize];
            *e = e.max(*dist);
        }
        let wmean: f32 = w.iter().sum::<f32>() / n as f32;
        let wmax = w.iter().cloned().fold(0f32, f32::max);
        println!("true width mean {wmean:.1} max {wmax:.1}");
        let s = d.stats;
        println!(
            "total {:.1} bounds {:.1} render {:.1} readback {:.1} rmean {:.1}",
            t.elapsed().as_secs_f64() * 1e3,
            s.bounds_ms,
            s.render_ms,
            s.readback_ms,
            s.radius_mean
        );
    }
}
