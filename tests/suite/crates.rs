//! The core compiles no file format: the readers and writers live in
//! `pixgeo-io`, which a library user need not take.

#[test]
fn the_core_depends_on_no_file_format() {
    let manifest = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/Cargo.toml"))
        .expect("the core's manifest");
    let section = manifest
        .split("\n[dependencies]\n")
        .nth(1)
        .and_then(|rest| rest.split("\n[").next())
        .expect("a [dependencies] section");
    let names: Vec<&str> = section
        .lines()
        .filter_map(|line| line.split(['=', '.', ' ']).next())
        .filter(|name| !name.is_empty() && !name.starts_with('#'))
        .collect();
    assert!(names.contains(&"ash"), "{names:?}");
    for format in ["csv", "npyz", "png", "serde_json", "tiff"] {
        assert!(!names.contains(&format), "the core depends on {format}");
    }
}
