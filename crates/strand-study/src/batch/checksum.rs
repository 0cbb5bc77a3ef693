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

    /// Mixes in a whole 64-bit word at once (one step of [`fnv1a_words`]).
    fn mix(&mut self, word: u64) {
        self.0 ^= word;
        self.0 = self.0.wrapping_mul(0x0000_0100_0000_01b3);
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

/// FNV-1a (64 bit) of `bytes`, as 16 hex digits (the provenance's hash, checked against
/// the published test vectors there).
pub(crate) fn fnv1a(bytes: &[u8]) -> String {
    strand_report::fnv1a64(bytes)
}

/// The first character of a [`fnv1a_words`] checksum, which a byte-wise [`fnv1a`]
/// (16 hex digits) never starts with: a recorded checksum says which of the two it is.
pub(crate) const WORDS_PREFIX: char = 'w';

/// FNV-1a (64 bit) over the 8-byte little-endian words of `bytes` (the last one
/// zero-padded), then their byte count, as `w` and 16 hex digits: one multiply per
/// eight bytes instead of one per byte, for a variant's `result.json` (100–300 kB,
/// the byte-wise hash was about 5 % of a batch that keeps every file). Every step is a
/// bijection of the state (xor with a word, multiplication by an odd number modulo
/// 2⁶⁴), so any change of a single word changes the hash, and the count catches a
/// truncation inside the padding.
pub(crate) fn fnv1a_words(bytes: &[u8]) -> String {
    let mut h = Fnv::default();
    let mut words = bytes.chunks_exact(8);
    for word in &mut words {
        h.mix(u64::from_le_bytes(word.try_into().expect("8 bytes")));
    }
    let mut last = [0u8; 8];
    last[..words.remainder().len()].copy_from_slice(words.remainder());
    h.mix(u64::from_le_bytes(last));
    h.mix(bytes.len() as u64);
    format!("{WORDS_PREFIX}{}", h.hex())
}

/// Whether `bytes` have the checksum `recorded`, of either kind ([`fnv1a_words`] when
/// it starts with [`WORDS_PREFIX`], else the byte-wise [`fnv1a`] of older batches).
pub(crate) fn matches_checksum(recorded: &str, bytes: &[u8]) -> bool {
    if recorded.starts_with(WORDS_PREFIX) {
        recorded == fnv1a_words(bytes)
    } else {
        recorded == fnv1a(bytes)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_streaming_hasher_is_the_byte_hash() {
        let bytes = b"state and result";
        assert_eq!(Fnv::default().bytes(bytes).hex(), fnv1a(bytes));
    }

    #[test]
    fn the_word_hash_is_fnv1a_over_padded_words_and_the_length() {
        // By hand: two words ("abcdefgh", then "ij" zero-padded), then the count 10.
        let mut h: u64 = 0xcbf2_9ce4_8422_2325;
        for w in [
            u64::from_le_bytes(*b"abcdefgh"),
            u64::from_le_bytes(*b"ij\0\0\0\0\0\0"),
            10,
        ] {
            h = (h ^ w).wrapping_mul(0x0000_0100_0000_01b3);
        }
        assert_eq!(fnv1a_words(b"abcdefghij"), format!("w{h:016x}"));
        assert!(!fnv1a(b"abcdefghij").starts_with(WORDS_PREFIX));
    }

    #[test]
    fn every_flipped_bit_and_every_truncation_changes_the_word_hash() {
        let bytes: Vec<u8> = (0..1001u32).map(|i| (i * 7919 % 251) as u8).collect();
        let hash = fnv1a_words(&bytes);
        for at in 0..bytes.len() {
            for bit in 0..8 {
                let mut damaged = bytes.clone();
                damaged[at] ^= 1 << bit;
                assert_ne!(fnv1a_words(&damaged), hash, "byte {at} bit {bit}");
            }
            assert_ne!(fnv1a_words(&bytes[..at]), hash, "truncated to {at}");
        }
        // Trailing zero bytes are not padding: the count differs.
        let mut padded = bytes.clone();
        padded.push(0);
        assert_ne!(fnv1a_words(&padded), hash);
    }

    #[test]
    fn a_recorded_checksum_of_either_kind_is_checked_as_its_kind() {
        let bytes = b"{\"rods\": []}";
        assert!(matches_checksum(&fnv1a(bytes), bytes));
        assert!(matches_checksum(&fnv1a_words(bytes), bytes));
        assert!(!matches_checksum(&fnv1a(bytes), b"{\"rods\": [1]}"));
        assert!(!matches_checksum(&fnv1a_words(bytes), b"{\"rods\": [1]}"));
        assert!(!matches_checksum("0000000000000000", bytes));
    }
}
