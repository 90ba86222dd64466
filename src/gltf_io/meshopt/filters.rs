//! The filters applied after `ATTRIBUTES` decoding: octahedral unit vectors,
//! quaternions with their largest component dropped, and floats with a
//! shared-width exponent and mantissa.

/// Applies `filter` to the decoded elements of `stride` bytes in place.
pub(super) fn apply(
    filter: &str,
    data: &mut [u8],
    stride: usize,
    mode: &str,
) -> Result<(), String> {
    if filter != "NONE" && mode != "ATTRIBUTES" {
        return Err(format!("filter {filter} applies to ATTRIBUTES only"));
    }
    match filter {
        "NONE" => Ok(()),
        "OCTAHEDRAL" => match stride {
            4 => {
                data.chunks_exact_mut(4).for_each(octahedral8);
                Ok(())
            }
            8 => {
                data.chunks_exact_mut(8).for_each(octahedral16);
                Ok(())
            }
            _ => Err(format!(
                "filter OCTAHEDRAL needs byteStride 4 or 8, not {stride}"
            )),
        },
        "QUATERNION" if stride == 8 => {
            data.chunks_exact_mut(8).for_each(quaternion);
            Ok(())
        }
        "QUATERNION" => Err(format!(
            "filter QUATERNION needs byteStride 8, not {stride}"
        )),
        "EXPONENTIAL" if stride.is_multiple_of(4) => {
            data.chunks_exact_mut(4).for_each(exponential);
            Ok(())
        }
        "EXPONENTIAL" => Err(format!(
            "filter EXPONENTIAL needs a byteStride divisible by 4, not {stride}"
        )),
        other => Err(format!("unknown filter '{other}'")),
    }
}

/// The unit vector of octahedral coordinates `x, y` scaled by `one`.
fn unit_from_octahedral(x: f32, y: f32, one: f32) -> [f32; 3] {
    let (mut x, mut y) = (x / one, y / one);
    let z = 1.0 - x.abs() - y.abs();
    // Folded back over the lower hemisphere.
    let t = z.min(0.0);
    x -= t.copysign(x);
    y -= t.copysign(y);
    let len = (x * x + y * y + z * z).sqrt();
    if len > 0.0 {
        [x / len, y / len, z / len]
    } else {
        [0.0, 0.0, 1.0]
    }
}

fn octahedral8(e: &mut [u8]) {
    let s = |k: usize| f32::from(e[k] as i8);
    let v = unit_from_octahedral(s(0), s(1), s(2));
    for k in 0..3 {
        e[k] = ((v[k] * 127.0).round() as i8) as u8;
    }
}

fn octahedral16(e: &mut [u8]) {
    let s = |k: usize| f32::from(i16::from_le_bytes([e[2 * k], e[2 * k + 1]]));
    let v = unit_from_octahedral(s(0), s(1), s(2));
    for k in 0..3 {
        let q = (v[k] * 32767.0).round() as i16;
        e[2 * k..2 * k + 2].copy_from_slice(&q.to_le_bytes());
    }
}

fn quaternion(e: &mut [u8]) {
    let s = |k: usize| i16::from_le_bytes([e[2 * k], e[2 * k + 1]]);
    let last = s(3);
    let one = f32::from(last | 3);
    let range = std::f32::consts::FRAC_1_SQRT_2;
    let x = f32::from(s(0)) / one * range;
    let y = f32::from(s(1)) / one * range;
    let z = f32::from(s(2)) / one * range;
    let w = (1.0 - x * x - y * y - z * z).max(0.0).sqrt();
    let largest = (last & 3) as usize;
    let mut out = [0i16; 4];
    out[(largest + 1) % 4] = (x * 32767.0).round() as i16;
    out[(largest + 2) % 4] = (y * 32767.0).round() as i16;
    out[(largest + 3) % 4] = (z * 32767.0).round() as i16;
    out[largest] = (w * 32767.0).round() as i16;
    for (k, q) in out.iter().enumerate() {
        e[2 * k..2 * k + 2].copy_from_slice(&q.to_le_bytes());
    }
}

fn exponential(e: &mut [u8]) {
    let v = i32::from_le_bytes([e[0], e[1], e[2], e[3]]);
    let exponent = v >> 24;
    let mantissa = (v << 8) >> 8;
    let value = (mantissa as f32) * 2f32.powi(exponent);
    e.copy_from_slice(&value.to_le_bytes());
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exponential_values_are_mantissa_times_a_power_of_two() {
        let encode = |e: i32, m: i32| ((e << 24) | (m & 0x00ff_ffff)).to_le_bytes();
        let mut data: Vec<u8> = [encode(-2, 5), encode(3, -7), encode(0, 0)].concat();
        apply("EXPONENTIAL", &mut data, 12, "ATTRIBUTES").unwrap();
        let f = |k: usize| f32::from_le_bytes(data[4 * k..4 * k + 4].try_into().unwrap());
        assert_eq!((f(0), f(1), f(2)), (1.25, -56.0, 0.0));
    }

    #[test]
    fn octahedral_coordinates_give_unit_vectors() {
        // (0, 0) is +z; (127, 0) with one = 127 is +x; (-64, -63) with
        // z = 1 - 64/127 - 63/127 = 0 lies on the equator.
        let mut data: Vec<u8> = [0i8, 0, 127, 9, 127, 0, 127, 0, -64, -63, 127, 0]
            .iter()
            .map(|&b| b as u8)
            .collect();
        apply("OCTAHEDRAL", &mut data, 4, "ATTRIBUTES").unwrap();
        let v: Vec<i8> = data.iter().map(|&b| b as i8).collect();
        assert_eq!(&v[0..4], &[0, 0, 127, 9], "the fourth byte passes through");
        assert_eq!(&v[4..7], &[127, 0, 0]);
        let (x, y, z) = (f32::from(v[8]), f32::from(v[9]), f32::from(v[10]));
        assert_eq!(z, 0.0);
        assert!(((x * x + y * y).sqrt() - 127.0).abs() < 1.0, "{x} {y}");
        assert!(x < 0.0 && y < 0.0);
    }

    #[test]
    fn a_quaternion_gets_its_largest_component_back() {
        // Identity (0, 0, 0, 1): w is the largest (index 3), the others 0;
        // one = 32767 with its low two bits holding the index.
        let one: i16 = 32767 & !3 | 3;
        let mut data: Vec<u8> = [0i16, 0, 0, one]
            .iter()
            .flat_map(|q| q.to_le_bytes())
            .collect();
        apply("QUATERNION", &mut data, 8, "ATTRIBUTES").unwrap();
        let q: Vec<i16> = data
            .chunks(2)
            .map(|b| i16::from_le_bytes([b[0], b[1]]))
            .collect();
        assert_eq!(q, vec![0, 0, 0, 32767]);
    }

    #[test]
    fn filters_outside_their_strides_or_modes_are_refused() {
        let mut data = vec![0u8; 12];
        assert!(apply("QUATERNION", &mut data, 4, "ATTRIBUTES").is_err());
        assert!(apply("OCTAHEDRAL", &mut data, 12, "ATTRIBUTES").is_err());
        assert!(apply("EXPONENTIAL", &mut data, 4, "TRIANGLES").is_err());
        assert!(apply("SHARPEN", &mut data, 4, "ATTRIBUTES").is_err());
    }
}
