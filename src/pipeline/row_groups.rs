//! Rows shared by neighbouring facets of a face cluster.
//!
//! Each facet of a tessellated curved surface is an element of its own (see
//! `crate::mesh::clusters`), with a hemi-cube of its own. On a million
//! triangles the facets are a few centimetres across, a hemi-cube per facet
//! is most of the solve's time, and neighbours a few centimetres apart whose
//! normals agree see nearly the same scene. So the facets of one cluster that
//! fall in one cell of a grid [`GROUP_CELL`] patch sizes wide, with normals
//! within [`GROUP_ANGLE_DEGREES`] of the first one's, form a group; the
//! member nearest the group's centre (its lead) renders the row, and the
//! others take a copy of it. The group is then one receiver of the size of
//! the elements a plain patch starts with.
//!
//! The adaptive part stays: after each solve, a group whose radiosity
//! differs from a neighbouring group of its cluster by more than the
//! refinement tolerance is split, as a quadtree splits an element: its
//! members regroup by the cells of a grid half as wide, and each new group
//! of two or more gets a lead of its own in the next pass. So only where
//! the light changes do groups shrink, down to single facets with rows of
//! their own. A cluster that would make a single group (a small object)
//! would have nothing to check it against: it is grouped in smaller cells
//! until it makes two or more.

use super::Settings;
use crate::formfactor::FormFactors;
use crate::mesh::{ElementKey, Mesh};
use crate::refine::{Contrast, RefineSettings};
use crate::solve::Radiosity;
use glam::DVec3;
use slotmap::SecondaryMap;
use std::collections::BTreeMap;

/// The grid cell that holds a group, in patch sizes: the size of the
/// elements a plain patch is first split into (half a patch).
pub(crate) const GROUP_CELL: f64 = 0.5;

/// Widest angle between a member's normal and its group's first member's:
/// the copied row was rendered facing the lead's way.
pub(crate) const GROUP_ANGLE_DEGREES: f64 = 10.0;

/// Most times a cluster that makes a single group is grouped again in cells
/// half as wide (a 256th of the first cell at the last).
const MAX_REGROUPS: usize = 8;

/// The facet groups of a solve.
#[derive(Debug, Default)]
pub(crate) struct RowGroups {
    /// Per leaf in a group of two or more, its group.
    group_of: SecondaryMap<ElementKey, u32>,
    groups: Vec<Group>,
    /// Per patch, its groups that have not been split (empty for patches
    /// without any).
    of_patch: BTreeMap<u32, Vec<u32>>,
}

#[derive(Debug)]
struct Group {
    members: Vec<ElementKey>,
    /// The member whose row the others copy.
    lead: ElementKey,
    /// Area-weighted centre of the members.
    centre: DVec3,
    /// True while the members copy the lead's row; false once split.
    shared: bool,
    /// The side of the grid cell that holds the group.
    cell: f64,
}

impl RowGroups {
    /// Groups the facets of every face cluster of `mesh` whose surfaces are
    /// still whole leaves; none unless `settings.shared_rows`.
    pub(crate) fn new(mesh: &Mesh, settings: &Settings, patch_size: f64) -> Self {
        let mut groups = RowGroups::default();
        if !settings.shared_rows {
            return groups;
        }
        let min_cos = GROUP_ANGLE_DEGREES.to_radians().cos();
        for (p, patch) in mesh.patches.iter().enumerate() {
            if !patch.is_cluster() {
                continue;
            }
            // Facets by grid cell, in root order within each cell.
            let leaves: Vec<ElementKey> = patch
                .roots
                .iter()
                .copied()
                .filter(|&k| mesh.elements[k].is_leaf())
                .collect();
            // A group is checked against its cluster's other groups; a
            // cluster that makes one group (a small object) would never be,
            // so it is grouped again in cells half as wide until it makes
            // two or more, or none (its facets then keep rows of their own).
            let mut cell = GROUP_CELL * patch_size;
            let mut found = like_facets(mesh, &leaves, cell, min_cos);
            for _ in 0..MAX_REGROUPS {
                if found.len() != 1 {
                    break;
                }
                cell *= 0.5;
                found = like_facets(mesh, &leaves, cell, min_cos);
            }
            if found.len() > 1 {
                for members in found {
                    let g = groups.push(mesh, members, cell);
                    groups.of_patch.entry(p as u32).or_default().push(g);
                }
            }
        }
        groups
    }

    /// Adds a group of `members` (two or more) held by a cell of side
    /// `cell`; returns its index.
    fn push(&mut self, mesh: &Mesh, members: Vec<ElementKey>, cell: f64) -> u32 {
        let area: f64 = members.iter().map(|&k| mesh.elements[k].area).sum();
        let centre = members
            .iter()
            .map(|&k| mesh.elements[k].centroid * mesh.elements[k].area)
            .sum::<DVec3>()
            / area;
        let lead = *members
            .iter()
            .min_by(|&&a, &&b| {
                let da = (mesh.elements[a].centroid - centre).length_squared();
                let db = (mesh.elements[b].centroid - centre).length_squared();
                da.total_cmp(&db)
            })
            .expect("a group has members");
        let g = self.groups.len() as u32;
        for &k in &members {
            self.group_of.insert(k, g);
        }
        self.groups.push(Group {
            members,
            lead,
            centre,
            shared: true,
            cell,
        });
        g
    }

    /// Splits group `g` into the groups of its members in each cell of a
    /// grid half as wide (members alone in theirs leave every group);
    /// returns the new groups.
    fn split(&mut self, mesh: &Mesh, g: u32) -> Vec<u32> {
        let group = &mut self.groups[g as usize];
        group.shared = false;
        let cell = 0.5 * group.cell;
        // Members that refinement has split since have rows per child.
        let members = group.members.clone().into_iter();
        let members = members.filter(|&k| mesh.elements[k].is_leaf());
        let mut children = Vec::new();
        for members in by_cell(mesh, members, cell) {
            if let [alone] = members[..] {
                self.group_of.remove(alone);
            } else {
                children.push(self.push(mesh, members, cell));
            }
        }
        children
    }

    /// Groups formed (of two or more facets), the split ones included.
    pub(crate) fn len(&self) -> usize {
        self.groups.len()
    }

    /// Splits `keys` (leaves about to get rows) into those to render and
    /// those that copy a lead's row, as (leaf, lead). A member copies only
    /// when its lead is rendered in the same batch or already has its row.
    pub(crate) fn borrowers(
        &self,
        keys: Vec<ElementKey>,
        form_factors: &FormFactors,
    ) -> (Vec<ElementKey>, Vec<(ElementKey, ElementKey)>) {
        if self.groups.is_empty() {
            return (keys, Vec::new());
        }
        let batch: std::collections::HashSet<ElementKey> = keys.iter().copied().collect();
        let mut render = Vec::with_capacity(keys.len());
        let mut copy = Vec::new();
        for k in keys {
            let lead = self
                .group_of
                .get(k)
                .map(|&g| &self.groups[g as usize])
                .filter(|g| g.shared && g.lead != k)
                .map(|g| g.lead);
            match lead {
                Some(l) if batch.contains(&l) || form_factors.state(l).is_computed() => {
                    copy.push((k, l));
                }
                _ => render.push(k),
            }
        }
        (render, copy)
    }

    /// Splits every group whose radiosity differs from a neighbouring group
    /// of its cluster (centres within two of the larger cells) by more than
    /// the refinement tolerance, measured as the criterion measures it
    /// ([`Contrast`]).
    /// Returns the members that now need rows of their own or from a new
    /// lead (the old leads keep theirs), in a deterministic order.
    pub(crate) fn unshare(
        &mut self,
        mesh: &Mesh,
        radiosity: &Radiosity,
        refine: &RefineSettings,
    ) -> Vec<ElementKey> {
        if self.groups.is_empty() {
            return Vec::new();
        }
        let Some(contrast) = Contrast::of_scene(mesh, radiosity, refine.dim_floor) else {
            return Vec::new();
        };
        let mut ending = vec![false; self.groups.len()];
        for groups in self.of_patch.values() {
            for (i, &a) in groups.iter().enumerate() {
                for &b in &groups[i + 1..] {
                    let (ga, gb) = (&self.groups[a as usize], &self.groups[b as usize]);
                    let reach = 2.0 * ga.cell.max(gb.cell) * 3f64.sqrt();
                    if (ga.centre - gb.centre).length_squared() > reach * reach {
                        continue;
                    }
                    if contrast.between(mesh, radiosity, ga.lead, gb.lead) > refine.tolerance {
                        ending[a as usize] = true;
                        ending[b as usize] = true;
                    }
                }
            }
        }
        let mut fresh = Vec::new();
        let of_patch = std::mem::take(&mut self.of_patch);
        for (patch, groups) in of_patch {
            let mut kept = Vec::with_capacity(groups.len());
            for g in groups {
                if !ending[g as usize] {
                    kept.push(g);
                    continue;
                }
                let group = &self.groups[g as usize];
                let lead = group.lead;
                fresh.extend(group.members.iter().copied().filter(|&k| k != lead));
                kept.extend(self.split(mesh, g));
            }
            self.of_patch.insert(patch, kept);
        }
        fresh
    }
}

/// The groups of two or more of `leaves` (facets of one cluster) that share
/// a grid cell of side `cell` and whose normals are within the angle whose
/// cosine is `min_cos` of the first one's.
fn like_facets(
    mesh: &Mesh,
    leaves: &[ElementKey],
    cell: f64,
    min_cos: f64,
) -> Vec<Vec<ElementKey>> {
    let normal = |k: ElementKey| mesh.surfaces()[mesh.elements[k].surface as usize].normal;
    let mut found = Vec::new();
    for mut left in by_cell(mesh, leaves.iter().copied(), cell) {
        while !left.is_empty() {
            let seed = normal(left[0]);
            let (members, rest): (Vec<_>, Vec<_>) = left
                .into_iter()
                .partition(|&k| normal(k).dot(seed) >= min_cos);
            left = rest;
            if members.len() > 1 {
                found.push(members);
            }
        }
    }
    found
}

/// `keys` by the cell of a grid of side `cell` that holds their centroids,
/// in the order of the cells and, within each, of `keys`.
fn by_cell(
    mesh: &Mesh,
    keys: impl Iterator<Item = ElementKey>,
    cell: f64,
) -> impl Iterator<Item = Vec<ElementKey>> {
    let mut cells: BTreeMap<[i64; 3], Vec<ElementKey>> = BTreeMap::new();
    for k in keys {
        let at = (mesh.elements[k].centroid / cell).floor();
        cells
            .entry([at.x as i64, at.y as i64, at.z as i64])
            .or_default()
            .push(k);
    }
    cells.into_values()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Rgb;
    use crate::scene::{Scene, SceneBuilder};
    use std::f64::consts::TAU;

    /// A column of `sides` x `rings` quads, radius 1, height 2, facing out.
    fn column(sides: usize, rings: usize) -> Scene {
        let mut b = SceneBuilder::new("column");
        let m = b.material("grey", Rgb::splat(0.5), Rgb::ZERO).unwrap();
        b.object("column");
        let at = |i: usize, j: usize| {
            let a = TAU * i as f64 / sides as f64;
            DVec3::new(a.cos(), 2.0 * j as f64 / rings as f64, a.sin())
        };
        for j in 0..rings {
            for i in 0..sides {
                b.polygon(m, &[at(i, j), at(i, j + 1), at(i + 1, j + 1), at(i + 1, j)])
                    .unwrap();
            }
        }
        b.build().unwrap()
    }

    fn groups_of(scene: &Scene, patch_size: f64) -> (Mesh, RowGroups) {
        let mesh = Mesh::build(scene, patch_size, usize::MAX, true).unwrap();
        let groups = RowGroups::new(&mesh, &Settings::default(), patch_size);
        (mesh, groups)
    }

    #[test]
    fn each_facet_is_in_at_most_one_group_of_one_cell_and_like_normals() {
        // 128 sides: 2.8 degrees between neighbours, so a group spans a few
        // sides within the angle and many rings within the cell.
        let scene = column(128, 16);
        let patch_size = 1.0;
        let (mesh, groups) = groups_of(&scene, patch_size);
        assert!(groups.len() > 10, "{} groups", groups.len());
        let mut seen = std::collections::HashSet::new();
        let min_cos = GROUP_ANGLE_DEGREES.to_radians().cos() - 1e-12;
        for g in &groups.groups {
            assert!(g.members.len() > 1);
            assert!(g.members.contains(&g.lead));
            let normal = |k: ElementKey| mesh.surfaces()[mesh.elements[k].surface as usize].normal;
            let first = g.members[0];
            assert_eq!(g.cell, GROUP_CELL * patch_size);
            let cell_of = |k: ElementKey| (mesh.elements[k].centroid / g.cell).floor();
            for &k in &g.members {
                assert!(seen.insert(k), "a facet in two groups");
                assert_eq!(
                    groups.group_of[k] as usize,
                    groups
                        .groups
                        .iter()
                        .position(|h| std::ptr::eq(h, g))
                        .unwrap()
                );
                assert!(normal(k).dot(normal(first)) >= min_cos);
                assert_eq!(cell_of(k), cell_of(first));
                assert_eq!(mesh.elements[k].patch, mesh.elements[first].patch);
            }
            // The lead is the member nearest the area-weighted centre.
            let d = |k: ElementKey| (mesh.elements[k].centroid - g.centre).length();
            assert!(g.members.iter().all(|&k| d(g.lead) <= d(k)));
        }
        // Every cluster with a group has at least two, so that each group
        // has another to be checked against.
        for groups in groups.of_patch.values() {
            assert!(groups.len() > 1);
        }
        // Most facets share: the column's 2048 facets in far fewer groups.
        assert!(seen.len() > 1500, "{} of 2048 facets grouped", seen.len());
    }

    /// A gently domed square `size` across of `n` x `n` quads, facing up,
    /// its corner at `at`: one face cluster whose normals are within a few
    /// degrees of one another.
    fn dome(n: usize, size: f64, at: DVec3) -> Scene {
        let mut b = SceneBuilder::new("dome");
        let m = b.material("grey", Rgb::splat(0.5), Rgb::ZERO).unwrap();
        b.object("dome");
        let p = |i: usize, j: usize| {
            let (x, z) = (size * i as f64 / n as f64, size * j as f64 / n as f64);
            let (u, v) = (x - 0.5 * size, z - 0.5 * size);
            at + DVec3::new(x, -0.05 * (u * u + v * v) / size, z)
        };
        for i in 0..n {
            for j in 0..n {
                b.polygon(m, &[p(i, j), p(i, j + 1), p(i + 1, j + 1), p(i + 1, j)])
                    .unwrap();
            }
        }
        b.build().unwrap()
    }

    #[test]
    fn a_small_cluster_is_grouped_in_smaller_cells_until_it_makes_two_groups() {
        // 0.2 m across inside one 0.5 m cell, its normals within 2 degrees:
        // one group at the first cell, so it is grouped again.
        let scene = dome(8, 0.2, DVec3::new(0.1, 0.1, 0.1));
        let (mesh, groups) = groups_of(&scene, 1.0);
        assert!(groups.len() >= 2, "{} groups", groups.len());
        for g in &groups.groups {
            assert!(g.cell < GROUP_CELL, "cell {}", g.cell);
            let cell_of = |k: ElementKey| (mesh.elements[k].centroid / g.cell).floor();
            assert!(g.members.iter().all(|&k| cell_of(k) == cell_of(g.lead)));
        }
        // With 1 km patches the square stays in one cell down to a 256th of
        // the first (1.95 m): it makes no groups, and keeps rows per facet.
        let (_, coarse) = groups_of(&dome(8, 0.2, DVec3::splat(100.1)), 1e3);
        assert_eq!(coarse.len(), 0);
    }

    #[test]
    fn a_group_differing_from_its_neighbour_splits_and_an_even_one_does_not() {
        let scene = column(128, 16);
        let patch_size = 1.0;
        let (mesh, mut groups) = groups_of(&scene, patch_size);
        let mut radiosity = Radiosity::emitted(&mesh);
        for k in mesh.leaves() {
            radiosity.set_element(k, Rgb::splat(1.0));
        }
        assert!(groups
            .unshare(&mesh, &radiosity, &RefineSettings::default())
            .is_empty());
        // One group's lead 10% darker: it and its neighbours within reach
        // are split; their members other than the leads need new rows.
        let before = groups.len();
        let g = before / 2;
        let lead = groups.groups[g].lead;
        radiosity.set_element(lead, Rgb::splat(0.9));
        let fresh = groups.unshare(&mesh, &radiosity, &RefineSettings::default());
        assert!(!groups.groups[g].shared);
        let ended: Vec<&Group> = groups.groups[..before]
            .iter()
            .filter(|g| !g.shared)
            .collect();
        assert!(
            ended.len() >= 2 && ended.len() < before,
            "{} of {before}",
            ended.len()
        );
        let mut dropped = 0;
        for old in &ended {
            dropped += old.members.len() - 1;
            for &k in &old.members {
                assert_eq!(k != old.lead, fresh.contains(&k));
                // Each member is now alone or in a shared group of half the
                // cell, made of members of the same old group.
                if let Some(&c) = groups.group_of.get(k) {
                    let child = &groups.groups[c as usize];
                    assert!(c as usize >= before && child.shared);
                    assert_eq!(child.cell, 0.5 * old.cell);
                    assert!(child.members.iter().all(|m| old.members.contains(m)));
                }
            }
        }
        assert_eq!(fresh.len(), dropped);
        // Rows to render: members alone, and the new leads. Splitting a
        // group into cells half as wide renders far fewer than a row per
        // member.
        let renders = |fresh: &[ElementKey], groups: &RowGroups| {
            fresh
                .iter()
                .filter(|&&k| {
                    groups
                        .group_of
                        .get(k)
                        .is_none_or(|&c| groups.groups[c as usize].lead == k)
                })
                .count()
        };
        let rendered = renders(&fresh, &groups);
        assert!(rendered * 2 < dropped, "{rendered} rows for {dropped}");
        // The groups go on splitting only while the dark facet leads one
        // that has a neighbour, and that ends.
        let mut rounds = 0;
        loop {
            let more = groups.unshare(&mesh, &radiosity, &RefineSettings::default());
            if more.is_empty() {
                break;
            }
            rounds += 1;
            assert!(rounds < 8, "still splitting after {rounds} rounds");
        }
        // Groups that were split are no longer checked: no new look finds
        // anything.
        assert!(groups
            .unshare(&mesh, &radiosity, &RefineSettings::default())
            .is_empty());
    }

    #[test]
    fn no_groups_when_shared_rows_are_off() {
        let scene = column(128, 16);
        let mesh = Mesh::build(&scene, 1.0, usize::MAX, true).unwrap();
        let settings = Settings {
            shared_rows: false,
            ..Settings::default()
        };
        assert_eq!(RowGroups::new(&mesh, &settings, 1.0).len(), 0);
    }
}
