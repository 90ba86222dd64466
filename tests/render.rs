//! Renderer and image output checked against closed-form expectations.

use glam::DVec3;
use radiosity::math::Rgb;
use radiosity::render::{
    auto_exposure, diff, draw_segments, draw_segments_depth_tested, read_hdr_image, render,
    render_supersampled, render_with_depth, srgb_encode, to_srgb8, write_exr, write_hdr, write_png,
    HdrImage, ShadedMesh, ToneMap,
};
use radiosity::scene::Camera;
use radiosity::{Error, GeometryFault};
use std::path::PathBuf;

/// At the origin, looking down -Z with +Y up: view axes are world axes.
fn camera(yfov_degrees: f64) -> Camera {
    Camera::look_at(DVec3::ZERO, DVec3::NEG_Z, DVec3::Y, yfov_degrees)
}

/// A quad as two triangles sharing the diagonal 0-2, vertices counter-clockwise
/// seen from the front.
fn quad(corners: [DVec3; 4], values: [Rgb; 4]) -> ShadedMesh {
    ShadedMesh {
        positions: corners.to_vec(),
        values: values.to_vec(),
        triangles: vec![[0, 1, 2], [0, 2, 3]],
        texels: None,
        cull_back_faces: false,
    }
}

fn merge(meshes: &[ShadedMesh]) -> ShadedMesh {
    let mut out = ShadedMesh::default();
    for m in meshes {
        let base = out.positions.len() as u32;
        out.positions.extend(&m.positions);
        out.values.extend(&m.values);
        out.triangles
            .extend(m.triangles.iter().map(|t| t.map(|i| i + base)));
    }
    out
}

/// The world direction (at unit depth) through pixel point `(px, py)` of a
/// `w` x `h` image for `camera(yfov)`.
fn pixel_ray(px: f64, py: f64, w: u32, h: u32, yfov_degrees: f64) -> DVec3 {
    let th = (yfov_degrees.to_radians() / 2.0).tan();
    let aspect = f64::from(w) / f64::from(h);
    let nx = 2.0 * px / f64::from(w) - 1.0;
    let ny = 1.0 - 2.0 * py / f64::from(h);
    DVec3::new(nx * th * aspect, ny * th, -1.0)
}

fn assert_close(got: Rgb, want: Rgb, rel: f64, what: &str) {
    for k in 0..3 {
        let tol = rel * want[k].abs().max(1e-12);
        assert!(
            (got[k] - want[k]).abs() <= tol,
            "{what}: got {:?}, want {:?}",
            got.0,
            want.0
        );
    }
}

// A 64x64 image through a 90 degree camera: at depth 4, pixel x is
// (X / 4 + 1) * 32 and pixel y is (1 - Y / 4) * 32. These corners put the
// quad's edges at pixel x 10.625 and 50.375, y 5.625 and 40.375: a quarter of
// a sample away from every 2x2 sample position and an eighth from centres.
const X0: f64 = -2.671875;
const X1: f64 = 2.296875;
const Y_TOP: f64 = 3.296875;
const Y_BOTTOM: f64 = -1.046875;

fn rectangle(value: Rgb) -> ShadedMesh {
    quad(
        [
            DVec3::new(X0, Y_BOTTOM, -4.0),
            DVec3::new(X1, Y_BOTTOM, -4.0),
            DVec3::new(X1, Y_TOP, -4.0),
            DVec3::new(X0, Y_TOP, -4.0),
        ],
        [value; 4],
    )
}

#[test]
fn quad_covers_exactly_the_pixels_whose_centres_it_contains() {
    let v = Rgb::new(0.25, 0.5, 1.0);
    let img = render(&rectangle(v), &camera(90.0), 64, 64).unwrap();
    for y in 0..64 {
        for x in 0..64 {
            // Centres x + 0.5 in (10.625, 50.375), y + 0.5 in (5.625, 40.375).
            let inside = (11..=49).contains(&x) && (6..=39).contains(&y);
            // Exactly v inside (no crack along the shared diagonal), black outside.
            let want = if inside { v } else { Rgb::ZERO };
            assert_eq!(img.get(x, y), want, "pixel ({x}, {y})");
        }
    }
}

#[test]
fn supersampling_averages_a_two_by_two_grid() {
    let v = Rgb::new(0.25, 0.5, 1.0);
    let img = render_supersampled(&rectangle(v), &camera(90.0), 64, 64, 2).unwrap();
    // Samples at x + 0.25 and x + 0.75: the edge at 10.625 keeps one of the two
    // sample columns of pixel 10, the edge at 50.375 one of pixel 50.
    let coverage = |i: u32, lo: u32, hi: u32| -> f64 {
        if i == lo || i == hi {
            0.5
        } else if i > lo && i < hi {
            1.0
        } else {
            0.0
        }
    };
    for y in 0..64 {
        for x in 0..64 {
            let c = coverage(x, 10, 50) * coverage(y, 5, 40);
            assert_eq!(img.get(x, y), v * c, "pixel ({x}, {y})");
        }
    }
}

#[test]
fn gouraud_matches_a_linear_function_on_a_square_on_plane() {
    // A plane facing the camera squarely at depth 4, larger than the view;
    // value linear in world X.
    let f = |p: DVec3| Rgb::new(1.0 + 0.5 * p.x, 2.0 - 0.25 * p.x, 0.75);
    let corners = [
        DVec3::new(-9.0, -9.0, -4.0),
        DVec3::new(9.0, -9.0, -4.0),
        DVec3::new(9.0, 9.0, -4.0),
        DVec3::new(-9.0, 9.0, -4.0),
    ];
    let mesh = quad(corners, corners.map(f));
    let (w, h) = (48, 32);
    let img = render(&mesh, &camera(70.0), w, h).unwrap();
    for y in 0..h {
        for x in 0..w {
            let d = pixel_ray(f64::from(x) + 0.5, f64::from(y) + 0.5, w, h, 70.0);
            let hit = d * 4.0;
            assert_close(img.get(x, y), f(hit), 1e-6, &format!("pixel ({x}, {y})"));
        }
    }
}

#[test]
fn gouraud_is_perspective_correct_on_a_tilted_plane() {
    // Plane Z = -5 + 0.3 X + 0.2 Y; value linear in world position.
    let plane_z = |x: f64, y: f64| -5.0 + 0.3 * x + 0.2 * y;
    let f = |p: DVec3| {
        Rgb::new(
            5.0 + 0.1 * p.x - 0.05 * p.y + 0.02 * p.z,
            1.0 - 0.04 * p.z,
            2.0,
        )
    };
    let corners = [(-20.0, -20.0), (20.0, -20.0), (20.0, 20.0), (-20.0, 20.0)]
        .map(|(x, y)| DVec3::new(x, y, plane_z(x, y)));
    let mesh = quad(corners, corners.map(f));
    let (w, h) = (80, 60);
    let img = render(&mesh, &camera(90.0), w, h).unwrap();
    for y in 0..h {
        for x in 0..w {
            let d = pixel_ray(f64::from(x) + 0.5, f64::from(y) + 0.5, w, h, 90.0);
            // t d on the plane: -t = -5 + 0.3 t dx + 0.2 t dy.
            let t = 5.0 / (1.0 + 0.3 * d.x + 0.2 * d.y);
            assert_close(img.get(x, y), f(d * t), 1e-6, &format!("pixel ({x}, {y})"));
        }
    }
}

fn square_at(depth: f64, half: f64, value: Rgb) -> ShadedMesh {
    quad(
        [
            DVec3::new(-half, -half, -depth),
            DVec3::new(half, -half, -depth),
            DVec3::new(half, half, -depth),
            DVec3::new(-half, half, -depth),
        ],
        [value; 4],
    )
}

#[test]
fn nearer_surface_hides_farther_in_either_order() {
    let near = square_at(3.0, 1.0, Rgb::new(1.0, 0.0, 0.0));
    let far = square_at(6.0, 10.0, Rgb::new(0.0, 0.0, 1.0));
    let a = render(&merge(&[near.clone(), far.clone()]), &camera(60.0), 40, 40).unwrap();
    let b = render(&merge(&[far, near]), &camera(60.0), 40, 40).unwrap();
    assert_eq!(a, b);
    assert_eq!(a.get(20, 20), Rgb::new(1.0, 0.0, 0.0));
    assert_eq!(a.get(1, 1), Rgb::new(0.0, 0.0, 1.0));
}

#[test]
fn back_faces_render_black_but_occlude() {
    let mut back = square_at(3.0, 1.0, Rgb::ONE);
    back.triangles = vec![[0, 2, 1], [0, 3, 2]]; // clockwise seen from the camera
    let far = square_at(6.0, 10.0, Rgb::new(0.0, 0.0, 1.0));
    for mesh in [
        merge(&[back.clone(), far.clone()]),
        merge(&[far.clone(), back]),
    ] {
        let img = render(&mesh, &camera(60.0), 40, 40).unwrap();
        assert_eq!(img.get(20, 20), Rgb::ZERO);
        assert_eq!(img.get(1, 1), Rgb::new(0.0, 0.0, 1.0));
    }
}

#[test]
fn front_face_wins_over_a_coincident_back_face() {
    // A double-sided surface stored as two patches back to back.
    let front = square_at(3.0, 1.0, Rgb::splat(0.5));
    let mut back = front.clone();
    back.triangles = vec![[0, 2, 1], [0, 3, 2]];
    for mesh in [merge(&[back.clone(), front.clone()]), merge(&[front, back])] {
        let img = render(&mesh, &camera(60.0), 40, 40).unwrap();
        for y in 15..25 {
            for x in 15..25 {
                assert_eq!(img.get(x, y), Rgb::splat(0.5), "pixel ({x}, {y})");
            }
        }
    }
}

/// Barycentric interpolation of `values` at the point where the ray `d` from the
/// eye meets the plane of `p` (Cramer's rule on `a p0 + b p1 + c p2 = t d`).
fn interpolate_on_ray(p: [DVec3; 3], values: [Rgb; 3], d: DVec3) -> Rgb {
    let det = p[0].dot(p[1].cross(p[2]));
    let u = [
        d.dot(p[1].cross(p[2])) / det,
        p[0].dot(d.cross(p[2])) / det,
        p[0].dot(p[1].cross(d)) / det,
    ];
    let s = u[0] + u[1] + u[2];
    values[0] * (u[0] / s) + values[1] * (u[1] / s) + values[2] * (u[2] / s)
}

#[test]
fn triangle_crossing_the_camera_plane_shows_its_visible_part() {
    // World = view with z flipped. A is in front (depth 2); B and C are behind
    // the eye (depth -2). Edge AB lies in the plane x = m z through the eye and
    // edge AC in y = k z, so both project to axis-aligned lines through A's
    // image at pixel (20.25, 20.25); the visible part is everything right of
    // and below it.
    let (m, k) = (-0.3671875, 0.3671875);
    let a = DVec3::new(2.0 * m, 2.0 * k, -2.0);
    let b = DVec3::new(-2.0 * m, -3.0, 2.0);
    let c = DVec3::new(3.0, -2.0 * k, 2.0);
    let (va, vb, vc) = (
        Rgb::new(1.0, 2.0, 3.0),
        Rgb::new(2.0, 1.0, 0.5),
        Rgb::new(0.5, 3.0, 1.0),
    );
    let whole = ShadedMesh {
        positions: vec![a, b, c],
        values: vec![va, vb, vc],
        triangles: vec![[0, 1, 2]],
        texels: None,
        cull_back_faces: false,
    };
    // The same triangle cut by hand at depth 0.25, 7/16 of the way from A.
    let t = 0.4375;
    let pre_clipped = ShadedMesh {
        positions: vec![a, a + (b - a) * t, a + (c - a) * t],
        values: vec![va, va + (vb - va) * t, va + (vc - va) * t],
        triangles: vec![[0, 1, 2]],
        texels: None,
        cull_back_faces: false,
    };
    let cam = camera(90.0);
    let img = render(&whole, &cam, 64, 64).unwrap();
    let reference = render(&pre_clipped, &cam, 64, 64).unwrap();
    for y in 0..64u32 {
        for x in 0..64u32 {
            let got = img.get(x, y);
            if x >= 20 && y >= 20 {
                let d = pixel_ray(f64::from(x) + 0.5, f64::from(y) + 0.5, 64, 64, 90.0);
                let want = interpolate_on_ray([a, b, c], [va, vb, vc], d);
                assert_close(got, want, 1e-9, &format!("pixel ({x}, {y})"));
                assert_close(got, reference.get(x, y), 1e-9, &format!("pixel ({x}, {y})"));
            } else {
                assert_eq!(got, Rgb::ZERO, "pixel ({x}, {y})");
                assert_eq!(reference.get(x, y), Rgb::ZERO, "pixel ({x}, {y})");
            }
        }
    }
}

/// A few thousand pseudo-random triangles around the camera, some crossing
/// the camera plane, some back-facing.
fn random_mesh(triangles: usize, seed: u64) -> ShadedMesh {
    let mut state = seed;
    let mut rand = move || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    let mut mesh = ShadedMesh::default();
    for t in 0..triangles {
        let centre = DVec3::new(rand() * 8.0 - 4.0, rand() * 8.0 - 4.0, -rand() * 10.0 + 1.0);
        for _ in 0..3 {
            let p = centre + DVec3::new(rand() - 0.5, rand() - 0.5, rand() - 0.5) * 2.0;
            mesh.positions.push(p);
            mesh.values.push(Rgb::new(rand(), rand(), rand()));
        }
        let i = 3 * t as u32;
        mesh.triangles.push([i, i + 1, i + 2]);
    }
    mesh
}

#[test]
fn same_bits_on_one_and_two_threads() {
    let mesh = random_mesh(3000, 7);
    let cam = Camera::look_at(
        DVec3::new(0.2, 0.1, 0.5),
        DVec3::new(0.0, 0.0, -5.0),
        DVec3::Y,
        75.0,
    );
    let run = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| render_with_depth(&mesh, &cam, 97, 61, 2).unwrap())
    };
    let (img1, depth1) = run(1);
    let (img2, depth2) = run(2);
    let bits = |img: &HdrImage| -> Vec<u64> {
        img.pixels
            .iter()
            .flat_map(|p| p.0.map(f64::to_bits))
            .collect()
    };
    assert_eq!(bits(&img1), bits(&img2));
    let dbits = |d: &[f64]| d.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
    assert_eq!(dbits(&depth1.inverse_depth), dbits(&depth2.inverse_depth));
    // The scene is not trivially empty.
    assert!(img1.pixels.iter().filter(|p| p.max_band() > 0.0).count() > 1000);
}

#[test]
fn bad_input_is_an_error_not_a_panic() {
    let mut mesh = square_at(3.0, 1.0, Rgb::ONE);
    mesh.triangles.push([0, 1, 9]);
    assert!(matches!(
        render(&mesh, &camera(60.0), 8, 8),
        Err(Error::Geometry {
            fault: GeometryFault::Mismatch,
            ..
        })
    ));
    let mesh = square_at(3.0, 1.0, Rgb::ONE);
    assert!(render(&mesh, &camera(60.0), 0, 8).is_err());
    assert!(render_supersampled(&mesh, &camera(60.0), 8, 8, 0).is_err());
    let mut cam = camera(60.0);
    cam.forward = DVec3::ZERO;
    assert!(render(&mesh, &cam, 8, 8).is_err());
}

#[test]
fn srgb_transfer_at_known_points() {
    assert_eq!(srgb_encode(0.0), 0.0);
    assert_eq!(srgb_encode(1.0), 1.0);
    // Both branches meet at the threshold, at the decoder's threshold 0.04045.
    let below = 12.92 * 0.0031308;
    let above = 1.055 * 0.0031308f64.powf(1.0 / 2.4) - 0.055;
    assert!((srgb_encode(0.0031308) - 0.04045).abs() < 1e-6);
    assert!((below - above).abs() < 1e-6);
    let mut img = HdrImage::new(4, 1);
    img.pixels = vec![Rgb::ZERO, Rgb::ONE, Rgb::splat(0.5), Rgb::splat(0.0031308)];
    let out = to_srgb8(&img, 0.0, ToneMap::Clamp);
    assert_eq!(out.get_pixel(0, 0).0, [0; 3]);
    assert_eq!(out.get_pixel(1, 0).0, [255; 3]);
    assert_eq!(out.get_pixel(2, 0).0, [188; 3]);
    // 0.04045 * 255 = 10.31
    assert_eq!(out.get_pixel(3, 0).0, [10; 3]);
}

#[test]
fn one_stop_doubles_linear_values() {
    let values = [0.01, 0.1, 0.2, 0.37, 0.45];
    let mut img = HdrImage::new(values.len() as u32, 1);
    img.pixels = values
        .iter()
        .map(|&v| Rgb::new(v, v * 0.5, v * 0.25))
        .collect();
    let mut doubled = img.clone();
    for p in &mut doubled.pixels {
        *p *= 2.0;
    }
    for tone in ToneMap::ALL {
        assert_eq!(
            to_srgb8(&img, 1.0, tone),
            to_srgb8(&doubled, 0.0, tone),
            "{tone}"
        );
        assert_eq!(
            to_srgb8(&doubled, -1.0, tone),
            to_srgb8(&img, 0.0, tone),
            "{tone}"
        );
    }
    // Reinhard at +1 stop on 0.5: 1 / (1 + 1) = 0.5 -> 188.
    let mut half = HdrImage::new(1, 1);
    half.pixels[0] = Rgb::splat(0.5);
    assert_eq!(
        to_srgb8(&half, 1.0, ToneMap::Reinhard).get_pixel(0, 0).0,
        [188; 3]
    );
}

#[test]
fn auto_exposure_maps_the_bright_end_to_eight_tenths() {
    // Uniform grey 0.5 with a black background: Reinhard reaches 0.8 at 4, so
    // 3 stops; Clamp reaches it at 0.8, so log2(1.6) stops.
    let mut img = HdrImage::new(10, 10);
    for p in img.pixels.iter_mut().take(60) {
        *p = Rgb::splat(0.5);
    }
    assert!((auto_exposure(&img, ToneMap::Reinhard) - 3.0).abs() < 1e-9);
    assert!((auto_exposure(&img, ToneMap::Clamp) - 1.6f64.log2()).abs() < 1e-9);
    // Values 1..=101: nearest rank 0.97 * 100 = 97 gives 98.
    let mut ramp = HdrImage::new(101, 1);
    for (i, p) in ramp.pixels.iter_mut().enumerate() {
        *p = Rgb::splat(i as f64 + 1.0);
    }
    assert!((auto_exposure(&ramp, ToneMap::Reinhard) - (4.0f64 / 98.0).log2()).abs() < 1e-9);
    assert_eq!(
        auto_exposure(&HdrImage::new(3, 3), ToneMap::AcesFitted),
        0.0
    );
}

fn scratch_dir(test: &str) -> PathBuf {
    std::env::temp_dir().join(format!("radiosity-render-{}-{test}", std::process::id()))
}

fn test_image() -> HdrImage {
    let mut img = HdrImage::new(7, 5);
    for (i, p) in img.pixels.iter_mut().enumerate() {
        let f = i as f64;
        *p = Rgb::new(0.1 + f * 0.37, 1e-3 * (f + 1.0), 7.0 / (f + 1.0));
    }
    img
}

#[test]
fn exr_round_trip_is_exact_in_f32() {
    let dir = scratch_dir("exr");
    let path = dir.join("nested").join("img.exr");
    let img = test_image();
    write_exr(&img, &path).unwrap();
    let back = read_hdr_image(&path).unwrap();
    assert_eq!((back.width, back.height), (7, 5));
    for (a, b) in img.pixels.iter().zip(&back.pixels) {
        assert_eq!(a.to_f32().map(f64::from), b.0);
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn hdr_round_trip_within_its_mantissa_precision() {
    let dir = scratch_dir("hdr");
    let path = dir.join("img.hdr");
    let img = test_image();
    write_hdr(&img, &path).unwrap();
    let back = read_hdr_image(&path).unwrap();
    assert_eq!((back.width, back.height), (7, 5));
    for (a, b) in img.pixels.iter().zip(&back.pixels) {
        // Shared exponent, 8-bit mantissas: error below 2^-7 of the largest band.
        let tol = a.max_band() / 128.0;
        for k in 0..3 {
            assert!((a[k] - b[k]).abs() <= tol, "{:?} vs {:?}", a.0, b.0);
        }
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn png_is_written_and_errors_name_the_path() {
    let dir = scratch_dir("png");
    let path = dir.join("img.png");
    write_png(&test_image(), &path, 0.0, ToneMap::AcesFitted).unwrap();
    assert!(std::fs::metadata(&path).unwrap().len() > 0);
    let missing = dir.join("missing.exr");
    match read_hdr_image(&missing) {
        Err(Error::Io { path, .. }) => assert_eq!(path, missing),
        other => panic!("expected an I/O error, got {other:?}"),
    }
    std::fs::write(dir.join("junk.hdr"), b"not an image").unwrap();
    let e = read_hdr_image(&dir.join("junk.hdr"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("junk.hdr"), "{e}");
    let empty = HdrImage::new(0, 3);
    assert!(matches!(
        write_exr(&empty, &dir.join("empty.exr")),
        Err(Error::Output { .. })
    ));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn diff_metrics_on_hand_made_images() {
    let mut a = HdrImage::new(2, 1);
    a.pixels = vec![Rgb::new(1.0, 2.0, 3.0), Rgb::ZERO];
    let mut b = HdrImage::new(2, 1);
    b.pixels = vec![Rgb::ONE, Rgb::new(0.0, 0.0, 2.0)];
    let (d, m) = diff(&a, &b).unwrap();
    assert_eq!(
        d.pixels,
        vec![Rgb::new(0.0, 1.0, 2.0), Rgb::new(0.0, 0.0, 2.0)]
    );
    // Differences 0, 1, 2, 0, 0, 2; reference values 1, 1, 1, 0, 0, 2.
    assert!((m.mae - 5.0 / 6.0).abs() < 1e-15);
    assert!((m.rmse - (9.0f64 / 6.0).sqrt()).abs() < 1e-15);
    assert!((m.relative_rmse - (9.0f64 / 7.0).sqrt()).abs() < 1e-15);
    assert_eq!(m.max_abs, 2.0);
    let (_, same) = diff(&a, &a).unwrap();
    assert_eq!(
        (same.mae, same.rmse, same.relative_rmse, same.max_abs),
        (0.0, 0.0, 0.0, 0.0)
    );
    assert!(diff(&a, &HdrImage::new(1, 2)).is_err());
}

#[test]
fn segments_are_drawn_where_they_project() {
    let cam = camera(90.0);
    let red = Rgb::new(1.0, 0.0, 0.0);
    // At depth 4, Y = 0.0625 is pixel y 31.5; X from -1 to 1 is pixel x 24 to 40.
    let seg = [
        DVec3::new(-1.0, 0.0625, -4.0),
        DVec3::new(1.0, 0.0625, -4.0),
    ];
    let mut img = HdrImage::new(64, 64);
    draw_segments(&mut img, &cam, &[seg], red).unwrap();
    for x in 24..=40 {
        assert_eq!(img.get(x, 31), red, "x {x}");
    }
    let lit = img.pixels.iter().filter(|p| **p == red).count();
    assert_eq!(lit, 17);

    // A segment from in front of the eye to behind it: the visible part runs
    // from pixel (36, 36) to the bottom-right corner, nothing wraps around.
    let mut img = HdrImage::new(64, 64);
    let crossing = [DVec3::new(0.5, -0.5, -4.0), DVec3::new(0.5, -0.5, 4.0)];
    draw_segments(&mut img, &cam, &[crossing], red).unwrap();
    for k in 37..64 {
        assert_eq!(img.get(k, k), red, "({k}, {k})");
    }
    assert!(img.pixels[..64 * 35].iter().all(|p| *p == Rgb::ZERO));
}

#[test]
fn depth_tested_segments_hide_behind_nearer_surfaces() {
    let cam = camera(90.0);
    // A wall at depth 4 with a line on it, and a small square at depth 2
    // covering the middle of the line.
    let wall = square_at(4.0, 8.0, Rgb::splat(0.2));
    let blocker = square_at(2.0, 0.25, Rgb::splat(0.4));
    let (mut img, depth) = render_with_depth(&merge(&[wall, blocker]), &cam, 64, 64, 2).unwrap();
    let seg = [
        DVec3::new(-2.0, 0.0625, -4.0),
        DVec3::new(2.0, 0.0625, -4.0),
    ];
    let red = Rgb::new(1.0, 0.0, 0.0);
    draw_segments_depth_tested(&mut img, &depth, &cam, &[seg], red).unwrap();
    // Blocker spans X in [-0.25, 0.25] at depth 2: pixel x 28 to 36.
    for x in 17..=26 {
        assert_eq!(img.get(x, 31), red, "visible at x {x}");
    }
    for x in 29..=35 {
        assert_eq!(img.get(x, 31), Rgb::splat(0.4), "hidden at x {x}");
    }
    for x in 38..=47 {
        assert_eq!(img.get(x, 31), red, "visible at x {x}");
    }
}
