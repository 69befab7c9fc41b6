//! Issue 50's stall, reproduced in seconds instead of after 13 km: a
//! reliable reader that stops acknowledging (the real recorder, stopped
//! with SIGSTOP as a starved one is) lets a reliable writer's send window
//! (RustDDS: 8192 unacknowledged samples) fill. With `WhenFull::Block`, the
//! QoS every node used, the next write never returns: vehicle_sim's
//! /state_estimation in the 853-building mission. With today's profiles
//! (odometry best effort, /tf and other reliable writes failing at once
//! with the window full) every writer goes on.
//! Runs only inside a loopback-only network namespace (tests/run_all.sh).

use std::process::Command;
use std::time::{Duration, Instant};

use ros2_client::QosProfile;
use ros2_client::qos::{Reliability, WhenFull};
use skyground_msgs::nav_msgs::Odometry;
use skyground_nodes::netns::is_isolated;

mod common;
use common::{bin, signal};
use skyground_nodes::runtime::{NodeRuntime, NodeSpec, RosArgs, qos};

const NODE: NodeSpec = NodeSpec {
    name: "stuck_reader_test",
    default_params: "",
    live: &[],
};

/// More samples than the window holds.
const PAST_THE_WINDOW: usize = 8192 + 10;

/// How many of `n` writes on `p` returned, and the longest one; a write
/// that has not returned after `hang` counts as hung and ends the run.
async fn write_many(
    p: &ros2_client::Publisher<Odometry>,
    n: usize,
    hang: Duration,
) -> (usize, usize, Duration) {
    let (mut returned, mut ok, mut longest) = (0, 0, Duration::ZERO);
    for _ in 0..n {
        let t = Instant::now();
        match tokio::time::timeout(hang, p.async_publish(Odometry::default())).await {
            Ok(r) => {
                returned += 1;
                ok += usize::from(r.is_ok());
                longest = longest.max(t.elapsed());
            }
            Err(_) => return (returned, ok, hang),
        }
    }
    (returned, ok, longest)
}

#[test]
fn a_reader_that_stops_acknowledging_blocks_a_blocking_writer_and_no_other() {
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
    unsafe { std::env::set_var("ROS_DOMAIN_ID", "203") };
    let rt = tokio::runtime::Runtime::new().expect("tokio");
    rt.block_on(async {
        let mut n = NodeRuntime::start(&NODE, &RosArgs::default()).expect("node");
        let old = QosProfile::publisher_default()
            .reliability(Reliability::Reliable {
                when_full: WhenFull::Block,
            })
            .history(ros2_client::qos::History::KeepLast { depth: 10 });
        let writers = [
            ("/stuck_block", old),
            ("/stuck_odom", qos::odometry()),
            ("/stuck_tf", qos::tf()),
            ("/stuck_status", qos::reliable(10)),
        ];
        let pubs: Vec<_> = writers
            .iter()
            .map(|(t, q)| n.publisher::<Odometry>(t, q.clone()).expect("publisher"))
            .collect();
        let dir = std::env::temp_dir().join(format!("skyground-stuck-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let mut recorder = Command::new(&exe)
            .arg("record")
            .arg("-o")
            .arg(dir.join("stuck.mcap"))
            .args(writers.iter().map(|(t, _)| format!("{t}:nav_msgs/msg/Odometry")))
            .stderr(std::fs::File::create(dir.join("recorder.log")).unwrap())
            .spawn()
            .expect("skyground record");
        let deadline = Instant::now() + Duration::from_secs(60);
        while pubs.iter().any(|p| p.get_subscription_count(n.node()) == 0) {
            assert!(Instant::now() < deadline, "the recorder never matched");
            tokio::time::sleep(Duration::from_millis(200)).await;
        }
        for p in &pubs {
            assert_eq!(write_many(p, 5, Duration::from_secs(5)).await.0, 5);
        }
        tokio::time::sleep(Duration::from_secs(1)).await;
        signal(&recorder, "-STOP");

        let hang = Duration::from_secs(5);
        let (block, _, _) = write_many(&pubs[0], PAST_THE_WINDOW, hang).await;
        let (odom, odom_ok, odom_longest) = write_many(&pubs[1], PAST_THE_WINDOW, hang).await;
        let (tf, _, tf_longest) = write_many(&pubs[2], PAST_THE_WINDOW, hang).await;
        let (status, _, status_longest) = write_many(&pubs[3], PAST_THE_WINDOW, hang).await;
        eprintln!(
            "reader stopped: Block writer returned {block} of {PAST_THE_WINDOW} writes, then hung; \
             odometry {odom} ({odom_ok} ok, longest {odom_longest:?}); tf {tf} (longest {tf_longest:?}); \
             reliable {status} (longest {status_longest:?})"
        );
        signal(&recorder, "-CONT");
        let _ = recorder.kill();
        let _ = recorder.wait();
        let _ = std::fs::remove_dir_all(&dir);

        // The reproduction: the window fills and the blocking writer hangs.
        assert!(
            (8000..PAST_THE_WINDOW).contains(&block),
            "the Block writer returned {block} writes"
        );
        // The fix: best effort never waits; /tf and the other reliable
        // writes fail at once and the node goes on.
        assert_eq!((odom, odom_ok), (PAST_THE_WINDOW, PAST_THE_WINDOW));
        assert_eq!(tf, PAST_THE_WINDOW);
        assert!(tf_longest < Duration::from_millis(500), "{tf_longest:?}");
        assert_eq!(status, PAST_THE_WINDOW);
        assert!(status_longest < Duration::from_millis(500), "{status_longest:?}");
    });
}
