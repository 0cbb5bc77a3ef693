//! FNV-1a (64 bit): the fingerprint of a case in `batch.json` and the checksums that
//! make a damaged `state.json` or `result.json` detectable (see [`super::integrity`]).
//! Not a cryptographic hash: it detects truncation and corruption, not forgery.

/// An FNV-1a (64 bit) hasher over bytes and 64-bit words.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Fnv(u64);

impl Default for Fnv {
    fn default() -> Self {
        Self(0xcbf2_9ce4_8422_2325)
    }
}

impl Fnv {
    /// Adds `bytes`.
    pub(crate) fn bytes(&mut self, bytes: &[u8]) -> &mut Self {
        for b in bytes {
            self.0 ^= u64::from(*b);
            self.0 = self.0.wrapping_mul(0x0000_0100_0000_01b3);
        }
        self
    }

    /// Adds a 64-bit word (little-endian bytes).
    pub(crate) fn word(&mut self, word: u64) -> &mut Self {
        self.bytes(&word.to_le_bytes())
    }

    /// The hash as 16 hex digits.
    pub(crate) fn hex(&self) -> String {
        format!("{:016x}", self.0)
    }
}

/// FNV-1a (64 bit) of `bytes`, as 16 hex digits.
pub(crate) fn fnv1a(bytes: &[u8]) -> String {
    Fnv::default().bytes(bytes).hex()
}
