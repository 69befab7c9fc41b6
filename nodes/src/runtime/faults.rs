//! A burst of large clouds, made on purpose (issue 50's soak): with
//! `SKYGROUND_LARGE_SCANS=FIRST:COUNT:POINTS`, vehicle_sim's scans FIRST to
//! FIRST + COUNT − 1 are sent with every point repeated until each holds
//! POINTS points (multi-MB samples, fragmented by DDS). The repeats fall in
//! the voxels their originals do, so the merge is the same; only the
//! transport is tried. `SKYGROUND_SPIN=NODE@MARKER` makes a node spin
//! once ([`spin_if_asked`]: global_planner as it sends a route,
//! local_explorer after it published a merge). For tests; nothing else
//! reads them.

/// The variable that asks for the burst.
pub const LARGE_SCANS_ENV: &str = "SKYGROUND_LARGE_SCANS";

/// The variable that makes a node spin: `SKYGROUND_SPIN=NODE@MARKER`.
pub const SPIN_ENV: &str = "SKYGROUND_SPIN";

/// A node spinning without progress, made on purpose (issue 50): when
/// `now` and [`SPIN_ENV`] names `node` and its MARKER file is not there
/// yet, the marker is made (so the restarted node works) and the calling
/// thread spins for good: CPU 100 %, no work step, no status. For tests.
pub fn spin_if_asked(node: &str, now: bool) {
    let Some(spec) = std::env::var(SPIN_ENV).ok().filter(|_| now) else {
        return;
    };
    let Some((_, marker)) = spec.split_once('@').filter(|(who, _)| *who == node) else {
        return;
    };
    // The marker is made by the node named only: another must not take its turn.
    let first = std::fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(marker);
    if first.is_ok() {
        loop {
            std::hint::spin_loop();
        }
    }
}

/// Which scans are made large, and how large.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct LargeScans {
    first: u64,
    count: u64,
    points: usize,
}

impl LargeScans {
    /// The burst `FIRST:COUNT:POINTS` asks for; `None` for anything else.
    pub fn parse(spec: &str) -> Option<LargeScans> {
        let mut it = spec.split(':').map(str::trim);
        let first = it.next()?.parse().ok()?;
        let count = it.next()?.parse().ok()?;
        let points = it.next()?.parse().ok()?;
        it.next().is_none().then_some(LargeScans {
            first,
            count,
            points,
        })
    }

    /// The burst the environment asks for, if any.
    pub fn from_env() -> Option<LargeScans> {
        LargeScans::parse(&std::env::var(LARGE_SCANS_ENV).ok()?)
    }

    /// Scan number `n` as it is sent: its points repeated up to the
    /// burst's size when `n` is in the burst (a scan with no point stays empty).
    pub fn apply(&self, n: u64, cloud: &mut skyground_core::cloud::Cloud) {
        let len = cloud.len();
        if n < self.first || n - self.first >= self.count || len == 0 || len >= self.points {
            return;
        }
        let rows: Vec<usize> = (0..self.points).map(|i| i % len).collect();
        *cloud = cloud.subset(&rows);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use skyground_core::cloud::Cloud;

    #[test]
    fn only_the_burst_is_made_large_and_of_the_same_points() {
        let b = LargeScans::parse("2:2:7").expect("a burst");
        assert_eq!(LargeScans::parse("2:2"), None);
        assert_eq!(LargeScans::parse("2:2:7:1"), None);
        assert_eq!(LargeScans::parse("a:2:7"), None);
        let scan = || {
            let mut c = Cloud::from_xyz(vec![[1.0, 2.0, 3.0], [4.0, 5.0, 6.0]]);
            c.label = Some(vec![6, 2]);
            c
        };
        for n in [0, 1, 4] {
            let mut c = scan();
            b.apply(n, &mut c);
            assert_eq!(c.len(), 2, "scan {n} is not in the burst");
        }
        for n in [2, 3] {
            let mut c = scan();
            b.apply(n, &mut c);
            assert_eq!(c.len(), 7);
            assert_eq!(c.xyz[6], [1.0, 2.0, 3.0]);
            assert_eq!(c.label.as_deref(), Some(&[6, 2, 6, 2, 6, 2, 6][..]));
        }
        let mut empty = Cloud::from_xyz(vec![]);
        b.apply(2, &mut empty);
        assert_eq!(empty.len(), 0);
    }
}
