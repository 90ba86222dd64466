//! Counter-based random numbers: every path owns a stream named by stable ids.
//!
//! A stream is a key (hashed from the seed, a domain tag and two indices) and a
//! counter. The n-th number of a stream is a hash of the key and n, so a stream
//! does not depend on which thread runs it or on what ran before: results are the
//! same bits at any thread count. Two streams never walk the same sequence with an
//! offset (as additive generators with hashed starting states can); at worst two
//! single numbers coincide, with probability 2^-64 per pair.

/// The golden-ratio increment, an odd constant with well-spread bits.
const GOLDEN_GAMMA: u64 = 0x9E37_79B9_7F4A_7C15;

/// Distinct tags for the places that draw random numbers, so that, say, probe
/// point 3 and object 3 never share a stream.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Domain {
    /// Paths of a probe point: indices (point, path).
    Probe = 1,
    /// Points and paths of an object mean: indices (object, sample).
    ObjectMean = 2,
    /// Stratified surface points: indices (0, point).
    SamplePoints = 3,
    /// Directions of a one-bounce gather: indices (point, ray).
    Gather = 4,
}

/// The 64-bit finaliser of SplitMix64 (Steele, Lea, Flood 2014): a bijection
/// whose output bits each depend on every input bit.
#[inline]
fn mix64(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// Folds one more word into a key. Each word is hashed on its own before the
/// xor so that nearby indices give unrelated keys.
#[inline]
fn absorb(key: u64, word: u64, salt: u64) -> u64 {
    mix64(key ^ mix64(word.wrapping_add(salt).wrapping_mul(GOLDEN_GAMMA)))
}

/// One random stream.
#[derive(Clone, Debug)]
pub(crate) struct Rng {
    key: u64,
    counter: u64,
}

impl Rng {
    /// The stream of `(seed, domain, a, b)`.
    pub(crate) fn for_stream(seed: u64, domain: Domain, a: u64, b: u64) -> Rng {
        let mut key = mix64(seed ^ 0x5851_F42D_4C95_7F2D);
        key = absorb(key, domain as u64, 0x1);
        key = absorb(key, a, 0x2);
        key = absorb(key, b, 0x3);
        Rng { key, counter: 0 }
    }

    /// The next 64 random bits.
    #[inline]
    pub(crate) fn next_u64(&mut self) -> u64 {
        self.counter = self.counter.wrapping_add(1);
        mix64(self.key ^ mix64(self.counter.wrapping_mul(GOLDEN_GAMMA)))
    }

    /// A uniform number in [0, 1) with 53 random bits.
    #[inline]
    pub(crate) fn uniform(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn streams_are_reproducible_and_distinct() {
        let mut a = Rng::for_stream(7, Domain::Probe, 3, 9);
        let mut b = Rng::for_stream(7, Domain::Probe, 3, 9);
        let mut c = Rng::for_stream(7, Domain::ObjectMean, 3, 9);
        let mut d = Rng::for_stream(7, Domain::Probe, 3, 10);
        for _ in 0..100 {
            let x = a.next_u64();
            assert_eq!(x, b.next_u64());
            assert_ne!(x, c.next_u64());
            assert_ne!(x, d.next_u64());
        }
    }

    #[test]
    fn uniforms_have_the_right_first_two_moments() {
        // Mean 1/2 and variance 1/12; with 1e5 draws the standard errors are
        // 9.1e-4 and 2.7e-4, so 5e-3 and 1.5e-3 are over five of them.
        let mut r = Rng::for_stream(1, Domain::SamplePoints, 0, 0);
        let n = 100_000;
        let (mut s, mut s2) = (0.0, 0.0);
        for _ in 0..n {
            let u = r.uniform();
            assert!((0.0..1.0).contains(&u));
            s += u;
            s2 += u * u;
        }
        let mean = s / n as f64;
        let var = s2 / n as f64 - mean * mean;
        assert!((mean - 0.5).abs() < 5e-3, "mean {mean}");
        assert!((var - 1.0 / 12.0).abs() < 1.5e-3, "variance {var}");
    }
}
