//! What the shooting has done so far: per patch the radiosity, the part still
//! unshot and the part already shot; per leaf element the irradiance received.

use super::Receivers;
use crate::math::Rgb;
use crate::mesh::{ElementKey, Mesh};
use crate::solve::Radiosity;
use slotmap::SecondaryMap;

/// What one shot delivered.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Delivery {
    /// `sum_e F_ei s A_e / A_i` before any scaling back (1 in a closed scene).
    pub implied_row_sum: f64,
    /// True when the reflected part of the implied row sum exceeded 1 in
    /// some band and the shot was scaled back.
    pub scaled: bool,
}

/// The bookkeeping of a progressive solve.
///
/// Invariants (up to rounding): a leaf's radiosity is `E + rho H` with `H` its
/// irradiance; a patch's radiosity is the area mean of its leaves; and
/// `radiosity = shot + unshot` for every patch.
#[derive(Clone, Debug)]
pub(crate) struct ShootingState {
    /// Radiosity of each patch.
    pub radiosity: Vec<Rgb>,
    /// Radiosity each patch has received (or emits) but not yet shot.
    pub unshot: Vec<Rgb>,
    /// Radiosity each patch has shot so far.
    pub shot: Vec<Rgb>,
    /// Irradiance (received flux per area) of each leaf element.
    pub irradiance: SecondaryMap<ElementKey, Rgb>,
    /// Per patch, its area over the area of its exposed leaves (see
    /// [`ShootingState::expose`]).
    pub open_scale: Vec<f64>,
    areas: Vec<f64>,
    emitted_power: f64,
}

impl ShootingState {
    /// The state before the first shot: every patch holds its emission, unshot.
    #[must_use]
    pub(crate) fn new(mesh: &Mesh) -> Self {
        let emission: Vec<Rgb> = (0..mesh.patches.len() as u32)
            .map(|p| mesh.patch_emission(p))
            .collect();
        let areas: Vec<f64> = mesh.patches.iter().map(|p| p.area).collect();
        let emitted_power = emission
            .iter()
            .zip(&areas)
            .map(|(e, a)| e.0.iter().sum::<f64>() * a)
            .sum();
        let mut irradiance = SecondaryMap::new();
        for k in mesh.leaves() {
            irradiance.insert(k, Rgb::ZERO);
        }
        ShootingState {
            radiosity: emission.clone(),
            unshot: emission,
            shot: vec![Rgb::ZERO; areas.len()],
            open_scale: vec![1.0; areas.len()],
            irradiance,
            areas,
            emitted_power,
        }
    }

    /// Takes each patch's exposed leaves from `receivers` (after every change
    /// of the mesh). Leaves shut inside an object receive nothing, so the
    /// patch's unshot power, an average over all of it, all sits on its
    /// exposed part: that part's radiosity is the average times the patch's
    /// area over the exposed area, the open scale. Gathering likewise lets
    /// the exposed elements alone stand for the patch.
    pub(crate) fn expose(&mut self, mesh: &Mesh, receivers: &Receivers) {
        for (p, range) in receivers.patch_leaves.iter().enumerate() {
            let exposed: f64 = range
                .clone()
                .filter(|&i| receivers.exposed[i as usize])
                .map(|i| receivers.areas[i as usize])
                .sum();
            let area = mesh.patches[p].area;
            self.open_scale[p] = if exposed > 0.0 && exposed < area {
                area / exposed
            } else {
                1.0
            };
        }
    }

    /// Shoots patch `p`'s unshot radiosity to the leaves of `factors` (`F_ei`
    /// from each leaf to the patch, without the open scale): each receives
    /// `u * s * F_ei` with `u` the unshot radiosity and `s` the open scale.
    ///
    /// The implied row sum `sum_e F_ei s A_e / A_i` is 1 in a closed scene, up
    /// to the point sampling of each receiver (a leaf that straddles an
    /// occluder's foot counts all its area, as it does when it gathers). Only
    /// where the reflected part `sum_e rho_e F_ei s A_e / A_i` would exceed 1
    /// in some band, so that the shot would create unshot power, is the shot
    /// scaled back, and said so.
    pub(crate) fn deliver(
        &mut self,
        mesh: &Mesh,
        radiosity: &mut Radiosity,
        p: u32,
        factors: &[(ElementKey, f64)],
    ) -> Delivery {
        let area = self.areas[p as usize];
        let scale = self.open_scale[p as usize];
        let mut row_sum = 0.0;
        let mut reflected = Rgb::ZERO;
        for &(k, f) in factors {
            let e = &mesh.elements[k];
            let w = f * scale * e.area / area;
            row_sum += w;
            reflected += mesh.surfaces[e.surface as usize].reflectance * w;
        }
        let worst = reflected.max_band();
        let scaled = worst > 1.0;
        let factor = if scaled { scale / worst } else { scale };
        let unshot = self.take_unshot(p);
        for &(k, f) in factors {
            self.receive(mesh, radiosity, k, unshot * (f * factor));
        }
        Delivery {
            implied_row_sum: row_sum,
            scaled,
        }
    }

    /// Emitted power summed over patches and bands.
    #[must_use]
    pub(crate) fn emitted_power(&self) -> f64 {
        self.emitted_power
    }

    /// The patch with the largest unshot power (bands summed, magnitudes, so
    /// that a negative correction from refinement is shot too); the lowest
    /// index among equals. `None` when nothing is left to shoot.
    #[must_use]
    pub(crate) fn choose_shooter(&self) -> Option<u32> {
        let mut best: Option<(u32, f64)> = None;
        for p in 0..self.unshot.len() {
            let power = self.unshot_power_of(p as u32);
            let better = match best {
                None => true,
                Some((_, b)) => power > b,
            };
            if power > 0.0 && better {
                best = Some((p as u32, power));
            }
        }
        best.map(|(p, _)| p)
    }

    /// Unshot power of patch `p`, bands summed (magnitudes).
    #[must_use]
    pub(crate) fn unshot_power_of(&self, p: u32) -> f64 {
        self.unshot[p as usize].abs().0.iter().sum::<f64>() * self.areas[p as usize]
    }

    /// Unshot power per band, magnitudes summed over patches.
    #[must_use]
    pub(crate) fn unshot_power(&self) -> Rgb {
        let mut sum = Rgb::ZERO;
        for (u, a) in self.unshot.iter().zip(&self.areas) {
            sum += u.abs() * *a;
        }
        sum
    }

    /// Unshot power over emitted power, bands summed (0 when nothing emits).
    #[must_use]
    pub(crate) fn unshot_fraction(&self) -> f64 {
        if self.emitted_power > 0.0 {
            self.unshot_power().0.iter().sum::<f64>() / self.emitted_power
        } else {
            0.0
        }
    }

    /// The largest unshot radiosity of any patch in any band: the residual
    /// `|E + rho F B - B|` of the system being solved.
    #[must_use]
    pub(crate) fn residual(&self) -> f64 {
        self.unshot
            .iter()
            .map(|u| u.abs().max_band())
            .fold(0.0, f64::max)
    }

    /// Takes patch `p`'s unshot radiosity for a shot: it becomes shot.
    pub(crate) fn take_unshot(&mut self, p: u32) -> Rgb {
        let u = std::mem::take(&mut self.unshot[p as usize]);
        self.shot[p as usize] += u;
        u
    }

    /// Leaf `key` receives irradiance `h`: its radiosity grows by `rho h`, and
    /// its patch's radiosity and unshot radiosity by the area-weighted share.
    pub(crate) fn receive(
        &mut self,
        mesh: &Mesh,
        radiosity: &mut Radiosity,
        key: ElementKey,
        h: Rgb,
    ) {
        let e = &mesh.elements[key];
        let rho = mesh.surfaces[e.surface as usize].reflectance;
        let db = rho * h;
        radiosity.add_to_element(key, db);
        if let Some(slot) = self.irradiance.get_mut(key) {
            *slot += h;
        } else {
            self.irradiance.insert(key, h);
        }
        let p = e.patch as usize;
        let share = db * (e.area / self.areas[p]);
        self.radiosity[p] += share;
        self.unshot[p] += share;
    }

    /// Sets a new leaf's irradiance outright (after a gather) and its radiosity
    /// to `E + rho H`. The patch totals are brought up to date by
    /// [`ShootingState::resum_patch`].
    pub(crate) fn set_leaf(
        &mut self,
        mesh: &Mesh,
        radiosity: &mut Radiosity,
        key: ElementKey,
        h: Rgb,
    ) {
        let e = &mesh.elements[key];
        let s = &mesh.surfaces[e.surface as usize];
        radiosity.set_element(key, s.emission + s.reflectance * h);
        self.irradiance.insert(key, h);
    }

    /// Recomputes patch `p`'s radiosity as the area mean of its leaves, and
    /// moves the change into its unshot radiosity so that what it has shot
    /// stays what it has shot. Returns the change in radiosity.
    pub(crate) fn resum_patch(&mut self, mesh: &Mesh, radiosity: &Radiosity, p: u32) -> Rgb {
        let mut sum = Rgb::ZERO;
        for k in mesh.patch_leaves(p) {
            sum += radiosity.element(k) * mesh.elements[k].area;
        }
        let b = sum / self.areas[p as usize];
        let change = b - self.radiosity[p as usize];
        self.radiosity[p as usize] = b;
        self.unshot[p as usize] += change;
        change
    }

    /// Absorbed power per band, `sum A (1 - rho) H` over the leaves.
    #[must_use]
    pub(crate) fn absorbed_power(&self, mesh: &Mesh) -> Rgb {
        let mut sum = Rgb::ZERO;
        for k in mesh.leaves() {
            let e = &mesh.elements[k];
            let rho = mesh.surfaces[e.surface as usize].reflectance;
            let h = self.irradiance.get(k).copied().unwrap_or(Rgb::ZERO);
            sum += (Rgb::ONE - rho) * h * e.area;
        }
        sum
    }
}
