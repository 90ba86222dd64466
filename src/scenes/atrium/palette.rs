//! The atrium's materials: diffuse colours of stone, plaster, wood, terracotta,
//! foliage and cloth (reflectance 0.1 to 0.75 per band), and the emitting sky.

use super::sink::Sink;
use crate::error::Result;
use crate::math::Rgb;

/// Emitted radiance of the sky, per band (W m^-2 sr^-1 in the scene's
/// relative units; its exitance is pi times this, about 3.1). A pale
/// blue-white: an overcast sky with some blue. The court is a deep well
/// (12 m wide, 14 m high), so its floor receives about a fifth of that
/// exitance (the 10 000-triangle solve at default settings: mean floor
/// radiosity 0.26, irradiance about 0.57); only ratios matter to images at
/// automatic exposure.
pub(super) const SKY_RADIANCE: Rgb = Rgb([0.9, 1.0, 1.15]);

/// Indices of the materials, registered with the sink in this order.
#[derive(Clone, Copy, Debug)]
pub(super) struct Palette {
    /// Warm limestone: columns, arches, balustrades, fountain.
    pub stone: u32,
    /// Pale plaster: walls and ceilings.
    pub plaster: u32,
    /// Stone paving of the floors.
    pub paving: u32,
    /// Light oak: tables and benches.
    pub wood: u32,
    /// Dark walnut: some tables and benches.
    pub dark_wood: u32,
    /// Terracotta planters.
    pub terracotta: u32,
    /// Garden soil in the planters.
    pub soil: u32,
    /// Shrubs.
    pub foliage: u32,
    /// The fountain's water (diffuse, as the method requires).
    pub water: u32,
    /// Banner cloths.
    pub cloths: [u32; 3],
    /// The emitting sky.
    pub sky: u32,
}

impl Palette {
    /// Registers every material with `sink`.
    pub(super) fn register<S: Sink>(sink: &mut S) -> Result<Palette> {
        let mut diffuse =
            |name: &str, r: f64, g: f64, b: f64| sink.material(name, Rgb::new(r, g, b), Rgb::ZERO);
        let stone = diffuse("stone", 0.62, 0.58, 0.5)?;
        let plaster = diffuse("plaster", 0.75, 0.71, 0.64)?;
        let paving = diffuse("paving", 0.46, 0.43, 0.39)?;
        let wood = diffuse("oak", 0.55, 0.4, 0.25)?;
        let dark_wood = diffuse("walnut", 0.3, 0.2, 0.13)?;
        let terracotta = diffuse("terracotta", 0.62, 0.33, 0.21)?;
        let soil = diffuse("soil", 0.22, 0.17, 0.12)?;
        let foliage = diffuse("foliage", 0.14, 0.32, 0.1)?;
        let water = diffuse("water", 0.2, 0.3, 0.33)?;
        let cloths = [
            diffuse("cloth_red", 0.62, 0.12, 0.1)?,
            diffuse("cloth_blue", 0.12, 0.2, 0.5)?,
            diffuse("cloth_ochre", 0.7, 0.52, 0.18)?,
        ];
        // Reflectance 0: light that reaches the sky leaves the scene.
        let sky = sink.material("sky", Rgb::ZERO, SKY_RADIANCE)?;
        Ok(Palette {
            stone,
            plaster,
            paving,
            wood,
            dark_wood,
            terracotta,
            soil,
            foliage,
            water,
            cloths,
            sky,
        })
    }
}
