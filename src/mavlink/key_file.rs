//! A signing key as a key file holds it, and the signing clock's epoch. The crate's build
//! script reads this file too (`#[path]`), so it uses `core` alone.

/// The secret key's length, bytes.
pub const KEY_LEN: usize = 32;

/// 2015-01-01T00:00:00Z, the signing clock's epoch, in Unix seconds.
const EPOCH_2015_S: u64 = 1_420_070_400;

/// A key as a key file holds it: 32 bytes as they are, or 64 hexadecimal digits (surrounding
/// whitespace ignored); `None` otherwise.
pub fn parse_key(file: &[u8]) -> Option<[u8; KEY_LEN]> {
    if let Ok(raw) = <[u8; KEY_LEN]>::try_from(file) {
        return Some(raw);
    }
    let text = core::str::from_utf8(file).ok()?.trim();
    if text.len() != 2 * KEY_LEN {
        return None;
    }
    let mut key = [0u8; KEY_LEN];
    for (i, k) in key.iter_mut().enumerate() {
        *k = u8::from_str_radix(text.get(2 * i..2 * i + 2)?, 16).ok()?;
    }
    Some(key)
}

/// A signing timestamp (10 us since 2015-01-01 UTC) from microseconds since the Unix epoch; 0
/// before 2015.
pub const fn timestamp_from_unix_us(unix_us: u64) -> u64 {
    (unix_us / 10).saturating_sub(EPOCH_2015_S * 100_000)
}
