//! One deterministic random generator for every test, with three streams: SplitMix64 (the
//! fuzzers and cage generators), xorshift64 and xorshift64*. Tests whose expected results were
//! drawn from one stream keep it: the constructor names the stream, the methods are shared.

/// A small deterministic random stream (no dependency; reproducible from its seed).
#[derive(Clone, Debug)]
pub struct Rng {
    state: u64,
    stream: Stream,
}

#[derive(Clone, Copy, Debug)]
enum Stream {
    SplitMix64,
    XorShift64,
    XorShift64Star,
}

impl Rng {
    /// A SplitMix64 stream from `seed`.
    pub fn splitmix(seed: u64) -> Rng {
        Rng {
            state: seed,
            stream: Stream::SplitMix64,
        }
    }

    /// The SplitMix64 stream of case `index` of a run with `seed` (cases are independent, so
    /// one case can be replayed alone).
    pub fn for_case(seed: u64, index: u64) -> Rng {
        let mut r = Rng::splitmix(seed ^ index.wrapping_mul(0xA076_1D64_78BD_642F));
        r.next_u64();
        r
    }

    /// A xorshift64 stream (shifts 13, 7, 17) from `seed` (not 0: zero stays zero).
    pub fn xorshift(seed: u64) -> Rng {
        Rng {
            state: seed,
            stream: Stream::XorShift64,
        }
    }

    /// A xorshift64* stream (shifts 12, 25, 27, then a multiply) from `seed` (not 0).
    pub fn xorshift_star(seed: u64) -> Rng {
        Rng {
            state: seed,
            stream: Stream::XorShift64Star,
        }
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        match self.stream {
            Stream::SplitMix64 => {
                self.state = self.state.wrapping_add(0x9E37_79B9_7F4A_7C15);
                let mut z = self.state;
                z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
                z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
                z ^ (z >> 31)
            }
            Stream::XorShift64 => {
                self.state ^= self.state << 13;
                self.state ^= self.state >> 7;
                self.state ^= self.state << 17;
                self.state
            }
            Stream::XorShift64Star => {
                self.state ^= self.state >> 12;
                self.state ^= self.state << 25;
                self.state ^= self.state >> 27;
                self.state.wrapping_mul(0x2545_F491_4F6C_DD1D)
            }
        }
    }

    /// Uniform in `0..n` (0 when `n == 0`): the next bits modulo `n`.
    pub fn below(&mut self, n: usize) -> usize {
        if n == 0 {
            0
        } else {
            (self.next_u64() % n as u64) as usize
        }
    }

    /// Uniform in `lo..=hi`.
    pub fn range(&mut self, lo: i64, hi: i64) -> i64 {
        lo + (self.next_u64() % (hi - lo + 1) as u64) as i64
    }

    /// `true` with probability `percent` / 100.
    pub fn chance(&mut self, percent: u64) -> bool {
        self.next_u64() % 100 < percent
    }

    /// One element of `xs`.
    pub fn pick<'a, T>(&mut self, xs: &'a [T]) -> &'a T {
        &xs[self.below(xs.len())]
    }

    /// Uniform in `[-1, 1)` (24 bits).
    pub fn unit(&mut self) -> f32 {
        (self.next_u64() >> 40) as f32 / (1u64 << 23) as f32 - 1.0
    }

    /// Uniform in `[0, 1)` from the top 24 bits.
    pub fn next_f32(&mut self) -> f32 {
        (self.next_u64() >> 40) as f32 / (1u64 << 24) as f32
    }

    /// Uniform in `[0, 1)` from the top 53 bits.
    pub fn next_f64(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }
}

#[cfg(test)]
mod tests {
    use super::Rng;

    /// The first values of each stream, computed by hand from the algorithms' definitions
    /// (SplitMix64 of seed 0 is the reference sequence of its paper).
    #[test]
    fn streams_give_their_reference_values() {
        let mut s = Rng::splitmix(0);
        assert_eq!(s.next_u64(), 0xE220_A839_7B1D_CDAF);
        assert_eq!(s.next_u64(), 0x6E78_9E6A_A1B9_65F4);
        let mut x = Rng::xorshift(1);
        assert_eq!(x.next_u64(), 0x4082_2041);
        let mut x = Rng::xorshift_star(1);
        assert_eq!(x.next_u64(), 0x47E4_CE4B_896C_DD1D);
    }

    #[test]
    fn draws_stay_in_their_ranges() {
        let mut r = Rng::for_case(7, 3);
        for _ in 0..1000 {
            assert!(r.below(5) < 5);
            assert!((-3..=4).contains(&r.range(-3, 4)));
            assert!((-1.0..1.0).contains(&r.unit()));
            assert!((0.0..1.0).contains(&r.next_f32()));
            assert!((0.0..1.0).contains(&r.next_f64()));
        }
        assert_eq!(r.below(0), 0);
    }
}
