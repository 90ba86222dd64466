//! Walking the node hierarchy of the scene to import, composing each node's local
//! transform (a matrix, or translation * rotation * scale) into its world transform
//! in double precision.

use super::document::Document;
use super::limits::ImportLimits;
use super::precise::numbers;
use super::{describe, gltf_error, gltf_error_at};
use crate::error::{Error, GltfKind, GltfObject, LimitKind, Result};
use glam::{DMat4, DQuat, DVec3};
use std::path::Path;

/// One node reached from the scene's roots, with its world transform.
#[derive(Clone, Debug)]
pub(super) struct Placed {
    /// Index into the document's nodes.
    pub node: usize,
    /// Local-to-world transform.
    pub world: DMat4,
}

/// Every node of the scene to import, in depth-first order (parents before
/// children, children in the file's order). The scene is the document's default
/// scene, else its first scene, else every node that is nobody's child.
///
/// A node reached twice (the hierarchy is not a tree, or has a cycle) is an error,
/// and so is nesting deeper than [`ImportLimits::max_node_depth`]; both bound the
/// walk by the number of nodes.
pub(super) fn walk(path: &Path, doc: &Document, limits: &ImportLimits) -> Result<Vec<Placed>> {
    let nodes = &doc.root.nodes;
    let roots: Vec<usize> =
        match doc
            .root
            .scene
            .map(|s| s.value())
            .or(if doc.root.scenes.is_empty() {
                None
            } else {
                Some(0)
            }) {
            Some(s) => doc
                .root
                .scenes
                .get(s)
                .ok_or_else(|| gltf_error(path, format!("scene {s} does not exist")))?
                .nodes
                .iter()
                .map(|n| n.value())
                .collect(),
            None => parentless(doc),
        };
    let mut reached = vec![false; nodes.len()];
    let mut out = Vec::new();
    // Explicit stack (node, parent's world transform, depth) instead of recursion.
    let mut stack: Vec<(usize, DMat4, usize)> = roots
        .iter()
        .rev()
        .map(|&n| (n, DMat4::IDENTITY, 1))
        .collect();
    while let Some((n, parent, depth)) = stack.pop() {
        let node = nodes
            .get(n)
            .ok_or_else(|| gltf_error(path, format!("node {n} does not exist")))?;
        let what = describe("node", n, node.name.as_deref());
        let object = || GltfObject::new(GltfKind::Node, n, node.name.as_deref());
        if reached[n] {
            return Err(gltf_error_at(
                path,
                object(),
                format!("{what} is reached twice from the scene's roots: the node hierarchy must be a tree"),
            ));
        }
        reached[n] = true;
        if depth > limits.max_node_depth {
            return Err(Error::limit(
                LimitKind::NodeDepth,
                format!(
                    "{}: {what} is nested deeper than {} levels",
                    path.display(),
                    limits.max_node_depth
                ),
            ));
        }
        let local = local_transform(doc, n)
            .map_err(|m| gltf_error_at(path, object(), format!("{what}: {m}")))?;
        let world = parent * local;
        if !world.is_finite() {
            return Err(gltf_error_at(
                path,
                object(),
                format!("{what}: its world transform is not finite"),
            ));
        }
        out.push(Placed { node: n, world });
        if let Some(children) = &node.children {
            for child in children.iter().rev() {
                stack.push((child.value(), world, depth + 1));
            }
        }
    }
    Ok(out)
}

/// Nodes that are no node's child, in index order.
fn parentless(doc: &Document) -> Vec<usize> {
    let mut has_parent = vec![false; doc.root.nodes.len()];
    for node in &doc.root.nodes {
        for child in node.children.iter().flatten() {
            if let Some(flag) = has_parent.get_mut(child.value()) {
                *flag = true;
            }
        }
    }
    (0..has_parent.len()).filter(|&i| !has_parent[i]).collect()
}

/// A node's local transform, from the full-precision JSON numbers.
fn local_transform(doc: &Document, n: usize) -> std::result::Result<DMat4, String> {
    let base = format!("/nodes/{n}");
    let node = &doc.root.nodes[n];
    let m = if node.matrix.is_some() {
        let a = numbers::<16>(&doc.raw, &format!("{base}/matrix"))
            .ok_or("its matrix is not 16 numbers")?;
        // glTF matrices are column-major, like glam's: the bottom row is
        // elements 3, 7, 11 and 15.
        let bottom = [a[3], a[7], a[11], a[15]];
        if bottom != [0.0, 0.0, 0.0, 1.0] {
            return Err(format!(
                "its matrix has the bottom row {bottom:?}, not [0, 0, 0, 1]: glTF node \
                 matrices must be affine (decomposable into translation, rotation and scale), \
                 and this one is projective"
            ));
        }
        DMat4::from_cols_array(&a)
    } else {
        let t = numbers::<3>(&doc.raw, &format!("{base}/translation")).unwrap_or([0.0; 3]);
        let r = numbers::<4>(&doc.raw, &format!("{base}/rotation")).unwrap_or([0.0, 0.0, 0.0, 1.0]);
        let s = numbers::<3>(&doc.raw, &format!("{base}/scale")).unwrap_or([1.0; 3]);
        let q = DQuat::from_array(r);
        let len = q.length();
        if !(len.is_finite() && len > 0.0) {
            return Err(format!("its rotation {r:?} is not a usable quaternion"));
        }
        // Files store unit quaternions rounded to a few digits: renormalise.
        DMat4::from_scale_rotation_translation(DVec3::from(s), q / len, DVec3::from(t))
    };
    if !m.is_finite() {
        return Err("its transform has non-finite numbers".to_string());
    }
    Ok(m)
}
