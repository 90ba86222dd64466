//! The generator's primitives: boxes with only the faces that can be seen,
//! and surfaces of revolution about a vertical axis (columns, balusters,
//! tables, planters), all facing out.

use super::plan::Frame;
use super::sink::Sink;
use super::trig::unit_circle;
use crate::error::Result;
use glam::DVec3;

/// Which faces of an axis-aligned box to make. Faces against a wall, a floor
/// or another part would only be hidden, so the callers leave them out.
#[derive(Clone, Copy, Debug)]
pub(super) struct Faces {
    /// The face at the low x end.
    pub neg_x: bool,
    /// The face at the high x end.
    pub pos_x: bool,
    /// The bottom.
    pub neg_y: bool,
    /// The top.
    pub pos_y: bool,
    /// The face at the low z (or d) end.
    pub neg_z: bool,
    /// The face at the high z (or d) end.
    pub pos_z: bool,
}

impl Faces {
    /// Every face.
    pub(super) const ALL: Faces = Faces {
        neg_x: true,
        pos_x: true,
        neg_y: true,
        pos_y: true,
        neg_z: true,
        pos_z: true,
    };
    /// All but the bottom: a block standing on something.
    pub(super) const STANDING: Faces = Faces {
        neg_y: false,
        ..Faces::ALL
    };
    /// The four sides only: a post between a floor and what it carries.
    pub(super) const SIDES: Faces = Faces {
        neg_y: false,
        pos_y: false,
        ..Faces::ALL
    };
    /// All but the top: a block hanging under something.
    pub(super) const HANGING: Faces = Faces {
        pos_y: false,
        ..Faces::ALL
    };

    /// How many faces are made.
    #[cfg(test)]
    pub(super) fn count(self) -> usize {
        [
            self.neg_x, self.pos_x, self.neg_y, self.pos_y, self.neg_z, self.pos_z,
        ]
        .iter()
        .filter(|f| **f)
        .count()
    }
}

/// The chosen faces of the box `lo..hi`, given in `frame`'s coordinates,
/// each facing out of the box.
pub(super) fn cuboid<S: Sink>(
    sink: &mut S,
    frame: Frame,
    material: u32,
    lo: DVec3,
    hi: DVec3,
    faces: Faces,
) -> Result<()> {
    let p = DVec3::new;
    let (a, b) = (lo, hi);
    // Each counter-clockwise seen from outside the box.
    let quads = [
        (
            faces.neg_x,
            [
                p(a.x, a.y, a.z),
                p(a.x, a.y, b.z),
                p(a.x, b.y, b.z),
                p(a.x, b.y, a.z),
            ],
        ),
        (
            faces.pos_x,
            [
                p(b.x, a.y, a.z),
                p(b.x, b.y, a.z),
                p(b.x, b.y, b.z),
                p(b.x, a.y, b.z),
            ],
        ),
        (
            faces.neg_y,
            [
                p(a.x, a.y, a.z),
                p(b.x, a.y, a.z),
                p(b.x, a.y, b.z),
                p(a.x, a.y, b.z),
            ],
        ),
        (
            faces.pos_y,
            [
                p(a.x, b.y, a.z),
                p(a.x, b.y, b.z),
                p(b.x, b.y, b.z),
                p(b.x, b.y, a.z),
            ],
        ),
        (
            faces.neg_z,
            [
                p(a.x, a.y, a.z),
                p(a.x, b.y, a.z),
                p(b.x, b.y, a.z),
                p(b.x, a.y, a.z),
            ],
        ),
        (
            faces.pos_z,
            [
                p(a.x, a.y, b.z),
                p(b.x, a.y, b.z),
                p(b.x, b.y, b.z),
                p(a.x, b.y, b.z),
            ],
        ),
    ];
    for (wanted, quad) in quads {
        if wanted {
            sink.polygon(material, &frame.polygon(&quad))?;
        }
    }
    Ok(())
}

/// A profile to revolve: points `(radius, height)` from the bottom up,
/// traced so that the solid lies to the profile's left when it runs up the
/// outside (outward, then up, then inward over a top), and one material per
/// segment.
#[derive(Clone, Debug, Default)]
pub(super) struct Profile {
    points: Vec<(f64, f64)>,
    materials: Vec<u32>,
}

impl Profile {
    /// A profile starting at `(radius, height)`.
    pub(super) fn start(radius: f64, height: f64) -> Profile {
        Profile {
            points: vec![(radius, height)],
            materials: Vec::new(),
        }
    }

    /// Continues with a straight segment to `(radius, height)`.
    pub(super) fn to(&mut self, radius: f64, height: f64, material: u32) -> &mut Profile {
        self.points.push((radius, height));
        self.materials.push(material);
        self
    }

    /// Continues along `curve(t)` for t in (0, 1] in `segments` straight pieces.
    pub(super) fn curve(
        &mut self,
        segments: usize,
        material: u32,
        curve: impl Fn(f64) -> (f64, f64),
    ) -> &mut Profile {
        for k in 1..=segments {
            let (r, y) = curve(k as f64 / segments as f64);
            self.to(r, y, material);
        }
        self
    }

    /// Triangles the profile makes when revolved in `around` steps.
    #[cfg(test)]
    pub(super) fn triangles(&self, around: usize) -> usize {
        self.points
            .windows(2)
            .map(|w| if w[0].0 > 0.0 && w[1].0 > 0.0 { 2 } else { 1 } * around)
            .sum()
    }
}

/// `profile` revolved about the vertical axis through `base` (world
/// coordinates; heights are added to `base.y`) in `around` steps: a quad per
/// step and segment, a triangle where the profile touches the axis. Every
/// lathe quad is an isosceles trapezoid, so it is planar and convex.
pub(super) fn lathe<S: Sink>(
    sink: &mut S,
    base: DVec3,
    profile: &Profile,
    around: usize,
) -> Result<()> {
    let circle = unit_circle(around);
    // x = r cos(theta), z = -r sin(theta): with this sense of turning a quad
    // (ring i, step k), (ring i, k+1), (ring i+1, k+1), (ring i+1, k) is
    // counter-clockwise seen from outside when the profile runs up the outside.
    let at = |(r, y): (f64, f64), (c, s): (f64, f64)| base + DVec3::new(r * c, y, -r * s);
    for (w, &material) in profile.points.windows(2).zip(&profile.materials) {
        let (p0, p1) = (w[0], w[1]);
        for k in 0..around {
            let (c0, c1) = (circle[k], circle[k + 1]);
            if p0.0 == 0.0 {
                sink.polygon(material, &[at(p0, c0), at(p1, c1), at(p1, c0)])?;
            } else if p1.0 == 0.0 {
                sink.polygon(material, &[at(p0, c0), at(p0, c1), at(p1, c0)])?;
            } else {
                sink.polygon(material, &[at(p0, c0), at(p0, c1), at(p1, c1), at(p1, c0)])?;
            }
        }
    }
    Ok(())
}

/// Steps around a circle of `radius` for `density` segments per metre, at
/// least `fewest`.
pub(super) fn steps_around(radius: f64, density: f64, fewest: usize) -> usize {
    steps_along(std::f64::consts::TAU * radius, density, fewest)
}

/// Segments along a curve of `length` for `density` segments per metre, at
/// least `fewest`.
pub(super) fn steps_along(length: f64, density: f64, fewest: usize) -> usize {
    ((length * density).ceil() as usize).max(fewest)
}

#[cfg(test)]
mod tests {
    use super::super::sink::Counter;
    use super::*;
    use crate::math::Rgb;
    use crate::scene::SceneBuilder;

    #[test]
    fn a_lathed_cylinder_with_a_lid_faces_out() {
        let mut b = SceneBuilder::new("lathe");
        let m = b.material("grey", Rgb::splat(0.5), Rgb::ZERO).unwrap();
        let mut profile = Profile::start(1.0, 0.0);
        profile.to(1.0, 2.0, m).to(0.0, 2.0, m);
        let base = DVec3::new(3.0, 0.0, -1.0);
        lathe(&mut b, base, &profile, 10).unwrap();
        let scene = b.build().unwrap();
        assert_eq!(scene.surfaces.len(), 20);
        let axis_point = base + DVec3::new(0.0, 1.0, 0.0);
        for s in &scene.surfaces {
            let c = s.centroid();
            if c.y > 1.999 {
                assert!(s.normal.y > 0.999, "lid faces up");
            } else {
                let out = DVec3::new(c.x - base.x, 0.0, c.z - base.z);
                assert!(s.normal.dot(out) > 0.9 * out.length(), "wall faces out");
                assert!(s.normal.dot(c - axis_point) > 0.0);
            }
        }
        let mut counter = Counter::default();
        lathe(&mut counter, base, &profile, 10).unwrap();
        assert_eq!(counter.triangles, profile.triangles(10));
        assert_eq!(counter.triangles, 10 * 2 + 10);
    }

    #[test]
    fn box_faces_face_out() {
        let mut b = SceneBuilder::new("box");
        let m = b.material("grey", Rgb::splat(0.5), Rgb::ZERO).unwrap();
        let (lo, hi) = (DVec3::new(1.0, 0.0, 2.0), DVec3::new(2.0, 0.5, 4.0));
        cuboid(&mut b, Frame::WORLD, m, lo, hi, Faces::STANDING).unwrap();
        let scene = b.build().unwrap();
        assert_eq!(scene.surfaces.len(), Faces::STANDING.count());
        let mid = (lo + hi) / 2.0;
        for s in &scene.surfaces {
            assert!(s.normal.dot(s.centroid() - mid) > 0.0);
            assert!(s.normal.y > -0.5, "no bottom");
        }
    }
}
