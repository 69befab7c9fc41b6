//! A DDS participant stopped and continued (SIGSTOP/SIGCONT: Ctrl-Z and
//! `fg`, a debugger; a system suspend interrupts its waits the same way)
//! still receives. RustDDS 0.15.1 ended both of its event loops when a wait
//! returned `EINTR`, so the process ran on with no DDS; the workspace takes
//! it with third_party/rustdds-eintr.patch (third_party/README.md). The real
//! recorder is stopped and continued between two bursts of messages; its bag
//! must hold both.
//! Runs only inside a loopback-only network namespace (tests/run_all.sh).

use std::process::Command;
use std::time::{Duration, Instant};

use skyground_msgs::nav_msgs::Odometry;
use skyground_nodes::netns::is_isolated;

mod common;
use common::{bin, signal};
use skyground_nodes::runtime::{NodeRuntime, NodeSpec, RosArgs, qos};

const NODE: NodeSpec = NodeSpec {
    name: "interrupted_poll_test",
    default_params: "",
    live: &[],
};

const TOPIC: &str = "/interrupted_odom";

/// Messages on [`TOPIC`] in the bag at `path`.
fn recorded(path: &std::path::Path) -> usize {
    let bytes = std::fs::read(path).expect("the bag");
    mcap::MessageStream::new(&bytes)
        .expect("an MCAP file")
        .filter_map(Result::ok)
        .filter(|m| m.channel.topic == TOPIC)
        .count()
}

#[test]
fn a_participant_stopped_and_continued_still_receives() {
    if !is_isolated() {
        eprintln!("SKIPPED: not in a loopback-only network namespace (run tests/run_all.sh)");
        return;
    }
    let exe = bin();
    if !exe.is_file() {
        eprintln!("SKIPPED: {} not built", exe.display());
        return;
    }
    // SAFETY: the only test in this binary; set before any thread starts.
    unsafe { std::env::set_var("ROS_DOMAIN_ID", "204") };
    let dir = std::env::temp_dir().join(format!("skyground-eintr-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let bag = dir.join("eintr.mcap");
    let rt = tokio::runtime::Runtime::new().expect("tokio");
    let (before, after) = rt.block_on(async {
        let mut n = NodeRuntime::start(&NODE, &RosArgs::default()).expect("node");
        let p = n
            .publisher::<Odometry>(TOPIC, qos::reliable(100))
            .expect("publisher");
        let mut recorder = Command::new(&exe)
            .arg("record")
            .arg("-o")
            .arg(&bag)
            .arg(format!("{TOPIC}:nav_msgs/msg/Odometry"))
            .stderr(std::fs::File::create(dir.join("recorder.log")).unwrap())
            .spawn()
            .expect("skyground record");
        let deadline = Instant::now() + Duration::from_secs(60);
        while p.get_subscription_count(n.node()) == 0 {
            assert!(Instant::now() < deadline, "the recorder never matched");
            tokio::time::sleep(Duration::from_millis(200)).await;
        }
        let burst = |k: usize| {
            let p = &p;
            async move {
                for _ in 0..k {
                    p.async_publish(Odometry::default()).await.expect("write");
                    tokio::time::sleep(Duration::from_millis(20)).await;
                }
            }
        };
        burst(5).await;
        tokio::time::sleep(Duration::from_secs(1)).await;
        signal(&recorder, "-STOP");
        tokio::time::sleep(Duration::from_secs(1)).await;
        signal(&recorder, "-CONT");
        tokio::time::sleep(Duration::from_secs(1)).await;
        burst(20).await;
        tokio::time::sleep(Duration::from_secs(2)).await;
        signal(&recorder, "-INT");
        let status = recorder.wait().expect("the recorder's exit");
        assert!(status.success(), "recorder: {status}");
        let log = std::fs::read_to_string(dir.join("recorder.log")).unwrap_or_default();
        (5, (recorded(&bag), log))
    });
    let (got, log) = after;
    let _ = std::fs::remove_dir_all(&dir);
    eprintln!("recorded {got} of {} messages", before + 20);
    assert!(
        !log.contains("poll failed") && !log.contains("Failed in waiting of poll"),
        "an event loop ended: {log}"
    );
    assert_eq!(got, before + 20, "messages after the stop were lost: {log}");
}
