//! The Monte Carlo reference against closed forms derived here, independently of
//! the library: furnace, point-to-rectangle form factors, the exact penumbra
//! table, back faces, the closed-scene energy identity, scale invariance and
//! determinism.

use glam::{DQuat, DVec3};
use radiosity::math::Rgb;
use radiosity::reference::{
    sample_points, ProbeEstimate, Reference, ReferenceSettings, SurfacePoint,
};
use radiosity::scene::{Scene, SceneBuilder};
use std::f64::consts::PI;

// ---------------------------------------------------------------- helpers

/// A scene builder that remembers surface indices (every quad added here is
/// planar, so it becomes exactly one surface).
struct Builder {
    inner: SceneBuilder,
    surfaces: u32,
    /// A rotation applied to everything added, to exercise non-axis-aligned
    /// planes (where rounding is not exact).
    turn: DQuat,
}

impl Builder {
    fn new(name: &str) -> Self {
        Builder {
            inner: SceneBuilder::new(name),
            surfaces: 0,
            turn: DQuat::IDENTITY,
        }
    }

    /// A material from reflectance and exitance E (the builder takes radiance E/pi).
    fn material(&mut self, reflectance: Rgb, exitance: Rgb) -> u32 {
        let name = format!("m{}", self.surfaces);
        self.inner
            .material(&name, reflectance, exitance * (1.0 / PI))
            .unwrap()
    }

    fn object(&mut self, name: &str) {
        self.inner.object(name);
    }

    /// Adds the rectangle `centre +- u +- v`, its front facing `toward`; returns
    /// its surface index.
    fn rect(&mut self, material: u32, centre: DVec3, u: DVec3, v: DVec3, toward: DVec3) -> u32 {
        let r = self.turn;
        let (centre, u, v, toward) = (r * centre, r * u, r * v, r * toward);
        let mut q = [
            centre - u - v,
            centre + u - v,
            centre + u + v,
            centre - u + v,
        ];
        if (q[1] - q[0]).cross(q[2] - q[0]).dot(toward) < 0.0 {
            q.reverse();
        }
        self.inner.quad(material, q[0], q[1], q[2], q[3]).unwrap();
        self.surfaces += 1;
        self.surfaces - 1
    }

    /// The six faces of the box `lo..hi`, each its own object, fronts facing
    /// inwards; `materials` in the order -x, +x, -y, +y, -z, +z.
    fn room(&mut self, lo: DVec3, hi: DVec3, materials: [u32; 6]) {
        let c = (lo + hi) * 0.5;
        let h = (hi - lo) * 0.5;
        let axes = [DVec3::X, DVec3::Y, DVec3::Z];
        for (face, m) in materials.iter().enumerate() {
            let axis = face / 2;
            let sign = if face % 2 == 0 { -1.0 } else { 1.0 };
            let n = axes[axis];
            let (a, b) = (axes[(axis + 1) % 3], axes[(axis + 2) % 3]);
            self.object(&format!("wall{face}"));
            self.rect(
                *m,
                c + n * (sign * h[axis]),
                a * h.dot(a),
                b * h.dot(b),
                -n * sign,
            );
        }
    }

    fn build(self) -> Scene {
        let scene = self.inner.build().unwrap();
        assert_eq!(scene.surfaces.len() as u32, self.surfaces);
        scene
    }
}

fn point(scene: &Scene, surface: u32, position: DVec3) -> SurfacePoint {
    SurfacePoint {
        surface,
        position,
        normal: scene.surfaces[surface as usize].normal,
    }
}

fn settings(paths: u64, seed: u64) -> ReferenceSettings {
    ReferenceSettings {
        paths,
        seed,
        ..ReferenceSettings::default()
    }
}

/// Asserts `|estimate - expected| <= 3 standard errors + slack` in every band.
fn assert_within_3se(what: &str, e: &ProbeEstimate, expected: Rgb, slack: f64) {
    for k in 0..3 {
        let err = (e.radiosity[k] - expected[k]).abs();
        assert!(
            err <= 3.0 * e.std_error[k] + slack,
            "{what}, band {k}: estimate {} +- {} but expected {} (off by {:.2} standard errors)",
            e.radiosity[k],
            e.std_error[k],
            expected[k],
            err / e.std_error[k]
        );
    }
}

/// Form factor from a point to the rectangle [0, X] x [0, Y] (in units of the
/// height c) on a parallel plane, the point facing it opposite the corner (0, 0):
/// F = 1/(2 pi) [X/sqrt(1+X^2) atan(Y/sqrt(1+X^2)) + Y/sqrt(1+Y^2) atan(X/sqrt(1+Y^2))].
/// It is odd in X and in Y, so signed sides work for inclusion-exclusion.
fn corner_form_factor(x: f64, y: f64) -> f64 {
    let sx = (1.0 + x * x).sqrt();
    let sy = (1.0 + y * y).sqrt();
    (x / sx * (y / sx).atan() + y / sy * (x / sy).atan()) / (2.0 * PI)
}

/// Form factor from a point at the origin, facing +z, to the parallel rectangle
/// [x0, x1] x [y0, y1] at height c, by inclusion-exclusion of corner rectangles.
fn rectangle_form_factor(x0: f64, x1: f64, y0: f64, y1: f64, c: f64) -> f64 {
    let f = |x: f64, y: f64| corner_form_factor(x / c, y / c);
    f(x1, y1) - f(x0, y1) - f(x1, y0) + f(x0, y0)
}

#[test]
fn corner_form_factor_matches_the_published_check_values() {
    // algorithms.md 4.2: (1,1) -> 0.138532; (2,3) -> 0.217575; (0.5,0.5) -> 0.059864.
    for (x, y, f) in [
        (1.0, 1.0, 0.138532),
        (2.0, 3.0, 0.217575),
        (0.5, 0.5, 0.059864),
    ] {
        assert!((corner_form_factor(x, y) - f).abs() < 6e-7);
    }
}

// ---------------------------------------------------------------- furnace

#[test]
fn furnace_gives_e_over_one_minus_rho_everywhere() {
    // Closed box, every face rho = 0.5 and exitance E: B = E + rho B, so
    // B = E/(1 - rho) = 2E at every point.
    let mut b = Builder::new("furnace");
    let m = b.material(Rgb::splat(0.5), Rgb::new(1.0, 2.0, 0.5));
    b.room(DVec3::ZERO, DVec3::new(2.0, 1.0, 1.5), [m; 6]);
    let scene = b.build();
    let expected = scene.materials[m as usize].emission * 2.0;
    let reference = Reference::new(&scene).unwrap();
    let mut points = sample_points(&scene, 4, 1).unwrap();
    // One point a hair from a concave corner, where light sampling alone would
    // have unbounded variance.
    points.push(point(&scene, 4, DVec3::new(1e-4, 2e-4, 0.0)));
    let estimates = reference
        .radiosity_at(&points, &settings(20_000, 5))
        .unwrap();
    for (p, e) in points.iter().zip(&estimates) {
        assert_eq!(e.paths, 20_000);
        assert_within_3se(&format!("furnace at {}", p.position), e, expected, 0.0);
        for k in 0..3 {
            assert!(
                e.std_error[k] < 0.01 * expected[k],
                "standard error {:?}",
                e.std_error
            );
        }
    }
    for (o, e) in reference
        .object_means(&settings(20_000, 6))
        .unwrap()
        .iter()
        .enumerate()
    {
        assert_within_3se(&format!("furnace object {o}"), e, expected, 0.0);
    }
}

// ---------------------------------------------------------------- direct light

/// A 1 x 1 light at height 1 over a large floor; only the floor reflects.
fn light_over_floor() -> (Scene, u32, Rgb, f64) {
    let mut b = Builder::new("light over floor");
    let rho = Rgb::new(0.6, 0.3, 0.9);
    let floor_m = b.material(rho, Rgb::ZERO);
    let light_m = b.material(Rgb::ZERO, Rgb::new(2.0, 1.0, 0.5));
    b.object("floor");
    let floor = b.rect(
        floor_m,
        DVec3::ZERO,
        DVec3::X * 3.0,
        DVec3::Y * 3.0,
        DVec3::Z,
    );
    b.object("light");
    b.rect(light_m, DVec3::Z, DVec3::X * 0.5, DVec3::Y * 0.5, -DVec3::Z);
    let scene = b.build();
    let exitance = scene.materials[light_m as usize].emission;
    (scene, floor, rho * exitance, 1.0)
}

#[test]
fn point_under_a_square_light_matches_the_exact_form_factor() {
    // Nothing reflects back onto the floor (the light is black, the floor is
    // planar), so B = rho E_light F exactly, F from the corner-rectangle sum.
    let (scene, floor, rho_e, height) = light_over_floor();
    let reference = Reference::new(&scene).unwrap();
    let spots = [(0.0, 0.0), (0.2, -0.1), (0.9, 0.3), (-1.7, 2.5)];
    let points: Vec<SurfacePoint> = spots
        .iter()
        .map(|(x, y)| point(&scene, floor, DVec3::new(*x, *y, 0.0)))
        .collect();
    let estimates = reference
        .radiosity_at(&points, &settings(40_000, 9))
        .unwrap();
    for ((x, y), e) in spots.iter().zip(&estimates) {
        let f = rectangle_form_factor(-0.5 - x, 0.5 - x, -0.5 - y, 0.5 - y, height);
        assert_within_3se(&format!("floor at ({x}, {y}), F = {f}"), e, rho_e * f, 0.0);
        assert!(e.std_error[0] < 0.01 * rho_e[0] * f);
    }
}

#[test]
fn half_occluded_light_matches_the_exact_penumbra_table() {
    // algorithms.md 4.4: a 1 x 1 light at height 4 facing down, a black
    // occluder at height 2 covering x > 0, receivers on the floor at y = 0.
    // Exact F (6 decimals) from the Lambert-contour penumbra oracle.
    let table = [
        (-1.5, 0.015116),
        (-0.5, 0.018917),
        (-0.3, 0.015573),
        (0.0, 0.009744),
        (0.3, 0.003707),
        (0.6, 0.0),
    ];
    // The occluder must block whichever way it faces.
    for occluder_faces in [-DVec3::Z, DVec3::Z] {
        penumbra_table_case(&table, occluder_faces);
    }
}

fn penumbra_table_case(table: &[(f64, f64)], occluder_faces: DVec3) {
    let mut b = Builder::new("penumbra");
    let rho = Rgb::new(1.0, 0.5, 0.25);
    let floor_m = b.material(rho, Rgb::ZERO);
    let black = b.material(Rgb::ZERO, Rgb::ZERO);
    let light_m = b.material(Rgb::ZERO, Rgb::splat(PI));
    b.object("floor");
    let floor = b.rect(
        floor_m,
        DVec3::ZERO,
        DVec3::X * 3.0,
        DVec3::Y * 3.0,
        DVec3::Z,
    );
    b.object("occluder");
    b.rect(
        black,
        DVec3::new(1.5, 0.0, 2.0),
        DVec3::X * 1.5,
        DVec3::Y * 3.0,
        occluder_faces,
    );
    b.object("light");
    b.rect(
        light_m,
        DVec3::new(0.0, 0.0, 4.0),
        DVec3::X * 0.5,
        DVec3::Y * 0.5,
        -DVec3::Z,
    );
    let scene = b.build();
    let rho_e = rho * scene.materials[light_m as usize].emission;
    let reference = Reference::new(&scene).unwrap();
    let points: Vec<SurfacePoint> = table
        .iter()
        .map(|(x, _)| point(&scene, floor, DVec3::new(*x, 0.0, 0.0)))
        .collect();
    let estimates = reference
        .radiosity_at(&points, &settings(100_000, 13))
        .unwrap();
    for ((x, f), e) in table.iter().zip(&estimates) {
        // The table's rounding (5e-7 in F) is added to the allowance.
        let what = format!("penumbra at x = {x}, occluder facing {occluder_faces}");
        assert_within_3se(&what, e, rho_e * *f, 5e-7 * rho_e[0]);
        if *f > 0.0 {
            assert!(e.std_error[0] < 0.01 * rho_e[0] * f);
        } else {
            // Full umbra: no path can carry light, so every path gives 0.
            assert_eq!(e.radiosity, Rgb::ZERO);
            assert_eq!(e.std_error, Rgb::ZERO);
        }
    }
}

// ---------------------------------------------------------------- back faces

/// A 1 x 1 grey floor under a light at height 4 facing down, optionally with a
/// 4 x 4 single-sided quad at height 2 facing DOWN (its back towards the light)
/// and a 1 x 1 grey ceiling at height 6 facing down (towards the light's back).
/// Returns the scene, the floor, the quad and ceiling if present, and the
/// light's exitance.
fn floor_under_light(with_quad: bool) -> (Scene, u32, Option<(u32, u32)>, Rgb) {
    let mut b = Builder::new("back face");
    let floor_m = b.material(Rgb::splat(0.5), Rgb::ZERO);
    let quad_m = b.material(Rgb::splat(0.8), Rgb::ZERO);
    let light_m = b.material(Rgb::splat(0.5), Rgb::splat(10.0));
    let (u, v) = (DVec3::X * 0.5, DVec3::Y * 0.5);
    b.object("floor");
    let floor = b.rect(floor_m, DVec3::ZERO, u, v, DVec3::Z);
    b.object("light");
    b.rect(light_m, DVec3::Z * 4.0, u, v, -DVec3::Z);
    let quad = with_quad.then(|| {
        b.object("quad");
        let quad = b.rect(quad_m, DVec3::Z * 2.0, u * 4.0, v * 4.0, -DVec3::Z);
        b.object("ceiling");
        (quad, b.rect(floor_m, DVec3::Z * 6.0, u, v, -DVec3::Z))
    });
    let scene = b.build();
    let light_e = scene.materials[light_m as usize].emission;
    (scene, floor, quad, light_e)
}

#[test]
fn back_faces_block_light() {
    // Rays from any floor point to the light cross height 2 within |x|, |y| <=
    // 0.5, inside the quad, so the whole floor is in umbra if the quad's back
    // blocks. The quad's front then sees only a dark floor, so B = 0 exactly on
    // the floor and on the quad's front, for every path. The ceiling sees only
    // the backs of the light and of the quad (which hides the floor), which
    // neither emit nor reflect: B = 0 there too.
    let (scene, floor, quad_and_ceiling, _) = floor_under_light(true);
    let (quad, ceiling) = quad_and_ceiling.unwrap();
    let reference = Reference::new(&scene).unwrap();
    let points = [
        point(&scene, floor, DVec3::new(0.3, -0.2, 0.0)),
        point(&scene, quad, DVec3::new(0.3, -0.2, 2.0)),
        point(&scene, ceiling, DVec3::new(0.3, -0.2, 6.0)),
    ];
    for e in reference
        .radiosity_at(&points, &settings(4_000, 2))
        .unwrap()
    {
        assert_eq!(e.radiosity, Rgb::ZERO);
        assert_eq!(e.std_error, Rgb::ZERO);
    }
    // Control, so that the test can fail: without the quad the same floor point
    // gets rho E F (the floor sees only the black light).
    let (scene, floor, _, light_e) = floor_under_light(false);
    let reference = Reference::new(&scene).unwrap();
    let lit = point(&scene, floor, DVec3::new(0.3, -0.2, 0.0));
    let e = reference.radiosity_at(&[lit], &settings(4_000, 2)).unwrap();
    let f = rectangle_form_factor(-0.8, 0.2, -0.3, 0.7, 4.0);
    assert_within_3se("control without the quad", &e[0], light_e * (0.5 * f), 0.0);
}

#[test]
fn double_sided_panels_are_lit_on_top_emit_below_and_block() {
    // A double-sided panel is two coincident back-to-back surfaces: here the
    // upper one grey (rho 0.7), the lower one an emitter E_p. A light E_l at
    // height 4 faces down onto it. The whole scene is turned by an arbitrary
    // rotation so that the coincident planes differ by rounding.
    // - A point on the upper twin sees only the (black) light:
    //   B = 0.7 E_l F(height 2); its twin must not shadow it.
    // - A floor point under the middle sees the lower twin, and the light only
    //   through the panel: B = 0.5 E_p F(height 2). Any leak of the light, or a
    //   ray that takes the upper twin's back for the lower twin's front, shows.
    let mut b = Builder::new("double-sided");
    b.turn = DQuat::from_axis_angle(DVec3::new(0.3, -0.5, 0.8).normalize(), 0.7);
    let turn = b.turn;
    let floor_m = b.material(Rgb::splat(0.5), Rgb::ZERO);
    let top_m = b.material(Rgb::splat(0.7), Rgb::ZERO);
    let under_m = b.material(Rgb::ZERO, Rgb::new(0.5, 1.0, 2.0));
    let light_m = b.material(Rgb::ZERO, Rgb::new(3.0, 2.0, 1.0));
    b.object("floor");
    let floor = b.rect(
        floor_m,
        DVec3::ZERO,
        DVec3::X * 10.0,
        DVec3::Y * 10.0,
        DVec3::Z,
    );
    b.object("panel");
    let (u, v) = (DVec3::X * 0.5, DVec3::Y * 0.5);
    let top = b.rect(top_m, DVec3::Z * 2.0, u, v, DVec3::Z);
    b.rect(under_m, DVec3::Z * 2.0, u, v, -DVec3::Z);
    b.object("light");
    b.rect(light_m, DVec3::Z * 4.0, u, v, -DVec3::Z);
    let scene = b.build();
    let reference = Reference::new(&scene).unwrap();
    // Several points on top: whether rounding puts a point's twin just in front
    // of it or just behind differs from point to point.
    let spots = [(0.1, 0.2), (-0.3, 0.05), (0.42, -0.37), (-0.2, -0.45)];
    let mut points: Vec<SurfacePoint> = spots
        .iter()
        .map(|(x, y)| point(&scene, top, turn * DVec3::new(*x, *y, 2.0)))
        .collect();
    points.push(point(&scene, floor, DVec3::ZERO));
    let e = reference
        .radiosity_at(&points, &settings(20_000, 4))
        .unwrap();
    let light = scene.materials[light_m as usize].emission;
    for ((x, y), est) in spots.iter().zip(&e) {
        let f = rectangle_form_factor(-0.5 - x, 0.5 - x, -0.5 - y, 0.5 - y, 2.0);
        assert_within_3se(
            &format!("panel top at ({x}, {y})"),
            est,
            light * (0.7 * f),
            0.0,
        );
    }
    let f_floor = rectangle_form_factor(-0.5, 0.5, -0.5, 0.5, 2.0);
    let under = scene.materials[under_m as usize].emission;
    assert_within_3se("floor under the panel", &e[4], under * (0.5 * f_floor), 0.0);
}

// ---------------------------------------------------------------- energy balance

#[test]
fn closed_scene_area_mean_is_mean_emission_over_one_minus_rho() {
    // Section 0: in a closed scene with uniform rho, sum A_i B_i =
    // sum A_i E_i / (1 - rho) whatever the emission pattern. Here: a room whose
    // faces emit differently per face and band, with a dark box inside.
    let rho = 0.6;
    let mut b = Builder::new("energy");
    let e = [
        Rgb::new(1.0, 0.0, 0.0),
        Rgb::ZERO,
        Rgb::new(0.0, 2.0, 0.0),
        Rgb::ZERO,
        Rgb::ZERO,
        Rgb::new(5.0, 4.0, 3.0),
    ];
    let m: Vec<u32> = e.iter().map(|e| b.material(Rgb::splat(rho), *e)).collect();
    b.room(
        DVec3::ZERO,
        DVec3::new(3.0, 2.0, 2.5),
        [m[0], m[1], m[2], m[3], m[4], m[5]],
    );
    let dark = b.material(Rgb::splat(rho), Rgb::ZERO);
    b.object("box");
    let (c, h) = (DVec3::new(1.0, 0.8, 0.6), DVec3::new(0.4, 0.3, 0.6));
    for (axis, n) in [DVec3::X, DVec3::Y, DVec3::Z].into_iter().enumerate() {
        let (a, bb) = (
            [DVec3::Y, DVec3::Z, DVec3::X][axis],
            [DVec3::Z, DVec3::X, DVec3::Y][axis],
        );
        for s in [-1.0, 1.0] {
            b.rect(
                dark,
                c + n * (s * h.dot(n)),
                a * h.dot(a),
                bb * h.dot(bb),
                n * s,
            );
        }
    }
    let scene = b.build();
    let mut area = vec![0.0; scene.objects.len()];
    let mut emitted = Rgb::ZERO;
    for s in &scene.surfaces {
        area[s.object as usize] += s.area;
        emitted += scene.materials[s.material as usize].emission * s.area;
    }
    let total: f64 = area.iter().sum();
    let expected = emitted * (1.0 / total / (1.0 - rho));
    let means = Reference::new(&scene)
        .unwrap()
        .object_means(&settings(20_000, 8))
        .unwrap();
    let mut mean = Rgb::ZERO;
    let mut variance = Rgb::ZERO;
    for (o, est) in means.iter().enumerate() {
        let w = area[o] / total;
        mean += est.radiosity * w;
        variance += est.std_error * est.std_error * (w * w);
    }
    let combined = ProbeEstimate {
        radiosity: mean,
        std_error: Rgb(variance.0.map(f64::sqrt)),
        paths: 0,
    };
    assert_within_3se("area-weighted mean", &combined, expected, 0.0);
    for k in 0..3 {
        assert!(combined.std_error[k] < 0.01 * expected[k]);
    }
}

// ---------------------------------------------------------------- a Cornell-like room

/// A closed room of 29 quads: four coloured walls, a floor of four quads, a
/// ceiling of nine with the middle one a light, and two dark boxes on the floor.
/// Every length is multiplied by `scale` and then moved by `offset`.
fn cornell_like(scale: f64, offset: DVec3) -> Scene {
    let p = |x: f64, y: f64, z: f64| DVec3::new(x, y, z) * scale + offset;
    let mut b = Builder::new("cornell-like");
    let white = b.material(Rgb::splat(0.75), Rgb::ZERO);
    let red = b.material(Rgb::new(0.63, 0.06, 0.04), Rgb::ZERO);
    let green = b.material(Rgb::new(0.15, 0.48, 0.09), Rgb::ZERO);
    let light = b.material(Rgb::splat(0.78), Rgb::new(17.0, 12.0, 4.0) * PI);
    let grey = b.material(Rgb::splat(0.4), Rgb::ZERO);
    let l = 5.5;
    let h = l / 2.0;
    let (x, y, z) = (DVec3::X * scale, DVec3::Y * scale, DVec3::Z * scale);
    b.object("left");
    b.rect(red, p(0.0, h, h), y * h, z * h, DVec3::X);
    b.object("right");
    b.rect(green, p(l, h, h), y * h, z * h, -DVec3::X);
    b.object("back");
    b.rect(white, p(h, l, h), x * h, z * h, -DVec3::Y);
    b.object("front");
    b.rect(white, p(h, 0.0, h), x * h, z * h, DVec3::Y);
    b.object("floor");
    for (i, j) in [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0)] {
        b.rect(
            white,
            p(h * (i + 0.5), h * (j + 0.5), 0.0),
            x * (h / 2.0),
            y * (h / 2.0),
            DVec3::Z,
        );
    }
    b.object("ceiling");
    let third = l / 3.0;
    for i in 0..3 {
        for j in 0..3 {
            let m = if i == 1 && j == 1 { light } else { white };
            let c = p(third * (i as f64 + 0.5), third * (j as f64 + 0.5), l);
            b.rect(m, c, x * (third / 2.0), y * (third / 2.0), -DVec3::Z);
        }
    }
    for (name, lo, hi) in [
        ("short box", [1.0, 1.0, 0.0], [2.5, 2.5, 1.6]),
        ("tall box", [3.0, 2.8, 0.0], [4.5, 4.3, 3.3]),
    ] {
        b.object(name);
        let (lo, hi) = (DVec3::from(lo), DVec3::from(hi));
        let (c, e) = ((lo + hi) * 0.5, (hi - lo) * 0.5);
        for (axis, n) in [DVec3::X, DVec3::Y, DVec3::Z].into_iter().enumerate() {
            let (a, bb) = (
                [DVec3::Y, DVec3::Z, DVec3::X][axis],
                [DVec3::Z, DVec3::X, DVec3::Y][axis],
            );
            for s in [-1.0, 1.0] {
                let centre = (c + n * (s * e.dot(n))) * scale + offset;
                b.rect(
                    grey,
                    centre,
                    a * (e.dot(a) * scale),
                    bb * (e.dot(bb) * scale),
                    n * s,
                );
            }
        }
    }
    b.build()
}

fn largest_relative_difference(a: &[ProbeEstimate], b: &[ProbeEstimate]) -> f64 {
    let mut worst: f64 = 0.0;
    for (x, y) in a.iter().zip(b) {
        for k in 0..3 {
            let scale = x.radiosity[k].abs().max(1e-300);
            worst = worst.max((x.radiosity[k] - y.radiosity[k]).abs() / scale);
        }
    }
    worst
}

#[test]
fn results_do_not_depend_on_the_scene_scale() {
    // Radiosity is scale-free: scaling all lengths keeps every form factor. With
    // the same seed the same random numbers drive the same paths, so only
    // rounding can differ.
    let s = settings(2_000, 21);
    let run = |scale: f64, offset: DVec3| {
        let scene = cornell_like(scale, offset);
        let reference = Reference::new(&scene).unwrap();
        let points = sample_points(&scene, 12, 3).unwrap();
        let mut all = reference.radiosity_at(&points, &s).unwrap();
        all.extend(reference.object_means(&s).unwrap());
        all
    };
    let unit = run(1.0, DVec3::ZERO);
    for (scale, offset) in [
        (1e-3, DVec3::ZERO),
        (1e4, DVec3::ZERO),
        (1e-3, DVec3::new(30.0, -20.0, 10.0)),
    ] {
        let other = run(scale, offset);
        let diff = largest_relative_difference(&unit, &other);
        assert!(
            diff < 1e-6,
            "scale {scale}, offset {offset}: relative difference {diff}"
        );
    }
}

#[test]
fn same_seed_same_bits_on_one_and_two_threads() {
    let scene = cornell_like(1.0, DVec3::ZERO);
    let reference = Reference::new(&scene).unwrap();
    let points = sample_points(&scene, 5, 17).unwrap();
    let s = settings(1_500, 99);
    let run = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| {
                let mut all = reference.radiosity_at(&points, &s).unwrap();
                all.extend(reference.object_means(&s).unwrap());
                all
            })
    };
    let bits = |v: &[ProbeEstimate]| -> Vec<u64> {
        v.iter()
            .flat_map(|e| e.radiosity.0.into_iter().chain(e.std_error.0))
            .map(f64::to_bits)
            .collect()
    };
    let (one, two) = (run(1), run(2));
    assert_eq!(bits(&one), bits(&two));
    // A different seed must change the result (the seed is really used).
    let other = reference
        .radiosity_at(&points, &settings(1_500, 100))
        .unwrap();
    assert_ne!(bits(&one[..5]), bits(&other));
}

// ---------------------------------------------------------------- points and errors

#[test]
fn sample_points_are_stratified_by_area_and_lie_on_their_surfaces() {
    let scene = cornell_like(1.0, DVec3::ZERO);
    let count = 2_000;
    let points = sample_points(&scene, count, 5).unwrap();
    assert_eq!(points.len(), count);
    assert_eq!(points, sample_points(&scene, count, 5).unwrap());
    let total = scene.total_area();
    let mut per_surface = vec![0usize; scene.surfaces.len()];
    for p in &points {
        let s = &scene.surfaces[p.surface as usize];
        per_surface[p.surface as usize] += 1;
        assert_eq!(p.normal, s.normal);
        let v = &s.vertices;
        assert!((p.position - v[0]).dot(s.normal).abs() < 1e-12);
        // Inside: on the inner side of every edge (counter-clockwise about n).
        for k in 0..v.len() {
            let edge = v[(k + 1) % v.len()] - v[k];
            assert!(s.normal.cross(edge).dot(p.position - v[k]) >= -1e-12);
        }
    }
    // Stratification: a surface owns an interval of length `share` strata; the
    // strata wholly inside give one point each and the two cut at its ends give
    // zero or one, so the count differs from the share by less than two (plain
    // random sampling would stray by about sqrt(share), 17 for 275).
    for (s, n) in scene.surfaces.iter().zip(&per_surface) {
        let share = count as f64 * s.area / total;
        assert!(
            (*n as f64 - share).abs() < 2.0,
            "{n} points for share {share}"
        );
    }
}

#[test]
fn locate_attaches_free_points_to_the_right_surface() {
    let scene = cornell_like(1.0, DVec3::ZERO);
    let reference = Reference::new(&scene).unwrap();
    // Slightly above the floor, facing up: the floor quad containing (1, 4).
    let p = reference
        .locate(DVec3::new(1.0, 4.0, 1e-6), DVec3::Z)
        .unwrap();
    let s = &scene.surfaces[p.surface as usize];
    assert_eq!(s.normal, DVec3::Z);
    assert_eq!(p.position, DVec3::new(1.0, 4.0, 0.0));
    let (lo, hi) = s
        .vertices
        .iter()
        .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(a, b), v| {
            (a.min(*v), b.max(*v))
        });
    assert!(lo.x <= 1.0 && 1.0 <= hi.x && lo.y <= 4.0 && 4.0 <= hi.y);
    // The top of the short box (height 1.6) is found there, not the floor.
    let top = reference
        .locate(DVec3::new(1.5, 1.5, 1.6), DVec3::Z)
        .unwrap();
    assert_eq!(top.position.z, 1.6);
    // Wrong facing, off the plane, or outside every polygon: nothing.
    assert!(reference
        .locate(DVec3::new(1.0, 4.0, 0.0), -DVec3::Z)
        .is_none());
    assert!(reference
        .locate(DVec3::new(1.0, 4.0, 0.01), DVec3::Z)
        .is_none());
    assert!(reference
        .locate(DVec3::new(-1.0, 4.0, 0.0), DVec3::Z)
        .is_none());
    assert!(reference.locate(DVec3::NAN, DVec3::Z).is_none());
}

#[test]
fn bad_input_is_an_error_not_a_panic() {
    let empty = Scene::default();
    assert!(Reference::new(&empty).is_err());
    assert!(sample_points(&empty, 3, 0).is_err());
    let scene = cornell_like(1.0, DVec3::ZERO);
    let reference = Reference::new(&scene).unwrap();
    let good = point(&scene, 0, DVec3::new(0.0, 1.0, 1.0));
    let bad_surface = SurfacePoint {
        surface: 1_000,
        ..good
    };
    let bad_position = SurfacePoint {
        position: DVec3::new(f64::NAN, 0.0, 0.0),
        ..good
    };
    let s = settings(100, 0);
    assert!(reference.radiosity_at(&[good, bad_surface], &s).is_err());
    assert!(reference.radiosity_at(&[bad_position], &s).is_err());
    assert!(reference.radiosity_at(&[good], &settings(1, 0)).is_err());
    assert!(reference.object_means(&settings(0, 0)).is_err());
    let mut broken = scene.clone();
    broken.surfaces[3].material = 99;
    assert!(Reference::new(&broken).is_err());
    let mut broken = scene.clone();
    broken.surfaces[3].object = 99;
    assert!(Reference::new(&broken).is_err());
    let mut broken = scene;
    broken.surfaces[3].normal = -broken.surfaces[3].normal;
    assert!(Reference::new(&broken).is_err());
}

#[test]
fn objects_without_surfaces_get_zeros() {
    let mut b = Builder::new("empty object");
    let m = b.material(Rgb::splat(0.5), Rgb::splat(1.0));
    b.object("nothing");
    b.object("square");
    b.rect(m, DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::Z);
    let scene = b.build();
    let means = Reference::new(&scene)
        .unwrap()
        .object_means(&settings(100, 0))
        .unwrap();
    assert_eq!(means.len(), 2);
    assert_eq!(means[0], ProbeEstimate::default());
    // A lone square sees nothing: B = E exactly.
    assert_eq!(means[1].radiosity, scene.materials[m as usize].emission);
    assert_eq!(means[1].paths, 100);
}
