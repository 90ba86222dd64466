//! The polygons a hemi-cube rasterizes: each patch's (one for a cell of a
//! surface's lattice, one per surface for a face cluster), or one per element.

use super::point_to_polygon;
use crate::mesh::{ElementKey, Mesh};
use glam::{DMat3, DVec3};

/// Below this ratio of a polygon's bounding radius to its distance, its
/// unoccluded form factor is taken as the differential one (area times the
/// two cosines over pi r^2, at its centroid) rather than from Lambert's
/// contour formula. Taken at the area centroid, the first-order terms cancel
/// and the two differ by the order of the ratio squared: under 1e-3 of the
/// form factor here (unit test), far below the hemi-cube's own errors. A
/// face cluster of a large mesh holds hundreds of small triangles, each an
/// arc tangent per edge in every row that sees it: half the time of the rows
/// of the million-triangle atrium went there.
const FAR: f64 = 0.03;

/// The area and area centroid of a convex planar polygon of 3 or 4
/// vertices (a quad as two triangles; its vertex mean is its centroid only
/// when it is a parallelogram).
fn area_and_centroid(v: &[DVec3]) -> (f64, DVec3) {
    let triangle =
        |a: DVec3, b: DVec3, c: DVec3| ((b - a).cross(c - a).length() * 0.5, (a + b + c) / 3.0);
    let (a1, c1) = triangle(v[0], v[1], v[2]);
    if v.len() < 4 {
        return (a1, c1);
    }
    let (a2, c2) = triangle(v[0], v[2], v[3]);
    let area = a1 + a2;
    if area <= 0.0 {
        return (0.0, c1);
    }
    (area, (c1 * a1 + c2 * a2) / area)
}

/// A polygon as the hemi-cube sees it.
#[derive(Clone, Debug)]
pub struct SourcePolygon {
    /// Vertices (the first `count` are used).
    pub vertices: [DVec3; 4],
    /// 3 or 4.
    pub count: u8,
    /// Unit front normal.
    pub normal: DVec3,
    /// The surface it lies on (a receiver never sees its own planar surface).
    pub surface: u32,
    /// Bounding sphere centre and radius, for culling.
    pub centre: DVec3,
    /// Bounding sphere radius.
    pub radius: f64,
    /// The patch (or element) it belongs to: the id the item buffer holds.
    pub patch: u32,
}

/// Every patch's polygons, patch by patch.
#[derive(Clone, Debug, Default)]
pub struct Sources {
    /// The polygons, patch by patch in patch order.
    pub polygons: Vec<SourcePolygon>,
    /// Per patch, the index of its first polygon, and one more entry: the
    /// number of polygons (so patch `p` holds `first[p]..first[p + 1]`).
    pub first: Vec<u32>,
    /// Ids of the patches that emit (their visibility is found exactly where
    /// the hemi-cube is unsure).
    pub emitters: Vec<u32>,
    /// Per patch, the face cluster seen from afar, where it is one (see
    /// [`FarField`]); empty when no patch is.
    far: Vec<Option<FarField>>,
}

/// A face cluster as a whole, for its form factor from receivers far from it.
///
/// Each facet's differential form factor is its area times its normal
/// dotted with a function `g` of its centroid; expanding `g` about the
/// cluster's area centroid to first order, the sum over the facets is the
/// vector area (areas times normals, summed) dotted with `g` there, plus the
/// gradient of `g` contracted with the moment of the normals about the
/// centroid (areas times normals times offsets, summed). What is left is of
/// the order of (radius / distance) squared, as for one polygon (see
/// [`FAR`]); the moment vanishes on a flat cluster and carries the curvature
/// of a curved one, whose first-order terms would otherwise not cancel (2%
/// to 5% off at a radius 0.02 of the distance on the atrium's columns). It
/// holds while every facet faces the receiver, which the cluster's normal
/// cone tells.
#[derive(Clone, Copy, Debug)]
struct FarField {
    centroid: DVec3,
    vector_area: DVec3,
    /// Sum over the facets of area times normal times the transposed offset
    /// of the facet's centroid from `centroid`.
    moment: DMat3,
    /// Bounding radius about `centroid`.
    radius: f64,
    /// Every facet faces a point whose direction from the centroid, as a
    /// unit vector, has a dot product with the unit vector area above this:
    /// the sine of the cone's half-angle about it.
    facing: f64,
}

impl FarField {
    /// The far field of `polygons`, or `None` where their normals do not all
    /// lie within a right angle of their vector area.
    fn of(polygons: &[SourcePolygon]) -> Option<Self> {
        let (mut area, mut moment, mut vector_area) = (0.0, DVec3::ZERO, DVec3::ZERO);
        for q in polygons {
            let (a, c) = area_and_centroid(q.corners());
            area += a;
            moment += c * a;
            vector_area += q.normal * a;
        }
        let axis = vector_area.try_normalize()?;
        if area <= 0.0 {
            return None;
        }
        let centroid = moment / area;
        let mut facing: f64 = 0.0;
        let mut radius: f64 = 0.0;
        let mut normal_moment = DMat3::ZERO;
        for q in polygons {
            let (a, c) = area_and_centroid(q.corners());
            let offset = c - centroid;
            let n = q.normal * a;
            normal_moment += DMat3::from_cols(n * offset.x, n * offset.y, n * offset.z);
            let cos = q.normal.dot(axis);
            if cos <= 0.0 {
                return None;
            }
            facing = facing.max((1.0 - cos * cos).max(0.0).sqrt());
            for v in q.corners() {
                radius = radius.max((*v - centroid).length());
            }
        }
        Some(FarField {
            centroid,
            vector_area,
            moment: normal_moment,
            radius,
            facing,
        })
    }

    /// The cluster's form factor from (`eye`, unit `normal`) where the
    /// receiver is far enough and every facet faces it, else `None`.
    fn form_factor(&self, eye: DVec3, normal: DVec3) -> Option<f64> {
        let d = self.centroid - eye;
        let r2 = d.length_squared();
        let r = r2.sqrt();
        let toward = -self.vector_area.dot(d);
        let up = normal.dot(d);
        // The cosines at either end, the cluster's less its cone (beyond
        // which some facet would show its back).
        let (receiving, sending) = (
            up / r,
            toward / (self.vector_area.length() * r) - self.facing,
        );
        // What the expansion leaves is of the order of (radius / distance)
        // squared, relative to the form factor over the smaller cosine.
        if self.radius * self.radius >= FAR * FAR * r2 * receiving.min(sending) || up <= self.radius
        {
            return None;
        }
        let m = &self.moment;
        let trace = m.x_axis.x + m.y_axis.y + m.z_axis.z;
        let gradient = -up * trace - d.dot(*m * normal) + 4.0 * up * d.dot(*m * d) / r2;
        Some((toward * up + gradient) / (std::f64::consts::PI * r2 * r2))
    }
}

/// Emitters that together send less than this share of the emitted power
/// ([`significant_emitters`])...
pub(crate) const FAINT_POWER_SHARE: f64 = 1e-3;

/// ...and each shine with less than this share of the brightest emitter's
/// radiance are looked at as any other patch.
pub(crate) const FAINT_RADIANCE_SHARE: f64 = 1e-2;

/// The patches whose emission the rows look at with care (exact visibility
/// where the pixels are unsure, shadow rays, entries taken at an element's
/// points), in increasing order: every emitting patch but the faint tail.
///
/// An emissive texture's black is seldom 0 in a JPEG: on the Khronos lamp
/// 2 594 of 7 997 patches emit, 2 446 of them together 0.1% of the power,
/// and the rows spent most of their time tracing shadow rays to those. The
/// faint ones still emit; the pixels alone say how much of them a receiver
/// sees, as for a reflecting patch, which moves at most a few tenths of
/// [`FAINT_POWER_SHARE`] of the light.
fn significant_emitters(mesh: &Mesh) -> Vec<u32> {
    let emitting: Vec<(u32, f64, f64)> = (0..mesh.patches.len() as u32)
        .filter_map(|p| {
            let radiance = mesh.patch_emission(p).max_band();
            (radiance > 0.0).then(|| (p, radiance, radiance * mesh.patches[p as usize].area))
        })
        .collect();
    let brightest = emitting.iter().map(|e| e.1).fold(0.0, f64::max);
    let total: f64 = emitting.iter().map(|e| e.2).sum();
    let mut by_power: Vec<&(u32, f64, f64)> = emitting.iter().collect();
    by_power.sort_by(|a, b| a.2.total_cmp(&b.2).then(a.0.cmp(&b.0)));
    let mut faint = vec![false; mesh.patches.len()];
    let mut sum = 0.0;
    for &&(p, radiance, power) in &by_power {
        sum += power;
        if sum >= FAINT_POWER_SHARE * total {
            break;
        }
        faint[p as usize] = radiance < FAINT_RADIANCE_SHARE * brightest;
    }
    emitting
        .iter()
        .map(|e| e.0)
        .filter(|&p| !faint[p as usize])
        .collect()
}

impl Sources {
    /// The patch polygons of a mesh.
    #[must_use]
    pub fn from_mesh(mesh: &Mesh) -> Self {
        let mut sources = Sources::default();
        for (id, p) in mesh.patches.iter().enumerate() {
            sources.first.push(sources.polygons.len() as u32);
            if !p.is_cluster() {
                let mut polygon = SourcePolygon::new(
                    &p.polygon,
                    mesh.surfaces[p.surface as usize].normal,
                    p.surface,
                );
                polygon.patch = id as u32;
                sources.polygons.push(polygon);
                continue;
            }
            for &root in &p.roots {
                let e = &mesh.elements[root];
                let lattice = &mesh.surfaces[e.surface as usize];
                let mut polygon =
                    SourcePolygon::new(&lattice.polygon(&e.cell), lattice.normal, e.surface);
                polygon.patch = id as u32;
                sources.polygons.push(polygon);
            }
        }
        sources.first.push(sources.polygons.len() as u32);
        sources.emitters = significant_emitters(mesh);
        if mesh.patches.iter().any(|p| p.is_cluster()) {
            sources.far = (0..mesh.patches.len() as u32)
                .map(|p| match sources.patch(p) {
                    [_] => None,
                    many => FarField::of(many),
                })
                .collect();
        }
        sources
    }

    /// The polygons of the given elements, each its own patch: ids are their
    /// positions in `keys` (an item buffer of element ids, as a shooting
    /// patch needs).
    #[must_use]
    pub(crate) fn from_elements(mesh: &Mesh, keys: &[ElementKey]) -> Self {
        let polygons = keys
            .iter()
            .enumerate()
            .map(|(i, &k)| {
                let e = &mesh.elements[k];
                let lattice = &mesh.surfaces[e.surface as usize];
                let mut polygon =
                    SourcePolygon::new(&lattice.polygon(&e.cell), lattice.normal, e.surface);
                polygon.patch = i as u32;
                polygon
            })
            .collect();
        Sources {
            polygons,
            first: (0..=keys.len() as u32).collect(),
            emitters: Vec::new(),
            far: Vec::new(),
        }
    }

    /// Sources of one polygon per patch, patch `i` being `polygons[i]`
    /// (their `patch` fields are set to match).
    #[must_use]
    pub fn one_per_patch(mut polygons: Vec<SourcePolygon>) -> Self {
        for (i, p) in polygons.iter_mut().enumerate() {
            p.patch = i as u32;
        }
        let first = (0..=polygons.len() as u32).collect();
        Sources {
            polygons,
            first,
            emitters: Vec::new(),
            far: Vec::new(),
        }
    }

    /// Number of patches.
    #[must_use]
    pub(crate) fn patch_count(&self) -> usize {
        self.first.len().saturating_sub(1)
    }

    /// The indices of patch `p`'s polygons.
    #[must_use]
    pub fn range(&self, p: u32) -> std::ops::Range<usize> {
        self.first[p as usize] as usize..self.first[p as usize + 1] as usize
    }

    /// Patch `p`'s polygons.
    #[must_use]
    pub fn patch(&self, p: u32) -> &[SourcePolygon] {
        &self.polygons[self.range(p)]
    }

    /// Lambert's unoccluded form factor from (`eye`, unit `normal`) to patch
    /// `p`, clipped to the horizon: its polygon's, or for a face cluster the
    /// sum over its polygons that face the eye (the others show their backs),
    /// taken as a whole where the eye is far from it (by its area, centroid
    /// and second moment, to the order of its radius over the distance
    /// squared).
    #[must_use]
    pub(crate) fn exact_form_factor(&self, p: u32, eye: DVec3, normal: DVec3) -> f64 {
        match self.patch(p) {
            [one] => one.form_factor(eye, normal),
            many => self
                .far
                .get(p as usize)
                .and_then(|f| f.as_ref())
                .and_then(|f| f.form_factor(eye, normal))
                .unwrap_or_else(|| facet_sum(many, eye, normal)),
        }
    }
}

/// The sum of the form factors of the `polygons` that face `eye`.
fn facet_sum(polygons: &[SourcePolygon], eye: DVec3, normal: DVec3) -> f64 {
    polygons
        .iter()
        .filter(|q| q.faces(eye))
        .map(|q| q.form_factor(eye, normal))
        .sum()
}

impl SourcePolygon {
    /// The source polygon of a convex world polygon (3 or 4 vertices) with its
    /// surface's unit normal (its `patch` 0 until set).
    #[must_use]
    pub fn new(polygon: &[DVec3], normal: DVec3, surface: u32) -> Self {
        let mut vertices = [DVec3::ZERO; 4];
        for (slot, v) in vertices.iter_mut().zip(polygon) {
            *slot = *v;
        }
        let centre = polygon.iter().copied().sum::<DVec3>() / polygon.len() as f64;
        let radius = polygon
            .iter()
            .map(|v| (*v - centre).length())
            .fold(0.0, f64::max);
        SourcePolygon {
            vertices,
            count: polygon.len() as u8,
            normal,
            surface,
            centre,
            radius,
            patch: 0,
        }
    }

    /// Its vertices.
    #[must_use]
    pub fn corners(&self) -> &[DVec3] {
        &self.vertices[..self.count as usize]
    }

    /// Its area and area centroid.
    #[must_use]
    pub(crate) fn area_and_centroid(&self) -> (f64, DVec3) {
        area_and_centroid(self.corners())
    }

    /// Its unoccluded form factor from (`eye`, unit `normal`), clipped to the
    /// horizon, either side facing: Lambert's formula, or where it is small
    /// and far (see [`FAR`]) and wholly above the horizon, the differential
    /// form factor at its centroid.
    #[must_use]
    pub(crate) fn form_factor(&self, eye: DVec3, normal: DVec3) -> f64 {
        self.form_factor_within(eye, normal, FAR)
    }

    /// [`Self::form_factor`], taking the differential form factor wherever
    /// the polygon's bounding radius is under `far` times its distance: the
    /// two differ by the order of that ratio squared.
    #[must_use]
    pub(crate) fn form_factor_within(&self, eye: DVec3, normal: DVec3, far: f64) -> f64 {
        self.form_factor_within_given(eye, normal, far, || self.area_and_centroid())
    }

    /// [`Self::form_factor_within`], with its area and area centroid from
    /// `area_centroid` (for a caller that keeps them) when it needs them.
    #[must_use]
    pub(crate) fn form_factor_within_given(
        &self,
        eye: DVec3,
        normal: DVec3,
        far: f64,
        area_centroid: impl FnOnce() -> (f64, DVec3),
    ) -> f64 {
        let d = self.centre - eye;
        let r2 = d.length_squared();
        if self.radius * self.radius < far * far * r2 && normal.dot(d) > self.radius {
            // At the area centroid the first-order terms cancel.
            let (area, centroid) = area_centroid();
            let d = centroid - eye;
            let r2 = d.length_squared();
            let (up, facing) = (normal.dot(d), self.normal.dot(d).abs());
            return area * up * facing / (std::f64::consts::PI * r2 * r2);
        }
        point_to_polygon(eye, normal, self.corners())
    }

    /// True when `eye` lies in front of its plane.
    #[must_use]
    pub fn faces(&self, eye: DVec3) -> bool {
        self.normal.dot(eye - self.vertices[0]) > 0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::formfactor::visibility::unit;
    use crate::math::Rgb;
    use crate::scene::SceneBuilder;

    /// A 1 m square lamp of radiance `lamp` under a floor of `n x n` tiles
    /// of 0.1 m, each of radiance `tile`.
    fn lamp_over_tiles(lamp: f64, tile: f64, n: u32) -> Mesh {
        let mut b = SceneBuilder::new("tiles");
        let bright = b
            .material("lamp", Rgb::splat(0.5), Rgb::splat(lamp))
            .unwrap();
        let faint = b
            .material("tile", Rgb::splat(0.5), Rgb::splat(tile))
            .unwrap();
        b.object("lamp");
        let v = DVec3::new;
        b.quad(
            bright,
            v(0., 3., 0.),
            v(1., 3., 0.),
            v(1., 3., 1.),
            v(0., 3., 1.),
        )
        .unwrap();
        b.object("floor");
        for i in 0..n {
            for j in 0..n {
                let (x, z) = (0.1 * f64::from(i), 0.1 * f64::from(j));
                b.quad(
                    faint,
                    v(x, 0., z),
                    v(x, 0., z + 0.1),
                    v(x + 0.1, 0., z + 0.1),
                    v(x + 0.1, 0., z),
                )
                .unwrap();
            }
        }
        Mesh::new(&b.build().unwrap(), 1.0, 100_000).unwrap()
    }

    /// The emitting patches of `mesh`, and those of them as bright as the
    /// brightest.
    fn emitting(mesh: &Mesh) -> (Vec<u32>, Vec<u32>) {
        let all: Vec<u32> = (0..mesh.patches.len() as u32)
            .filter(|&p| mesh.patch_emission(p).max_band() > 0.0)
            .collect();
        let brightest = all
            .iter()
            .map(|&p| mesh.patch_emission(p).max_band())
            .fold(0.0, f64::max);
        let bright = all
            .iter()
            .copied()
            .filter(|&p| mesh.patch_emission(p).max_band() == brightest)
            .collect();
        (all, bright)
    }

    #[test]
    fn a_faint_tail_of_emitters_is_looked_at_as_reflectors_and_the_rest_as_emitters() {
        // Tiles at 1e-5 of the lamp's radiance send 1.6e-5 of the power all
        // told: below both shares, so only the lamp's patches are emitters.
        let mesh = lamp_over_tiles(10.0, 1e-4, 40);
        let (all, lamp) = emitting(&mesh);
        assert!(all.len() > lamp.len());
        assert_eq!(Sources::from_mesh(&mesh).emitters, lamp);
        // At 1e-2 of the lamp's radiance (14% of the power) and as bright as
        // the lamp, every emitting patch is an emitter.
        for tile in [0.1, 10.0] {
            let mesh = lamp_over_tiles(10.0, tile, 40);
            assert_eq!(Sources::from_mesh(&mesh).emitters, emitting(&mesh).0);
        }
    }

    #[test]
    fn small_far_polygons_match_lamberts_formula_to_1e_minus_3() {
        // Random triangles and trapezoids just inside the threshold, at
        // random distances, directions and tilts above a receiver facing +z:
        // the differential form factor against Lambert's contour formula
        // (measured: 5.9e-4 at worst).
        let mut state = 11u64;
        let mut next = || unit(&mut state);
        let (mut far, mut worst) = (0, 0.0f64);
        for k in 0..4000 {
            let distance = 0.5 + 20.0 * next();
            let dir = DVec3::new(next() - 0.5, next() - 0.5, 0.2 + next()).normalize();
            let centre = dir * distance;
            let size = FAR * distance * (0.5 + 0.45 * next());
            let tilt = DVec3::new(next() - 0.5, next() - 0.5, next() - 0.5).normalize();
            let u = tilt.any_orthonormal_vector();
            let w = tilt.cross(u);
            let corners: Vec<DVec3> = if k % 2 == 0 {
                (0..3)
                    .map(|i| {
                        let a = std::f64::consts::TAU * (i as f64 + 0.3 * next()) / 3.0;
                        centre + (u * a.cos() + w * a.sin()) * size
                    })
                    .collect()
            } else {
                // A trapezoid, whose vertex mean is not its centroid.
                let (top, bottom) = (0.2 + 0.5 * next(), 0.7);
                [(-bottom, -0.6), (bottom, -0.6), (top, 0.6), (-top, 0.6)]
                    .iter()
                    .map(|(x, y)| centre + (u * *x + w * *y) * size)
                    .collect()
            };
            let poly = SourcePolygon::new(&corners, tilt, 0);
            let exact = point_to_polygon(DVec3::ZERO, DVec3::Z, &corners);
            let got = poly.form_factor(DVec3::ZERO, DVec3::Z);
            if exact <= 1e-12 {
                continue;
            }
            let far_enough = poly.radius < FAR * poly.centre.length();
            far += usize::from(far_enough && poly.centre.z > poly.radius);
            worst = worst.max((got - exact).abs() / exact);
        }
        assert!(far > 3000, "{far} polygons took the differential form");
        assert!(worst < 1e-3, "worst relative difference {worst:.2e}");
    }

    #[test]
    fn far_face_clusters_match_the_sum_over_their_facets() {
        // Every face cluster of the 10k atrium from the centres of a spread
        // of its leaves: taken whole where far, against the sum over its
        // facets (measured: 6.6e-4 at worst; 1.5e-2 when the distance did
        // not depend on the cosines, 5.5e-2 without the normals' moment).
        use crate::mesh::Mesh;
        let scene = crate::scenes::atrium(10_000).unwrap();
        let mesh = Mesh::new(&scene, scene.extent() / 10.0, 1_000_000).unwrap();
        let sources = Sources::from_mesh(&mesh);
        let clusters: Vec<u32> = (0..sources.patch_count() as u32)
            .filter(|&p| sources.patch(p).len() > 1)
            .collect();
        assert!(clusters.len() > 100);
        let (mut whole, mut pairs, mut worst) = (0, 0, 0.0f64);
        for k in mesh.leaves().into_iter().step_by(97) {
            let e = mesh.element(k).unwrap();
            let normal = mesh.surfaces[e.surface as usize].normal;
            let eye = e.centroid + normal * 1e-3;
            for &p in &clusters {
                pairs += 1;
                let sum = facet_sum(sources.patch(p), eye, normal);
                let far = sources.far[p as usize].and_then(|f| f.form_factor(eye, normal));
                let Some(far) = far else {
                    assert_eq!(sources.exact_form_factor(p, eye, normal), sum);
                    continue;
                };
                whole += 1;
                assert_eq!(sources.exact_form_factor(p, eye, normal), far);
                let rel = (far - sum).abs() / sum;
                worst = worst.max(rel);
            }
        }
        eprintln!("{whole} of {pairs} taken whole, worst relative difference {worst:.2e}");
        assert!(whole > 1000, "{whole}");
        assert!(worst < 1e-3, "{worst}");
    }
}
