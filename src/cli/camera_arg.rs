//! Parsing `--camera` values.

use anyhow::{bail, Context, Result};
use glam::DVec3;
use radiosity::scene::Camera;

/// Parses `EYE_X,EYE_Y,EYE_Z,TARGET_X,TARGET_Y,TARGET_Z,FOV_DEGREES`.
pub fn parse_camera(text: &str) -> Result<Camera> {
    let v: Vec<f64> = text
        .split(',')
        .map(|s| s.trim().parse::<f64>())
        .collect::<std::result::Result<_, _>>()
        .with_context(|| format!("--camera '{text}': expected 7 numbers separated by commas"))?;
    if v.len() != 7 {
        bail!(
            "--camera '{text}': expected 7 numbers (eye xyz, target xyz, fov), got {}",
            v.len()
        );
    }
    if v.iter().any(|x| !x.is_finite()) {
        bail!("--camera '{text}': numbers must be finite");
    }
    let eye = DVec3::new(v[0], v[1], v[2]);
    let target = DVec3::new(v[3], v[4], v[5]);
    if (target - eye).length() <= 0.0 {
        bail!("--camera '{text}': eye and target coincide");
    }
    if !(v[6] > 0.0 && v[6] < 180.0) {
        bail!("--camera '{text}': field of view must lie between 0 and 180 degrees");
    }
    Ok(Camera::look_at(eye, target, DVec3::Y, v[6]))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_and_rejects() {
        let c = parse_camera("0,0,5,0,0,0,45").unwrap();
        assert!((c.forward - DVec3::NEG_Z).length() < 1e-12);
        assert!((c.yfov - 45f64.to_radians()).abs() < 1e-12);
        assert!(parse_camera("0,0,5").is_err());
        assert!(parse_camera("0,0,0,0,0,0,45").is_err());
        assert!(parse_camera("0,0,5,0,0,0,190").is_err());
    }
}
