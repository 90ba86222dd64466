//! What the shooting has done so far: per patch the radiosity, the part still
//! unshot and the part already shot; per leaf element the irradiance received.

use crate::math::Rgb;
use crate::mesh::{ElementKey, Mesh};
use slotmap::SecondaryMap;

/// The bookkeeping of a progressive solve.
///
/// Invariants (up to rounding): a leaf's radiosity is `E + rho H` with `H` its
/// irradiance; a patch's radiosity is the area mean of its leaves; and
/// `radiosity = shot + unshot` for every patch.
#[derive(Clone, Debug)]
pub struct ShootingState {
    /// Radiosity of each patch.
    pub radiosity: Vec<Rgb>,
    /// Radiosity each patch has received (or emits) but not yet shot.
    pub unshot: Vec<Rgb>,
    /// Radiosity each patch has shot so far.
    pub shot: Vec<Rgb>,
    /// Irradiance (received flux per area) of each leaf element.
    pub irradiance: SecondaryMap<ElementKey, Rgb>,
    /// Per patch, its open part's radiosity over its average (see
    /// `ShotFactors::open_scale`), from its last shot; 1 before it shoots.
    pub open_scale: Vec<f64>,
    areas: Vec<f64>,
    emitted_power: f64,
}

impl ShootingState {
    /// The state before the first shot: every patch holds its emission, unshot.
    #[must_use]
    pub fn new(mesh: &Mesh) -> Self {
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

    /// Emitted power summed over patches and bands.
    #[must_use]
    pub fn emitted_power(&self) -> f64 {
        self.emitted_power
    }

    /// The patch with the largest unshot power (bands summed, magnitudes, so
    /// that a negative correction from refinement is shot too); the lowest
    /// index among equals. `None` when nothing is left to shoot.
    #[must_use]
    pub fn choose_shooter(&self) -> Option<u32> {
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
    pub fn unshot_power_of(&self, p: u32) -> f64 {
        self.unshot[p as usize].abs().0.iter().sum::<f64>() * self.areas[p as usize]
    }

    /// Unshot power per band, magnitudes summed over patches.
    #[must_use]
    pub fn unshot_power(&self) -> Rgb {
        let mut sum = Rgb::ZERO;
        for (u, a) in self.unshot.iter().zip(&self.areas) {
            sum += u.abs() * *a;
        }
        sum
    }

    /// Unshot power over emitted power, bands summed (0 when nothing emits).
    #[must_use]
    pub fn unshot_fraction(&self) -> f64 {
        if self.emitted_power > 0.0 {
            self.unshot_power().0.iter().sum::<f64>() / self.emitted_power
        } else {
            0.0
        }
    }

    /// The largest unshot radiosity of any patch in any band: the residual
    /// `|E + rho F B - B|` of the system being solved.
    #[must_use]
    pub fn residual(&self) -> f64 {
        self.unshot
            .iter()
            .map(|u| u.abs().max_band())
            .fold(0.0, f64::max)
    }

    /// Takes patch `p`'s unshot radiosity for a shot: it becomes shot.
    pub fn take_unshot(&mut self, p: u32) -> Rgb {
        let u = std::mem::take(&mut self.unshot[p as usize]);
        self.shot[p as usize] += u;
        u
    }

    /// Leaf `key` receives irradiance `h`: its radiosity grows by `rho h`, and
    /// its patch's radiosity and unshot radiosity by the area-weighted share.
    pub fn receive(&mut self, mesh: &mut Mesh, key: ElementKey, h: Rgb) {
        let e = &mut mesh.elements[key];
        let rho = mesh.surfaces[e.surface as usize].reflectance;
        let db = rho * h;
        e.radiosity += db;
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
    pub fn set_leaf(&mut self, mesh: &mut Mesh, key: ElementKey, h: Rgb) {
        let e = &mut mesh.elements[key];
        let s = &mesh.surfaces[e.surface as usize];
        e.radiosity = s.emission + s.reflectance * h;
        self.irradiance.insert(key, h);
    }

    /// Recomputes patch `p`'s radiosity as the area mean of its leaves, and
    /// moves the change into its unshot radiosity so that what it has shot
    /// stays what it has shot. Returns the change in radiosity.
    pub fn resum_patch(&mut self, mesh: &Mesh, p: u32) -> Rgb {
        let mut sum = Rgb::ZERO;
        for k in mesh.patch_leaves(p) {
            let e = &mesh.elements[k];
            sum += e.radiosity * e.area;
        }
        let b = sum / self.areas[p as usize];
        let change = b - self.radiosity[p as usize];
        self.radiosity[p as usize] = b;
        self.unshot[p as usize] += change;
        change
    }

    /// Absorbed power per band, `sum A (1 - rho) H` over the leaves.
    #[must_use]
    pub fn absorbed_power(&self, mesh: &Mesh) -> Rgb {
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
