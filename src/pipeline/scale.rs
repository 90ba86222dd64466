//! The solve's emission scale. Radiosities are linear in emission, so a
//! scene whose brightest emission lies far from 1 is solved with every
//! emission multiplied by a power of two that brings the brightest band into
//! [1, 2), and the results are multiplied back at the end. Without it an
//! emission of 1e-300 puts the small terms of every sweep among the subnormal
//! doubles (a hundred times slower), and the stopping rule's `tolerance x
//! largest radiosity` can underflow to 0 and never be met; near 1e300 the
//! sums overflow. A power of two changes no significant bit, so a scene in
//! the comfortable range is left exactly as it is.

use crate::math::Rgb;
use crate::mesh::Mesh;
use crate::pipeline::SolveStats;
use crate::scene::Scene;
use crate::solve::{PatchSystem, Radiosity};

/// Brightest emissions whose binary exponent lies within this many of 0
/// (about 5e-20 to 2e19) are solved as they are.
const COMFORTABLE_EXPONENT: i32 = 64;

/// The power of two the solve's emissions were multiplied by.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct EmissionScale {
    /// The solve's values are the scene's times `2^-exponent`.
    exponent: i32,
}

impl EmissionScale {
    /// No scaling.
    pub(crate) const ONE: EmissionScale = EmissionScale { exponent: 0 };

    /// Scales the emissions of `mesh` when its brightest band lies outside
    /// the comfortable range, and returns the scale. A band so much dimmer
    /// than the brightest that it would leave the normal doubles (more than
    /// about 1e308 times dimmer) cannot count at any tolerance: it is set to
    /// 0, with a warning in `warnings` naming its material.
    ///
    /// A scene with punctual lights or a sky is solved at its own scale:
    /// their direct light is computed from the scene's intensities, in its
    /// units.
    pub(crate) fn normalise(mesh: &mut Mesh, scene: &Scene, warnings: &mut Vec<String>) -> Self {
        if !scene.lights.is_empty() || scene.sky.is_some() {
            return Self::ONE;
        }
        let brightest = mesh
            .surfaces
            .iter()
            .map(|s| s.emission.max_band())
            .fold(0.0, f64::max);
        if !brightest.is_normal() {
            return Self::ONE;
        }
        let exponent = binary_exponent(brightest);
        let scale = if exponent.abs() > COMFORTABLE_EXPONENT {
            EmissionScale { exponent }
        } else {
            Self::ONE
        };
        let floor = f64::MIN_POSITIVE * times_pow2(brightest, -scale.exponent);
        let mut dropped: Vec<&str> = Vec::new();
        for (lattice, surface) in mesh.surfaces.iter_mut().zip(&scene.surfaces) {
            let before = lattice.emission;
            let kept = Rgb(before.0.map(|e| {
                let scaled = times_pow2(e, -scale.exponent);
                if scaled.is_normal() && scaled >= floor {
                    scaled
                } else {
                    0.0
                }
            }));
            let lost = (0..3).any(|band| before[band] != 0.0 && kept[band] == 0.0);
            if lost {
                let name = scene.material_of(surface).name.as_str();
                if !dropped.contains(&name) {
                    dropped.push(name);
                }
            }
            lattice.emission = kept;
            if lattice.has_emission_texture() {
                lattice.emission_scale = times_pow2(1.0, -scale.exponent);
            }
        }
        if !scale.is_one() {
            let Mesh {
                elements, surfaces, ..
            } = mesh;
            for e in elements.values_mut() {
                e.emission = surfaces[e.surface as usize].cell_emission(&e.cell);
            }
        }
        if !dropped.is_empty() {
            warnings.push(format!(
                "emission treated as 0 in materials {}: more than {:e} times dimmer than \
                 the brightest emission ({brightest:e}), too little to represent beside it",
                dropped
                    .iter()
                    .map(|n| format!("'{n}'"))
                    .collect::<Vec<_>>()
                    .join(", "),
                1.0 / f64::MIN_POSITIVE,
            ));
        }
        scale
    }

    /// True when the solve runs at the scene's own scale.
    pub(crate) fn is_one(self) -> bool {
        self.exponent == 0
    }

    /// A value of the solve at the scene's scale.
    pub(crate) fn restore(self, x: f64) -> f64 {
        times_pow2(x, self.exponent)
    }

    /// A colour of the solve at the scene's scale.
    pub(crate) fn restore_rgb(self, x: Rgb) -> Rgb {
        Rgb(x.0.map(|v| self.restore(v)))
    }

    /// Brings everything a finished solve holds in radiosity or power units
    /// back to the scene's scale: the mesh's emissions (surfaces' and
    /// elements'), the radiosities, the
    /// patch system's emissions and the figures.
    pub(crate) fn restore_solution(
        self,
        mesh: &mut Mesh,
        radiosity: &mut Radiosity,
        system: &mut PatchSystem,
        stats: &mut SolveStats,
    ) {
        if self.is_one() {
            return;
        }
        for s in &mut mesh.surfaces {
            s.emission = self.restore_rgb(s.emission);
            s.emission_scale = 1.0;
        }
        for e in mesh.elements.values_mut() {
            e.emission = self.restore_rgb(e.emission);
        }
        radiosity.map_values(|v| self.restore_rgb(v));
        for e in &mut system.emission {
            *e = self.restore_rgb(*e);
        }
        let energy = &mut stats.energy;
        for power in [
            &mut energy.emitted_power,
            &mut energy.absorbed_power,
            &mut energy.back_face_power,
            &mut energy.escaped_power,
        ] {
            *power = self.restore_rgb(*power);
        }
        stats.solver.residual = self.restore(stats.solver.residual);
        stats.solver.error_bound = self.restore(stats.solver.error_bound);
        if let Some(p) = &mut stats.progressive {
            p.ambient = self.restore_rgb(p.ambient);
        }
    }
}

/// `floor(log2(x))` of a normal positive double.
fn binary_exponent(x: f64) -> i32 {
    ((x.to_bits() >> 52) & 0x7ff) as i32 - 1023
}

/// `x * 2^k`, exact while the result stays a normal double: in two steps, as
/// `2^k` alone may not be representable.
pub(crate) fn times_pow2(x: f64, k: i32) -> f64 {
    let half = k / 2;
    x * pow2(half) * pow2(k - half)
}

/// `2^k` for `k` in [-1022, 1023].
fn pow2(k: i32) -> f64 {
    let k = k.clamp(-1022, 1023);
    f64::from_bits(((k + 1023) as u64) << 52)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn powers_of_two_change_no_significant_bit() {
        for x in [1.0, 3.7, 1e-300, 2.5e300, f64::MIN_POSITIVE] {
            for k in [-1000, -64, -1, 0, 1, 64, 1000] {
                let y = times_pow2(x, k);
                if y.is_normal() {
                    assert_eq!(times_pow2(y, -k), x, "{x} {k}");
                }
            }
        }
        assert_eq!(binary_exponent(1.0), 0);
        assert_eq!(binary_exponent(3.9), 1);
        assert_eq!(binary_exponent(0.75), -1);
        assert_eq!(times_pow2(1e-300, 996), 1e-300 * 2f64.powi(996));
    }
}
