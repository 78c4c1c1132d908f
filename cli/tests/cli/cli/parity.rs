//! The command line answers as the core does, bit for bit, with and without
//! a device: the nearest and furthest sites and the Delaunay triangles of
//! every input of the parity generator, read from `.npy` as written.

use pixgeo::{
    algorithms::{
        delaunay::{delaunay, DelaunayOptions},
        higher_order::furthest,
        voronoi::{voronoi, VoronoiOptions},
    },
    geometry::{metric::Metric, Frame},
    Backend,
};
use pixgeo_io::npy;
use pixgeo_reference::hostile::hostile;

use super::{answer, pixgeo, temp, write_npy};

fn bits(d: &[f32]) -> Vec<u32> {
    d.iter().map(|v| v.to_bits()).collect()
}

#[test]
fn the_command_line_answers_as_the_core_on_every_route() {
    let (sites, labels, distances) = (
        temp("parity.npy"),
        temp("parity-l.npy"),
        temp("parity-d.npy"),
    );
    for case in hostile(28, 20) {
        let xy: Vec<f64> = case.sites.iter().flat_map(|p| [p.x, p.y]).collect();
        write_npy(&sites, &[case.sites.len() as u64, 2], &xy);
        let bbox = case.bbox();
        let frame = Frame::with_bbox(28, Some(20), bbox).unwrap();
        let nearest = voronoi(&Backend::Cpu, &case.sites, &VoronoiOptions::exact(frame)).unwrap();
        let far = furthest(&Backend::Cpu, &case.sites, &frame, Metric::L2).unwrap();
        let answers = [
            (None, (nearest.labels, bits(&nearest.distances))),
            (Some("--furthest"), (far.labels, bits(&far.distances))),
        ];
        let box_arg = bbox.map(|v| v.to_string()).join(",");
        for device in ["cpu", "lavapipe"] {
            let name = format!("{device} {}", case.name);
            for (extra, (want_labels, want_bits)) in &answers {
                let mut args = vec![
                    "voronoi",
                    "--sites",
                    sites.to_str().unwrap(),
                    "--bbox",
                    &box_arg,
                    "--size",
                    "28x20",
                    "--y-axis",
                    "down",
                    "--device",
                    device,
                    "--labels",
                    labels.to_str().unwrap(),
                    "--distance",
                    distances.to_str().unwrap(),
                ];
                args.extend(*extra);
                let (ok, _, err) = pixgeo(&args);
                assert!(ok, "{name} {extra:?}: {err}");
                let got = npy::read::<u32>(&labels).unwrap().1;
                assert!(got == *want_labels, "{name} {extra:?}: labels");
                let got = npy::read::<f32>(&distances).unwrap().1;
                assert!(bits(&got) == *want_bits, "{name} {extra:?}: distances");
            }
            let (ok, out, err) = pixgeo(&[
                "delaunay",
                "--sites",
                sites.to_str().unwrap(),
                "--device",
                device,
                "--json",
            ]);
            match delaunay(&Backend::Cpu, &case.sites, &DelaunayOptions::default()) {
                Ok(d) => {
                    assert!(ok, "{name}: {err}");
                    let result = answer(&out, "delaunay");
                    let got: Vec<[u32; 3]> =
                        serde_json::from_value(result["triangles"].clone()).unwrap();
                    assert!(got == d.triangles, "{name}: triangles");
                }
                Err(e) => assert!(!ok && err.contains(&e.to_string()), "{name}: {err}"),
            }
        }
    }
}
