//! The MCAP bag writer and reader: round trip of every sample type, the rosbag2 layout,
//! dropped and cut-off recordings, and the errors.

use std::path::PathBuf;

use mcap::records::Record;
use skyground_msgs::samples::{self, Sample};
use skyground_msgs::{full_definition, known_types};
use skyground_nodes::bag::{
    BagError, BagMessage, BagWriter, TopicQos, read_intact_messages, read_messages,
};

const BASE_NS: u64 = 1_700_000_000_000_000_000;

/// A fresh path in the temp directory, unique per test and process.
fn temp_bag(name: &str) -> PathBuf {
    let path =
        std::env::temp_dir().join(format!("skyground-bag-{}-{name}.mcap", std::process::id()));
    let _ = std::fs::remove_file(&path);
    path
}

fn topic_of(sample: &Sample) -> String {
    format!("/sample/{}", sample.type_name.replacen("/msg/", "/", 1))
}

/// Adds every sample's topic and writes sample `i` at `BASE_NS + i µs`.
fn write_all_samples(bag: &mut BagWriter) -> Vec<BagMessage> {
    let mut expected = Vec::new();
    for (i, sample) in (0u64..).zip(samples::all()) {
        let topic = topic_of(&sample);
        let channel = bag
            .add_topic(&topic, sample.type_name, &TopicQos::default())
            .unwrap();
        let log_time_ns = BASE_NS + i * 1_000;
        bag.write(channel, log_time_ns, log_time_ns - 7, &sample.cdr)
            .unwrap();
        expected.push(BagMessage {
            topic,
            type_name: sample.type_name.to_owned(),
            log_time_ns,
            publish_time_ns: log_time_ns - 7,
            cdr: sample.cdr,
        });
    }
    expected
}

#[test]
fn every_sample_type_round_trips() {
    let path = temp_bag("round-trip");
    let mut bag = BagWriter::create(&path).unwrap();
    let expected = write_all_samples(&mut bag);
    bag.finish().unwrap();

    assert_eq!(expected.len(), known_types().len());
    let read = read_messages(&path).unwrap();
    assert_eq!(read, expected);
    assert_eq!(read_intact_messages(&path).unwrap(), expected);
    std::fs::remove_file(&path).unwrap();
}

#[test]
fn file_has_the_rosbag2_layout() {
    let path = temp_bag("layout");
    let mut bag = BagWriter::create(&path).unwrap();
    let qos = TopicQos {
        reliable: false,
        transient_local: true,
        depth: 1,
    };
    let a = bag
        .add_topic("/a", "sensor_msgs/msg/PointCloud2", &qos)
        .unwrap();
    let b = bag
        .add_topic("/b", "sensor_msgs/PointCloud2", &TopicQos::default())
        .unwrap();
    assert_ne!(a, b);
    assert_eq!(
        bag.add_topic("/a", "sensor_msgs/msg/PointCloud2", &qos)
            .unwrap(),
        a,
        "adding a topic again returns its channel"
    );
    let cloud = samples::all()
        .into_iter()
        .find(|s| s.type_name == "sensor_msgs/msg/PointCloud2")
        .unwrap();
    bag.write(a, BASE_NS, BASE_NS, &cloud.cdr).unwrap();
    bag.write(b, BASE_NS + 1, BASE_NS + 1, &cloud.cdr).unwrap();
    bag.finish().unwrap();

    let bytes = std::fs::read(&path).unwrap();
    let header = mcap::read::LinearReader::new(&bytes)
        .unwrap()
        .find_map(|r| match r.unwrap() {
            Record::Header(h) => Some(h),
            _ => None,
        })
        .unwrap();
    assert_eq!(header.profile, "ros2");

    let summary = mcap::Summary::read(&bytes).unwrap().unwrap();
    assert_eq!(summary.schemas.len(), 1, "one schema per type");
    let schema = summary.schemas.values().next().unwrap();
    assert_eq!(schema.name, "sensor_msgs/msg/PointCloud2");
    assert_eq!(schema.encoding, "ros2msg");
    assert_eq!(
        std::str::from_utf8(&schema.data).unwrap(),
        full_definition("sensor_msgs/msg/PointCloud2").unwrap()
    );
    let channel = &summary.channels[&a];
    assert_eq!(channel.topic, "/a");
    assert_eq!(channel.message_encoding, "cdr");
    let profiles = &channel.metadata["offered_qos_profiles"];
    assert!(profiles.contains("reliability: best_effort"), "{profiles}");
    assert!(
        profiles.contains("durability: transient_local"),
        "{profiles}"
    );
    assert!(profiles.contains("depth: 1\n"), "{profiles}");
    assert!(!summary.chunk_indexes.is_empty());
    assert!(
        summary
            .chunk_indexes
            .iter()
            .all(|c| c.compression == "zstd")
    );
    let stats = summary.stats.unwrap();
    assert_eq!(stats.message_count, 2);
    assert_eq!(stats.channel_count, 2);
    std::fs::remove_file(&path).unwrap();
}

#[test]
fn dropped_writer_still_leaves_a_complete_bag() {
    let path = temp_bag("dropped");
    let expected = {
        let mut bag = BagWriter::create(&path).unwrap();
        write_all_samples(&mut bag)
        // `bag` dropped here without finish().
    };
    assert_eq!(read_messages(&path).unwrap(), expected);
    std::fs::remove_file(&path).unwrap();
}

#[test]
fn cut_off_recording_is_reported_and_its_complete_chunks_recovered() {
    let path = temp_bag("cut-off");
    let mut bag = BagWriter::create(&path).unwrap();
    let mut expected = write_all_samples(&mut bag);
    bag.flush().unwrap(); // closes the first chunk
    let channel = bag
        .add_topic("/late", "rosgraph_msgs/msg/Clock", &TopicQos::default())
        .unwrap();
    let clock = samples::all()
        .into_iter()
        .find(|s| s.type_name == "rosgraph_msgs/msg/Clock")
        .unwrap();
    bag.write(channel, BASE_NS + 999_000, BASE_NS, &clock.cdr)
        .unwrap();
    bag.finish().unwrap();

    let bytes = std::fs::read(&path).unwrap();
    let summary = mcap::Summary::read(&bytes).unwrap().unwrap();
    assert_eq!(summary.chunk_indexes.len(), 2);
    let last = &summary.chunk_indexes[1];
    let first_chunk_count = expected.len();
    expected.push(BagMessage {
        topic: "/late".into(),
        type_name: "rosgraph_msgs/msg/Clock".into(),
        log_time_ns: BASE_NS + 999_000,
        publish_time_ns: BASE_NS,
        cdr: clock.cdr,
    });
    let data_end = mcap::read::footer(&bytes).unwrap().summary_start;

    // (cut at, messages intact): inside the last chunk, at its start, after the data end,
    // after the magic, before anything.
    let cuts = [
        (
            last.chunk_start_offset + last.chunk_length / 2,
            first_chunk_count,
        ),
        (last.chunk_start_offset, first_chunk_count),
        (data_end, expected.len()),
        (8, 0),
        (0, 0),
    ];
    for (cut, intact) in cuts {
        let cut_path = temp_bag(&format!("cut-off-{cut}"));
        std::fs::write(&cut_path, &bytes[..cut as usize]).unwrap();
        match read_messages(&cut_path) {
            Err(BagError::Truncated { intact: n, .. }) => assert_eq!(n, intact, "cut at {cut}"),
            other => panic!("cut at {cut}: expected Truncated, got {other:?}"),
        }
        let message = read_messages(&cut_path).unwrap_err().to_string();
        assert!(message.contains(&*cut_path.to_string_lossy()), "{message}");
        assert_eq!(
            read_intact_messages(&cut_path).unwrap(),
            expected[..intact],
            "cut at {cut}"
        );
        std::fs::remove_file(&cut_path).unwrap();
    }
    std::fs::remove_file(&path).unwrap();
}

/// A ROS 2 serialized `uint8[]`-like payload of `len` bytes that zstd cannot shrink much.
fn incompressible_cdr(len: usize, seed: u32) -> Vec<u8> {
    let mut state = seed.wrapping_mul(2_654_435_761) | 1;
    let mut cdr = vec![0, 1, 0, 0];
    cdr.extend((0..len).map(|_| {
        state ^= state << 13;
        state ^= state >> 17;
        state ^= state << 5;
        state.to_le_bytes()[0]
    }));
    cdr
}

#[test]
fn killed_recorder_is_reported_and_its_flushed_chunks_recovered() {
    // A writer that is never dropped stands for a recorder killed with SIGKILL: the
    // open chunk has its placeholder header and part of its compressed data on disk.
    let path = temp_bag("killed");
    let mut bag = BagWriter::create(&path).unwrap();
    let channel = bag
        .add_topic(
            "/blob",
            "sensor_msgs/msg/CompressedImage",
            &TopicQos::default(),
        )
        .unwrap();
    let first = incompressible_cdr(1000, 1);
    bag.write(channel, BASE_NS, BASE_NS, &first).unwrap();
    bag.flush().unwrap();
    for i in 0..3 {
        let big = incompressible_cdr(200_000, i + 2);
        bag.write(channel, BASE_NS + 1 + u64::from(i), BASE_NS, &big)
            .unwrap();
    }
    std::mem::forget(bag);

    let on_disk = std::fs::metadata(&path).unwrap().len();
    assert!(
        on_disk > 100_000,
        "partial chunk reached the file ({on_disk} bytes)"
    );
    match read_messages(&path) {
        Err(BagError::Truncated { intact: 1, .. }) => {}
        other => panic!("expected Truncated with 1 intact message, got {other:?}"),
    }
    let intact = read_intact_messages(&path).unwrap();
    assert_eq!(intact.len(), 1);
    assert_eq!(intact[0].cdr, first);
    std::fs::remove_file(&path).unwrap();
}

#[test]
fn corrupt_chunk_is_malformed() {
    let path = temp_bag("corrupt");
    let mut bag = BagWriter::create(&path).unwrap();
    write_all_samples(&mut bag);
    bag.finish().unwrap();
    let mut bytes = std::fs::read(&path).unwrap();
    let chunk = &mcap::Summary::read(&bytes).unwrap().unwrap().chunk_indexes[0];
    let inside = chunk.chunk_start_offset + chunk.chunk_length - 10;
    bytes[inside as usize] ^= 0x55;
    std::fs::write(&path, &bytes).unwrap();
    assert!(matches!(
        read_messages(&path),
        Err(BagError::Malformed { .. })
    ));
    assert!(matches!(
        read_intact_messages(&path),
        Err(BagError::Malformed { .. })
    ));
    std::fs::remove_file(&path).unwrap();
}

/// Set in the child process of [`recording_stopped_by_sigint_is_valid`]: the bag path.
const SIGINT_CHILD: &str = "SKYGROUND_BAG_SIGINT_CHILD";
/// What the child prints once its SIGINT handler is in place.
const READY: &str = "sigint-child: recording";
/// What the child prints after finishing, followed by the message count.
const WROTE: &str = "sigint-child: wrote ";

/// The child: records a clock every millisecond until SIGINT, then finishes the bag
/// and prints how many messages it wrote.
#[cfg(unix)]
fn record_until_sigint(path: &str) {
    use tokio::signal::unix::{SignalKind, signal};
    let runtime = tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build()
        .unwrap();
    runtime.block_on(async {
        let mut interrupt = signal(SignalKind::interrupt()).unwrap();
        let mut bag = BagWriter::create(path).unwrap();
        let channel = bag
            .add_topic("/clock", "rosgraph_msgs/msg/Clock", &TopicQos::default())
            .unwrap();
        let clock = samples::all()
            .into_iter()
            .find(|s| s.type_name == "rosgraph_msgs/msg/Clock")
            .unwrap();
        // libtest prints "test <name> ... " before this, on the same line.
        println!("{READY}");
        let give_up = tokio::time::sleep(std::time::Duration::from_secs(30));
        tokio::pin!(give_up);
        let mut written = 0u64;
        loop {
            tokio::select! {
                _ = interrupt.recv() => break,
                _ = &mut give_up => {
                    println!("no SIGINT within 30 s");
                    return;
                }
                _ = tokio::time::sleep(std::time::Duration::from_millis(1)) => {
                    bag.write(channel, BASE_NS + written, BASE_NS, &clock.cdr).unwrap();
                    written += 1;
                }
            }
        }
        bag.finish().unwrap();
        println!("{WROTE}{written}");
    });
}

#[cfg(unix)]
#[test]
fn recording_stopped_by_sigint_is_valid() {
    use std::io::{BufRead, BufReader};
    use std::process::{Command, Stdio};

    if let Ok(path) = std::env::var(SIGINT_CHILD) {
        record_until_sigint(&path);
        return;
    }
    let path = temp_bag("sigint");
    let mut child = Command::new(std::env::current_exe().unwrap())
        .args([
            "--exact",
            "recording_stopped_by_sigint_is_valid",
            "--nocapture",
            "--test-threads=1",
        ])
        .env(SIGINT_CHILD, &path)
        .stdout(Stdio::piped())
        .spawn()
        .unwrap();
    let mut lines = BufReader::new(child.stdout.take().unwrap()).lines();
    assert!(
        lines.by_ref().any(|l| l.unwrap().ends_with(READY)),
        "child never started recording"
    );
    std::thread::sleep(std::time::Duration::from_millis(300));
    let kill = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(kill.success());
    // Read to the end: closing the pipe early would fail the child's own output.
    let rest: Vec<String> = lines.map(|l| l.unwrap()).collect();
    let written: usize = rest
        .iter()
        .find_map(|l| l.strip_prefix(WROTE).map(|n| n.parse().unwrap()))
        .unwrap_or_else(|| panic!("child did not report what it wrote: {rest:?}"));
    assert!(child.wait().unwrap().success());

    let messages = read_messages(&path).unwrap();
    assert!(written > 10, "only {written} messages in 300 ms");
    assert_eq!(messages.len(), written);
    assert!(messages.iter().all(|m| m.topic == "/clock"));
    std::fs::remove_file(&path).unwrap();
}

#[test]
fn empty_bag_is_valid() {
    let path = temp_bag("empty");
    BagWriter::create(&path).unwrap().finish().unwrap();
    assert!(read_messages(&path).unwrap().is_empty());
    std::fs::remove_file(&path).unwrap();
}

#[test]
fn unknown_type_is_an_error() {
    let path = temp_bag("unknown-type");
    let mut bag = BagWriter::create(&path).unwrap();
    let err = bag
        .add_topic("/x", "nope_msgs/msg/Nope", &TopicQos::default())
        .unwrap_err();
    assert!(
        matches!(&err, BagError::UnknownType { topic, type_name, .. }
            if topic == "/x" && type_name == "nope_msgs/msg/Nope"),
        "{err:?}"
    );
    assert!(err.to_string().contains(&*path.to_string_lossy()), "{err}");
    bag.finish().unwrap();
    std::fs::remove_file(&path).unwrap();
}

#[test]
fn misuse_is_reported() {
    let path = temp_bag("misuse");
    let mut bag = BagWriter::create(&path).unwrap();
    let channel = bag
        .add_topic("/t", "builtin_interfaces/msg/Time", &TopicQos::default())
        .unwrap();
    assert!(matches!(
        bag.add_topic("/t", "std_msgs/msg/Header", &TopicQos::default()),
        Err(BagError::TopicTypeConflict { .. })
    ));
    assert!(matches!(
        bag.write(channel + 100, 0, 0, &[0, 1, 0, 0]),
        Err(BagError::UnknownChannel { channel: c, .. }) if c == channel + 100
    ));
    assert!(matches!(
        bag.write(channel, 0, 0, &[0, 1]),
        Err(BagError::NotCdr { len: 2, .. })
    ));
    bag.finish().unwrap();
    std::fs::remove_file(&path).unwrap();

    let missing_dir = std::env::temp_dir().join("skyground-no-such-dir/x.mcap");
    assert!(matches!(
        BagWriter::create(&missing_dir),
        Err(BagError::Create { .. })
    ));
    assert!(matches!(
        read_messages(&missing_dir),
        Err(BagError::Read { .. })
    ));

    let garbage = temp_bag("garbage");
    std::fs::write(&garbage, b"not an mcap file at all, just some bytes").unwrap();
    assert!(matches!(
        read_messages(&garbage),
        Err(BagError::Malformed { .. })
    ));
    std::fs::remove_file(&garbage).unwrap();
}
