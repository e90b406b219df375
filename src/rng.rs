//! The one seeded random generator: SplitMix64 (Steele, Lea & Flood 2014), kept in-tree so that presets,
//! generated scenes and test inputs stay bit-identical whatever a crate release changes. Tiny, fast, and good
//! enough for jitter and test data; not for anything that needs statistical strength.

/// A SplitMix64 stream: the state steps by the golden-ratio increment and each output is the state mixed.
#[derive(Clone, Debug)]
pub struct SplitMix64(u64);

impl SplitMix64 {
    /// The stream whose state starts at `seed` (the reference implementation's seeding).
    pub const fn new(seed: u64) -> Self {
        Self(seed)
    }

    /// Stream `stream` of `seed`: the stream number is scrambled before it is mixed into the seed, so the
    /// streams of one seed start far apart.
    pub fn stream(seed: u64, stream: u64) -> Self {
        Self(seed ^ Self(stream).next_u64())
    }

    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in `[0, 1)` with 24 bits (the top 24 bits of the next output).
    pub fn unit(&mut self) -> f32 {
        (self.next_u64() >> 40) as f32 * (1.0 / (1u32 << 24) as f32)
    }

    /// Uniform in `[lo, hi)`.
    pub fn range(&mut self, lo: f32, hi: f32) -> f32 {
        lo + (hi - lo) * self.unit()
    }

    /// Uniform angle in `[0, 2π)`.
    pub fn angle(&mut self) -> f32 {
        self.range(0.0, std::f32::consts::TAU)
    }

    /// Uniform integer in `[lo, hi]` (`next_u64` modulo the span; `lo <= hi`).
    pub fn int(&mut self, lo: usize, hi: usize) -> usize {
        lo + (self.next_u64() % (hi - lo + 1) as u64) as usize
    }

    /// Standard normal (Box–Muller, two outputs per draw).
    pub fn normal(&mut self) -> f32 {
        let u = 1.0 - self.unit();
        let v = self.unit();
        (-2.0 * u.ln()).sqrt() * (std::f32::consts::TAU * v).cos()
    }
}

#[cfg(test)]
mod tests {
    use super::SplitMix64;

    fn first<const N: usize>(seed: u64) -> [u64; N] {
        let mut rng = SplitMix64::new(seed);
        std::array::from_fn(|_| rng.next_u64())
    }

    #[test]
    fn matches_the_published_reference_outputs() {
        // Rosetta Code, "Pseudo-random numbers/Splitmix64": the first five outputs for seed 1234567.
        assert_eq!(
            first::<5>(1_234_567),
            [
                6_457_827_717_110_365_317,
                3_203_168_211_198_807_973,
                9_817_491_932_198_370_423,
                4_593_380_528_125_082_431,
                16_408_922_859_458_223_821,
            ]
        );
        // Vigna's splitmix64.c seeded with 0.
        assert_eq!(first::<1>(0), [0xE220_A839_7B1D_CDAF]);
    }

    #[test]
    fn stream_mixes_the_scrambled_stream_number_into_the_seed() {
        // Stream s of seed x starts at x ^ (first output of the stream seeded with s).
        let seed = 1_234_567u64;
        assert_eq!(
            SplitMix64::stream(seed, 0).next_u64(),
            SplitMix64::new(seed ^ 0xE220_A839_7B1D_CDAF).next_u64()
        );
        assert_ne!(
            SplitMix64::stream(seed, 1).next_u64(),
            SplitMix64::stream(seed, 2).next_u64()
        );
    }

    #[test]
    fn unit_takes_the_top_24_bits() {
        // 6457827717110365317 >> 40 = 5873360, so the first unit draw of seed 1234567 is 5873360 / 2^24.
        assert_eq!(SplitMix64::new(1_234_567).unit(), 5_873_360.0 / 16_777_216.0);
        let mut rng = SplitMix64::new(7);
        for _ in 0..10_000 {
            let u = rng.unit();
            assert!((0.0..1.0).contains(&u), "{u}");
            let i = rng.int(3, 5);
            assert!((3..=5).contains(&i), "{i}");
            let a = rng.range(-2.0, -1.0);
            assert!((-2.0..-1.0).contains(&a), "{a}");
            assert!(rng.normal().is_finite());
        }
    }
}
