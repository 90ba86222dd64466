//! Turning a primitive's vertex stream into triangles: the three triangle modes,
//! indexed or not, as the glTF specification orders their vertices.

use gltf_json::mesh::Mode;

/// How a primitive's vertices make triangles, or `None` for points and lines.
pub(super) fn triangle_mode(mode: Mode) -> Option<Mode> {
    match mode {
        Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan => Some(mode),
        Mode::Points | Mode::Lines | Mode::LineLoop | Mode::LineStrip => None,
    }
}

/// How many triangles `n` vertices (or indices) make in `mode`.
pub(super) fn triangle_count(mode: Mode, n: usize) -> usize {
    match mode {
        Mode::Triangles => n / 3,
        Mode::TriangleStrip | Mode::TriangleFan => n.saturating_sub(2),
        _ => 0,
    }
}

/// The triangles of a stream of `n` vertex references, as positions in the
/// stream, front faces counter-clockwise. Strip triangle `i` is
/// `(i, i + 1 + i % 2, i + 2 - i % 2)` and fan triangle `i` is `(i + 1, i + 2, 0)`,
/// as glTF 2.0 defines them.
pub(super) fn triangles(mode: Mode, n: usize) -> Vec<[usize; 3]> {
    let count = triangle_count(mode, n);
    (0..count)
        .map(|i| match mode {
            Mode::TriangleStrip => [i, i + 1 + i % 2, i + 2 - i % 2],
            Mode::TriangleFan => [i + 1, i + 2, 0],
            _ => [3 * i, 3 * i + 1, 3 * i + 2],
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strips_alternate_and_fans_pivot_on_the_first_vertex() {
        assert_eq!(
            triangles(Mode::TriangleStrip, 5),
            vec![[0, 1, 2], [1, 3, 2], [2, 3, 4]]
        );
        assert_eq!(
            triangles(Mode::TriangleFan, 5),
            vec![[1, 2, 0], [2, 3, 0], [3, 4, 0]]
        );
        assert_eq!(triangles(Mode::Triangles, 7), vec![[0, 1, 2], [3, 4, 5]]);
        assert!(triangles(Mode::TriangleStrip, 2).is_empty());
        assert_eq!(triangle_count(Mode::Lines, 9), 0);
    }
}
