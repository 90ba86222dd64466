//! Enclosure identities that hold for any geometry (one colour band).
//!
//! In a closed scene every row of form factors sums to one. With a uniform
//! reflectance `rho`, multiplying `B_i = E_i + rho sum_j F_ij B_j` by `A_i`,
//! summing over `i` and using reciprocity (`A_i F_ij = A_j F_ji`) gives
//! `sum_i A_i B_i = sum_i A_i E_i / (1 - rho)`. If the emission is uniform too
//! (the furnace), the solution itself is uniform: `B = E / (1 - rho)`.

use crate::error::{Error, GeometryFault, Result};

/// The radiosity everywhere in a closed enclosure whose surfaces all have the
/// same reflectance `reflectance` and emitted exitance `emission`:
/// `E / (1 - rho)`.
///
/// Fails unless `0 <= rho < 1` and `E` is finite and non-negative.
pub fn furnace_radiosity(emission: f64, reflectance: f64) -> Result<f64> {
    check_reflectance(reflectance)?;
    check_emission(emission)?;
    Ok(emission / (1.0 - reflectance))
}

/// The area-weighted mean radiosity `sum A_i B_i / sum A_i` of a closed
/// enclosure with uniform reflectance, whatever the emission's layout:
/// `sum A_i E_i / ((1 - rho) sum A_i)`.
///
/// Fails unless `areas` and `emission` have the same non-zero length, areas are
/// finite and positive, emissions finite and non-negative, and `0 <= rho < 1`.
pub fn enclosure_mean_radiosity(areas: &[f64], emission: &[f64], reflectance: f64) -> Result<f64> {
    check_reflectance(reflectance)?;
    if areas.is_empty() || areas.len() != emission.len() {
        let fault = if areas.len() == emission.len() {
            GeometryFault::NoSurfaces
        } else {
            GeometryFault::Mismatch
        };
        return Err(Error::geometry(
            fault,
            format!(
                "enclosure needs one area per emission value and at least one surface, got {} areas and {} emissions",
                areas.len(),
                emission.len()
            ),
        ));
    }
    if let Some(a) = areas.iter().find(|a| !(a.is_finite() && **a > 0.0)) {
        return Err(Error::geometry(
            GeometryFault::OutOfRange,
            format!("enclosure surface area {a} is not finite and positive"),
        ));
    }
    for e in emission {
        check_emission(*e)?;
    }
    let total_area: f64 = areas.iter().sum();
    let power: f64 = areas.iter().zip(emission).map(|(a, e)| a * e).sum();
    Ok(power / ((1.0 - reflectance) * total_area))
}

fn check_reflectance(rho: f64) -> Result<()> {
    if (0.0..1.0).contains(&rho) {
        Ok(())
    } else {
        Err(Error::Material {
            material: "enclosure".to_string(),
            message: format!(
                "uniform reflectance {rho} must be in [0, 1): at 1 a closed scene has no finite radiosity"
            ),
        })
    }
}

fn check_emission(e: f64) -> Result<()> {
    if e.is_finite() && e >= 0.0 {
        Ok(())
    } else {
        Err(Error::Material {
            material: "enclosure".to_string(),
            message: format!("emission {e} is negative or not finite"),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn furnace_and_mean() {
        assert_eq!(furnace_radiosity(2.0, 0.5).unwrap(), 4.0);
        let m = enclosure_mean_radiosity(&[1.0, 3.0], &[4.0, 0.0], 0.75).unwrap();
        assert_eq!(m, 4.0);
    }

    #[test]
    fn out_of_range_is_refused() {
        assert!(furnace_radiosity(1.0, 1.0).is_err());
        assert!(furnace_radiosity(-1.0, 0.5).is_err());
        assert!(enclosure_mean_radiosity(&[1.0], &[1.0, 2.0], 0.5).is_err());
        assert!(enclosure_mean_radiosity(&[0.0], &[1.0], 0.5).is_err());
    }
}
