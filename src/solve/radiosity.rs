//! What a solver produces: the radiosity of every element node and patch,
//! kept apart from the mesh, which holds geometry only.

use crate::math::Rgb;
use crate::mesh::{ElementKey, Mesh, Patch};
use slotmap::SecondaryMap;

/// Radiosity (exitance, per band) per element node and per patch.
///
/// Leaves hold what the last gather or shot gave them; interior nodes the
/// area-weighted mean of their children once a solve has finished (during a
/// solve they hold whatever they had when they were split). Patches hold the
/// solution of the coarse system.
#[derive(Clone, Debug, Default)]
pub struct Radiosity {
    elements: SecondaryMap<ElementKey, Rgb>,
    patches: Vec<Rgb>,
}

impl Radiosity {
    /// Every element and patch of `mesh` at its surface's emission: the
    /// radiosity before any light has been reflected.
    #[must_use]
    pub fn emitted(mesh: &Mesh) -> Self {
        let mut elements = SecondaryMap::with_capacity(mesh.elements.len());
        for (k, e) in &mesh.elements {
            elements.insert(k, e.emission);
        }
        let patches = (0..mesh.patches.len() as u32)
            .map(|p| mesh.patch_emission(p))
            .collect();
        Radiosity { elements, patches }
    }

    /// The radiosity of element node `k` (0 for a key it does not hold).
    #[inline]
    #[must_use]
    pub fn element(&self, k: ElementKey) -> Rgb {
        self.elements.get(k).copied().unwrap_or(Rgb::ZERO)
    }

    /// Sets element node `k`'s radiosity.
    #[inline]
    pub(crate) fn set_element(&mut self, k: ElementKey, value: Rgb) {
        self.elements.insert(k, value);
    }

    /// Adds `delta` to element node `k`'s radiosity.
    #[inline]
    pub(crate) fn add_to_element(&mut self, k: ElementKey, delta: Rgb) {
        match self.elements.get_mut(k) {
            Some(v) => *v += delta,
            None => {
                self.elements.insert(k, delta);
            }
        }
    }

    /// The patches' radiosities, by patch id.
    #[must_use]
    pub fn patches(&self) -> &[Rgb] {
        &self.patches
    }

    /// Replaces the patches' radiosities.
    pub(crate) fn set_patches(&mut self, values: &[Rgb]) {
        self.patches.clear();
        self.patches.extend_from_slice(values);
    }

    /// Replaces every element and patch value `v` by `f(v)`.
    pub(crate) fn map_values(&mut self, f: impl Fn(Rgb) -> Rgb) {
        for v in self.elements.values_mut() {
            *v = f(*v);
        }
        for v in &mut self.patches {
            *v = f(*v);
        }
    }

    /// The children of a split element start with its radiosity.
    pub fn inherit(&mut self, parent: ElementKey, children: &[ElementKey]) {
        let value = self.element(parent);
        for &c in children {
            self.elements.insert(c, value);
        }
    }

    /// Sets every interior node below `key` to the area-weighted mean of its
    /// children, and returns `key`'s value.
    pub(crate) fn push_up(&mut self, mesh: &Mesh, key: ElementKey) -> Rgb {
        let e = &mesh.elements[key];
        if e.is_leaf() {
            return self.element(key);
        }
        let mut sum = Rgb::ZERO;
        for &c in &e.children {
            sum += self.push_up(mesh, c) * mesh.elements[c].area;
        }
        let mean = sum / e.area;
        self.elements.insert(key, mean);
        mean
    }

    /// Sets every interior node of patch `p`'s trees to the area-weighted
    /// mean of its children, and returns the patch's area-weighted mean.
    pub(crate) fn patch_mean(&mut self, mesh: &Mesh, p: &Patch) -> Rgb {
        if let [root] = p.roots[..] {
            return self.push_up(mesh, root);
        }
        let mut sum = Rgb::ZERO;
        for &root in &p.roots {
            sum += self.push_up(mesh, root) * mesh.elements[root].area;
        }
        sum / p.area
    }

    /// Heap bytes held (the element table and the patch values).
    #[must_use]
    pub fn heap_bytes(&self) -> usize {
        self.elements.capacity() * std::mem::size_of::<(u32, Rgb)>()
            + self.patches.capacity() * std::mem::size_of::<Rgb>()
    }
}
