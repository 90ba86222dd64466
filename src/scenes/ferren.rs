//! A model in the spirit of John Ferren's sculpture "Construction in Wood, A
//! Daylight Experiment", the example of Greenberg, Cohen and Torrance (1986).
//!
//! The paper describes painted wooden panels, white on the front and a colour
//! on the back, lit mainly by a window behind them; the white fronts look
//! coloured because the coloured backs of the panels in front of them reflect
//! daylight onto them. The paper's drawings of the model are not available, so
//! this one follows the description, not the original's layout:
//!
//! - **Room**: an open-fronted box [`WIDTH`] x [`HEIGHT`] x [`DEPTH`] (x right,
//!   y up, z towards the viewer), its faces pointing in: `floor` (grey 0.45),
//!   `left_wall`, `right_wall`, `ceiling` and `back_wall` (white 0.75; the back
//!   wall is four quads framing the window). The side at `z = DEPTH` is open
//!   and the camera stands outside it. Walls, floor and white paint are neutral
//!   grey, so any colour on a white front comes from the panel backs.
//! - **Window**: the emitting `window` filling most of the back wall (`z = 0`),
//!   2.1 m x 1.8 m, facing the panels: white radiance [`WINDOW_RADIANCE`],
//!   reflectance 0 (light that reaches a window leaves the room).
//! - **Fill**: a dim white strip `fill_light`, 0.2 m deep along the front edge
//!   of the ceiling, facing down, at a tenth of the window's radiance (1.3% of
//!   the emitted power): the counterpart of the dimmer point light in front
//!   that the paper's ray tracer used. Without it the white fronts, which face
//!   away from the window, would get almost no direct light, and the
//!   direct-only image (`--direct-only`) would be black where the paper's
//!   ray-traced one is white.
//! - **Panels**: 27 boards, 0.45 m wide and 2 cm thick, standing on the floor
//!   in three rows of nine, 0.33 m, 0.8 m and 1.27 m from the window, 1.45 m,
//!   1.1 m and 0.75 m tall (the back rows show above the front ones, and
//!   daylight over the back rows reaches the front rows). Each board is turned
//!   60 degrees about the vertical, like a louvre: its white front
//!   (`panel_NN_front`, reflectance 0.8) looks towards the viewer's side and
//!   to the right, its coloured back (`panel_NN_back`) towards the window and
//!   the left. Neighbours in a row stand 0.26 m apart, so every front faces the
//!   back of its right-hand neighbour across a 0.2 m gap, and that back sees
//!   the window: the coloured backs become coloured light sources for the
//!   fronts. The last board of each row faces the right wall instead and stays
//!   white. The backs are saturated red (0.8, 0.1, 0.1), yellow (0.8, 0.7,
//!   0.1), blue (0.1, 0.2, 0.8) and green (0.1, 0.6, 0.15), cycling along each
//!   row and shifted by one from row to row. A board is a box without a bottom
//!   (it stands on the floor): its two ends and top are `panel_NN_edges`,
//!   white. `NN` counts from 00 at the left end of the window row, row by row
//!   towards the viewer.
//! - **Camera** `view`: outside the open side, to the right and above, so that
//!   it sees the white fronts and none of the coloured backs.
//!
//! At the default patch size ([`Settings::patch_size_for`]: the bounding-box
//! diagonal over 10, 0.347 m) the scene has 900 patches, about the paper's 960.
//!
//! [`Settings::patch_size_for`]: crate::pipeline::Settings::patch_size_for

use crate::math::Rgb;
use crate::scene::{Camera, Scene, SceneBuilder};
use glam::DVec3;

/// Inside width of the room (x), metres.
pub const WIDTH: f64 = 2.4;
/// Inside height of the room (y), metres.
pub const HEIGHT: f64 = 2.0;
/// Depth of the room from the window wall to the open side (z), metres.
pub const DEPTH: f64 = 1.5;
/// Emitted radiance of the window, per band (white daylight).
pub const WINDOW_RADIANCE: f64 = 10.0;
/// Emitted radiance of the fill strip, per band.
pub(crate) const FILL_RADIANCE: f64 = 1.0;
/// Reflectance of the white paint on the panels' fronts, per band.
pub const WHITE_PAINT: f64 = 0.8;

/// Where everything goes (one layout; the struct just names the numbers).
struct Layout {
    /// Width of a panel, metres.
    panel_width: f64,
    /// Thickness of a panel, metres.
    panel_thickness: f64,
    /// Panels per row.
    per_row: usize,
    /// Rows from the window towards the viewer: distance of the panels'
    /// centres from the window wall, height, turn about the vertical in
    /// degrees from facing the viewer squarely (positive: the fronts look
    /// towards +x).
    rows: [(f64, f64, f64); 3],
    /// Clearance between the outermost panels and the side walls, metres.
    side_clearance: f64,
    /// Window edges: distance from the side walls, the floor and the ceiling.
    window_margins: (f64, f64, f64),
    /// Depth of the fill strip along the ceiling's front edge, metres.
    fill_depth: f64,
    /// Camera eye, target and vertical field of view in degrees.
    camera: (DVec3, DVec3, f64),
}

const LAYOUT: Layout = Layout {
    panel_width: 0.45,
    panel_thickness: 0.02,
    per_row: 9,
    rows: [(0.33, 1.45, 60.0), (0.8, 1.1, 60.0), (1.27, 0.75, 60.0)],
    side_clearance: 0.04,
    window_margins: (0.15, 0.1, 0.1),
    fill_depth: 0.2,
    camera: (DVec3::new(2.3, 1.7, 3.0), DVec3::new(1.1, 0.5, 0.6), 45.0),
};

/// Back colours, cycled along each row.
const BACK_COLOURS: [(&str, [f64; 3]); 4] = [
    ("red", [0.8, 0.1, 0.1]),
    ("yellow", [0.8, 0.7, 0.1]),
    ("blue", [0.1, 0.2, 0.8]),
    ("green", [0.1, 0.6, 0.15]),
];

/// The Ferren sculpture scene described in the [module notes](self).
#[must_use]
pub fn ferren_sculpture() -> Scene {
    build(&LAYOUT).expect("the built-in Ferren sculpture data is valid")
}

/// A rectangle `origin, origin + u, origin + u + v, origin + v`, facing
/// `u x v`.
fn rect(origin: DVec3, u: DVec3, v: DVec3) -> [DVec3; 4] {
    [origin, origin + u, origin + u + v, origin + v]
}

fn build(layout: &Layout) -> crate::Result<Scene> {
    let mut b = SceneBuilder::new("ferren_sculpture");
    let white = b.material("white_paint", Rgb::splat(WHITE_PAINT), Rgb::ZERO)?;
    let wall = b.material("wall", Rgb::splat(0.75), Rgb::ZERO)?;
    let floor = b.material("floor", Rgb::splat(0.45), Rgb::ZERO)?;
    let window = b.material("window", Rgb::ZERO, Rgb::splat(WINDOW_RADIANCE))?;
    let fill = b.material("fill_light", Rgb::ZERO, Rgb::splat(FILL_RADIANCE))?;
    let mut colours = Vec::new();
    for (name, [r, g, bl]) in BACK_COLOURS {
        colours.push(b.material(name, Rgb::new(r, g, bl), Rgb::ZERO)?);
    }

    room(&mut b, layout, wall, floor, window, fill)?;

    let mut n = 0;
    for (row, &(z, height, turn_degrees)) in layout.rows.iter().enumerate() {
        let turn = turn_degrees.to_radians();
        let tangent = DVec3::new(turn.cos(), 0.0, -turn.sin());
        let normal = DVec3::new(turn.sin(), 0.0, turn.cos());
        // Centres spread so that the outermost boards clear the side walls.
        let half_extent = 0.5
            * (layout.panel_width * turn.cos().abs() + layout.panel_thickness * turn.sin().abs());
        let first = layout.side_clearance + half_extent;
        let pitch = (WIDTH - 2.0 * first) / (layout.per_row - 1) as f64;
        for k in 0..layout.per_row {
            let centre = DVec3::new(first + k as f64 * pitch, 0.0, z);
            let colour = colours[(k + row) % colours.len()];
            let board = Board {
                centre,
                tangent,
                normal,
                height,
            };
            board.add(&mut b, layout, n, white, colour)?;
            n += 1;
        }
    }

    let (eye, target, fov) = layout.camera;
    let mut camera = Camera::look_at(eye, target, DVec3::Y, fov);
    camera.name = "view".to_string();
    b.camera(camera);
    b.build()
}

/// The room: floor, ceiling with the fill strip, side walls, the back wall
/// framing the window.
fn room(
    b: &mut SceneBuilder,
    layout: &Layout,
    wall: u32,
    floor: u32,
    window: u32,
    fill: u32,
) -> crate::Result<()> {
    let (x, y, z) = (DVec3::X, DVec3::Y, DVec3::Z);
    let (w, h, d) = (WIDTH, HEIGHT, DEPTH);
    let fill_depth = layout.fill_depth;
    b.object("floor");
    b.polygon(floor, &rect(DVec3::ZERO, z * d, x * w))?;
    b.object("ceiling");
    b.polygon(wall, &rect(y * h, x * w, z * (d - fill_depth)))?;
    b.object("fill_light");
    b.polygon(
        fill,
        &rect(y * h + z * (d - fill_depth), x * w, z * fill_depth),
    )?;
    b.object("left_wall");
    b.polygon(wall, &rect(DVec3::ZERO, y * h, z * d))?;
    b.object("right_wall");
    b.polygon(wall, &rect(x * w, z * d, y * h))?;

    let (side, bottom, top) = layout.window_margins;
    let window_height = h - bottom - top;
    b.object("window");
    b.polygon(
        window,
        &rect(
            x * side + y * bottom,
            x * (w - 2.0 * side),
            y * window_height,
        ),
    )?;
    b.object("back_wall");
    b.polygon(wall, &rect(DVec3::ZERO, x * w, y * bottom))?;
    b.polygon(wall, &rect(y * (h - top), x * w, y * top))?;
    b.polygon(wall, &rect(y * bottom, x * side, y * window_height))?;
    b.polygon(
        wall,
        &rect(x * (w - side) + y * bottom, x * side, y * window_height),
    )?;
    Ok(())
}

/// A board standing on the floor at `centre`: its white front faces
/// `normal`, its coloured back `-normal`, `tangent` runs along its width.
struct Board {
    centre: DVec3,
    tangent: DVec3,
    normal: DVec3,
    height: f64,
}

impl Board {
    /// Adds the board as panel `n`: front, back and edges objects.
    fn add(
        &self,
        b: &mut SceneBuilder,
        layout: &Layout,
        n: usize,
        white: u32,
        colour: u32,
    ) -> crate::Result<()> {
        let centre = self.centre;
        let across = self.tangent * layout.panel_width;
        let half_across = across * 0.5;
        let through = self.normal * layout.panel_thickness;
        let half_through = through * 0.5;
        let up = DVec3::Y * self.height;
        // tangent x up = normal, so (across, up) faces the front.
        b.object(&format!("panel_{n:02}_front"));
        b.polygon(
            white,
            &rect(centre + half_through - half_across, across, up),
        )?;
        b.object(&format!("panel_{n:02}_back"));
        b.polygon(
            colour,
            &rect(centre - half_through + half_across, -across, up),
        )?;
        b.object(&format!("panel_{n:02}_edges"));
        // The ends face +tangent and -tangent (normal x up = -tangent); the
        // top faces up (normal x tangent = up).
        b.polygon(
            white,
            &rect(centre + half_across + half_through, -through, up),
        )?;
        b.polygon(
            white,
            &rect(centre - half_across - half_through, through, up),
        )?;
        b.polygon(
            white,
            &rect(centre - half_across - half_through + up, through, across),
        )?;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pipeline::Settings;

    fn object_of<'a>(scene: &'a Scene, s: &crate::scene::Surface) -> &'a str {
        &scene.objects[s.object as usize].name
    }

    #[test]
    fn room_faces_point_inwards_and_boards_outwards() {
        let scene = ferren_sculpture();
        let inside = DVec3::new(0.5 * WIDTH, 0.5 * HEIGHT, 0.5 * DEPTH);
        for s in &scene.surfaces {
            let name = object_of(&scene, s);
            let c = s.centroid();
            if name.starts_with("panel_") {
                // Outwards from the board's own centre line.
                let board: Vec<DVec3> = scene
                    .surfaces
                    .iter()
                    .filter(|t| object_of(&scene, t).starts_with(&name[..8]))
                    .flat_map(|t| t.vertices.iter().copied())
                    .collect();
                let mid = board.iter().copied().sum::<DVec3>() / board.len() as f64;
                assert!(s.normal.dot(c - mid) > 0.0, "{name}: {}", s.normal);
            } else {
                assert!(s.normal.dot(inside - c) > 0.0, "{name}: {}", s.normal);
            }
        }
    }

    #[test]
    fn fronts_face_the_viewer_and_backs_the_window() {
        let scene = ferren_sculpture();
        let mut fronts = 0;
        let mut backs = 0;
        for s in &scene.surfaces {
            let name = object_of(&scene, s);
            let m = scene.material_of(s);
            if name.ends_with("_front") {
                fronts += 1;
                // Towards the open side, turned 60 degrees: cos 60 = 0.5.
                assert!((s.normal.z - 0.5).abs() < 1e-12, "{name}");
                assert_eq!(m.reflectance, Rgb::splat(WHITE_PAINT));
            } else if name.ends_with("_back") {
                backs += 1;
                assert!((s.normal.z + 0.5).abs() < 1e-12, "{name}");
                // Saturated: the strongest band at least 5 times the weakest.
                assert!(m.reflectance.max_band() >= 5.0 * m.reflectance.min_band());
            }
        }
        assert_eq!((fronts, backs), (27, 27));
    }

    #[test]
    fn only_the_window_and_the_fill_emit_white_light() {
        let scene = ferren_sculpture();
        let emitters: Vec<&str> = scene
            .surfaces
            .iter()
            .filter(|s| scene.material_of(s).is_emitter())
            .map(|s| object_of(&scene, s))
            .collect();
        assert_eq!(emitters, ["fill_light", "window"]);
        for s in &scene.surfaces {
            let e = scene.material_of(s).emission;
            assert!(e[0] == e[1] && e[1] == e[2], "{}", object_of(&scene, s));
        }
    }

    #[test]
    fn boards_stay_inside_the_room_and_clear_of_each_other() {
        let scene = ferren_sculpture();
        for s in &scene.surfaces {
            for v in &s.vertices {
                let inside = (0.0..=WIDTH).contains(&v.x)
                    && (0.0..=HEIGHT).contains(&v.y)
                    && (0.0..=DEPTH).contains(&v.z);
                assert!(inside, "{} at {v}", object_of(&scene, s));
            }
        }
        let l = &LAYOUT;
        for &(z, height, turn_degrees) in &l.rows {
            let turn = turn_degrees.to_radians();
            // Neighbours are parallel planes: the gap between them (pitch
            // times the sine of the turn) must exceed the thickness.
            let half_extent = 0.5 * (l.panel_width * turn.cos() + l.panel_thickness * turn.sin());
            let first = l.side_clearance + half_extent;
            let pitch = (WIDTH - 2.0 * first) / (l.per_row - 1) as f64;
            assert!(pitch * turn.sin() > l.panel_thickness + 0.1);
            assert!(height < HEIGHT && z > 0.0);
        }
        // Rows do not touch: each board reaches this far either side in z.
        let reach = |turn: f64| {
            let t = turn.to_radians();
            0.5 * (l.panel_width * t.sin() + l.panel_thickness * t.cos())
        };
        for pair in l.rows.windows(2) {
            assert!(pair[1].0 - reach(pair[1].2) > pair[0].0 + reach(pair[0].2) + 0.05);
        }
    }

    #[test]
    fn default_patch_size_gives_within_a_tenth_of_the_papers_960_patches() {
        // Greenberg, Cohen and Torrance's sculpture has 960 patches; the
        // default patch size (the scene's diagonal over 10) cuts this
        // reconstruction into 900.
        let scene = ferren_sculpture();
        let size = Settings::default().patch_size_for(&scene);
        let mesh = crate::mesh::Mesh::new(&scene, size, 50_000).unwrap();
        let n = mesh.patches.len() as f64;
        assert!((n / 960.0 - 1.0).abs() < 0.1, "{n} patches of {size} m");
    }
}
