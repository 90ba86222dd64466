//! The bitstreams against streams written by hand from the specification,
//! and attributes against a small encoder written here from it.

use super::attributes;
use super::indices::{decode_indices, decode_triangles};

fn u16s(bytes: &[u8]) -> Vec<u32> {
    bytes
        .chunks(2)
        .map(|b| u32::from(u16::from_le_bytes([b[0], b[1]])))
        .collect()
}

#[test]
fn triangles_decode_from_every_kind_of_code() {
    let mut stream = vec![0xe1];
    // Codes: three new vertices through the table; an edge and the next
    // vertex; three explicit deltas; an edge and last - 1; an edge and a
    // recent vertex.
    stream.extend([0xf0, 0x00, 0xff, 0x0d, 0x15]);
    // Extra data of the explicit triangle: its byte, then +5, -2, +1 zigzag.
    stream.extend([0xff, 0x0a, 0x03, 0x02]);
    stream.extend([0u8; 16]);
    let decoded = decode_triangles(&stream, 15, 2).unwrap();
    assert_eq!(
        u16s(&decoded),
        vec![0, 1, 2, 0, 2, 3, 5, 3, 4, 5, 4, 3, 3, 4, 2]
    );
    // Four-byte indices: the same values.
    let wide = decode_triangles(&stream, 15, 4).unwrap();
    assert_eq!(wide.len(), 60);
    assert_eq!(
        u32::from_le_bytes([wide[56], wide[57], wide[58], wide[59]]),
        2
    );
    // Extra data left over, or missing, is an error.
    let mut longer = stream.clone();
    longer.insert(9, 0x00);
    assert!(decode_triangles(&longer, 15, 2).is_err());
    let mut shorter = stream.clone();
    shorter.remove(8);
    assert!(decode_triangles(&shorter, 15, 2).is_err());
    assert!(
        decode_triangles(&stream, 14, 2).is_err(),
        "not whole triangles"
    );
}

#[test]
fn indices_decode_against_two_baselines() {
    // 5 and 6 from baseline 0, 2 from baseline 1, 1 from baseline 0 again.
    let stream = [0xd1, 0x14, 0x04, 0x09, 0x12, 0, 0, 0, 0];
    assert_eq!(
        u16s(&decode_indices(&stream, 4, 2).unwrap()),
        vec![5, 6, 2, 1]
    );
    assert!(decode_indices(&stream, 5, 2).is_err());
    assert!(decode_indices(&stream, 3, 2).is_err());
}

fn zigzag(d: u8) -> u8 {
    let s = d as i8;
    ((s << 1) ^ (s >> 7)) as u8
}

/// One group of 16 deltas at `width` bits with sentinels: the packed codes,
/// then the bytes that did not fit.
fn sentinel_group(d: &[u8], width: usize) -> Vec<u8> {
    let per = 8 / width;
    let sentinel = (1u8 << width) - 1;
    let mut packed = vec![0u8; 16 / per];
    let mut extra = Vec::new();
    for (i, &x) in d.iter().enumerate() {
        let code = if x < sentinel {
            x
        } else {
            extra.push(x);
            sentinel
        };
        packed[i / per] |= code << (8 - width * (i % per + 1));
    }
    packed.extend(extra);
    packed
}

/// An attribute stream of `data` (elements of `stride` bytes), each group in
/// its shortest code, from a zero baseline.
fn encode_attributes(data: &[u8], stride: usize) -> Vec<u8> {
    let count = data.len() / stride;
    let block = ((8192 / stride) & !15).min(256);
    let mut out = vec![0xa0];
    let mut last = vec![0u8; stride];
    let mut first = 0;
    while first < count {
        let n = block.min(count - first);
        let groups = n.div_ceil(16);
        for k in 0..stride {
            let mut deltas = vec![0u8; groups * 16];
            for i in 0..n {
                let v = data[(first + i) * stride + k];
                deltas[i] = zigzag(v.wrapping_sub(last[k]));
                last[k] = v;
            }
            let mut header = vec![0u8; groups.div_ceil(4)];
            let mut body = Vec::new();
            for g in 0..groups {
                let d = &deltas[g * 16..(g + 1) * 16];
                let (bits, bytes) = if d.iter().all(|&x| x == 0) {
                    (0, Vec::new())
                } else {
                    [
                        (1, sentinel_group(d, 2)),
                        (2, sentinel_group(d, 4)),
                        (3, d.to_vec()),
                    ]
                    .into_iter()
                    .min_by_key(|(_, b)| b.len())
                    .unwrap()
                };
                header[g / 4] |= bits << ((g % 4) * 2);
                body.extend(bytes);
            }
            out.extend(header);
            out.extend(body);
        }
        first += n;
    }
    out.extend(vec![0u8; 32.max(stride)]);
    out
}

#[test]
fn attributes_decode_what_the_specification_encodes() {
    // Smooth, noisy and constant bytes, 300 elements of 12 bytes: two
    // blocks, groups in every code.
    let stride = 12;
    let mut x: u32 = 1;
    let data: Vec<u8> = (0..300 * stride)
        .map(|i| {
            x = x.wrapping_mul(1_103_515_245).wrapping_add(12345);
            match i % stride {
                0..=3 => (i / stride) as u8,
                4..=7 => (x >> 24) as u8,
                8 => ((i / stride) / 7) as u8 ^ ((x >> 30) as u8),
                _ => 42,
            }
        })
        .collect();
    let stream = encode_attributes(&data, stride);
    assert!(stream.len() < data.len(), "the test encoder compresses");
    assert_eq!(attributes::decode(&stream, 300, stride).unwrap(), data);
    // The example of the specification: 4-bit codes with two sentinels.
    let mut example = vec![0xa0, 0b10];
    example.extend([0x17, 0x5f, 0xf0, 0xbc, 0x77, 0xa9, 0x21, 0x00, 0x34, 0xb5]);
    // Bytes 1..3 of the element: all zero deltas.
    example.extend([0, 0, 0]);
    example.extend([0u8; 32]);
    let decoded = attributes::decode(&example, 16, 4).unwrap();
    let deltas: [i8; 16] = [-1, -4, -3, 26, -91, 0, -6, 6, -4, -4, 5, -5, 1, -1, 0, 0];
    let mut value: u8 = 0;
    for (i, d) in deltas.iter().enumerate() {
        value = value.wrapping_add(*d as u8);
        assert_eq!(decoded[4 * i], value, "element {i}");
        assert_eq!(&decoded[4 * i + 1..4 * i + 4], &[0, 0, 0]);
    }
    // A wrong version, or a stream cut short, is an error.
    let mut wrong = stream.clone();
    wrong[0] = 0xa1;
    assert!(attributes::decode(&wrong, 300, stride).is_err());
    assert!(attributes::decode(&stream[..stream.len() - 40], 300, stride).is_err());
    // A count that needs fewer groups leaves bytes over.
    assert!(attributes::decode(&stream, 280, stride).is_err());
}
