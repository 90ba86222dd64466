//! Figures of the progressive solver on the Cornell box: agreement with
//! Gauss-Seidel per surface, time to the first preview, the first preview's
//! mean radiosity against the converged mean with and without the ambient
//! term, and the error against the converged solution as a function of time.
//!
//! `cargo run --release --example progressive_figures -- [PATCH_SIZE|default] [DEPTH|adaptive] [SHOOTER_DEPTH] [hybrid|hemicube]`
//! (defaults: the scene's default patch size, uniform depth 1, shooter depth 1,
//! hybrid). A uniform depth keeps the mesh fixed, so that previews and the
//! converged solution compare leaf by leaf; with `adaptive` only the agreement
//! with Gauss-Seidel is printed.

use radiosity::formfactor::FormFactorMethod;
use radiosity::math::Rgb;
use radiosity::pipeline::{solve_with_previews, Preview};
use radiosity::pipeline::{ProgressiveSettings, SolverKind};
use radiosity::refine::RefineSettings;
use radiosity::{scenes, Settings};
use std::time::Instant;

struct Snapshot {
    shots: usize,
    seconds: f64,
    unshot_fraction: f64,
    leaves: Vec<Rgb>,
    reflectance: Vec<Rgb>,
    ambient: Rgb,
}

fn leaf_values(p: &Preview<'_>) -> (Vec<Rgb>, Vec<Rgb>, Vec<f64>) {
    let mut b = Vec::new();
    let mut rho = Vec::new();
    let mut area = Vec::new();
    for k in p.mesh.leaves() {
        let e = &p.mesh[k];
        b.push(p.radiosity.element(k));
        rho.push(p.mesh.surfaces()[e.surface() as usize].reflectance);
        area.push(e.area());
    }
    (b, rho, area)
}

/// Area-weighted RMS of the luminance difference over the area-weighted mean
/// luminance of the reference.
fn relative_rms(values: &[Rgb], reference: &[Rgb], areas: &[f64]) -> f64 {
    let (mut sq, mut mean, mut total) = (0.0, 0.0, 0.0);
    for ((v, r), a) in values.iter().zip(reference).zip(areas) {
        let d = v.luminance() - r.luminance();
        sq += d * d * a;
        mean += r.luminance() * a;
        total += a;
    }
    (sq / total).sqrt() / (mean / total)
}

fn mean_luminance(values: &[Rgb], areas: &[f64]) -> f64 {
    let total: f64 = areas.iter().sum();
    values
        .iter()
        .zip(areas)
        .map(|(v, a)| v.luminance() * a)
        .sum::<f64>()
        / total
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let scene = scenes::cornell_box();
    let patch_size = args
        .get(1)
        .filter(|a| *a != "default")
        .map(|a| a.parse::<f64>().expect("patch size"));
    let depth: Option<u8> = match args.get(2).map(String::as_str) {
        None => Some(1),
        Some("adaptive") => None,
        Some(a) => Some(a.parse().expect("depth")),
    };
    let shooter_depth: u8 = args.get(3).map_or(1, |a| a.parse().expect("shooter depth"));
    let method: FormFactorMethod = args
        .get(4)
        .map_or(FormFactorMethod::Hybrid, |a| a.parse().expect("method"));
    let base = Settings {
        patch_size,
        form_factors: method,
        refine: RefineSettings {
            uniform_depth: depth,
            ..RefineSettings::default()
        },
        ..Settings::default()
    };

    let t = Instant::now();
    let gs = radiosity::solve(&scene, &base, &|_| {}).expect("Gauss-Seidel");
    let gs_seconds = t.elapsed().as_secs_f64();

    let settings = Settings {
        solver_kind: SolverKind::Progressive,
        progressive: ProgressiveSettings {
            preview_every: Some(1),
            shooter_depth,
            ..ProgressiveSettings::default()
        },
        ..base
    };
    let mut snapshots: Vec<Snapshot> = Vec::new();
    let mut areas = Vec::new();
    // Keep every shot early on, then thin out geometrically.
    let mut next_kept = 1usize;
    let pr = solve_with_previews(&scene, &settings, &|_| {}, &mut |p| {
        if p.shots == next_kept {
            let (leaves, reflectance, a) = leaf_values(p);
            areas = a;
            snapshots.push(Snapshot {
                shots: p.shots,
                seconds: p.seconds,
                unshot_fraction: p.unshot_fraction,
                leaves,
                reflectance,
                ambient: p.ambient,
            });
            next_kept = (next_kept * 5 / 4).max(next_kept + 1);
        }
    })
    .expect("progressive");
    let stats = pr.stats().progressive.as_ref().expect("progressive stats");

    println!(
        "patch size {:.4} m, uniform depth {depth:?}, shooter depth {shooter_depth}, {method:?}: \
         {} patches, {} leaves",
        pr.stats().patch_size,
        pr.stats().patches,
        pr.stats().elements
    );
    println!(
        "Gauss-Seidel {gs_seconds:.2} s; progressive {:.2} s, {} shots, {} shot hemi-cubes, \
         unshot {:.2e}, stop {:?}",
        pr.stats().seconds.total,
        stats.shots,
        stats.shot_hemicubes,
        stats.unshot_fraction,
        stats.stop
    );
    println!(
        "shooter splits {} clips {} hidden-eye splits {} hidden cells {} row sums > 1: {} \
         scaled {} unshot increases {} implied row sum mean {:.4} max {:.4}",
        stats.shooter_splits,
        stats.reciprocity_clips,
        stats.hidden_eye_splits,
        stats.hidden_cells,
        stats.row_sums_above_one,
        stats.scaled_shots,
        stats.unshot_increases,
        stats.mean_implied_row_sum,
        stats.max_implied_row_sum
    );
    println!("\nper surface, progressive vs Gauss-Seidel (relative, per band):");
    let mut worst: f64 = 0.0;
    for (a, b) in gs
        .object_radiosity(&scene)
        .iter()
        .zip(pr.object_radiosity(&scene))
    {
        let d: Vec<f64> = (0..3)
            .map(|i| (b.radiosity[i] - a.radiosity[i]) / a.radiosity[i])
            .collect();
        worst = d.iter().fold(worst, |w, x| w.max(x.abs()));
        println!(
            "  {:<12} {:+.3}% {:+.3}% {:+.3}%",
            a.name,
            100.0 * d[0],
            100.0 * d[1],
            100.0 * d[2]
        );
    }
    println!("  worst {:.3}%", 100.0 * worst);
    if depth.is_none() {
        return;
    }

    let converged: Vec<Rgb> = pr.leaves().iter().map(|l| l.radiosity).collect();
    let converged_mean = mean_luminance(&converged, &areas);
    let first = &snapshots[0];
    let with_ambient = |s: &Snapshot| -> Vec<Rgb> {
        s.leaves
            .iter()
            .zip(&s.reflectance)
            .map(|(b, rho)| *b + *rho * s.ambient)
            .collect()
    };
    println!(
        "\nfirst preview after {} shot(s), {:.3} s into the solve",
        first.shots, first.seconds
    );
    println!(
        "  mean luminance: converged {:.4}; first preview without ambient {:.4} ({:+.1}%), \
         with ambient {:.4} ({:+.1}%)",
        converged_mean,
        mean_luminance(&first.leaves, &areas),
        100.0 * (mean_luminance(&first.leaves, &areas) / converged_mean - 1.0),
        mean_luminance(&with_ambient(first), &areas),
        100.0 * (mean_luminance(&with_ambient(first), &areas) / converged_mean - 1.0),
    );
    println!("\nerror against the converged solution over time (area-weighted RMS of leaf luminance / mean):");
    println!("  shots  seconds  unshot     ambient(lum)  rms no ambient  rms with ambient  mean err no amb  mean err with amb");
    for s in &snapshots {
        let wa = with_ambient(s);
        println!(
            "  {:>5}  {:>7.3}  {:>9.3e}  {:>11.3e}  {:>13.4}  {:>15.4}  {:>+14.2}%  {:>+15.2}%",
            s.shots,
            s.seconds,
            s.unshot_fraction,
            s.ambient.luminance(),
            relative_rms(&s.leaves, &converged, &areas),
            relative_rms(&wa, &converged, &areas),
            100.0 * (mean_luminance(&s.leaves, &areas) / converged_mean - 1.0),
            100.0 * (mean_luminance(&wa, &areas) / converged_mean - 1.0),
        );
    }
}
