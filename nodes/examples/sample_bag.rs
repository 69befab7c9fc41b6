//! Writes a bag holding one sample message of every known type: `sample_bag OUT.mcap`.
//!
//! Sample `i` of `skyground_msgs::samples::all()` goes to topic `/sample/<pkg>/<Type>`
//! with log time `1_700_000_000 s + i ms` and publish time 1 µs earlier.
//! `tests/python/test_bag_format.py` decodes the result with the Python MCAP and
//! rosbags readers.

use std::process::ExitCode;

use skyground_msgs::samples;
use skyground_nodes::bag::{BagError, BagWriter, TopicQos};

/// Log time of the first sample, nanoseconds since the Unix epoch.
const BASE_NS: u64 = 1_700_000_000_000_000_000;
/// Log time step between samples.
const STEP_NS: u64 = 1_000_000;

fn main() -> ExitCode {
    let Some(path) = std::env::args().nth(1) else {
        eprintln!("usage: sample_bag OUT.mcap");
        return ExitCode::from(2);
    };
    match write_samples(&path) {
        Ok(count) => {
            eprintln!("{path}: {count} sample messages");
            ExitCode::SUCCESS
        }
        Err(error) => {
            eprintln!("{error}");
            ExitCode::FAILURE
        }
    }
}

/// Writes every sample on its own topic; returns how many.
fn write_samples(path: &str) -> Result<usize, BagError> {
    let mut bag = BagWriter::create(path)?;
    let samples = samples::all();
    for (i, sample) in (0u64..).zip(&samples) {
        let topic = format!("/sample/{}", sample.type_name.replacen("/msg/", "/", 1));
        let channel = bag.add_topic(&topic, sample.type_name, &TopicQos::default())?;
        let log_time = BASE_NS + i * STEP_NS;
        bag.write(channel, log_time, log_time - 1_000, &sample.cdr)?;
    }
    bag.finish()?;
    Ok(samples.len())
}
