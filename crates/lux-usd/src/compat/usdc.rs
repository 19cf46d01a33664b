//! The `.usdc` compatibility fix: time-sample times of crate files older than version 0.7.0.
//!
//! A crate `TimeSamples` value (OpenUSD `pxr/usd/sdf/crateFile.cpp`,
//! `CrateFile::_Reader::Read(TimeSamples *)`) starts with a `ValueRep` for its times, which
//! the writer packs as a `std::vector<double>` (type `DoubleVector`). A `std::vector<T>` is
//! written the same way in every crate version — a `uint64_t` element count, then the elements
//! (`_Writer::Write(vector<T> const &)` / `_Reader::Read(vector<T> *)`). `openusd` 0.6 reads
//! `DoubleVector` with its `VtArray` reader instead (`src/usdc/reader.rs`, `Type::DoubleVector
//! => sdf::Value::DoubleVec(self.read_floats(value)?)`, reached from the `Type::TimeSamples`
//! arm), whose header depends on the version (`unpack_array_len`): before 0.5.0 a `uint32_t`
//! rank then a `uint32_t` count, before 0.7.0 a `uint32_t` count, from 0.7.0 a `uint64_t`
//! count. From 0.7.0 on the two layouts agree; before, openusd reads the `uint64_t` count as
//! two `uint32_t`:
//!
//! - below 0.5.0 (e.g. 0.4.0, the version of Pixar's `animatedTop` tutorial asset) the count's
//!   low half is taken for the rank and its high half (0) for the count: no times, and the
//!   layer fails with `Invalid time samples count`;
//! - at 0.5.0 and 0.6.0 the low half is the right count but the times are read 4 bytes early,
//!   so the layer loads with wrong times (a file written with times 1 and 3 reads back as 0 and
//!   5.3e-315) — silently.
//!
//! [`fix_time_samples`] rewrites the bytes `openusd` receives: it appends a copy of each such
//! times vector in the layout `openusd` expects for the file's version and points the times
//! `ValueRep` at it. The file's structure (table of contents, sections, every other offset) is
//! untouched, so the same bytes still read the same everywhere else.

use openusd::usdc::{CrateData, CrateFile};
use std::collections::{HashMap, HashSet};
use std::io::Cursor;
use std::panic::{AssertUnwindSafe, catch_unwind};

/// Crate value type `TimeSamples` (`crateDataTypes.h`).
const TYPE_TIME_SAMPLES: u64 = 46;
/// Crate value type `DoubleVector` (`std::vector<double>`).
const TYPE_DOUBLE_VECTOR: u64 = 48;
const INLINED_BIT: u64 = 1 << 62;
const COMPRESSED_BIT: u64 = 1 << 61;
const ARRAY_BIT: u64 = 1 << 63;
const PAYLOAD_MASK: u64 = (1 << 48) - 1;

fn value_type(rep: u64) -> u64 {
    (rep >> 48) & 0xff
}

fn read_u64(bytes: &[u8], at: u64) -> Option<u64> {
    let at = usize::try_from(at).ok()?;
    let raw = bytes.get(at..at.checked_add(8)?)?;
    Some(u64::from_le_bytes(raw.try_into().ok()?))
}

/// The crate version `(major, minor, patch)` of `bytes`, when they start with the crate
/// bootstrap header (`_BootStrap` in `crateFile.cpp`: the identifier `PXR-USDC`, then the
/// version bytes).
pub fn crate_version(bytes: &[u8]) -> Option<(u8, u8, u8)> {
    if !bytes.starts_with(openusd::usdc::MAGIC) || bytes.len() < 11 {
        return None;
    }
    Some((bytes[8], bytes[9], bytes[10]))
}

/// Upper bound on the bytes an LZ4 block of `c` bytes decompresses to (LZ4's ratio is at most
/// 255:1), with slack for tiny blocks.
fn max_decompressed(c: u64) -> u64 {
    c.saturating_mul(255).saturating_add(64)
}

/// Upper bound on the integers an LZ4 block of `c` bytes of `Usd_IntegerCompression` data
/// holds (two bits per integer at best).
fn max_encoded_ints(c: u64) -> u64 {
    max_decompressed(c).saturating_mul(4).saturating_add(1024)
}

/// Checks the size fields of a crate file's structural sections before `openusd` 0.6 reads
/// them: its `CrateFile::open` allocates what each count or size claims (`vec![0; n]`) before
/// it reads the data, so a malformed file can abort the process by exhausting memory — which
/// no `catch_unwind` recovers from. Each count must fit the compressed block it is decoded
/// from and each block the file (the layouts of `crateFile.cpp`'s `_ReadTokens`,
/// `_ReadStrings`, `_ReadFields`, `_ReadFieldSets`, `_ReadPaths` and `_ReadSpecs` for version
/// 0.4.0 and later; older files are left to `openusd`). `Err` names the first implausible
/// size.
pub fn check_structure(bytes: &[u8]) -> Result<(), String> {
    let Some((0, minor, _)) = crate_version(bytes) else {
        return Ok(());
    };
    if minor < 4 {
        return Ok(());
    }
    let len = bytes.len() as u64;
    let word = |at: u64| read_u64(bytes, at).ok_or_else(|| format!("offset {at} is past the end"));
    // A compressed block at `at` (`uint64_t` size, then the data): where it ends, and its size.
    let block = |at: u64| -> Result<(u64, u64), String> {
        let c = word(at)?;
        let end = at
            .checked_add(8)
            .and_then(|d| d.checked_add(c))
            .filter(|end| *end <= len)
            .ok_or_else(|| format!("a compressed block of {c} bytes at {at} is past the end"))?;
        Ok((end, c))
    };
    let plausible = |what: &str, n: u64, bound: u64| {
        if n <= bound {
            Ok(())
        } else {
            Err(format!("{what} {n} does not fit its data"))
        }
    };
    let toc = word(16)?;
    let sections = word(toc)?;
    if sections == 0 || sections >= 64 {
        return Ok(()); // openusd refuses it itself
    }
    for i in 0..sections {
        let rec = toc.saturating_add(8).saturating_add(32 * i);
        let name = bytes
            .get(usize::try_from(rec).unwrap_or(usize::MAX)..)
            .and_then(|r| r.get(..16))
            .ok_or("the table of contents is past the end")?;
        let name = &name[..name.iter().position(|c| *c == 0).unwrap_or(16)];
        let start = word(rec.saturating_add(16))?;
        match name {
            b"TOKENS" => {
                let uncompressed = word(start.saturating_add(8))?;
                let (_, c) = block(start.saturating_add(16))?;
                plausible("token bytes", uncompressed, max_decompressed(c))?;
            }
            b"STRINGS" => {
                let n = word(start)?;
                plausible("string count", n, (len - start.min(len)) / 4)?;
            }
            b"FIELDS" => {
                let n = word(start)?;
                let (end, c) = block(start.saturating_add(8))?;
                plausible("field count", n, max_encoded_ints(c))?;
                let (_, c) = block(end)?;
                plausible("field count", n.saturating_mul(8), max_decompressed(c))?;
            }
            b"FIELDSETS" => {
                let n = word(start)?;
                let (_, c) = block(start.saturating_add(8))?;
                plausible("field set count", n, max_encoded_ints(c))?;
            }
            b"PATHS" | b"SPECS" => {
                let n = word(start)?;
                let mut at = start.saturating_add(8);
                let mut encoded = n;
                if name == b"PATHS" {
                    encoded = word(at)?;
                    at = at.saturating_add(8);
                }
                for _ in 0..3 {
                    let (end, c) = block(at)?;
                    plausible("path or spec count", n, max_encoded_ints(c))?;
                    plausible("path or spec count", encoded, max_encoded_ints(c))?;
                    at = end;
                }
            }
            _ => {}
        }
    }
    Ok(())
}

/// Rewrites the time-sample times of a crate file older than 0.7.0 so that `openusd` 0.6 reads
/// the times the file holds (see the [module documentation](self)). Returns how many
/// time-sample values were repointed; 0 for a file that needs nothing (version 0.7.0 or later,
/// no time samples, not a crate file). A table the fix cannot follow (an offset out of the
/// file, a count too large for the old layout) is left as it is, for `openusd` to report; the
/// function itself never fails or panics.
pub fn fix_time_samples(bytes: &mut Vec<u8>) -> usize {
    let Some((major, minor, _)) = crate_version(bytes) else {
        return 0;
    };
    if major != 0 || minor >= 7 {
        return 0;
    }
    let with_rank = minor < 5;
    if check_structure(bytes).is_err() {
        return 0;
    }
    // The structural sections (fields and their value reps), read by openusd itself (which
    // panics on some malformed files: caught, and the file left for `read_crate` to refuse).
    let reps: Vec<u64> = match catch_unwind(AssertUnwindSafe(|| {
        CrateFile::open(Cursor::new(&bytes[..])).ok()
    })) {
        Ok(Some(file)) => file
            .fields
            .iter()
            .map(|f| f.value_rep.0)
            .filter(|rep| value_type(*rep) == TYPE_TIME_SAMPLES && rep & INLINED_BIT == 0)
            .collect(),
        _ => return 0,
    };
    let mut patched_reps = HashSet::new();
    let mut copies: HashMap<u64, u64> = HashMap::new();
    let mut count = 0;
    for rep in reps {
        let payload = rep & PAYLOAD_MASK;
        // `_RecursiveRead`: an int64 offset, relative to its own position, to the times rep.
        let Some(rel) = read_u64(bytes, payload) else {
            continue;
        };
        let Some(rep_at) = payload.checked_add_signed(rel as i64) else {
            continue;
        };
        if !patched_reps.insert(rep_at) {
            continue;
        }
        let Some(times_rep) = read_u64(bytes, rep_at) else {
            continue;
        };
        if value_type(times_rep) != TYPE_DOUBLE_VECTOR
            || times_rep & (INLINED_BIT | COMPRESSED_BIT | ARRAY_BIT) != 0
        {
            continue;
        }
        let times_at = times_rep & PAYLOAD_MASK;
        if times_at == 0 {
            continue;
        }
        let new_at = match copies.get(&times_at) {
            Some(at) => *at,
            None => {
                let Some(at) = copy_times(bytes, times_at, with_rank) else {
                    continue;
                };
                copies.insert(times_at, at);
                at
            }
        };
        let new_rep = (times_rep & !PAYLOAD_MASK) | new_at;
        let Ok(at) = usize::try_from(rep_at) else {
            continue;
        };
        if let Some(slot) = at.checked_add(8).and_then(|end| bytes.get_mut(at..end)) {
            slot.copy_from_slice(&new_rep.to_le_bytes());
            count += 1;
        }
    }
    count
}

/// Reads the structure of a crate layer with `openusd` (`CrateData::open` with its safety
/// checks), as `openusd` itself will when it opens the layer, and runs `screen` on it:
/// `Ok(Some(screen(data)))` when it reads, `Ok(None)` when `openusd` returns an error (which
/// `openusd` reports again when it opens the layer), and `Err(message)` when `openusd` 0.6's
/// reader panics instead — a `todo!()` for crate versions before 0.4.0, an index out of range
/// or a size that overflows an allocation in a malformed file — in the structure or in the
/// values `screen` reads, or when [`check_structure`] finds a size that would make it allocate
/// without bound, so that the caller can refuse the layer before `openusd` opens it.
pub fn read_crate<T>(
    bytes: &[u8],
    screen: impl FnOnce(&CrateData<Cursor<&[u8]>>) -> T,
) -> Result<Option<T>, String> {
    check_structure(bytes)?;
    catch_unwind(AssertUnwindSafe(|| {
        CrateData::open(Cursor::new(bytes), true)
            .ok()
            .map(|data| screen(&data))
    }))
    .map_err(|payload| {
        let what = payload
            .downcast_ref::<&str>()
            .map(|s| (*s).to_owned())
            .or_else(|| payload.downcast_ref::<String>().cloned())
            .unwrap_or_default();
        format!("openusd's crate reader panics on it: {what}")
    })
}

/// Appends the `std::vector<double>` at `at` (`uint64_t` count, doubles) in `openusd`'s array
/// layout for the file's version (`[uint32_t rank = 1]`, `uint32_t` count, doubles) and returns
/// where; `None` if it does not fit the file or the layout.
fn copy_times(bytes: &mut Vec<u8>, at: u64, with_rank: bool) -> Option<u64> {
    let n = read_u64(bytes, at)?;
    let n32 = u32::try_from(n).ok()?;
    let start = usize::try_from(at.checked_add(8)?).ok()?;
    let end = start.checked_add(usize::try_from(n).ok()?.checked_mul(8)?)?;
    if end > bytes.len() {
        return None;
    }
    let new_at = u64::try_from(bytes.len()).ok()?;
    if new_at > PAYLOAD_MASK {
        return None;
    }
    if with_rank {
        bytes.extend_from_slice(&1u32.to_le_bytes());
    }
    bytes.extend_from_slice(&n32.to_le_bytes());
    bytes.extend_from_within(start..end);
    Some(new_at)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn not_a_crate_or_recent_is_untouched() {
        let mut text = b"#usda 1.0\n".to_vec();
        assert_eq!(fix_time_samples(&mut text), 0);
        assert_eq!(text, b"#usda 1.0\n");
        let mut v7 = b"PXR-USDC\x00\x07\x00\x00\x00\x00\x00\x00".to_vec();
        assert_eq!(fix_time_samples(&mut v7), 0);
        assert_eq!(v7.len(), 16);
    }

    #[test]
    fn truncated_and_garbage_crates_never_panic() {
        let mut short = b"PXR-USDC\x00\x04".to_vec();
        assert_eq!(fix_time_samples(&mut short), 0);
        let mut garbage =
            b"PXR-USDC\x00\x04\x00\x00\x00\x00\x00\x00\xff\xff\xff\xff\xff\xff\xff\x7f".to_vec();
        assert_eq!(fix_time_samples(&mut garbage), 0);
    }
}
