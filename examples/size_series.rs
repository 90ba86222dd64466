//! The size series of `papers/performance.md`: solves the built-in atrium at
//! each given triangle target with the command-line tool, one process per
//! size, and prints a Markdown table (triangles, patches, elements, CPU and
//! wall seconds, peak memory) and the exponents of CPU time and memory fitted
//! against the triangle count.
//!
//! ```text
//! cargo build --release
//! cargo run --release --example size_series -- 10000 30000 100000 200000
//! ```
//!
//! The tool is the `radiosity` binary next to this example's directory
//! (`target/release`); outputs go to a temporary directory, removed after.
//! CPU seconds are the child's user and system time (Linux: read from
//! `/proc/self/stat` after it ends), the comparable figure on a shared
//! machine; wall seconds depend on what else runs.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

/// One solved size.
struct Row {
    target: usize,
    triangles: u64,
    patches: u64,
    elements: u64,
    hemicubes: u64,
    cpu: f64,
    wall: f64,
    peak_mb: f64,
}

/// User plus system CPU seconds of this process's waited-for children.
fn children_cpu() -> Result<f64, String> {
    let stat = std::fs::read_to_string("/proc/self/stat").map_err(|e| e.to_string())?;
    // Fields after the command name (in parentheses, which may hold spaces).
    let rest = stat.rsplit_once(')').ok_or("bad /proc/self/stat")?.1;
    let fields: Vec<&str> = rest.split_whitespace().collect();
    // cutime and cstime are fields 16 and 17 of the line (counted from 1),
    // 13 and 14 here: the line's field 3, the state, is our 0.
    let ticks = |i: usize| -> Result<f64, String> {
        fields
            .get(i)
            .and_then(|f| f.parse::<f64>().ok())
            .ok_or_else(|| format!("no field {i} in /proc/self/stat"))
    };
    // The kernel's clock tick is 100 Hz on every common Linux build.
    Ok((ticks(13)? + ticks(14)?) / 100.0)
}

/// The number at `path` (dot-separated keys) in the stats `json`.
fn number(json: &serde_json::Value, path: &str) -> Result<f64, String> {
    path.split('.')
        .try_fold(json, |v, key| v.get(key))
        .and_then(serde_json::Value::as_f64)
        .ok_or_else(|| format!("no number at {path} in the stats"))
}

fn solve(tool: &Path, target: usize, out: &Path) -> Result<Row, String> {
    let name = format!("atrium_{target}");
    let before = children_cpu()?;
    let start = Instant::now();
    let status = Command::new(tool)
        .args(["solve", &name, "--quiet", "--out"])
        .arg(out)
        .status()
        .map_err(|e| format!("{}: {e}", tool.display()))?;
    let wall = start.elapsed().as_secs_f64();
    let cpu = children_cpu()? - before;
    if !status.success() {
        return Err(format!("{name}: the solve failed ({status})"));
    }
    let stats_path = out.join(format!("{name}.json"));
    let text = std::fs::read_to_string(&stats_path)
        .map_err(|e| format!("{}: {e}", stats_path.display()))?;
    let json: serde_json::Value =
        serde_json::from_str(&text).map_err(|e| format!("{}: {e}", stats_path.display()))?;
    let triangles = radiosity::scenes::atrium::atrium(target)
        .map(|s| radiosity::scenes::atrium::triangle_count(&s) as u64)
        .map_err(|e| e.to_string())?;
    Ok(Row {
        target,
        triangles,
        patches: number(&json, "counts.patches")? as u64,
        elements: number(&json, "counts.elements")? as u64,
        hemicubes: number(&json, "hemicube.hemicubes")? as u64,
        cpu,
        wall,
        peak_mb: number(&json, "memory.peak_resident_bytes")? / 1e6,
    })
}

/// The least-squares slope of log y against log x.
fn exponent(points: &[(f64, f64)]) -> f64 {
    let n = points.len() as f64;
    let (mx, my) = points.iter().fold((0.0, 0.0), |(a, b), (x, y)| {
        (a + x.ln() / n, b + y.ln() / n)
    });
    let (mut sxy, mut sxx) = (0.0, 0.0);
    for (x, y) in points {
        sxy += (x.ln() - mx) * (y.ln() - my);
        sxx += (x.ln() - mx).powi(2);
    }
    sxy / sxx
}

fn main() -> Result<(), String> {
    let targets: Vec<usize> = std::env::args()
        .skip(1)
        .map(|a| a.parse().map_err(|_| format!("not a triangle count: {a}")))
        .collect::<Result<_, _>>()?;
    if targets.is_empty() {
        return Err("usage: size_series TARGET... (triangle counts)".into());
    }
    let exe = std::env::current_exe().map_err(|e| e.to_string())?;
    let tool: PathBuf = exe
        .parent()
        .and_then(Path::parent)
        .map(|dir| dir.join("radiosity"))
        .filter(|p| p.exists())
        .ok_or("build the tool first: cargo build --release")?;
    let out = std::env::temp_dir().join(format!("radiosity-size-series-{}", std::process::id()));
    let mut rows = Vec::new();
    for &target in &targets {
        eprintln!("solving atrium_{target} ...");
        let row = solve(&tool, target, &out);
        let _ = std::fs::remove_dir_all(&out);
        rows.push(row?);
    }
    println!(
        "| target | triangles | patches | elements | hemi-cubes | CPU (s) | wall (s) | peak memory (MB) |"
    );
    println!("| ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |");
    for r in &rows {
        println!(
            "| {} | {} | {} | {} | {} | {:.0} | {:.0} | {:.0} |",
            r.target, r.triangles, r.patches, r.elements, r.hemicubes, r.cpu, r.wall, r.peak_mb
        );
    }
    if rows.len() >= 2 {
        let fit = |f: fn(&Row) -> f64| {
            exponent(
                &rows
                    .iter()
                    .map(|r| (r.triangles as f64, f(r)))
                    .collect::<Vec<_>>(),
            )
        };
        println!();
        println!(
            "Fitted over triangles: CPU time ~ triangles^{:.2}, peak memory ~ triangles^{:.2}, hemi-cubes ~ triangles^{:.2}",
            fit(|r| r.cpu),
            fit(|r| r.peak_mb),
            fit(|r| r.hemicubes as f64)
        );
    }
    Ok(())
}
