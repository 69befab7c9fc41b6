//! Rust ↔ Rust over real DDS in one process (two participants): a 1 M-point
//! cloud arrives whole through tiles, and a typed message through a tap.
//! Runs only inside a loopback-only network namespace (tests/run_all.sh).

use std::time::Duration;

use skyground_core::cloud::synthetic;
use skyground_msgs::geometry_msgs::PoseStamped;
use skyground_msgs::nav_msgs::Path;
use skyground_msgs::std_msgs::Header;
use skyground_msgs::{builtin_interfaces::Time, from_cdr};
use skyground_nodes::convert::pointcloud2::{EncodeOptions, encode};
use skyground_nodes::netns::is_isolated;
use skyground_nodes::runtime::{NodeRuntime, NodeSpec, RosArgs, qos};
use skyground_nodes::tap::tap;
use skyground_nodes::transport::{CloudPublisher, CloudSubscription, Received, TransportConfig};

const PUB: NodeSpec = NodeSpec {
    name: "transport_test_pub",
    default_params: "",
    live: &[],
};
const SUB: NodeSpec = NodeSpec {
    name: "transport_test_sub",
    default_params: "",
    live: &[],
};

#[test]
fn cloud_and_path_cross_dds_intact() {
    if !is_isolated() {
        eprintln!("SKIPPED: not in a loopback-only network namespace (run tests/run_all.sh)");
        return;
    }
    // SAFETY: the only test in this binary; set before any thread starts.
    unsafe { std::env::set_var("ROS_DOMAIN_ID", "201") };
    let rt = tokio::runtime::Runtime::new().expect("tokio");
    rt.block_on(async {
        let mut a = NodeRuntime::start(&PUB, &RosArgs::default()).expect("publisher node");
        let mut b = NodeRuntime::start(&SUB, &RosArgs::default()).expect("subscriber node");

        let mut clouds =
            CloudSubscription::new(&mut b, "/t_cloud", qos::reliable(300), 65_536).expect("sub");
        let mut paths = tap(
            &mut b,
            "/t_path",
            "nav_msgs/msg/Path",
            qos::latched(1),
            true,
        )
        .expect("tap");
        let publisher = CloudPublisher::new(
            &mut a,
            "/t_cloud",
            qos::reliable(1),
            TransportConfig::default(),
        )
        .expect("pub");
        assert!(
            publisher
                .wait_for_subscriptions(1, Duration::from_secs(30))
                .await
        );
        tokio::time::sleep(Duration::from_millis(500)).await;

        let cloud = synthetic::tilted_plane(1_000_000);
        let header = Header {
            stamp: Time { sec: 7, nanosec: 9 },
            frame_id: "map".into(),
        };
        let stats = publisher
            .publish(encode(&cloud, header, &EncodeOptions::default()))
            .await
            .expect("publish");
        assert_eq!(stats.tiles, 1_000_000 / 65_536 + 1);
        assert!(stats.acknowledged);
        match tokio::time::timeout(Duration::from_secs(60), clouds.next()).await {
            Ok(Some(Received::Cloud { msg, decoded })) => {
                assert_eq!(msg.header.stamp, Time { sec: 7, nanosec: 9 });
                assert_eq!(decoded.cloud.xyz, cloud.xyz);
                assert_eq!(decoded.cloud.label, cloud.label);
                assert_eq!(decoded.cloud.building, cloud.building);
            }
            Ok(Some(Received::Bad(e))) => panic!("bad cloud: {e}"),
            _ => panic!("no cloud within 60 s"),
        }

        let path = Path {
            header: Header {
                stamp: Time { sec: 1, nanosec: 2 },
                frame_id: "map".into(),
            },
            poses: (0..5)
                .map(|i| {
                    let mut p = PoseStamped::default();
                    p.pose.position.x = f64::from(i) * 0.5;
                    p
                })
                .collect(),
        };
        let path_pub = a
            .publisher::<Path>("/t_path", qos::latched(1))
            .expect("path pub");
        path_pub
            .async_publish(path.clone())
            .await
            .expect("publish path");
        let got = tokio::time::timeout(Duration::from_secs(30), paths.next())
            .await
            .expect("path within 30 s")
            .expect("stream open")
            .expect("readable");
        assert_eq!(from_cdr::<Path>(&got.cdr).expect("cdr"), path);
        assert_eq!(
            got.json.expect("json")["poses"][4]["pose"]["position"]["x"],
            2.0
        );
        b.stop().await;
        a.stop().await;
    });
}
