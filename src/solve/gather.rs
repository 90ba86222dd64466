//! One gather from patches to leaf elements.

use super::balance::Balance;
use super::source_shape::{EntryFactors, NearWeights, PartViews, SourceShapes};
use super::Radiosity;
use crate::formfactor::{FormFactors, RowView};
use crate::math::Rgb;
use crate::mesh::{ElementKey, Mesh};
use rayon::prelude::*;

/// Power totals of a gather, for the energy balance.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct GatherTotals {
    /// Emitted power, sum of `A_e E_e` (per band).
    pub emitted: Rgb,
    /// Absorbed power, sum of `A_e (1 - rho_e) H_e` with irradiance
    /// `H_e = sum_j F_ej B_j`.
    pub absorbed: Rgb,
    /// Power absorbed by back faces: the back of a single-sided surface
    /// blocks light and reflects none, so what each element sends there,
    /// `A_e B_e` times its row's back-face form factor, ends there.
    pub back_faces: Rgb,
    /// Power that leaves the scene: `A_e B_e` times the form factor of the
    /// part of each element's view where nothing lies (0 in a closed scene).
    pub escaped: Rgb,
}

impl GatherTotals {
    /// Adds what a leaf of `area` with `radiosity` sends to back faces and out
    /// of the scene, by its row's `view`.
    pub(crate) fn add_hidden(&mut self, area: f64, radiosity: Rgb, view: RowView) {
        // A leaf that other objects cover in part sends its light from its
        // visible part, by that part's view; its row also counts the
        // covered part as seeing back faces (see `Row::covered`).
        let covered = f64::from(view.covered);
        let (back, open) = if covered > 0.0 {
            let visible = view.visible();
            (
                ((view.back_faces - covered) / visible).max(0.0),
                view.open / visible,
            )
        } else {
            (view.back_faces, view.open)
        };
        self.back_faces += radiosity * (area * back);
        self.escaped += radiosity * (area * open);
    }
}

/// Sets every leaf's radiosity in `radiosity` to `E + rho sum_j F_ej B_j`
/// from the patch radiosities `b` and the leaves' rows, every interior node's
/// to the area-weighted mean of its children, and every patch's to `b`.
/// Returns the power totals.
pub fn gather(
    mesh: &Mesh,
    form_factors: &FormFactors,
    radiosity: &mut Radiosity,
    b: &[Rgb],
) -> GatherTotals {
    gather_with(mesh, form_factors, radiosity, b, &GatherOptions::default())
}

/// How [`gather_with`] works.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct GatherOptions<'a> {
    /// Every reflectance, emission and patch radiosity is grey: gather one
    /// band and copy it (the same bits as three bands, for a third of the
    /// arithmetic).
    pub grey: bool,
    /// Per patch, true when its elements were given no rows because they
    /// reflect nothing (see [`crate::pipeline::Skips`]). The power such a
    /// patch absorbs is then summed from the other elements' rows by
    /// reciprocity: element `e` sends `A_e F_ej B_e` of its power to patch
    /// `j`, which absorbs all of it.
    pub rowless: Option<&'a [bool]>,
    /// The scales that balance the rows ([`crate::solve::PatchSystem::balance`],
    /// made for the mesh's current leaves); `None` gathers the rows as they
    /// are.
    pub balance: Option<&'a Balance>,
    /// The irradiance of punctual lights on each leaf (`None`: the scene has
    /// none); its reflection joins the leaf's emission, and the power it
    /// brings joins the emitted and absorbed totals.
    pub direct: Option<&'a super::DirectLight>,
    /// The factors on the patch radiosities that each row gathers, for the
    /// unevenly lit patches seen by their parts from near receivers (see
    /// [`super::source_shape`] and [`shaped_factors`]); `None` gathers
    /// every patch's mean.
    pub factors: Option<&'a EntryFactors>,
}

/// What the near receivers of `shapes` weigh of them (see
/// [`SourceShapes::near_weights`]); `None` when no patch is unevenly lit.
/// Where `views` is given, receivers whose rows see too little of a near
/// patch's parts weigh them by what their hemi-cubes, drawn in the scene it
/// builds (only when one is needed), show of each.
pub(crate) fn shaped_weights<'s>(
    mesh: &'s Mesh,
    form_factors: &FormFactors,
    shapes: &SourceShapes,
    views: Option<&PartViews<'_, 's>>,
) -> Option<NearWeights> {
    shapes.near_weights(mesh, form_factors, &mesh.leaves(), views)
}

/// The factors a gather with `options` puts on the patch radiosities of
/// `shapes`, by what their near receivers weigh (`near`, see
/// [`shaped_weights`]) and the parts' present values (see
/// [`SourceShapes::factors`]).
pub(crate) fn shaped_factors(
    mesh: &Mesh,
    form_factors: &FormFactors,
    shapes: &SourceShapes,
    options: &GatherOptions<'_>,
    near: &NearWeights,
) -> EntryFactors {
    let leaves: Vec<ElementKey> = mesh.leaves();
    let balance = options.balance.filter(|x| !x.seen.is_empty());
    // As the gather scales each row: a receiver that takes no part in the
    // balance gathers by its row as it is.
    let row_scale = |i: usize| {
        let patch = mesh.elements[leaves[i]].patch as usize;
        if balance.is_some_and(|x| x.is_excluded(patch)) {
            1.0
        } else {
            options.balance.map_or(1.0, |x| x.receiver(i))
        }
    };
    shapes.factors(mesh, form_factors, &leaves, row_scale, near)
}

/// [`gather`] with `options`.
pub(crate) fn gather_with(
    mesh: &Mesh,
    form_factors: &FormFactors,
    radiosity: &mut Radiosity,
    b: &[Rgb],
    options: &GatherOptions<'_>,
) -> GatherTotals {
    let leaves: Vec<ElementKey> = mesh.leaves();
    let rowless = options.rowless;
    let balance = options.balance.filter(|x| !x.seen.is_empty());
    let seen: Vec<Rgb>;
    let b_seen = match balance {
        None => b,
        Some(balance) => {
            seen = b
                .iter()
                .enumerate()
                .map(|(j, x)| *x * balance.seen(j))
                .collect();
            &seen
        }
    };
    let receiver_scale = |i: usize| {
        options.balance.map_or(1.0, |x| {
            debug_assert!(x.receiver.is_empty() || x.receiver.len() == leaves.len());
            x.receiver(i)
        })
    };
    // A receiver that takes no part in the balance gathers by its row as
    // it is.
    let excluded = |i: usize| {
        let patch = mesh.elements[leaves[i]].patch as usize;
        balance.is_some_and(|x| x.is_excluded(patch))
    };
    let factors = options.factors;
    // Per leaf: radiosity, irradiance, and the form factor of its row to
    // patches without rows.
    let results: Vec<(Rgb, Rgb, f64)> = leaves
        .par_iter()
        .enumerate()
        .map(|(i, &k)| {
            let e = &mesh.elements[k];
            let entries = form_factors.entries(k);
            let (r, b_seen) = if excluded(i) {
                (1.0, b)
            } else {
                (receiver_scale(i), b_seen)
            };
            // The factors on unevenly lit sources, in row order.
            let none = [];
            let mut near = factors
                .as_ref()
                .map_or(&none[..], |f| f.near.row(i))
                .iter()
                .peekable();
            let reflects = e.reflectance.max_band() > 0.0;
            let mut source = |i: usize, j: u32| {
                let b = b_seen[j as usize];
                match &factors {
                    Some(f) => b * f.factor(&mut near, i, j, reflects),
                    None => b,
                }
            };
            // A facet that borrows its group lead's row sees the emitters
            // as it does itself (see `FormFactors::emitter_shift`).
            let shift = form_factors.emitter_shift(k);
            let (scale, added) =
                shift.map_or((1.0, &[][..]), |s| (f64::from(s.scale), &s.entries[..]));
            let h = if options.grey {
                let mut h = 0.0;
                for (i, &(j, f)) in entries.iter().enumerate() {
                    h += source(i, j).0[0] * f64::from(f);
                }
                h *= scale;
                for &(j, d) in added {
                    h += b_seen[j as usize].0[0] * f64::from(d);
                }
                Rgb::splat(h * r)
            } else {
                let mut h = Rgb::ZERO;
                for (i, &(j, f)) in entries.iter().enumerate() {
                    h += source(i, j) * f64::from(f);
                }
                h *= scale;
                for &(j, d) in added {
                    h += b_seen[j as usize] * f64::from(d);
                }
                h * r
            };
            let to_rowless = rowless.map_or(0.0, |flags| {
                entries
                    .iter()
                    .filter(|(j, _)| flags[*j as usize])
                    .map(|&(_, f)| f64::from(f))
                    .sum::<f64>()
            });
            // Light from punctual lights arrives as irradiance like the
            // rest, so it is reflected like the rest.
            let h_all = match options.direct {
                None => h,
                Some(direct) => h + direct.irradiance(k),
            };
            let radiosity = if options.grey {
                let (rho, emission) = (e.reflectance.0[0], e.emission.0[0]);
                Rgb::splat(emission + rho * h_all.0[0])
            } else {
                e.emission + e.reflectance * h_all
            };
            (radiosity, h, to_rowless)
        })
        .collect();
    let mut totals = GatherTotals::default();
    for (&k, (value, h, to_rowless)) in leaves.iter().zip(&results) {
        radiosity.set_element(k, *value);
        let e = &mesh.elements[k];
        totals.emitted += e.emission * e.area;
        totals.absorbed += (Rgb::ONE - e.reflectance) * *h * e.area;
        if let Some(direct) = options.direct {
            // What punctual lights deliver counts as emitted into the scene.
            let hd = direct.irradiance(k);
            totals.emitted += hd * e.area;
            totals.absorbed += (Rgb::ONE - e.reflectance) * hd * e.area;
        }
        if let Some(view) = form_factors.view(k) {
            totals.add_hidden(e.area, *value, view);
        }
        if *to_rowless > 0.0 {
            totals.absorbed += *value * (e.area * to_rowless);
        }
    }
    for &k in &mesh.top_roots {
        radiosity.push_up(mesh, k);
    }
    radiosity.set_patches(b);
    totals
}
