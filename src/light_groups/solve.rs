//! Each light group solved on the finished solve's refined mesh and rows.
//!
//! Everything after refinement is linear in emission once the few choices
//! that depend on the light are frozen at the solve with every light on:
//!
//! - The patch system's rows and the balance scales depend on the rows alone
//!   (and on whether the scene is closed, which the emitters decide: taken
//!   once, with all of them).
//! - Gauss-Seidel converges to the system's one solution, linear in its
//!   source; each group stops at [`GROUP_TOLERANCE`], far below the solve's,
//!   so that the groups add up to a solve of the whole to about 1e-12 of the
//!   brightest value. (Its extrapolation and clamping are not linear steps,
//!   but they only change how fast it converges, not where to.)
//! - The punctual lights' direct light is a sum over lights, computed per
//!   group with the group's lights (the same shadow rays in all).
//! - A shaped gather is not linear in emission: its factors are ratios of
//!   a patch's parts to its mean, corrected per patch with clamped ratios.
//!   Each group keeps the whole solve's choice of unevenly lit patches and
//!   what their near receivers weigh of their parts (geometry, and the part
//!   views drawn), takes the parts' values from its own gathers, and makes as
//!   many corrections as the whole solve did (see `KeptShapes`): a group
//!   alone is then shaped by its own light. Gathering each patch by its
//!   parts is linear; what is not is the ratio's denominator (the parts'
//!   mean, against the patch radiosity it multiplies) and the clamped
//!   corrections, so the groups add up to the whole to within what those
//!   change (measured in `papers/light-groups.md`); with shaped gathers off
//!   they add up to it exactly.
//! - The solve's emission scale (a power of two) is exact.

use crate::error::{Error, Result, SolverFault};
use crate::formfactor::{FormFactors, Sources};
use crate::math::Rgb;
use crate::mesh::{ElementKey, Mesh};
use crate::pipeline::{times_pow2, weighted_patch_means, Progress, Settings, Stage};
use crate::scene::light_groups::LightGroups;
use crate::scene::Scene;
use crate::solution::Solution;
use crate::solution::{mask, unmask};
use crate::solve::{
    gather_bounces, gather_with, gauss_seidel_with_source, scene_is_closed, shaped_factors,
    DirectLight, GatherOptions, KeptShapes, PatchSystem, Radiosity, SolverSettings,
};
use std::sync::Arc;
use std::time::Instant;

/// The Gauss-Seidel tolerance of each group: the bound on any patch's error
/// as a fraction of the group's brightest radiosity.
pub const GROUP_TOLERANCE: f64 = 1e-12;

/// Brightest emissions whose binary exponent lies within this many of 0 are
/// solved as they are (as the whole solve does; see `crate::pipeline`'s
/// emission scale).
const COMFORTABLE_EXPONENT: i32 = 64;

/// What the group solves share: the frozen choices of the whole solve.
struct Frozen {
    closed: bool,
    grey: bool,
    leaves: Vec<ElementKey>,
    sources: Option<Sources>,
    tolerance: SolverSettings,
    bounces: Option<u32>,
}

/// Solves every group of `groups` on `solution` (a solve of `scene` with
/// `settings`, its mesh refined for all the light): fills its group parts and
/// sets its radiosity to their sum.
pub(crate) fn solve_groups(
    scene: &Scene,
    settings: &Settings,
    groups: &LightGroups,
    solution: &mut Solution,
    progress: &(dyn Fn(Progress) + Sync),
) -> Result<()> {
    let started = Instant::now();
    let mut kept = match solution
        .light_groups
        .kept_shapes
        .take()
        .map(Arc::try_unwrap)
    {
        None => None,
        Some(Ok(kept)) => Some(kept),
        Some(Err(_)) => {
            return Err(Error::solver(
                SolverFault::Internal,
                "the shaped gather kept for the light groups is held elsewhere".to_string(),
            ))
        }
    };
    let surface_group = groups.surface_groups(scene);
    let Solution {
        mesh,
        form_factors,
        system,
        ..
    } = solution;
    let leaves = mesh.leaves();
    let frozen = Frozen {
        closed: scene_is_closed(mesh, form_factors, &leaves),
        grey: settings.skips.grey && is_grey(mesh, scene),
        leaves,
        sources: (!scene.lights.is_empty() || scene.sky.is_some())
            .then(|| Sources::from_mesh(mesh)),
        tolerance: SolverSettings {
            tolerance: GROUP_TOLERANCE.min(settings.solver.tolerance),
            max_iterations: settings.solver.max_iterations,
        },
        bounces: settings.bounces,
    };
    let mut out = Vec::with_capacity(groups.len());
    for (g, group) in groups.groups.iter().enumerate() {
        progress(Progress {
            stage: Stage::LightGroups,
            done: g,
            total: groups.len(),
        });
        // The lights' reflected direct light, weighted as the whole solve
        // weighed it (with every emitter on).
        let lights: Vec<_> = group
            .lights
            .iter()
            .map(|&l| scene.lights[l as usize].clone())
            .collect();
        let direct = frozen
            .sources
            .as_ref()
            .filter(|_| !lights.is_empty() || group.sky)
            .map(|s| {
                let mut d = DirectLight::default();
                d.update(mesh, s, &lights, scene.sky.as_ref().filter(|_| group.sky));
                d
            });
        let reflected = direct
            .as_ref()
            .map(|d| d.patch_exitance(mesh, form_factors));
        let exponent = group_exponent(mesh, &surface_group, g as u32, scene);
        let saved = mask(
            mesh,
            &surface_group,
            Some(g as u32),
            times_pow2(1.0, -exponent),
        );
        let solved = solve_one(
            (mesh, form_factors, system),
            &frozen,
            kept.as_mut(),
            direct.as_ref(),
            reflected.as_deref(),
        );
        unmask(mesh, saved);
        let mut radiosity = solved?;
        // Back at the scene's scale. A shaped gather's corrections can leave
        // a group a few parts in 1e6 below 0 where it barely reaches; no
        // light is negative.
        radiosity.map_values(|v| Rgb(v.0.map(|x| times_pow2(x, exponent).max(0.0))));
        out.push(radiosity);
    }
    progress(Progress {
        stage: Stage::LightGroups,
        done: groups.len(),
        total: groups.len(),
    });
    solution.radiosity = sum(&solution.mesh, &out);
    let parts = &mut solution.light_groups;
    parts.groups = groups.clone();
    parts.surface_group = surface_group;
    parts.radiosity = out;
    parts.seconds = started.elapsed().as_secs_f64();
    Ok(())
}

/// The radiosity of one group, the mesh's emission masked to it: the patch
/// system solved for its emission and reflected direct light, gathered (and
/// with `kept`, shaped and corrected by the group's own light).
fn solve_one(
    (mesh, form_factors, system): (&Mesh, &FormFactors, &mut PatchSystem),
    frozen: &Frozen,
    kept: Option<&mut KeptShapes>,
    direct: Option<&DirectLight>,
    reflected: Option<&[Rgb]>,
) -> Result<Radiosity> {
    let patches = mesh.patches.len();
    let source: Vec<Rgb> = (0..patches)
        .map(|p| {
            let d = reflected.map_or(Rgb::ZERO, |r| r[p]);
            mesh.patch_emission(p as u32) + d
        })
        .collect();
    let mut radiosity = Radiosity::emitted(mesh);
    // From the source, as the whole solve starts (the iteration stops at
    // once on a start of 0).
    let mut b = source.clone();
    let options = GatherOptions {
        grey: frozen.grey,
        rowless: None,
        balance: Some(&system.balance),
        direct,
        factors: None,
    };
    if let Some(n) = frozen.bounces {
        // The truncated solve reads the system's emission.
        let whole = std::mem::replace(&mut system.emission, source);
        let result = gather_bounces(
            mesh,
            form_factors,
            &mut radiosity,
            system,
            &mut b,
            n,
            &options,
        );
        system.emission = whole;
        result?;
        return Ok(radiosity);
    }
    gauss_seidel_with_source(system, &source, &mut b, &frozen.tolerance)?;
    gather_with(mesh, form_factors, &mut radiosity, &b, &options);
    let Some(kept) = kept else {
        return Ok(radiosity);
    };
    let closed = frozen.closed;
    let means = |r: &Radiosity| weighted_patch_means(mesh, form_factors, r, &frozen.leaves, closed);
    // The parts take the plain gather's values, as in the whole solve's
    // first shaped gather.
    let mut shaped_gather = |radiosity: &mut Radiosity, b: &[Rgb]| {
        kept.shapes.refresh(mesh, form_factors, radiosity, closed);
        let factors = shaped_factors(mesh, form_factors, &kept.shapes, &options, &kept.near);
        let shaped = GatherOptions {
            factors: Some(&factors),
            ..options
        };
        gather_with(mesh, form_factors, radiosity, b, &shaped);
    };
    shaped_gather(&mut radiosity, &b);
    for _ in 0..kept.corrections {
        // As the whole solve corrects its patch radiosities after a shaped
        // gather: what the shapes change in each patch's mean is solved
        // again as extra emission, and the parts take the last values.
        let mut plain = radiosity.clone();
        gather_with(mesh, form_factors, &mut plain, &b, &options);
        let corrected: Vec<Rgb> = means(&radiosity)
            .into_iter()
            .zip(means(&plain))
            .zip(&source)
            .map(|((s, m), e)| *e + (s - m))
            .collect();
        gauss_seidel_with_source(system, &corrected, &mut b, &frozen.tolerance)?;
        shaped_gather(&mut radiosity, &b);
    }
    // As after the whole solve's shaped gathers: each patch's radiosity is its
    // elements' area mean.
    let means: Vec<Rgb> = mesh
        .patches
        .iter()
        .map(|p| radiosity.patch_mean(mesh, p))
        .collect();
    radiosity.set_patches(&means);
    Ok(radiosity)
}

/// The power of two group `g` is solved at (see the whole solve's emission
/// scale): 0 unless the scene has no punctual light and no sky (whose direct
/// light is not scaled) and the group's brightest emission lies far from 1.
fn group_exponent(mesh: &Mesh, surface_group: &[Option<u32>], g: u32, scene: &Scene) -> i32 {
    if !scene.lights.is_empty() || scene.sky.is_some() {
        return 0;
    }
    let in_group = |s: u32| surface_group.get(s as usize).copied().flatten() == Some(g);
    let brightest = mesh
        .elements
        .values()
        .filter(|e| in_group(e.surface))
        .map(|e| e.emission.max_band())
        .fold(0.0, f64::max);
    if !brightest.is_normal() {
        return 0;
    }
    let exponent = ((brightest.to_bits() >> 52) & 0x7ff) as i32 - 1023;
    if exponent.abs() > COMFORTABLE_EXPONENT {
        exponent
    } else {
        0
    }
}

/// Whether every reflectance, emission and light of the solve is grey, so
/// that a gather may work on one band (the same bits as three).
fn is_grey(mesh: &Mesh, scene: &Scene) -> bool {
    mesh.surfaces.iter().all(|s| {
        s.texture.is_none()
            && s.emissive_texture.is_none()
            && s.reflectance.is_grey()
            && s.emission.is_grey()
    }) && scene.lights.iter().all(|l| l.colour.is_grey())
        && scene.sky.is_none_or(|s| s.zenith.is_grey())
}

/// The sum of the groups' radiosities, element by element and patch by
/// patch, in group order.
fn sum(mesh: &Mesh, groups: &[Radiosity]) -> Radiosity {
    let mut total = Radiosity::default();
    let patches: Vec<Rgb> = (0..mesh.patches.len())
        .map(|p| {
            groups
                .iter()
                .map(|r| r.patches()[p])
                .fold(Rgb::ZERO, |a, b| a + b)
        })
        .collect();
    for k in mesh.elements.keys() {
        let value = groups
            .iter()
            .map(|r| r.element(k))
            .fold(Rgb::ZERO, |a, b| a + b);
        total.set_element(k, value);
    }
    total.set_patches(&patches);
    total
}
