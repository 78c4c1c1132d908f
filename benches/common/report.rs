//! A benchmark's report: its markdown (the tables `docs/benchmarks.md` and the
//! guide quote), each table again as CSV for other tools, and the machine it
//! ran on.

use std::{path::Path, process::Command};

/// Writes `DIR/NAME.md`, `DIR/NAME.csv` (`NAME-2.csv`, ... for further
/// tables) and `DIR/machine.txt`.
pub fn write(dir: &Path, name: &str, markdown: &str, device: &str) -> std::io::Result<()> {
    std::fs::create_dir_all(dir)?;
    std::fs::write(dir.join(format!("{name}.md")), markdown)?;
    for (k, table) in tables(markdown).iter().enumerate() {
        let file = match k {
            0 => format!("{name}.csv"),
            k => format!("{name}-{}.csv", k + 1),
        };
        std::fs::write(dir.join(file), table)?;
    }
    std::fs::write(dir.join("machine.txt"), machine(device))?;
    eprintln!("wrote {}", dir.join(format!("{name}.md")).display());
    Ok(())
}

/// Each markdown table of `text` as CSV: cells quoted where they hold a comma
/// or a quote, the separator row left out.
fn tables(text: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut current = String::new();
    for line in text.lines().map(str::trim) {
        if !line.starts_with('|') {
            if !current.is_empty() {
                out.push(std::mem::take(&mut current));
            }
            continue;
        }
        let cells: Vec<&str> = line.trim_matches('|').split('|').map(str::trim).collect();
        if cells
            .iter()
            .all(|c| !c.is_empty() && c.chars().all(|x| matches!(x, '-' | ':')))
        {
            continue;
        }
        let quoted: Vec<String> = cells
            .iter()
            .map(|c| {
                if c.contains([',', '"']) {
                    format!("\"{}\"", c.replace('"', "\"\""))
                } else {
                    c.to_string()
                }
            })
            .collect();
        current.push_str(&quoted.join(","));
        current.push('\n');
    }
    if !current.is_empty() {
        out.push(current);
    }
    out
}

/// The CPU, its cores, the memory, the Vulkan device, the compiler and the date.
fn machine(device: &str) -> String {
    let cpuinfo = std::fs::read_to_string("/proc/cpuinfo").unwrap_or_default();
    let cpu = cpuinfo
        .lines()
        .find_map(|l| {
            l.strip_prefix("model name")
                .map(|v| v.trim_start_matches([' ', '\t', ':']))
        })
        .unwrap_or("unknown");
    let memory = std::fs::read_to_string("/proc/meminfo")
        .unwrap_or_default()
        .lines()
        .next()
        .unwrap_or_default()
        .to_string();
    let run = |program: &str, args: &[&str]| {
        Command::new(program)
            .args(args)
            .output()
            .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string())
            .unwrap_or_default()
    };
    format!(
        "cpu: {cpu}\ncores: {}\n{memory}\ndevice: {device}\nrustc: {}\ndate: {}\n",
        std::thread::available_parallelism().map_or(0, |n| n.get()),
        run("rustc", &["--version"]),
        run("date", &["-u", "+%Y-%m-%dT%H:%M:%SZ"]),
    )
}
