//! What the shooting has done so far: per patch the radiosity, the part still
//! unshot and the part already shot; per leaf element the irradiance received.

use super::Receivers;
use crate::math::Rgb;
use crate::mesh::{ElementKey, Mesh};
use crate::solve::balance::Balance;
use crate::solve::{DirectLight, Radiosity};
use slotmap::SecondaryMap;

/// What one shot delivered.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Delivery {
    /// `sum_e F_ei A_e / W_i` (`W_i` the patch's exposure), unscaled: 1 in a
    /// closed scene up to the point sampling of the receivers.
    pub implied_row_sum: f64,
    /// True when the reflected part of what the shot delivers exceeded 1 in
    /// some band and the shot was scaled back.
    pub scaled: bool,
}

/// The bookkeeping of a progressive solve.
///
/// A patch's radiosity here is its radiosity as a source: the mean of its
/// leaves' radiosities weighted by their exposure (area times the part of
/// their view that front faces fill), as the Gauss-Seidel path's patch system
/// has it (see [`crate::solve::PatchSystem`]). A leaf shut inside an object
/// has no weight, a leaf that sees the room only through a gap little.
///
/// Invariants (up to rounding): a leaf's radiosity is `E + rho H` with `H` its
/// irradiance; a patch's radiosity is the exposure-weighted mean of its
/// leaves; and `radiosity = shot + unshot` for every patch.
#[derive(Clone, Debug)]
pub(crate) struct ShootingState {
    /// Radiosity of each patch as a source.
    pub radiosity: Vec<Rgb>,
    /// Radiosity each patch has received (or emits) but not yet shot.
    pub unshot: Vec<Rgb>,
    /// Radiosity each patch has shot so far.
    pub shot: Vec<Rgb>,
    /// Irradiance (received flux per area) of each leaf element.
    pub irradiance: SecondaryMap<ElementKey, Rgb>,
    /// Per patch, its exposure: the sum of its leaves' weights (see
    /// [`ShootingState::expose`]). A shot of unshot radiosity `u` sends `u`
    /// times this to front faces.
    pub exposure: Vec<f64>,
    /// Per leaf, its weight in its patch's radiosity: area times exposure.
    weights: SecondaryMap<ElementKey, f64>,
    /// Per leaf that other objects cover in part, its visible share: its
    /// radiosity is its mean over its area, and its visible part stands for
    /// it as a source (see `formfactor/contacts.rs`). Absent: 1.
    visible: SecondaryMap<ElementKey, f64>,
    /// The scales that balance the gathering rows, once shots deliver by
    /// them (see [`ShootingState::set_balance`]).
    balance: Option<Scales>,
    areas: Vec<f64>,
    emitted_power: f64,
    /// The punctual lights' irradiance per leaf, which joins what the leaf
    /// receives from shots (`None`: the scene has no punctual light).
    direct: Option<DirectLight>,
}

/// The balance of the gathering rows, keyed for shots.
#[derive(Clone, Debug)]
struct Scales {
    /// Per patch, `c_j`.
    seen: Vec<f64>,
    /// Per leaf, `r_e`.
    receiver: SecondaryMap<ElementKey, f64>,
}

impl ShootingState {
    /// The state before the first shot: every patch holds its emission, unshot,
    /// and every leaf counts with its whole area until [`ShootingState::expose`]
    /// says otherwise. With punctual lights (`direct`), their reflected light
    /// is emission too: the first shots send it on.
    #[must_use]
    pub(crate) fn new(mesh: &Mesh, direct: Option<&DirectLight>) -> Self {
        let mut emission: Vec<Rgb> = (0..mesh.patches.len() as u32)
            .map(|p| mesh.patch_emission(p))
            .collect();
        if let Some(direct) = direct {
            for (e, d) in emission.iter_mut().zip(direct.patch_area_means(mesh)) {
                *e += d;
            }
        }
        let areas: Vec<f64> = mesh.patches.iter().map(|p| p.area).collect();
        let emitted_power = emission
            .iter()
            .zip(&areas)
            .map(|(e, a)| e.0.iter().sum::<f64>() * a)
            .sum();
        let mut irradiance = SecondaryMap::new();
        let mut weights = SecondaryMap::new();
        for k in mesh.leaves() {
            irradiance.insert(k, Rgb::ZERO);
            weights.insert(k, mesh.elements[k].area);
        }
        ShootingState {
            radiosity: emission.clone(),
            unshot: emission,
            shot: vec![Rgb::ZERO; areas.len()],
            exposure: areas.clone(),
            weights,
            visible: SecondaryMap::new(),
            balance: None,
            irradiance,
            areas,
            emitted_power,
            direct: direct.cloned(),
        }
    }

    /// Takes the punctual lights' irradiance of the current leaves (after a
    /// refinement pass made new ones).
    pub(crate) fn set_direct(&mut self, direct: Option<&DirectLight>) {
        self.direct = direct.cloned();
    }

    /// The punctual lights' irradiance on leaf `key`.
    #[must_use]
    pub(crate) fn direct_irradiance(&self, key: ElementKey) -> Option<Rgb> {
        self.direct.as_ref().map(|d| d.irradiance(key))
    }

    /// Takes each leaf's exposure from `receivers` (after every change of the
    /// mesh, and when gathered rows replace the fan of rays): its weight in
    /// its patch's radiosity becomes its area times that exposure. Then every
    /// patch's radiosity is the weighted mean of its leaves again, and the
    /// change is unshot (see [`ShootingState::resum_patch`]).
    ///
    /// Leaves shut inside an object receive nothing and send nothing, so the
    /// patch's unshot power all sits on its exposed part; gathering likewise
    /// lets the exposed elements alone stand for the patch.
    pub(crate) fn expose(
        &mut self,
        mesh: &Mesh,
        radiosity: &Radiosity,
        receivers: &Receivers,
    ) -> Rgb {
        self.weights.clear();
        self.visible.clear();
        for (i, &k) in receivers.leaves.iter().enumerate() {
            self.weights
                .insert(k, receivers.areas[i] * receivers.exposure[i]);
            if receivers.visible[i] < 1.0 {
                self.visible.insert(k, receivers.visible[i]);
            }
        }
        let mut change = Rgb::ZERO;
        for p in 0..mesh.patches.len() as u32 {
            change += self.resum_patch(mesh, radiosity, p) * self.exposure[p as usize];
        }
        change
    }

    /// From now on, shots deliver by balanced rows: a shot of patch `j`
    /// reaches leaf `e` by `r_e F_ej c_j` (see [`crate::solve::balance`]),
    /// with `receiver[i]` the scale of `receivers.leaves[i]`. `None` delivers
    /// by the factors as they are.
    pub(crate) fn set_balance(&mut self, receivers: &Receivers, balance: Option<&Balance>) {
        self.balance = balance.map(|b| Scales {
            seen: b.seen.clone(),
            receiver: receivers
                .leaves
                .iter()
                .enumerate()
                .map(|(i, &k)| (k, b.receiver(i)))
                .collect(),
        });
    }

    /// The factor by which a shot of patch `p` reaches leaf `k`, beyond its
    /// form factor: the balance's `c_p r_k`, or 1.
    #[must_use]
    pub(crate) fn delivery_scale(&self, p: u32, k: ElementKey) -> f64 {
        self.balance.as_ref().map_or(1.0, |s| {
            s.seen.get(p as usize).copied().unwrap_or(1.0)
                * s.receiver.get(k).copied().unwrap_or(1.0)
        })
    }

    /// Shoots patch `p`'s unshot radiosity to the leaves of `factors` (`F_ei`
    /// from each leaf to the patch): each receives `u * F_ei` times the
    /// balance's scales, with `u` the unshot radiosity.
    ///
    /// The shot sends `u W_i` to front faces (`W_i` the patch's exposure) and
    /// delivers `u sum_e F_ei A_e` times the scales: with balanced rows, the
    /// same. Shooter-side factors carry the point sampling of each receiver
    /// (the implied row sum `sum_e F_ei A_e / W_i` is not quite 1 even in a
    /// closed scene, and the shooter's cells cannot tell how much of it is
    /// sampling and how much open sky). Only where the reflected part of what
    /// a shot delivers, `sum_e rho_e F_ei A_e / W_i` with the scales, would
    /// exceed 1 in some band, so that the shot would raise the unshot power,
    /// is the shot scaled back, and said so.
    pub(crate) fn deliver(
        &mut self,
        mesh: &Mesh,
        radiosity: &mut Radiosity,
        p: u32,
        factors: &[(ElementKey, f64)],
    ) -> Delivery {
        let exposure = self.exposure[p as usize];
        let mut row_sum = 0.0;
        let mut reflected = Rgb::ZERO;
        for &(k, f) in factors {
            let e = &mesh.elements[k];
            let w = f * e.area / exposure;
            row_sum += w;
            reflected += e.reflectance * (w * self.delivery_scale(p, k));
        }
        let worst = reflected.max_band();
        let scaled = worst > 1.0;
        let factor = if scaled { 1.0 / worst } else { 1.0 };
        let unshot = self.take_unshot(p);
        for &(k, f) in factors {
            let h = unshot * (f * factor * self.delivery_scale(p, k));
            self.receive(mesh, radiosity, k, h);
        }
        Delivery {
            implied_row_sum: if exposure > 0.0 { row_sum } else { 0.0 },
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

    /// Unshot power of patch `p`, bands summed (magnitudes): its unshot
    /// radiosity times its exposure, what a shot would send to front faces.
    #[must_use]
    pub(crate) fn unshot_power_of(&self, p: u32) -> f64 {
        self.unshot[p as usize].abs().0.iter().sum::<f64>() * self.exposure[p as usize]
    }

    /// Unshot power per band, magnitudes summed over patches.
    #[must_use]
    pub(crate) fn unshot_power(&self) -> Rgb {
        let mut sum = Rgb::ZERO;
        for (u, w) in self.unshot.iter().zip(&self.exposure) {
            sum += u.abs() * *w;
        }
        sum
    }

    /// Unshot power per band, signed: the light still to be delivered (never
    /// negative in a solve that conserves energy, since it is what has been
    /// emitted and not yet absorbed or lost).
    #[must_use]
    pub(crate) fn signed_unshot_power(&self) -> Rgb {
        let mut sum = Rgb::ZERO;
        for (u, w) in self.unshot.iter().zip(&self.exposure) {
            sum += *u * *w;
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
    /// its patch's radiosity and unshot radiosity by the exposure-weighted
    /// share (none for a leaf with no exposure, which sends nothing).
    pub(crate) fn receive(
        &mut self,
        mesh: &Mesh,
        radiosity: &mut Radiosity,
        key: ElementKey,
        h: Rgb,
    ) {
        let e = &mesh.elements[key];
        let rho = e.reflectance;
        let db = rho * h;
        radiosity.add_to_element(key, db);
        if let Some(slot) = self.irradiance.get_mut(key) {
            *slot += h;
        } else {
            self.irradiance.insert(key, h);
        }
        let p = e.patch as usize;
        let w = self.weights.get(key).copied().unwrap_or(e.area);
        if self.exposure[p] > 0.0 {
            let visible = self.visible.get(key).copied().unwrap_or(1.0);
            let share = db * (w / (self.exposure[p] * visible));
            self.radiosity[p] += share;
            self.unshot[p] += share;
        }
    }

    /// Sets a new leaf's irradiance outright (after a gather) and its radiosity
    /// to `E + rho (H + Hd)`, `Hd` the punctual lights' irradiance. The patch totals are brought up to date by
    /// [`ShootingState::resum_patch`].
    pub(crate) fn set_leaf(
        &mut self,
        mesh: &Mesh,
        radiosity: &mut Radiosity,
        key: ElementKey,
        h: Rgb,
    ) {
        let e = &mesh.elements[key];
        let h_all = match self.direct_irradiance(key) {
            None => h,
            Some(hd) => h + hd,
        };
        radiosity.set_element(key, e.emission + e.reflectance * h_all);
        self.irradiance.insert(key, h);
    }

    /// Recomputes patch `p`'s exposure and radiosity, the weighted mean of
    /// its leaves (the area mean where no leaf is exposed), and moves the
    /// change of radiosity into its unshot radiosity so that what it has shot
    /// stays what it has shot. Returns the change in radiosity.
    pub(crate) fn resum_patch(&mut self, mesh: &Mesh, radiosity: &Radiosity, p: u32) -> Rgb {
        let (mut sum, mut total, mut area_sum) = (Rgb::ZERO, 0.0, Rgb::ZERO);
        for k in mesh.patch_leaves(p) {
            let e = &mesh.elements[k];
            let b = radiosity.element(k);
            let w = self.weights.get(k).copied().unwrap_or(e.area);
            let visible = self.visible.get(k).copied().unwrap_or(1.0);
            sum += (e.emission + (b - e.emission) / visible) * w;
            total += w;
            area_sum += b * e.area;
        }
        self.exposure[p as usize] = total;
        let b = if total > 0.0 {
            sum / total
        } else {
            area_sum / self.areas[p as usize]
        };
        let change = b - self.radiosity[p as usize];
        self.radiosity[p as usize] = b;
        self.unshot[p as usize] += change;
        change
    }

    /// Absorbed power per band, `sum A (1 - rho) H` over the leaves (`H`
    /// with the punctual lights' irradiance).
    #[must_use]
    pub(crate) fn absorbed_power(&self, mesh: &Mesh) -> Rgb {
        let mut sum = Rgb::ZERO;
        for k in mesh.leaves() {
            let e = &mesh.elements[k];
            let rho = e.reflectance;
            let mut h = self.irradiance.get(k).copied().unwrap_or(Rgb::ZERO);
            if let Some(hd) = self.direct_irradiance(k) {
                h += hd;
            }
            sum += (Rgb::ONE - rho) * h * e.area;
        }
        sum
    }
}
