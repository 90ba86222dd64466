//! A fixed hash for the variations of procedural scenes (box sizes, furniture
//! choices): the same bits on every run and platform, unlike a seeded random
//! number generator whose algorithm may change between crate versions.

/// SplitMix64's finaliser: well-spread bits from a counter.
pub(crate) fn splitmix64(x: u64) -> u64 {
    let mut z = x.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// 16 bits of `h` starting at bit `shift`, as a fraction in [0, 1].
pub(crate) fn unit(h: u64, shift: u32) -> f64 {
    f64::from((h >> shift) as u16) / f64::from(u16::MAX)
}
