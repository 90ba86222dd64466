//! The exact oracles against the research brief's check values, against each
//! other, and against independent numerical integration and Monte Carlo written
//! here, without the library's clipping or quadrature code.

use glam::DVec3;
use radiosity::analytic::convex_clip::convex_intersection;
use radiosity::analytic::cube::{unit_cube_form_factors, CubeFace};
use radiosity::analytic::{
    enclosure_mean_radiosity, furnace_radiosity, integrate_over_polygon, integrate_unit_square,
    parallel_rectangles, perpendicular_rectangles, point_to_polygon, point_to_rectangle_corner,
    unit_cube_ceiling_lit, unit_cube_radiosity, OccludedLight, QuadratureSettings,
};
use radiosity::math::polygon_area;
use radiosity::scenes::penumbra::{self, PenumbraSpec, VARIANTS};
use std::f64::consts::PI;

// ---------------------------------------------------------------------------
// Independent numerical tools.

/// Gauss-Legendre nodes and weights on [0, 1], by Newton's method on P_n.
fn gauss_legendre(n: usize) -> Vec<(f64, f64)> {
    let legendre = |x: f64| {
        let (mut p0, mut p1) = (1.0, x);
        for k in 2..=n {
            let k = k as f64;
            let p2 = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k;
            p0 = p1;
            p1 = p2;
        }
        let derivative = n as f64 * (x * p1 - p0) / (x * x - 1.0);
        (p1, derivative)
    };
    (0..n)
        .map(|i| {
            let mut x = (PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
            for _ in 0..100 {
                let (p, dp) = legendre(x);
                let step = p / dp;
                x -= step;
                if step.abs() < 1e-16 {
                    break;
                }
            }
            let (_, dp) = legendre(x);
            (0.5 * (x + 1.0), 1.0 / ((1.0 - x * x) * dp * dp))
        })
        .collect()
}

/// Composite tensor Gauss-Legendre over [u0, u1] x [v0, v1]: `cells` x `cells`
/// cells with an `order`-point rule on each.
fn composite_gauss(
    f: &mut dyn FnMut(f64, f64) -> f64,
    (u0, u1): (f64, f64),
    (v0, v1): (f64, f64),
    cells: usize,
    order: usize,
) -> f64 {
    let rule = gauss_legendre(order);
    let (du, dv) = ((u1 - u0) / cells as f64, (v1 - v0) / cells as f64);
    let mut sum = 0.0;
    for i in 0..cells {
        for j in 0..cells {
            for (x, wx) in &rule {
                for (y, wy) in &rule {
                    let u = u0 + du * (i as f64 + x);
                    let v = v0 + dv * (j as f64 + y);
                    sum += wx * wy * f(u, v);
                }
            }
        }
    }
    sum * du * dv
}

/// The point-to-area form factor kernel `cos_i cos_j / (pi r^2)` from a point
/// with unit normal `n` to a surface point `q` with unit normal `m`; the
/// receiver's cosine is clamped at zero unless `clamp` is false.
fn kernel(p: DVec3, n: DVec3, q: DVec3, m: DVec3, clamp: bool) -> f64 {
    let r = q - p;
    let r2 = r.length_squared();
    let d = r2.sqrt();
    let mut cos_i = n.dot(r) / d;
    if clamp {
        cos_i = cos_i.max(0.0);
    }
    cos_i * m.dot(r).abs() / d / (PI * r2)
}

/// A small seeded generator (SplitMix64), so that the Monte Carlo checks are
/// reproducible bit for bit.
struct SplitMix64(u64);

impl SplitMix64 {
    fn next_f64(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        (z >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }
}

/// True when the open segment from `a` to `b` crosses the convex planar quad.
fn segment_hits_quad(a: DVec3, b: DVec3, quad: &[DVec3; 4]) -> bool {
    let m = (quad[1] - quad[0]).cross(quad[2] - quad[0]);
    let denominator = m.dot(b - a);
    if denominator == 0.0 {
        return false;
    }
    let t = m.dot(quad[0] - a) / denominator;
    if !(t > 0.0 && t < 1.0) {
        return false;
    }
    let h = a + (b - a) * t;
    let sides: Vec<f64> = (0..4)
        .map(|k| (quad[(k + 1) % 4] - quad[k]).cross(h - quad[k]).dot(m))
        .collect();
    sides.iter().all(|s| *s >= 0.0) || sides.iter().all(|s| *s <= 0.0)
}

/// Monte Carlo estimate of the visible form factor from floor point `x` (normal
/// +y) to the light, with its standard error.
fn monte_carlo_form_factor(spec: &PenumbraSpec, x: DVec3, samples: usize, seed: u64) -> (f64, f64) {
    monte_carlo_occluded(&spec.light, &spec.occluders, x, DVec3::Y, samples, seed)
}

/// Monte Carlo estimate of the visible form factor from `x` with unit normal `n`
/// to a convex light behind quad occluders, with its standard error: uniform
/// samples on the light (a fan of triangles chosen by area),
/// `A cos_i cos_l V / (pi r^2)`.
fn monte_carlo_occluded(
    light: &[DVec3],
    occluders: &[[DVec3; 4]],
    x: DVec3,
    n: DVec3,
    samples: usize,
    seed: u64,
) -> (f64, f64) {
    let light_normal = (light[1] - light[0]).cross(light[2] - light[0]).normalize();
    let triangles: Vec<[DVec3; 3]> = (1..light.len() - 1)
        .map(|k| [light[0], light[k], light[k + 1]])
        .collect();
    let areas: Vec<f64> = triangles
        .iter()
        .map(|t| 0.5 * (t[1] - t[0]).cross(t[2] - t[0]).length())
        .collect();
    let total_area: f64 = areas.iter().sum();
    let mut rng = SplitMix64(seed);
    let (mut sum, mut sum2) = (0.0, 0.0);
    for _ in 0..samples {
        let mut pick = rng.next_f64() * total_area;
        let mut k = 0;
        while k + 1 < areas.len() && pick >= areas[k] {
            pick -= areas[k];
            k += 1;
        }
        let [a, b, c] = triangles[k];
        let r1 = rng.next_f64().sqrt();
        let r2 = rng.next_f64();
        let y = a * (1.0 - r1) + b * (r1 * (1.0 - r2)) + c * (r1 * r2);
        let hidden = occluders.iter().any(|q| segment_hits_quad(x, y, q));
        let value = if hidden {
            0.0
        } else {
            total_area * kernel(x, n, y, light_normal, true)
        };
        sum += value;
        sum2 += value * value;
    }
    let n = samples as f64;
    let mean = sum / n;
    let variance = (sum2 / n - mean * mean).max(0.0) * n / (n - 1.0);
    (mean, (variance / n).sqrt())
}

fn assert_close(actual: f64, expected: f64, tolerance: f64, what: &str) {
    assert!(
        (actual - expected).abs() <= tolerance,
        "{what}: got {actual:.12}, expected {expected:.12} (tolerance {tolerance:e})"
    );
}

// ---------------------------------------------------------------------------
// Closed forms against the brief's tables (section 4.1, 4.2).

#[test]
fn howell_c11_check_values() {
    let table = [
        (1.0, 1.0, 1.0, 0.199825),
        (1.0, 1.0, 0.5, 0.415253),
        (1.0, 1.0, 2.0, 0.068590),
        (1.0, 2.0, 1.0, 0.285875),
        (1.0, 1.5, 0.5, 0.475576),
    ];
    for (a, b, c, f) in table {
        assert_close(parallel_rectangles(a, b, c).unwrap(), f, 1e-6, "C-11");
        // Symmetric in the two sides.
        assert_close(
            parallel_rectangles(b, a, c).unwrap(),
            parallel_rectangles(a, b, c).unwrap(),
            1e-15,
            "C-11 a <-> b",
        );
    }
}

#[test]
fn howell_c14_check_values_and_reciprocity() {
    let table = [
        (1.0, 1.0, 1.0, 0.200044),
        (1.0, 2.0, 1.0, 0.232853),
        (2.0, 1.0, 1.0, 0.116426),
        (1.0, 1.0, 2.0, 0.240636),
        (2.0, 2.0, 1.0, 0.149300),
    ];
    for (w, h, l, f) in table {
        assert_close(perpendicular_rectangles(w, h, l).unwrap(), f, 1e-6, "C-14");
    }
    // Reciprocity: A1 F12 = A2 F21, i.e. w F(w, h, l) = h F(h, w, l); and only
    // ratios matter.
    for (w, h, l) in [
        (1.0, 2.0, 1.0),
        (0.3, 5.0, 2.0),
        (7.0, 0.2, 0.9),
        (1.0, 1.0, 3.0),
    ] {
        let f12 = perpendicular_rectangles(w, h, l).unwrap();
        let f21 = perpendicular_rectangles(h, w, l).unwrap();
        assert_close(w * l * f12, h * l * f21, 1e-14 * w * l, "C-14 reciprocity");
        let scaled = perpendicular_rectangles(3.0 * w, 3.0 * h, 3.0 * l).unwrap();
        assert_close(scaled, f12, 1e-14, "C-14 scale invariance");
    }
}

#[test]
fn corner_formula_check_values() {
    for (x, y, f) in [
        (1.0, 1.0, 0.138532),
        (2.0, 3.0, 0.217575),
        (0.5, 0.5, 0.059864),
    ] {
        assert_close(
            point_to_rectangle_corner(x, y, 1.0).unwrap(),
            f,
            1e-6,
            "corner",
        );
    }
}

// ---------------------------------------------------------------------------
// Lambert's formula against the corner formula and numerical integration.

#[test]
fn lambert_agrees_with_the_corner_formula() {
    for (a, b, c) in [
        (1.0, 1.0, 1.0),
        (2.0, 3.0, 1.0),
        (0.5, 0.5, 1.0),
        (0.3, 4.0, 2.5),
    ] {
        // Receiver at the origin facing +y; the rectangle's corner is above it.
        let rect = [
            DVec3::new(0.0, c, 0.0),
            DVec3::new(a, c, 0.0),
            DVec3::new(a, c, b),
            DVec3::new(0.0, c, b),
        ];
        let lambert = point_to_polygon(DVec3::ZERO, DVec3::Y, &rect).unwrap();
        let corner = point_to_rectangle_corner(a, b, c).unwrap();
        assert_close(lambert, corner, 1e-12, "Lambert vs corner formula");
    }
    // A foot inside the rectangle: the sum of four corner rectangles.
    let rect = [
        DVec3::new(-0.4, 2.0, -1.0),
        DVec3::new(1.1, 2.0, -1.0),
        DVec3::new(1.1, 2.0, 0.7),
        DVec3::new(-0.4, 2.0, 0.7),
    ];
    let four: f64 = [(0.4, 1.0), (1.1, 1.0), (1.1, 0.7), (0.4, 0.7)]
        .iter()
        .map(|(a, b)| point_to_rectangle_corner(*a, *b, 2.0).unwrap())
        .sum();
    let lambert = point_to_polygon(DVec3::ZERO, DVec3::Y, &rect).unwrap();
    assert_close(lambert, four, 1e-12, "Lambert vs four corners");
}

#[test]
fn lambert_agrees_with_integration_for_a_tilted_triangle() {
    let p = DVec3::new(0.1, -0.2, 0.3);
    let n = DVec3::new(0.3, 1.0, -0.2).normalize();
    let [a, b, c] = [
        DVec3::new(-0.5, 1.2, 0.1),
        DVec3::new(0.8, 0.9, -0.4),
        DVec3::new(0.2, 1.6, 0.9),
    ];
    for v in [a, b, c] {
        assert!(
            n.dot(v - p) > 0.1,
            "the triangle is meant to be wholly visible"
        );
    }
    let m = (b - a).cross(c - a).normalize();
    let twice_area = (b - a).cross(c - a).length();
    // Collapsed square: q = a + u (b - a) + u v (c - b), Jacobian 2 A u.
    let mut f = |u: f64, v: f64| {
        let q = a + (b - a) * u + (c - b) * (u * v);
        kernel(p, n, q, m, true) * twice_area * u
    };
    let integrated = composite_gauss(&mut f, (0.0, 1.0), (0.0, 1.0), 2, 12);
    let lambert = point_to_polygon(p, n, &[a, b, c]).unwrap();
    assert_close(lambert, integrated, 1e-12, "tilted triangle");
}

#[test]
fn lambert_clips_a_polygon_that_straddles_the_horizon() {
    // Receiver at the origin tilted towards +z; the parallelogram in the plane
    // x = 1 is parametrised so that its horizon line is s = 0:
    // q(s, t) = (1, s - 0.3 t, t), with n.q proportional to s.
    let p = DVec3::ZERO;
    let n = DVec3::new(0.0, 1.0, 0.3).normalize();
    let q = |s: f64, t: f64| DVec3::new(1.0, s - 0.3 * t, t);
    let polygon = [q(-0.5, -1.0), q(1.0, -1.0), q(1.0, 1.0), q(-0.5, 1.0)];
    let m = DVec3::X;
    // The Jacobian |dq/ds x dq/dt| is 1.
    let visible = composite_gauss(
        &mut |s, t| kernel(p, n, q(s, t), m, true),
        (0.0, 1.0),
        (-1.0, 1.0),
        4,
        12,
    );
    let lambert = point_to_polygon(p, n, &polygon).unwrap();
    assert_close(lambert, visible, 1e-12, "straddling parallelogram");
    // Without clipping, the part below the horizon would count negatively.
    let unclipped = composite_gauss(
        &mut |s, t| kernel(p, n, q(s, t), m, false),
        (-0.5, 1.0),
        (-1.0, 1.0),
        4,
        12,
    );
    assert!(
        lambert - unclipped > 0.01,
        "clipping must matter here: {lambert} vs {unclipped}"
    );
}

#[test]
fn lambert_integrated_over_a_square_gives_c11() {
    // The brief: 24 x 24 Gauss-Legendre over the receiver gives 0.1998248957.
    let top = [
        DVec3::new(0.0, 1.0, 0.0),
        DVec3::new(1.0, 1.0, 0.0),
        DVec3::new(1.0, 1.0, 1.0),
        DVec3::new(0.0, 1.0, 1.0),
    ];
    let integrated = composite_gauss(
        &mut |u, v| point_to_polygon(DVec3::new(u, 0.0, v), DVec3::Y, &top).unwrap(),
        (0.0, 1.0),
        (0.0, 1.0),
        1,
        24,
    );
    assert_close(integrated, 0.1998248957, 1e-10, "integrated Lambert");
    assert_close(
        integrated,
        parallel_rectangles(1.0, 1.0, 1.0).unwrap(),
        1e-10,
        "C-11",
    );
}

// ---------------------------------------------------------------------------
// The 6-patch cube and the furnace identities (section 4.5).

#[test]
fn cube_check_values() {
    let floor = CubeFace::Floor.index();
    let ceiling = CubeFace::Ceiling.index();
    for (rho, b_floor, b_ceiling, b_wall, mean) in [
        (0.5, 0.181746, 1.090909, 0.181836, 0.333333),
        (0.8, 0.689551, 1.551724, 0.689681, 0.833333),
    ] {
        let b = unit_cube_ceiling_lit(rho).unwrap();
        assert_close(b[floor], b_floor, 1e-6, "cube floor");
        assert_close(b[ceiling], b_ceiling, 1e-6, "cube ceiling");
        for wall in &CubeFace::ALL[2..] {
            assert_close(b[wall.index()], b_wall, 1e-6, "cube wall");
        }
        let b_mean = b.iter().sum::<f64>() / 6.0;
        assert_close(b_mean, mean, 1e-6, "cube mean");
        // The enclosure identity holds exactly for the discrete system.
        let mut e = [0.0; 6];
        e[ceiling] = 1.0;
        let identity = enclosure_mean_radiosity(&[1.0; 6], &e, rho).unwrap();
        assert_close(b_mean, identity, 1e-14, "area-mean identity");
        // And the furnace: uniform emission gives E / (1 - rho) everywhere.
        let furnace = unit_cube_radiosity([rho; 6], [0.7; 6]).unwrap();
        for v in furnace {
            assert_close(v, furnace_radiosity(0.7, rho).unwrap(), 1e-13, "furnace");
        }
    }
}

#[test]
fn cube_form_factors_match_integrated_lambert_between_the_face_polygons() {
    // Checks the face numbering and geometry against the closed forms: the
    // adjacent-face integrand has a log-type edge singularity, hence the
    // composite rule.
    let f = unit_cube_form_factors();
    let rule = |i: CubeFace, j: CubeFace| {
        let src = i.polygon();
        let dst = j.polygon();
        let n = (src[1] - src[0]).cross(src[2] - src[0]).normalize();
        let mut g = |u: f64, v: f64| {
            let x = src[0] + (src[1] - src[0]) * u + (src[3] - src[0]) * v;
            point_to_polygon(x, n, &dst).unwrap()
        };
        composite_gauss(&mut g, (0.0, 1.0), (0.0, 1.0), 8, 8)
    };
    for (i, j) in [
        (CubeFace::Floor, CubeFace::Ceiling),
        (CubeFace::Floor, CubeFace::WallXMin),
        (CubeFace::WallXMax, CubeFace::WallZMin),
        (CubeFace::WallZMax, CubeFace::WallZMin),
        (CubeFace::Ceiling, CubeFace::WallZMax),
    ] {
        assert_close(rule(i, j), f[i.index()][j.index()], 1e-6, "cube face pair");
    }
}

// ---------------------------------------------------------------------------
// The exact penumbra (section 4.4).

/// The brief's set-up: a 1 x 1 light at height 4 facing down, a half-plane
/// occluder at height 2 with its edge at x = 0 (a large quad), floor points.
fn brief_penumbra() -> OccludedLight {
    let light = [
        DVec3::new(-0.5, 4.0, -0.5),
        DVec3::new(0.5, 4.0, -0.5),
        DVec3::new(0.5, 4.0, 0.5),
        DVec3::new(-0.5, 4.0, 0.5),
    ];
    let half_plane = [
        DVec3::new(0.0, 2.0, -50.0),
        DVec3::new(50.0, 2.0, -50.0),
        DVec3::new(50.0, 2.0, 50.0),
        DVec3::new(0.0, 2.0, 50.0),
    ];
    OccludedLight::new(&light, &[half_plane]).unwrap()
}

#[test]
fn penumbra_check_values() {
    let oracle = brief_penumbra();
    for (x, f) in [
        (-1.5, 0.015116),
        (-0.5, 0.018917),
        (-0.3, 0.015573),
        (0.0, 0.009744),
        (0.3, 0.003707),
        (0.5, 0.0),
        (0.7, 0.0),
        (1.5, 0.0),
    ] {
        let got = oracle
            .visible_form_factor(DVec3::new(x, 0.0, 0.0), DVec3::Y)
            .unwrap();
        assert_close(got, f, 1e-6, &format!("penumbra at x = {x}"));
    }
    // At x = 0 exactly half the light is hidden; the light is symmetric about
    // x = 0 as seen from there, so the visible part is half the full value.
    let x = DVec3::ZERO;
    let full = oracle.unoccluded_form_factor(x, DVec3::Y).unwrap();
    let visible = oracle.visible_form_factor(x, DVec3::Y).unwrap();
    assert_close(visible, 0.5 * full, 1e-15, "half hidden");
}

#[test]
fn tilted_receiver_with_an_occluder_through_its_level_and_beyond_the_light() {
    // A vertical wall at x = 0.3 reaching from below the receiver to above the
    // light plane: only its part between the receiver's level (parallel to the
    // light) and the light plane can hide anything. The receiver is tilted so
    // that its horizon also cuts the light.
    let light = [
        DVec3::new(-0.5, 4.0, -0.5),
        DVec3::new(0.5, 4.0, -0.5),
        DVec3::new(0.5, 4.0, 0.5),
        DVec3::new(-0.5, 4.0, 0.5),
    ];
    let wall = [
        DVec3::new(0.3, -1.0, -2.0),
        DVec3::new(0.3, -1.0, 0.1),
        DVec3::new(0.3, 6.0, 0.1),
        DVec3::new(0.3, 6.0, -2.0),
    ];
    let x = DVec3::new(0.9, 0.5, 0.2);
    let n = DVec3::new(1.0, 0.3, 0.1).normalize();
    let oracle = OccludedLight::new(&light, &[wall]).unwrap();
    let exact = oracle.visible_form_factor(x, n).unwrap();
    let full = oracle.unoccluded_form_factor(x, n).unwrap();
    let horizon_cut = light.iter().any(|v| n.dot(*v - x) < 0.0);
    assert!(
        horizon_cut,
        "the receiver's horizon is meant to cut the light"
    );
    assert!(
        exact > 0.05 * full && exact < 0.95 * full,
        "{exact} of {full}"
    );
    let (mc, se) = monte_carlo_occluded(&light, &[wall], x, n, 200_000, 4242);
    assert!(
        (exact - mc).abs() <= 3.0 * se,
        "exact {exact}, Monte Carlo {mc} +- {se}"
    );
}

/// The brief's recipe, steps 2-4: project the occluder's vertices from the point
/// onto the light plane, intersect with the light in that plane.
fn projected_recipe(light: &[DVec3], occluder: &[DVec3; 4], x: DVec3) -> f64 {
    let ln = (light[1] - light[0]).cross(light[2] - light[0]).normalize();
    let projected: Vec<DVec3> = occluder
        .iter()
        .map(|o| {
            let t = ln.dot(light[0] - x) / ln.dot(*o - x);
            assert!(t >= 1.0, "occluder must lie between point and light");
            x + (*o - x) * t
        })
        .collect();
    let full = point_to_polygon(x, DVec3::Y, light).unwrap();
    let hidden = convex_intersection(light, &projected).unwrap();
    let blocked = if hidden.len() >= 3 {
        point_to_polygon(x, DVec3::Y, &hidden).unwrap()
    } else {
        0.0
    };
    full - blocked
}

#[test]
fn cone_clipping_equals_the_projection_recipe() {
    for (name, build) in VARIANTS {
        let spec = build();
        if spec.occluders.len() != 1 {
            continue;
        }
        let oracle = spec.oracle().unwrap();
        for (x, z) in [
            (-0.3, 0.2),
            (0.1, -0.4),
            (0.45, 0.55),
            (1.9, 0.0),
            (2.0, -1.1),
        ] {
            let p = DVec3::new(x, 0.0, z);
            let recipe = projected_recipe(&spec.light, &spec.occluders[0], p);
            let cone = oracle.visible_form_factor(p, DVec3::Y).unwrap();
            assert_close(cone, recipe, 1e-14, name);
        }
    }
}

/// Floor points for each variant, chosen to cover light, penumbra and umbra.
fn probe_points(spec: &PenumbraSpec) -> Vec<DVec3> {
    let xz: &[(f64, f64)] = match spec.name {
        "penumbra_narrow" => &[
            (-0.5, 0.2),
            (0.05, 0.3),
            (-0.08, -0.2),
            (1.95, 0.0),
            (0.6, -1.05),
            (1.0, 0.0),
        ],
        "penumbra_two_occluders" => &[
            (-1.2, 0.4),
            (0.6, 0.6),
            (0.9, 1.1),
            (-0.2, 0.5),
            (0.3, -0.7),
            (1.7, -1.2),
        ],
        _ => &[
            (-1.2, 0.4),
            (-0.2, 0.1),
            (0.2, -0.7),
            (0.6, 0.6),
            (1.0, 0.1),
            (1.7, -1.2),
            (1.9, 1.3),
        ],
    };
    xz.iter().map(|(x, z)| DVec3::new(*x, 0.0, *z)).collect()
}

#[test]
fn penumbra_oracle_agrees_with_monte_carlo_in_every_variant() {
    for (variant, (name, build)) in VARIANTS.iter().enumerate() {
        let spec = build();
        let oracle = spec.oracle().unwrap();
        let mut penumbra_points = 0;
        for (k, p) in probe_points(&spec).into_iter().enumerate() {
            let exact = oracle.visible_form_factor(p, DVec3::Y).unwrap();
            let full = oracle.unoccluded_form_factor(p, DVec3::Y).unwrap();
            if exact > 0.02 * full && exact < 0.98 * full {
                penumbra_points += 1;
            }
            let seed = (variant as u64 + 1) * 1_000_003 + k as u64 * 7919;
            let (mc, se) = monte_carlo_form_factor(&spec, p, 100_000, seed);
            assert!(
                (exact - mc).abs() <= 3.0 * se + 1e-12,
                "{name} at {p}: exact {exact:.6e}, Monte Carlo {mc:.6e} +- {se:.1e}"
            );
            // The scene's radiosity is the same form factor scaled.
            let b = spec.exact_radiosity(p).unwrap();
            let scale = penumbra::FLOOR_REFLECTANCE * spec.light_exitance()[0];
            assert_close(b[1], scale * exact, 1e-15 * scale, "radiosity");
        }
        assert!(
            penumbra_points >= 2,
            "{name}: only {penumbra_points} probe points in penumbra"
        );
    }
}

#[test]
fn two_occluders_hide_the_union_not_the_sum() {
    let spec = penumbra::penumbra_two_occluders();
    let both = spec.oracle().unwrap();
    let singles: Vec<OccludedLight> = spec
        .occluders
        .iter()
        .map(|o| OccludedLight::new(&spec.light, &[*o]).unwrap())
        .collect();
    // Points where each occluder alone hides at least a tenth of the light and
    // part of the light stays visible: the two hidden parts overlap.
    for (k, (x, z)) in [(-0.2, 0.0), (0.8, 0.8), (0.8, 1.0), (0.6, 0.6)]
        .into_iter()
        .enumerate()
    {
        let p = DVec3::new(x, 0.0, z);
        let full = both.unoccluded_form_factor(p, DVec3::Y).unwrap();
        let exact = both.visible_form_factor(p, DVec3::Y).unwrap();
        let hidden_by_each: Vec<f64> = singles
            .iter()
            .map(|s| full - s.visible_form_factor(p, DVec3::Y).unwrap())
            .collect();
        assert!(
            hidden_by_each.iter().all(|h| *h > 0.1 * full),
            "{p}: {hidden_by_each:?}"
        );
        assert!(exact > 0.01 * full, "{p} is meant to be in penumbra");
        let naive = full - hidden_by_each.iter().sum::<f64>();
        let (mc, se) = monte_carlo_form_factor(&spec, p, 200_000, 77 + k as u64);
        assert!(
            (exact - mc).abs() <= 3.0 * se,
            "union at {p}: {exact} vs {mc} +- {se}"
        );
        assert!(
            (naive - mc).abs() > 10.0 * se,
            "at {p} the naive sum {naive} should be wrong (Monte Carlo {mc})"
        );
    }
}

// ---------------------------------------------------------------------------
// Quadrature.

#[test]
fn quadrature_integrates_a_kink() {
    let s = QuadratureSettings::with_tolerance(1e-8);
    let r = integrate_unit_square(|u, _| (u - 0.3).abs(), &s).unwrap();
    assert_close(r.value, (0.09 + 0.49) / 2.0, 1e-6, "|x - 0.3|");
    assert!(r.error_estimate <= 1e-8);
    // A kink along a slanted line over a triangle: |x + 2 z - 1| over the
    // triangle (0,0), (2,0), (0,2) of the (x, z) plane.
    let tri = [
        DVec3::ZERO,
        DVec3::new(2.0, 0.0, 0.0),
        DVec3::new(0.0, 0.0, 2.0),
    ];
    let r = integrate_over_polygon(&tri, |p| (p.x + 2.0 * p.z - 1.0).abs(), &s).unwrap();
    // Independent: the integral of a linear function over a polygon is area
    // times its value at the centroid; split the triangle along x + 2z = 1.
    let g = |p: DVec3| p.x + 2.0 * p.z - 1.0;
    let below = [
        DVec3::ZERO,
        DVec3::new(1.0, 0.0, 0.0),
        DVec3::new(0.0, 0.0, 0.5),
    ];
    let above = [
        DVec3::new(1.0, 0.0, 0.0),
        DVec3::new(2.0, 0.0, 0.0),
        DVec3::new(0.0, 0.0, 2.0),
        DVec3::new(0.0, 0.0, 0.5),
    ];
    let centroid_value = |poly: &[DVec3]| {
        // Fan from vertex 0: sum of triangle areas times centroid values.
        (1..poly.len() - 1)
            .map(|k| {
                let t = [poly[0], poly[k], poly[k + 1]];
                polygon_area(&t) * g((t[0] + t[1] + t[2]) / 3.0)
            })
            .sum::<f64>()
    };
    let exact = -centroid_value(&below) + centroid_value(&above);
    assert_close(r.value, exact, 1e-6, "kink over a triangle");
}

#[test]
fn element_mean_of_a_lit_element_equals_a_dense_fixed_rule() {
    let spec = penumbra::penumbra_parallel();
    let element = [
        DVec3::new(-2.0, 0.0, -2.0),
        DVec3::new(-2.0, 0.0, -1.5),
        DVec3::new(-1.5, 0.0, -1.5),
        DVec3::new(-1.5, 0.0, -2.0),
    ];
    // Fully lit: at its corners the oracle sees the whole light.
    let oracle = spec.oracle().unwrap();
    for v in element {
        let full = oracle.unoccluded_form_factor(v, DVec3::Y).unwrap();
        assert_eq!(oracle.visible_form_factor(v, DVec3::Y).unwrap(), full);
    }
    let mean = spec.exact_element_mean(&element).unwrap();
    let scale = penumbra::FLOOR_REFLECTANCE * spec.light_exitance()[0];
    let dense = composite_gauss(
        &mut |x, z| scale * point_to_polygon(DVec3::new(x, 0.0, z), DVec3::Y, &spec.light).unwrap(),
        (-2.0, -1.5),
        (-2.0, -1.5),
        4,
        8,
    ) / 0.25;
    assert_close(mean[0], dense, 1e-9 * dense, "lit element mean");
}

#[test]
fn element_mean_across_a_penumbra_edge_and_split_into_triangles() {
    // In penumbra_parallel, for |z| <= 0.5 the light is cut only by the
    // occluder's edge x = 0, whose penumbra ends at x = -0.5 with a kink. Split
    // the dense rule exactly at the kink.
    let spec = penumbra::penumbra_parallel();
    let (x0, x1, z0, z1) = (-0.75, -0.25, -0.25, 0.25);
    let quad = [
        DVec3::new(x0, 0.0, z0),
        DVec3::new(x0, 0.0, z1),
        DVec3::new(x1, 0.0, z1),
        DVec3::new(x1, 0.0, z0),
    ];
    let b = |x: f64, z: f64| spec.exact_radiosity(DVec3::new(x, 0.0, z)).unwrap()[0];
    let dense = (composite_gauss(&mut |x, z| b(x, z), (x0, -0.5), (z0, z1), 2, 10)
        + composite_gauss(&mut |x, z| b(x, z), (-0.5, x1), (z0, z1), 2, 10))
        / ((x1 - x0) * (z1 - z0));
    let mean = spec.exact_element_mean(&quad).unwrap()[0];
    let light_on = b(-0.5, 0.0);
    assert_close(mean, dense, 1e-6 * light_on, "penumbra element mean");
    // The same element as two triangles, weighted by area.
    let t1 = [quad[0], quad[1], quad[2]];
    let t2 = [quad[0], quad[2], quad[3]];
    let m1 = spec.exact_element_mean(&t1).unwrap()[0];
    let m2 = spec.exact_element_mean(&t2).unwrap()[0];
    assert_close(0.5 * (m1 + m2), dense, 2e-5 * light_on, "two triangles");
}

#[test]
fn quadrature_of_the_unoccluded_oracle_gives_c11() {
    // A 1 x 1 floor element under the coaxial 1 x 1 light at height 3: the
    // element's mean form factor is Howell C-11.
    let light = [
        DVec3::new(-0.5, 3.0, -0.5),
        DVec3::new(0.5, 3.0, -0.5),
        DVec3::new(0.5, 3.0, 0.5),
        DVec3::new(-0.5, 3.0, 0.5),
    ];
    let none: [[DVec3; 4]; 0] = [];
    let oracle = OccludedLight::new(&light, &none).unwrap();
    let element = light.map(|v| DVec3::new(v.x, 0.0, v.z));
    let s = QuadratureSettings::with_tolerance(1e-12);
    let r = integrate_over_polygon(
        &element,
        |p| oracle.visible_form_factor(p, DVec3::Y).unwrap(),
        &s,
    )
    .unwrap();
    assert_close(
        r.value,
        parallel_rectangles(1.0, 1.0, 3.0).unwrap(),
        1e-11,
        "C-11 at c = 3",
    );
}
