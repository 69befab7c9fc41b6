//! What px4_bridge publishes: to PX4 (heartbeat, setpoints, commands) and
//! to the planners and RViz (the drone in the map, way-point, status).

use ros2_client::Publisher;
use skyground_core::follow::FollowEvent;
use skyground_core::mission::{VehicleEvent, VehicleStatus};
use skyground_core::px4::{MapPose, Offboard, Out};
use skyground_msgs::diagnostic_msgs::DiagnosticArray;
use skyground_msgs::geometry_msgs::PointStamped;
use skyground_msgs::nav_msgs::Odometry;
use skyground_msgs::px4_msgs::{self as px4, topics};
use skyground_msgs::tf2_msgs::TFMessage;

use super::Params;
use crate::convert::diagnostics::array;
use crate::convert::path::point_stamped;
use crate::convert::px4 as conv;
use crate::convert::tf::tf_message;
use crate::runtime::{NodeRuntime, RuntimeError, qos};

/// The name /uav/vehicle_status is signed with (worded as robot_bridge's).
const NAME: &str = "px4_bridge";

/// What the bridge publishes.
pub(super) struct Pubs {
    mode: Publisher<px4::OffboardControlMode>,
    setpoint: Publisher<px4::TrajectorySetpoint>,
    command: Publisher<px4::VehicleCommand>,
    odom: Publisher<Odometry>,
    tf: Publisher<TFMessage>,
    way: Publisher<PointStamped>,
    status: Publisher<DiagnosticArray>,
}

impl Pubs {
    pub(super) fn new(rt: &mut NodeRuntime) -> Result<Self, RuntimeError> {
        // PX4's readers are best effort: a reliable writer (its example's) matches them.
        Ok(Self {
            mode: rt.publisher(topics::OFFBOARD_CONTROL_MODE, qos::reliable(10))?,
            setpoint: rt.publisher(topics::TRAJECTORY_SETPOINT, qos::reliable(10))?,
            command: rt.publisher(topics::VEHICLE_COMMAND, qos::reliable(10))?,
            odom: rt.publisher("/uav/state_estimation", qos::odometry())?,
            tf: rt.publisher("/tf", qos::tf())?,
            way: rt.publisher("/uav/way_point", qos::reliable(10))?,
            status: rt.publisher("/uav/vehicle_status", qos::reliable(10))?,
        })
    }

    /// The drone in the map: /uav/state_estimation and /tf.
    pub(super) async fn pose(&self, rt: &NodeRuntime, p: &Params, pose: &MapPose) {
        let header = rt.header(&p.frame_id);
        let o = conv::odometry(header.clone(), &p.child_frame_id, pose);
        rt.log
            .sent("/uav/state_estimation", self.odom.async_publish(o).await);
        let tf = tf_message(conv::transform(header, &p.child_frame_id, pose));
        rt.log.sent("/tf", self.tf.async_publish(tf).await);
    }

    /// One output of the state machine, sent or said.
    pub(super) async fn send(&self, rt: &NodeRuntime, p: &Params, b: &Offboard, out: Out, us: u64) {
        let (goal, event) = match out {
            Out::Heartbeat(s) => {
                let (mode, sp) = conv::heartbeat(&s, us);
                rt.log.sent(
                    topics::OFFBOARD_CONTROL_MODE,
                    self.mode.async_publish(mode).await,
                );
                rt.log.sent(
                    topics::TRAJECTORY_SETPOINT,
                    self.setpoint.async_publish(sp).await,
                );
                return;
            }
            Out::Command(c) => {
                rt.log
                    .info(&format!("asking PX4: {c:?} (command {})", c.mavlink().0));
                let m = conv::command(c, us);
                rt.log
                    .sent(topics::VEHICLE_COMMAND, self.command.async_publish(m).await);
                return;
            }
            Out::Follow(FollowEvent::WayPoint(w)) => {
                let msg = point_stamped(rt.header(&p.frame_id), w);
                rt.log
                    .sent("/uav/way_point", self.way.async_publish(msg).await);
                return;
            }
            Out::Follow(FollowEvent::Arrived { goal }) => {
                let [x, y, z] = goal;
                rt.log.info(&format!("arrived at ({x:.1}, {y:.1}, {z:.1})"));
                (goal, VehicleEvent::Arrived)
            }
            Out::Follow(FollowEvent::Blocked { goal, reason }) => {
                let [x, y, z] = goal;
                rt.log.warn(&format!(
                    "blocked going to ({x:.1}, {y:.1}, {z:.1}): {reason}"
                ));
                (goal, VehicleEvent::Blocked(reason))
            }
        };
        let s = VehicleStatus::from_follower(NAME, event, goal, b.follower());
        let s = array(rt.header(&p.frame_id), s.to_wire());
        rt.log
            .sent("/uav/vehicle_status", self.status.async_publish(s).await);
    }
}
