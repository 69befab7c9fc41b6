//! Scans told apart by id: a scan's id is its `header.stamp` (robot time,
//! as `ros2 topic echo` shows it), in nanoseconds. vehicle_sim stamps one
//! scan per clock step at most, and a restarted or resumed vehicle_sim
//! goes on after the last stamp it sent (from its log of sent ids), so the
//! id is unique over a mission. The log of sent ids is text, one
//! `SEC.NANOSEC` a line, each line written by one `write` to a file opened
//! for appending: a killed sender leaves whole lines (a torn last line, as
//! after a power cut, is dropped on reading).

use std::io::Write;
use std::path::{Path, PathBuf};

use crate::file::FileError;

/// A platform's scans carry its index in the id's top byte (the ground
/// robot 0, the drone 1): two vehicles may stamp a scan at the same robot
/// time, and stamps stay below 2^56 ns (2.28 years).
const PLATFORM_SHIFT: u32 = 56;

/// `id` marked as platform `platform`'s.
pub fn tagged(id: u64, platform: u8) -> u64 {
    id | (u64::from(platform) << PLATFORM_SHIFT)
}

/// The platform index an id carries.
pub fn platform(id: u64) -> u8 {
    (id >> PLATFORM_SHIFT) as u8
}

/// The id without its platform: the stamp's.
pub fn untagged(id: u64) -> u64 {
    id & ((1 << PLATFORM_SHIFT) - 1)
}

/// The id of a scan stamped `sec`, `nanosec` (negative stamps wrap, still unique).
pub fn id(sec: i32, nanosec: u32) -> u64 {
    (i64::from(sec) * 1_000_000_000 + i64::from(nanosec)) as u64
}

/// The id as its stamp reads: `SEC.NANOSEC`.
pub fn format(id: u64) -> String {
    let ns = id as i64;
    format!(
        "{}.{:09}",
        ns.div_euclid(1_000_000_000),
        ns.rem_euclid(1_000_000_000)
    )
}

/// An id read back from [`format`]; `None` for anything else.
pub fn parse(s: &str) -> Option<u64> {
    let (sec, ns) = s.trim().split_once('.')?;
    if ns.len() != 9 || !ns.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    let sec: i32 = sec.parse().ok()?;
    Some(id(sec, ns.parse().ok()?))
}

/// Seconds of the stamp an id is.
pub fn secs(id: u64) -> f64 {
    (id as i64) as f64 * 1e-9
}

/// The ids in a sent log's text: whole lines only, unreadable ones skipped.
pub fn read_text(text: &str) -> Vec<u64> {
    let whole = text.rfind('\n').map_or("", |end| &text[..end]);
    whole.lines().filter_map(parse).collect()
}

/// The ids the log at `path` holds (none when there is no log).
pub fn read_log(path: &Path) -> Result<Vec<u64>, FileError> {
    match std::fs::read(path) {
        Ok(b) => Ok(read_text(&String::from_utf8_lossy(&b))),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(Vec::new()),
        Err(e) => Err(FileError::new(path, e)),
    }
}

/// The sender's log of sent ids, open for appending.
#[derive(Debug)]
pub struct SentLog {
    path: PathBuf,
    file: std::fs::File,
}

impl SentLog {
    /// Opens (or makes) the log at `path`.
    pub fn open(path: &Path) -> Result<SentLog, FileError> {
        let file = std::fs::OpenOptions::new()
            .create(true)
            .append(true)
            .open(path)
            .map_err(|e| FileError::new(path, e))?;
        Ok(SentLog {
            path: path.into(),
            file,
        })
    }

    /// Appends one id as one line in one write.
    pub fn sent(&self, id: u64) -> Result<(), FileError> {
        let line = format!("{}\n", format(id));
        (&self.file)
            .write_all(line.as_bytes())
            .map_err(|e| FileError::new(&self.path, e))
    }
}

/// Sent and merged ids compared: how many of each, and the sent ones not
/// merged (the first `cap` of them), the merged ones never sent, and the
/// ids merged or sent twice.
#[derive(Debug, Clone, Default, PartialEq, Eq, serde::Serialize)]
pub struct IdCheck {
    /// Distinct ids sent.
    pub sent: usize,
    /// Distinct ids merged.
    pub merged: usize,
    /// Sent and not merged.
    pub missing: usize,
    /// The first of them, as stamps.
    pub missing_ids: Vec<String>,
    /// Merged and never sent (scans of another sender).
    pub unsent: usize,
    /// Ids that came twice in the sent log or the merge.
    pub repeated: usize,
    /// Distinct ids sent and merged per platform: [ground robot, drone].
    pub by_platform: [[usize; 2]; 2],
}

/// Compares the `sent` ids with the `merged` ones, listing `cap` missing at most.
pub fn check(sent: &[u64], merged: &[u64], cap: usize) -> IdCheck {
    use std::collections::BTreeSet;
    let s: BTreeSet<u64> = sent.iter().copied().collect();
    let m: BTreeSet<u64> = merged.iter().copied().collect();
    let missing: Vec<u64> = s.difference(&m).copied().collect();
    IdCheck {
        sent: s.len(),
        merged: m.len(),
        missing: missing.len(),
        missing_ids: missing.iter().take(cap).map(|&i| format(i)).collect(),
        unsent: m.difference(&s).count(),
        repeated: (sent.len() - s.len()) + (merged.len() - m.len()),
        by_platform: [0u8, 1].map(|k| {
            let of = |set: &BTreeSet<u64>| set.iter().filter(|&&i| platform(i) == k).count();
            [of(&s), of(&m)]
        }),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_drone_scan_stamped_as_a_ground_scan_has_another_id_that_reads_back() {
        let stamp = id(41, 500_000_000);
        let uav = tagged(stamp, 1);
        assert_ne!(uav, stamp);
        assert_eq!((platform(uav), platform(stamp)), (1, 0));
        assert_eq!(untagged(uav), stamp);
        assert_eq!(parse(&format(uav)), Some(uav));
        let c = check(&[stamp, uav, tagged(stamp + 1, 1)], &[stamp, uav], 5);
        assert_eq!(
            c.by_platform,
            [[1, 1], [2, 1]],
            "sent and merged, per platform"
        );
        assert_eq!(c.missing, 1);
    }

    #[test]
    fn ids_read_as_stamps_and_back() {
        for (sec, ns, text) in [
            (12, 500_000_000, "12.500000000"),
            (0, 7, "0.000000007"),
            (-2, 1, "-2.000000001"),
        ] {
            let i = id(sec, ns);
            assert_eq!(format(i), text);
            assert_eq!(parse(text), Some(i));
        }
        assert!((secs(id(3, 250_000_000)) - 3.25).abs() < 1e-12);
        for bad in [
            "",
            "12",
            "12.5",
            "x.000000001",
            "1.00000000a",
            "99999999999.000000000",
        ] {
            assert_eq!(parse(bad), None, "{bad:?}");
        }
    }

    #[test]
    fn a_torn_last_line_is_dropped_and_the_log_appends() {
        assert_eq!(read_text("1.000000000\n2.0000"), [id(1, 0)]);
        assert_eq!(
            read_text("1.000000000\nnoise\n2.000000000\n"),
            [id(1, 0), id(2, 0)]
        );
        let path = std::env::temp_dir().join(format!("skyground-sent-{}", std::process::id()));
        let _ = std::fs::remove_file(&path);
        assert!(read_log(&path).unwrap().is_empty());
        SentLog::open(&path).unwrap().sent(id(1, 5)).unwrap();
        let again = SentLog::open(&path).unwrap();
        again.sent(id(2, 0)).unwrap();
        assert_eq!(read_log(&path).unwrap(), [id(1, 5), id(2, 0)]);
        std::fs::remove_file(&path).unwrap();
    }

    #[test]
    fn the_check_names_missing_unsent_and_repeated_ids() {
        let c = check(&[1, 2, 3, 4, 4], &[2, 3, 9, 3], 1);
        assert_eq!(
            (c.sent, c.merged, c.missing, c.unsent, c.repeated),
            (4, 3, 2, 1, 2)
        );
        assert_eq!(c.missing_ids, [format(1)]);
        assert_eq!(
            check(&[5, 6], &[6, 5], 10),
            IdCheck {
                sent: 2,
                merged: 2,
                by_platform: [[2, 2], [0, 0]],
                ..IdCheck::default()
            }
        );
    }
}
