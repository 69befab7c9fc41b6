//! What the demo says while it runs: a progress bar on a terminal, one line
//! per change of the mission's state otherwise (a log stays short).

use std::io::IsTerminal;

use indicatif::{ProgressBar, ProgressStyle};

/// The demo's stderr while the mission runs.
pub(super) struct Console {
    bar: Option<ProgressBar>,
    /// The last state line printed (without its time), so a line is printed once.
    last: String,
}

impl Console {
    /// A bar when stderr is a terminal, plain lines when it is a file or a pipe.
    pub fn new() -> Self {
        let bar = std::io::stderr().is_terminal().then(|| {
            let b = ProgressBar::new(0);
            let style = ProgressStyle::with_template(
                "  [{elapsed:>4}] {prefix} [{bar:30}] {pos}/{len} targets | {msg}",
            )
            .map_or_else(
                |_| ProgressStyle::default_bar(),
                |s| s.progress_chars("=> "),
            );
            b.set_style(style);
            b
        });
        Self {
            bar,
            last: String::new(),
        }
    }

    /// One line of news, above the bar when there is one.
    pub fn say(&self, line: &str) {
        match &self.bar {
            Some(b) => b.println(line),
            None => eprintln!("{line}"),
        }
    }

    /// The mission's state: `stage` (round and phase), targets `done` of
    /// `stops`, `gain` (coverage so far), and `odometer` (distance and robot
    /// time, which move all the time and so are shown, not watched).
    pub fn state(
        &mut self,
        elapsed_s: f64,
        (stage, done, stops): (&str, usize, usize),
        gain: &str,
        odometer: &str,
    ) {
        if let Some(b) = &self.bar {
            b.set_prefix(stage.to_string());
            b.set_length(stops as u64);
            b.set_position(done as u64);
            b.set_message(format!("{gain} | {odometer}"));
            return;
        }
        let line = format!("{stage}: targets {done}/{stops} | {gain}");
        if line != self.last {
            eprintln!("  [{elapsed_s:>5.0} s] {line} | {odometer}");
            self.last = line;
        }
    }

    /// Clears the bar (the summary lines follow it).
    pub fn finish(&self) {
        if let Some(b) = &self.bar {
            b.finish_and_clear();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_state_is_printed_once_until_it_changes() {
        let mut c = Console {
            bar: None,
            last: String::new(),
        };
        c.state(5.0, ("round 1 driving", 3, 10), "coverage 90.00 %", "5 m");
        let first = c.last.clone();
        c.state(10.0, ("round 1 driving", 3, 10), "coverage 90.00 %", "9 m");
        assert_eq!(c.last, first);
        c.state(15.0, ("round 1 driving", 4, 10), "coverage 90.00 %", "12 m");
        assert_ne!(c.last, first);
        assert!(c.last.contains("targets 4/10"), "{}", c.last);
    }
}
