//! A stand-in for PX4 in tests (not a user command): speaks PX4 v1.15's
//! uXRCE-DDS topics and its offboard rules, flying a point mass.
//!
//!     px4_peer --log FILE [--bad-every N]
//!
//! As PX4: setpoints move it only once it has been switched to offboard
//! (176, param1 1, param2 6), which it refuses unless the heartbeat
//! (OffboardControlMode) streams at ≥ 2 Hz and a setpoint is known, and armed
//! (400, param1 1); a heartbeat lost for 1 s drops it to hold (loiter);
//! NAV_LAND (21) descends to the ground and disarms. It flies towards the
//! setpoint at most 5 m/s across, 2 m/s up or down, 4 m/s² and 1 rad/s of
//! yaw; publishes VehicleOdometry in NED at 50 Hz (best effort, as PX4) and
//! VehicleStatus at 5 Hz. Every N-th odometry is a bad one (NaN or an FRD
//! frame 1 km off) when asked. Writes one JSON line per event to FILE
//! (every odometry sent, every command and what it made of it); prints
//! {"event": "ready"} on stdout.

use std::collections::VecDeque;
use std::io::Write;
use std::process::ExitCode;
use std::time::Duration;

use futures::StreamExt;
use serde_json::json;
use skyground_msgs::px4_msgs::{
    OffboardControlMode, TrajectorySetpoint, VehicleCommand, VehicleOdometry, VehicleStatus, topics,
};
use skyground_nodes::runtime::{NodeRuntime, NodeSpec, RuntimeError, qos, run_node};

const SPEC: NodeSpec = NodeSpec {
    name: "px4_peer",
    default_params: "",
    live: &[],
};
const DT: f64 = 0.02;

/// The simulated autopilot.
#[derive(Default)]
struct Px4 {
    ned: [f64; 3],
    vel: [f64; 3],
    yaw: f64,
    armed: bool,
    nav: u8,
    beats: VecDeque<f64>,
    setpoint: Option<([f64; 3], f64)>,
    moved: bool,
}

impl Px4 {
    /// Heartbeats in the last second.
    fn rate(&self, t: f64) -> usize {
        self.beats.iter().filter(|&&b| t - b <= 1.0).count()
    }

    /// A command: whether PX4 would take it.
    fn command(&mut self, c: &VehicleCommand, t: f64) -> bool {
        match (c.command, c.param1, c.param2) {
            (176, p1, p2) if p1 == 1.0 && p2 == 6.0 => {
                let ok = self.rate(t) >= 2 && self.setpoint.is_some();
                if ok {
                    self.nav = VehicleStatus::NAVIGATION_STATE_OFFBOARD;
                }
                ok
            }
            (400, p1, _) => {
                self.armed = p1 == 1.0;
                true
            }
            (21, _, _) if self.armed => {
                self.nav = VehicleStatus::NAVIGATION_STATE_AUTO_LAND;
                true
            }
            _ => false,
        }
    }

    /// One step of DT seconds at time `t`.
    fn step(&mut self, t: f64) {
        let offboard = self.nav == VehicleStatus::NAVIGATION_STATE_OFFBOARD;
        if offboard && self.beats.back().is_none_or(|b| t - b > 1.0) {
            self.nav = VehicleStatus::NAVIGATION_STATE_AUTO_LOITER; // offboard lost: hold
        }
        let target = match (self.armed, self.nav, self.setpoint) {
            (true, VehicleStatus::NAVIGATION_STATE_OFFBOARD, Some(s)) => Some(s),
            (true, VehicleStatus::NAVIGATION_STATE_AUTO_LAND, _) => {
                Some(([self.ned[0], self.ned[1], 0.0], self.yaw))
            }
            (true, _, _) => Some((self.ned, self.yaw)),
            _ => None,
        };
        let Some((goal, yaw)) = target else {
            self.vel = [0.0; 3];
            return;
        };
        let mut want: Vec<f64> = (0..3).map(|i| goal[i] - self.ned[i]).collect();
        let across = want[0].hypot(want[1]);
        if across > 5.0 {
            (want[0], want[1]) = (want[0] * 5.0 / across, want[1] * 5.0 / across);
        }
        want[2] = want[2].clamp(-2.0, 2.0);
        for ((v, p), w) in self.vel.iter_mut().zip(&mut self.ned).zip(&want) {
            *v += (w - *v).clamp(-4.0 * DT, 4.0 * DT);
            *p += *v * DT;
        }
        let turn = (yaw - self.yaw + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU)
            - std::f64::consts::PI;
        self.yaw += turn.clamp(-DT, DT);
        if self.nav == VehicleStatus::NAVIGATION_STATE_AUTO_LAND && self.ned[2] > -0.05 {
            self.armed = false;
        }
    }

    fn odometry(&self, us: u64) -> VehicleOdometry {
        let h = self.yaw / 2.0;
        VehicleOdometry {
            timestamp: us,
            timestamp_sample: us,
            pose_frame: VehicleOdometry::POSE_FRAME_NED,
            position: self.ned.map(|v| v as f32),
            q: [h.cos() as f32, 0.0, 0.0, h.sin() as f32],
            velocity_frame: VehicleOdometry::VELOCITY_FRAME_NED,
            velocity: self.vel.map(|v| v as f32),
            angular_velocity: [0.0; 3],
            ..VehicleOdometry::default()
        }
    }

    fn status(&self, us: u64) -> VehicleStatus {
        VehicleStatus {
            timestamp: us,
            arming_state: if self.armed { 2 } else { 1 },
            nav_state: self.nav,
            vehicle_type: 1,
            pre_flight_checks_pass: true,
            ..VehicleStatus::default()
        }
    }
}

/// Makes every `every`-th odometry bad, in turn NaN and in an FRD frame 1 km off.
fn spoil(o: &mut VehicleOdometry, n: u64, every: u64) -> bool {
    let bad = every > 0 && n.is_multiple_of(every);
    if bad && n.is_multiple_of(2 * every) {
        o.position[0] = f32::NAN;
    } else if bad {
        (o.pose_frame, o.position[0]) = (VehicleOdometry::POSE_FRAME_FRD, o.position[0] + 1000.0);
    }
    bad
}

fn main() -> ExitCode {
    run_node(SPEC, async |rt, args| fly(rt, args).await)
}

fn arg(args: &[String], name: &str) -> Option<String> {
    args.iter()
        .position(|a| a == name)
        .and_then(|i| args.get(i + 1).cloned())
}

async fn fly(rt: &mut NodeRuntime, args: Vec<String>) -> Result<(), RuntimeError> {
    let path =
        arg(&args, "--log").ok_or_else(|| RuntimeError::Node("--log FILE is required".into()))?;
    let bad_every: u64 = arg(&args, "--bad-every")
        .and_then(|s| s.parse().ok())
        .unwrap_or(0);
    let mut log =
        std::fs::File::create(&path).map_err(|e| RuntimeError::Node(format!("{path}: {e}")))?;
    let odom_pub = rt.publisher::<VehicleOdometry>(topics::VEHICLE_ODOMETRY, qos::sensor(10))?;
    let status_pub = rt.publisher::<VehicleStatus>(topics::VEHICLE_STATUS, qos::sensor(10))?;
    let modes =
        rt.subscription::<OffboardControlMode>(topics::OFFBOARD_CONTROL_MODE, qos::sensor(10))?;
    let sps =
        rt.subscription::<TrajectorySetpoint>(topics::TRAJECTORY_SETPOINT, qos::sensor(10))?;
    let cmds = rt.subscription::<VehicleCommand>(topics::VEHICLE_COMMAND, qos::sensor(10))?;
    let (modes, sps, cmds) = (
        modes.async_stream(),
        sps.async_stream(),
        cmds.async_stream(),
    );
    futures::pin_mut!(modes, sps, cmds);
    let mut px4 = Px4 {
        nav: VehicleStatus::NAVIGATION_STATE_AUTO_LOITER,
        ..Px4::default()
    };
    let mut tick = tokio::time::interval(Duration::from_secs_f64(DT));
    let start = std::time::Instant::now();
    let mut n: u64 = 0;
    println!("{}", json!({"event": "ready"}));
    loop {
        let t = start.elapsed().as_secs_f64();
        let us = (t * 1e6) as u64;
        let mut line = None;
        tokio::select! {
            _ = rt.shutdown.wait() => break,
            Some(Ok((m, _))) = modes.next() => {
                if m.position {
                    px4.beats.push_back(t);
                    if px4.beats.len() > 50 { px4.beats.pop_front(); }
                }
            }
            Some(Ok((s, _))) = sps.next() => {
                if s.position.iter().all(|v| v.is_finite()) {
                    px4.setpoint = Some((s.position.map(f64::from), f64::from(s.yaw)));
                }
            }
            Some(Ok((c, _))) = cmds.next() => {
                let rate = px4.rate(t);
                let accepted = px4.command(&c, t);
                line = Some(json!({"event": "command", "t": t, "command": c.command, "accepted": accepted,
                    "heartbeat_hz": rate, "armed": px4.armed, "nav_state": px4.nav}));
            }
            _ = tick.tick() => {
                px4.step(t);
                n += 1;
                let mut o = px4.odometry(us);
                let bad = spoil(&mut o, n, bad_every);
                let _ = odom_pub.async_publish(o.clone()).await;
                if n.is_multiple_of(10) {
                    let _ = status_pub.async_publish(px4.status(us)).await;
                }
                let moving = px4.ned.iter().map(|v| v * v).sum::<f64>() > 0.05 * 0.05;
                if moving && !px4.moved {
                    px4.moved = true;
                    writeln!(log, "{}", json!({"event": "first_move", "t": t, "armed": px4.armed,
                        "nav_state": px4.nav, "heartbeat_hz": px4.rate(t)})).ok();
                }
                line = Some(json!({"event": "odom", "t": t, "bad": bad, "frame": o.pose_frame,
                    "ned": o.position.map(|v| if v.is_finite() { f64::from(v) } else { f64::MAX })}));
            }
        }
        if let Some(l) = line {
            writeln!(log, "{l}").ok();
        }
    }
    Ok(())
}
