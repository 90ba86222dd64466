//! Base-colour textures as reflectance that varies over a surface.
//!
//! A [`Texture`] is a decoded linear image with the glTF sampler's wrap modes
//! and filter, the `KHR_texture_transform` of the material's texture
//! reference, which texture coordinate set it reads, and the factor its texels
//! are multiplied by (`baseColorFactor` times `1 - metallic`). Surfaces carry
//! per-vertex texture coordinates ([`Surface::uv`](super::Surface::uv)); each
//! element's reflectance is the texture averaged over the element's footprint
//! (see [`Texture::mean_over`]).

use super::LinearImage;
use crate::math::Rgb;
use glam::{DMat3, DVec2};
use smallvec::SmallVec;
use std::sync::Arc;

/// How texture coordinates outside 0 to 1 are brought back into the image
/// (glTF sampler `wrapS` / `wrapT`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Wrap {
    /// The image tiles (glTF's default).
    #[default]
    Repeat,
    /// The image tiles, every other copy mirrored.
    MirroredRepeat,
    /// Coordinates clamp to the edge texels.
    ClampToEdge,
}

impl Wrap {
    /// The wrap mode of a glTF sampler code (10497, 33648, 33071); any other
    /// code is glTF's default, repeat.
    #[must_use]
    pub(crate) fn from_gltf(code: u32) -> Self {
        match code {
            33648 => Wrap::MirroredRepeat,
            33071 => Wrap::ClampToEdge,
            _ => Wrap::Repeat,
        }
    }

    /// Texel index `i` of an axis `n` texels long, wrapped into range.
    fn texel(self, i: i64, n: u32) -> u32 {
        let n = i64::from(n.max(1));
        let r = match self {
            Wrap::Repeat => i.rem_euclid(n),
            Wrap::MirroredRepeat => {
                let m = i.rem_euclid(2 * n);
                if m < n {
                    m
                } else {
                    2 * n - 1 - m
                }
            }
            Wrap::ClampToEdge => i.clamp(0, n - 1),
        };
        r as u32
    }
}

/// A base-colour texture as a material uses it.
#[derive(Clone, Debug, PartialEq)]
pub struct Texture {
    /// The decoded image, shared by every material showing it.
    pub image: Arc<LinearImage>,
    /// Wrap modes along u and v.
    pub wrap: [Wrap; 2],
    /// Nearest texel instead of bilinear filtering (a sampler whose
    /// `magFilter` is `NEAREST`): what a viewer draws, so what is averaged.
    pub nearest: bool,
    /// Maps a vertex's texture coordinates to the image's (the
    /// `KHR_texture_transform` offset, rotation and scale; identity without).
    pub transform: DMat3,
    /// The `TEXCOORD_n` set the texture reads.
    pub texcoord: u32,
    /// What each texel is multiplied by: the base colour factor times
    /// `1 - metallic`.
    pub factor: Rgb,
    /// The largest value a band may take: the importer's reflectance clamp
    /// for a base-colour texture, infinity for an emissive one.
    pub max_value: f64,
}

/// Samples along each axis of an element's footprint: 8 x 8 on a quad cell,
/// 64 equal sub-triangles on a triangle cell. Fixed, so that the same element
/// always gets the same bits; a power of two, so that the sample cells of a
/// split element are exactly its children's and texel edges at binary
/// fractions of the surface fall between samples.
pub const FOOTPRINT_SAMPLES: u32 = 8;

impl Texture {
    /// A texture of `width x height` linear texels (row-major, row 0 at
    /// v = 0) shown as they are: nearest texel, tiled, no transform, read
    /// from `TEXCOORD_0`, factor 1, values at most 1. For scenes built in
    /// code; change the fields for anything else.
    #[must_use]
    pub fn nearest(width: u32, height: u32, texels: Vec<[f32; 3]>) -> Texture {
        Texture {
            image: Arc::new(LinearImage {
                width,
                height,
                texels,
            }),
            wrap: [Wrap::Repeat; 2],
            nearest: true,
            transform: DMat3::IDENTITY,
            texcoord: 0,
            factor: Rgb::ONE,
            max_value: 1.0,
        }
    }

    /// The value (reflectance, or exitance for an emissive texture) at texture
    /// coordinates `uv` (before the transform): the filtered texel times the
    /// factor, each band clamped to the maximum.
    #[must_use]
    pub fn value_at(&self, uv: DVec2) -> Rgb {
        let p = self.transform.transform_point2(uv);
        let texel = if self.nearest {
            self.nearest_texel(p)
        } else {
            self.bilinear(p)
        };
        Rgb((texel * self.factor)
            .0
            .map(|r| r.clamp(0.0, self.max_value)))
    }

    /// The mean value over a quad footprint whose texture coordinates are
    /// the bilinear map of `corners` (counter-clockwise from (0, 0)), or a
    /// triangle footprint (three corners), from a fixed stratified set of
    /// samples ([`FOOTPRINT_SAMPLES`]).
    #[must_use]
    pub fn mean_over(&self, corners: &[DVec2]) -> Rgb {
        self.sample_footprint(corners).mean()
    }

    /// [`Texture::mean_over`], where the samples disagree sharply (by more
    /// than [`SHARP_CONTRAST`] of the brightest) found again as the mean of
    /// the footprint's four quarters, `depth` times over. Stratified samples
    /// misplace a sharp edge by up to half their spacing; for emission,
    /// where a small bright detail's power decides the light around it,
    /// each level halves that error where it matters and costs nothing
    /// where the texture is even.
    #[must_use]
    pub fn mean_over_refined(&self, corners: &[DVec2], depth: u32) -> Rgb {
        let samples = self.sample_footprint(corners);
        if depth == 0 || !samples.is_sharp() {
            return samples.mean();
        }
        let quarters = quarters(corners);
        let sum = quarters.iter().fold(Rgb::ZERO, |sum, q| {
            sum + self.mean_over_refined(q, depth - 1)
        });
        sum / quarters.len().max(1) as f64
    }

    /// The stratified samples of a footprint (see [`Texture::mean_over`]).
    fn sample_footprint(&self, corners: &[DVec2]) -> Samples {
        let n = FOOTPRINT_SAMPLES;
        let step = 1.0 / f64::from(n);
        let mut samples = Samples::new();
        if corners.len() == 4 {
            for j in 0..n {
                for i in 0..n {
                    let s = (f64::from(i) + 0.5) * step;
                    let t = (f64::from(j) + 0.5) * step;
                    let bottom = corners[0].lerp(corners[1], s);
                    let top = corners[3].lerp(corners[2], s);
                    samples.add(self.value_at(bottom.lerp(top, t)));
                }
            }
        } else if corners.len() == 3 {
            // The centroids of the n^2 equal triangles a regular subdivision
            // cuts: "up" ones at (i + 1/3, j + 1/3), "down" ones at
            // (i + 2/3, j + 2/3), in steps of 1/n along the two legs.
            let (o, a, b) = (corners[0], corners[1] - corners[0], corners[2] - corners[0]);
            for j in 0..n {
                for i in 0..n - j {
                    let up = [1.0 / 3.0, 1.0 / 3.0];
                    let down = [2.0 / 3.0, 2.0 / 3.0];
                    for (k, d) in [up, down].iter().enumerate() {
                        if k == 1 && i + j + 1 >= n {
                            continue;
                        }
                        let s = (f64::from(i) + d[0]) * step;
                        let t = (f64::from(j) + d[1]) * step;
                        samples.add(self.value_at(o + a * s + b * t));
                    }
                }
            }
        }
        samples
    }

    fn texel(&self, x: i64, y: i64) -> Rgb {
        let img = &self.image;
        let x = self.wrap[0].texel(x, img.width);
        let y = self.wrap[1].texel(y, img.height);
        Rgb(img.texel(x, y).map(f64::from))
    }

    fn nearest_texel(&self, p: DVec2) -> Rgb {
        let x = (p.x * f64::from(self.image.width)).floor();
        let y = (p.y * f64::from(self.image.height)).floor();
        self.texel(saturate(x), saturate(y))
    }

    fn bilinear(&self, p: DVec2) -> Rgb {
        // Texel centres sit at half-integers.
        let x = p.x * f64::from(self.image.width) - 0.5;
        let y = p.y * f64::from(self.image.height) - 0.5;
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = (x - x0, y - y0);
        let (x0, y0) = (saturate(x0), saturate(y0));
        let top = self.texel(x0, y0) * (1.0 - fx) + self.texel(x0 + 1, y0) * fx;
        let bottom = self.texel(x0, y0 + 1) * (1.0 - fx) + self.texel(x0 + 1, y0 + 1) * fx;
        top * (1.0 - fy) + bottom * fy
    }
}

/// How many times an emissive texture's footprint is quartered where its
/// samples disagree sharply (see [`Texture::mean_over_refined`]).
pub const EMISSION_DEPTH: u32 = 3;

/// Samples of a footprint disagree sharply when their range in some band
/// exceeds this fraction of the brightest sample.
pub const SHARP_CONTRAST: f64 = 0.25;

/// A running sum of footprint samples, with their range.
struct Samples {
    sum: Rgb,
    count: u32,
    low: Rgb,
    high: Rgb,
}

impl Samples {
    fn new() -> Self {
        Samples {
            sum: Rgb::ZERO,
            count: 0,
            low: Rgb::splat(f64::INFINITY),
            high: Rgb::ZERO,
        }
    }

    fn add(&mut self, x: Rgb) {
        self.sum += x;
        self.count += 1;
        self.low = Rgb(std::array::from_fn(|i| self.low.0[i].min(x.0[i])));
        self.high = self.high.max(x);
    }

    fn mean(&self) -> Rgb {
        self.sum / f64::from(self.count.max(1))
    }

    fn is_sharp(&self) -> bool {
        (self.high - self.low).max_band() > SHARP_CONTRAST * self.high.max_band()
    }
}

/// The four quarters of a footprint, each of equal parameter area: a quad's
/// (the bilinear map restricted to a quarter of its square is the bilinear
/// map of the quarter's corners) or a triangle's (cut at its edges' midpoints).
fn quarters(c: &[DVec2]) -> SmallVec<[SmallVec<[DVec2; 4]>; 4]> {
    let mid = |a: DVec2, b: DVec2| (a + b) * 0.5;
    match c.len() {
        4 => {
            let centre = (c[0] + c[1] + c[2] + c[3]) * 0.25;
            let (b, r, t, l) = (
                mid(c[0], c[1]),
                mid(c[1], c[2]),
                mid(c[3], c[2]),
                mid(c[0], c[3]),
            );
            smallvec::smallvec![
                smallvec::smallvec![c[0], b, centre, l],
                smallvec::smallvec![b, c[1], r, centre],
                smallvec::smallvec![centre, r, c[2], t],
                smallvec::smallvec![l, centre, t, c[3]],
            ]
        }
        3 => {
            let (ab, bc, ca) = (mid(c[0], c[1]), mid(c[1], c[2]), mid(c[2], c[0]));
            smallvec::smallvec![
                smallvec::smallvec![c[0], ab, ca],
                smallvec::smallvec![ab, c[1], bc],
                smallvec::smallvec![ca, bc, c[2]],
                smallvec::smallvec![bc, ca, ab],
            ]
        }
        _ => SmallVec::new(),
    }
}

/// A texel index from a float, kept well inside `i64` (NaN becomes 0) so
/// that the wrap arithmetic cannot overflow.
fn saturate(x: f64) -> i64 {
    if x.is_nan() {
        0
    } else {
        x.clamp(-1e15, 1e15) as i64
    }
}

/// The `KHR_texture_transform` matrix: `T * R * S` as the extension defines
/// it (rotation counter-clockwise in UV space, which runs down the image).
#[must_use]
pub(crate) fn uv_transform(offset: [f64; 2], rotation: f64, scale: [f64; 2]) -> DMat3 {
    let (s, c) = rotation.sin_cos();
    let t = DMat3::from_cols_array(&[1.0, 0.0, 0.0, 0.0, 1.0, 0.0, offset[0], offset[1], 1.0]);
    let r = DMat3::from_cols_array(&[c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 1.0]);
    let sc = DMat3::from_cols_array(&[scale[0], 0.0, 0.0, 0.0, scale[1], 0.0, 0.0, 0.0, 1.0]);
    t * r * sc
}

#[cfg(test)]
mod tests {
    use super::*;

    fn checker() -> Texture {
        let (d, b) = ([0.2f32; 3], [0.8f32; 3]);
        Texture::nearest(2, 2, vec![d, b, b, d])
    }

    fn square(x0: f64, y0: f64, s: f64) -> [DVec2; 4] {
        [
            DVec2::new(x0, y0),
            DVec2::new(x0 + s, y0),
            DVec2::new(x0 + s, y0 + s),
            DVec2::new(x0, y0 + s),
        ]
    }

    #[test]
    fn a_checker_square_is_its_texel_and_a_straddling_one_the_mean() {
        let t = checker();
        assert_eq!(
            t.mean_over(&square(0.0, 0.0, 0.5)),
            Rgb::splat(0.2f32 as f64)
        );
        assert_eq!(
            t.mean_over(&square(0.5, 0.0, 0.25)),
            Rgb::splat(0.8f32 as f64)
        );
        let mid = t.mean_over(&square(0.25, 0.25, 0.5)).0[0];
        assert!((mid - 0.5).abs() < 1e-7, "{mid}");
        let tri = t.mean_over(&[DVec2::ZERO, DVec2::new(0.5, 0.0), DVec2::new(0.0, 0.5)]);
        assert_eq!(tri, Rgb::splat(0.2f32 as f64));
    }

    #[test]
    fn refined_means_place_a_sharp_edge_where_it_is() {
        // A footprint from u = 0.4 to 0.65 over the checker's edge at 0.5
        // (v inside one row): the dark part covers 0.1 / 0.25 = 0.4 of it,
        // so the exact mean is 0.4 x 0.2 + 0.6 x 0.8 = 0.56.
        let t = checker();
        let footprint = [
            DVec2::new(0.4, 0.1),
            DVec2::new(0.65, 0.1),
            DVec2::new(0.65, 0.35),
            DVec2::new(0.4, 0.35),
        ];
        let exact = 0.4 * f64::from(0.2f32) + 0.6 * f64::from(0.8f32);
        let error = |depth| (t.mean_over_refined(&footprint, depth).0[0] - exact).abs();
        // Eight samples across put the edge up to half a sample off (0.6 x
        // 1/16 of the footprint); each level of quarters halves that bound.
        assert!(error(0) > 0.01, "{}", error(0));
        for depth in 1..=3 {
            let bound = 0.6 / 16.0 / f64::from(1u32 << depth);
            assert!(
                error(depth) <= bound + 1e-12,
                "depth {depth}: {}",
                error(depth)
            );
        }
        assert_eq!(t.mean_over_refined(&footprint, 0), t.mean_over(&footprint));
        // Triangles are quartered too: one whose legs straddle the edge.
        let tri = [
            DVec2::new(0.4, 0.1),
            DVec2::new(0.65, 0.1),
            DVec2::new(0.4, 0.35),
        ];
        // Dark where u < 0.5: the part of the triangle left of the line,
        // a trapezoid of area (0.25 + 0.15) / 2 x 0.1 over the triangle's
        // 0.25^2 / 2.
        let dark = (0.25 + 0.15) / 2.0 * 0.1 / (0.25 * 0.25 / 2.0);
        let exact = dark * f64::from(0.2f32) + (1.0 - dark) * f64::from(0.8f32);
        let coarse = (t.mean_over(&tri).0[0] - exact).abs();
        let fine = (t.mean_over_refined(&tri, 3).0[0] - exact).abs();
        assert!(fine < coarse / 4.0 && fine < 0.01, "{coarse} {fine}");
    }

    #[test]
    fn wrap_modes_and_the_transform() {
        assert_eq!(Wrap::Repeat.texel(-1, 4), 3);
        assert_eq!(Wrap::MirroredRepeat.texel(4, 4), 3);
        assert_eq!(Wrap::MirroredRepeat.texel(-1, 4), 0);
        assert_eq!(Wrap::ClampToEdge.texel(9, 4), 3);
        let m = uv_transform([0.5, 0.0], 0.0, [2.0, 2.0]);
        let p = m.transform_point2(DVec2::new(0.25, 0.25));
        assert!((p - DVec2::new(1.0, 0.5)).length() < 1e-12);
    }
}
