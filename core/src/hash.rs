//! A fixed, portable 64-bit content hash (FNV-1a over 8-byte words with a
//! final avalanche), used to compare documents bit for bit. Not for
//! security; stable across platforms, Rust versions and runs.

use crate::mesh::TriMesh;

/// Accumulates a content hash.
#[derive(Clone, Debug)]
pub struct ContentHasher(u64);

impl Default for ContentHasher {
    fn default() -> Self {
        Self::new()
    }
}

impl ContentHasher {
    const PRIME: u64 = 0x0000_0100_0000_01b3;

    /// A hasher in its initial state.
    pub fn new() -> Self {
        Self(0xcbf2_9ce4_8422_2325)
    }

    /// Mixes in one word.
    pub fn u64(&mut self, x: u64) {
        self.0 = (self.0 ^ x).wrapping_mul(Self::PRIME);
        self.0 ^= self.0 >> 29;
    }

    /// Mixes in a float's exact bits.
    pub fn f64(&mut self, x: f64) {
        self.u64(x.to_bits());
    }

    /// Mixes in bytes (length-prefixed, so concatenations differ).
    pub fn bytes(&mut self, b: &[u8]) {
        self.u64(b.len() as u64);
        for chunk in b.chunks(8) {
            let mut w = [0u8; 8];
            w[..chunk.len()].copy_from_slice(chunk);
            self.u64(u64::from_le_bytes(w));
        }
    }

    /// Mixes in a mesh's positions, triangles and sources, bit for bit.
    pub fn mesh(&mut self, m: &TriMesh) {
        self.u64(m.positions.len() as u64);
        for p in &m.positions {
            p.iter().for_each(|x| self.f64(*x));
        }
        self.u64(m.triangles.len() as u64);
        for t in &m.triangles {
            self.u64(t[0] as u64 | (t[1] as u64) << 32);
            self.u64(t[2] as u64);
        }
        self.u64(m.tri_source.len() as u64);
        for s in &m.tri_source {
            self.u64(*s as u64);
        }
    }

    /// The hash.
    pub fn finish(&self) -> u64 {
        let mut x = self.0;
        x ^= x >> 33;
        x = x.wrapping_mul(0xff51_afd7_ed55_8ccd);
        x ^= x >> 33;
        x
    }
}
