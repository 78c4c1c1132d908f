//! The core's shape: it compiles no file format (the readers and writers live
//! in `pixgeo-io`, which a library user need not take), no two of its modules
//! import each other (a route is its problem's child, not its peer), and
//! rationals are computed with in the exact kernel alone.

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

/// The core's modules by path (`["algorithms", "voronoi"]`), each with the
/// text of its file up to its unit tests.
fn modules() -> Vec<(Vec<String>, String)> {
    fn walk(dir: &std::path::Path, out: &mut Vec<std::path::PathBuf>) {
        for entry in std::fs::read_dir(dir).expect("the core's sources") {
            let path = entry.expect("a source").path();
            if path.is_dir() {
                walk(&path, out);
            } else if path.extension().is_some_and(|e| e == "rs") {
                out.push(path);
            }
        }
    }
    let src = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    walk(&src, &mut files);
    files
        .into_iter()
        .map(|file| {
            let relative = file.strip_prefix(&src).unwrap().with_extension("");
            let mut path: Vec<String> = relative
                .iter()
                .map(|p| p.to_string_lossy().into_owned())
                .collect();
            if matches!(path.last().map(String::as_str), Some("mod" | "lib")) {
                path.pop();
            }
            let text = std::fs::read_to_string(&file).unwrap();
            let text = text.split("#[cfg(test)]").next().unwrap_or("").to_string();
            (path, text)
        })
        .collect()
}

/// The modules `text` (the module `me`) names through `crate::` and `super::`
/// paths, as the longest prefixes that are modules.
fn named(me: &[String], text: &str, known: &[Vec<String>]) -> Vec<Vec<String>> {
    let mut found = Vec::new();
    let words: Vec<&str> = text
        .split(|c: char| !(c.is_alphanumeric() || c == '_' || c == ':'))
        .collect();
    for word in words {
        let mut parts: Vec<&str> = word.split("::").filter(|p| !p.is_empty()).collect();
        let mut target: Vec<String> = match parts.first() {
            Some(&"crate") => Vec::new(),
            Some(&"super") => me.to_vec(),
            _ => continue,
        };
        if parts[0] == "crate" {
            parts.remove(0);
        }
        while parts.first() == Some(&"super") {
            parts.remove(0);
            target.pop();
        }
        target.extend(parts.iter().map(|p| p.to_string()));
        while !target.is_empty() && !known.contains(&target) {
            target.pop();
        }
        if !target.is_empty() {
            found.push(target);
        }
    }
    found
}

#[test]
fn no_two_modules_of_the_core_import_each_other() {
    let modules = modules();
    let known: Vec<Vec<String>> = modules.iter().map(|(p, _)| p.clone()).collect();
    let edges: std::collections::BTreeSet<(Vec<String>, Vec<String>)> = modules
        .iter()
        .flat_map(|(me, text)| named(me, text, &known).into_iter().map(|t| (me.clone(), t)))
        .collect();
    assert!(edges.len() > 100, "{} imports found", edges.len());
    let related = |a: &[String], b: &[String]| a.starts_with(b) || b.starts_with(a);
    let circles: Vec<_> = edges
        .iter()
        .filter(|(a, b)| a < b && !related(a, b) && edges.contains(&(b.clone(), a.clone())))
        .map(|(a, b)| format!("{} <-> {}", a.join("/"), b.join("/")))
        .collect();
    assert!(
        circles.is_empty(),
        "modules importing each other: {circles:?}"
    );
}

/// Every file of the core outside `geometry/exact/` that names a rational or
/// big-integer type or crate, with the name.
fn rationals_outside_the_kernel() -> (Vec<String>, usize) {
    let names = [
        "num_rational",
        "num_bigint",
        "num_traits",
        "num_integer",
        "BigRational",
        "BigInt",
    ];
    let (mut outside, mut inside) = (Vec::new(), 0);
    for (path, _) in modules() {
        let file = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
        let file = path.iter().fold(file, |f, p| f.join(p));
        let text = std::fs::read_to_string(file.with_extension("rs"))
            .or_else(|_| std::fs::read_to_string(file.join("mod.rs")))
            .or_else(|_| std::fs::read_to_string(file.join("lib.rs")))
            .expect("the module's file");
        for name in names.iter().filter(|n| text.contains(*n)) {
            match path.starts_with(&["geometry".to_string(), "exact".to_string()]) {
                true => inside += 1,
                false => outside.push(format!("{} names {name}", path.join("/"))),
            }
        }
    }
    (outside, inside)
}

#[test]
fn rationals_are_computed_with_in_the_exact_kernel_alone() {
    let (outside, inside) = rationals_outside_the_kernel();
    assert!(inside > 10, "the kernel names rationals {inside} times");
    assert!(
        outside.is_empty(),
        "rationals outside geometry::exact: {outside:?}"
    );
}

/// The oracles in `pixgeo-reference` compute apart from what they check: they
/// read pixgeo's types (the frame, the metric, a site) as data, and call
/// none of pixgeo's geometry or algorithms.
#[test]
fn the_oracles_compute_with_nothing_of_the_core() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("reference/src");
    let data = [
        "Frame",
        "metric::Metric",
        "Metric",
        "site::{Shape, Site}",
        "Error",
        "Result",
    ];
    let computations = [
        "metric.distance(",
        "metric.key(",
        ".to_world(",
        ".to_pixel(",
        "euclidean_bounds()",
        "distance_to_shape",
        "ray_crossings",
        "frame.len()",
        ".distance(metric",
        "pixgeo::algorithms",
        "pixgeo::with_",
        "pixgeo::simple",
    ];
    let mut files = 0;
    for entry in std::fs::read_dir(&dir).expect("the oracles' sources") {
        let path = entry.expect("a source").path();
        let text = std::fs::read_to_string(&path).expect("a source file");
        files += 1;
        for call in computations {
            assert!(!text.contains(call), "{} calls {call}", path.display());
        }
        // Every name taken from pixgeo is one of its data types.
        let flat = text.split_whitespace().collect::<Vec<_>>().join(" ");
        for import in flat.split("use pixgeo::").skip(1) {
            let import = import.split(';').next().unwrap_or("");
            let names = import
                .trim_start_matches("geometry::")
                .trim_start_matches('{')
                .trim_end_matches('}');
            let mut rest = names.to_string();
            for name in data {
                rest = rest.replace(name, "");
            }
            assert!(
                rest.chars().all(|c| c == ',' || c == ' '),
                "{} takes {import} from pixgeo",
                path.display()
            );
        }
    }
    assert!(files > 10, "{files} oracle files read");
}
