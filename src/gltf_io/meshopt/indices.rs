//! Modes `TRIANGLES` (triangle lists coded against a FIFO of recent edges and
//! one of recent vertices, most triangles in one byte) and `INDICES` (zigzag
//! deltas against two baselines).

use super::{index_bytes, varint};

/// Recent edges or vertices; entry 0 is the most recently added.
struct Fifo<T: Copy + Default> {
    entries: [T; 16],
    head: usize,
}

impl<T: Copy + Default> Fifo<T> {
    fn new() -> Self {
        Fifo {
            entries: [T::default(); 16],
            head: 0,
        }
    }

    fn push(&mut self, x: T) {
        self.entries[self.head & 15] = x;
        self.head = self.head.wrapping_add(1);
    }

    fn get(&self, recent: usize) -> T {
        self.entries[self.head.wrapping_sub(1 + recent) & 15]
    }
}

/// A zigzag delta from `last`, which it updates.
fn delta_index(v: u32, last: &mut u32) -> u32 {
    let delta = if v & 1 == 0 { v >> 1 } else { !(v >> 1) };
    *last = last.wrapping_add(delta);
    *last
}

/// Decodes `count` triangle-list indices of `size` bytes (2 or 4).
pub(super) fn decode_triangles(data: &[u8], count: usize, size: usize) -> Result<Vec<u8>, String> {
    if size != 2 && size != 4 {
        return Err(format!("byteStride {size} must be 2 or 4"));
    }
    if !count.is_multiple_of(3) {
        return Err(format!("count {count} is not a whole number of triangles"));
    }
    let triangles = count / 3;
    if data.len() < 1 + triangles + 16 {
        return Err(format!(
            "{} bytes are too few for {triangles} triangles",
            data.len()
        ));
    }
    if data[0] != 0xe1 {
        return Err(format!("the stream starts with {:#04x}, not 0xe1", data[0]));
    }
    let codes = &data[1..1 + triangles];
    let end = data.len() - 16;
    let aux = &data[end..];
    let mut at = 1 + triangles;
    let (mut next, mut last) = (0u32, 0u32);
    let mut edges: Fifo<(u32, u32)> = Fifo::new();
    let mut vertices: Fifo<u32> = Fifo::new();
    let mut out = Vec::with_capacity(count);
    let short = || "the stream ends inside a triangle's extra data".to_string();
    for &code in codes {
        let (hi, lo) = (usize::from(code >> 4), usize::from(code & 15));
        let (a, b, c);
        if hi < 15 {
            (a, b) = edges.get(hi);
            c = match lo {
                0 => {
                    next = next.wrapping_add(1);
                    next.wrapping_sub(1)
                }
                1..=12 => vertices.get(lo),
                13 | 14 => {
                    last = if lo == 13 {
                        last.wrapping_sub(1)
                    } else {
                        last.wrapping_add(1)
                    };
                    last
                }
                _ => delta_index(varint(data, &mut at, end)?, &mut last),
            };
            edges.push((c, b));
            edges.push((a, c));
            if !(1..=12).contains(&lo) {
                vertices.push(c);
            }
        } else {
            let zw = if lo < 14 {
                aux[lo]
            } else {
                let byte = *data.get(at).filter(|_| at < end).ok_or_else(short)?;
                at += 1;
                if byte == 0 {
                    next = 0;
                }
                byte
            };
            let (z, w) = (usize::from(zw >> 4), usize::from(zw & 15));
            let explicit = lo == 15;
            a = if explicit {
                delta_index(varint(data, &mut at, end)?, &mut last)
            } else {
                next = next.wrapping_add(1);
                next.wrapping_sub(1)
            };
            let mut third = |k: usize| -> Result<u32, String> {
                Ok(match k {
                    0 => {
                        next = next.wrapping_add(1);
                        next.wrapping_sub(1)
                    }
                    15 if lo >= 14 => delta_index(varint(data, &mut at, end)?, &mut last),
                    _ => vertices.get(k - 1),
                })
            };
            b = third(z)?;
            c = third(w)?;
            edges.push((b, a));
            edges.push((c, b));
            edges.push((a, c));
            vertices.push(a);
            let fresh = |k: usize| k == 0 || (k == 15 && lo >= 14);
            if fresh(z) {
                vertices.push(b);
            }
            if fresh(w) {
                vertices.push(c);
            }
        }
        out.extend([a, b, c]);
    }
    if at != end {
        return Err(format!("{} bytes of extra data left over", end - at));
    }
    Ok(index_bytes(&out, size))
}

/// Decodes `count` indices of `size` bytes (2 or 4) of any topology.
pub(super) fn decode_indices(data: &[u8], count: usize, size: usize) -> Result<Vec<u8>, String> {
    if size != 2 && size != 4 {
        return Err(format!("byteStride {size} must be 2 or 4"));
    }
    if data.len() < 1 + 4 || data[0] != 0xd1 {
        return Err("the stream does not start with 0xd1".to_string());
    }
    let end = data.len() - 4;
    let mut at = 1;
    let mut last = [0u32; 2];
    let mut out = Vec::with_capacity(count);
    for _ in 0..count {
        let v = varint(data, &mut at, end)?;
        let base = (v & 1) as usize;
        let v = v >> 1;
        let delta = if v & 1 == 0 { v >> 1 } else { !(v >> 1) };
        last[base] = last[base].wrapping_add(delta);
        out.push(last[base]);
    }
    if at != end {
        return Err(format!("{} bytes left over", end - at));
    }
    Ok(index_bytes(&out, size))
}
