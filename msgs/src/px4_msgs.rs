//! `px4_msgs`: the part of PX4's ROS 2 interface (uXRCE-DDS) an offboard
//! companion needs, from PX4 **v1.15**'s `msg/*.msg` (px4_msgs branch
//! `release/1.15`): field order and types exactly as there, so the CDR layout
//! is PX4's. v1.15 has no versioned topic names (v1.16 renamed some, e.g.
//! `/fmu/out/vehicle_status_v1`). Only the constants skyground uses are kept.
//!
//! PX4's frames: world NED (x north, y east, z down) with its origin where the
//! estimator started, body FRD; quaternions `[w, x, y, z]` body → world.

use serde::{Deserialize, Serialize};

use crate::message::ros_message;

/// The uXRCE-DDS bridge's topic names (v1.15, default namespace).
pub mod topics {
    /// Offboard heartbeat, PX4 subscribes (≥ 2 Hz or it leaves offboard).
    pub const OFFBOARD_CONTROL_MODE: &str = "/fmu/in/offboard_control_mode";
    /// Offboard setpoints, PX4 subscribes.
    pub const TRAJECTORY_SETPOINT: &str = "/fmu/in/trajectory_setpoint";
    /// Commands (mode, arm, land), PX4 subscribes.
    pub const VEHICLE_COMMAND: &str = "/fmu/in/vehicle_command";
    /// The estimator's odometry, PX4 publishes (best effort).
    pub const VEHICLE_ODOMETRY: &str = "/fmu/out/vehicle_odometry";
    /// Arming and navigation state, PX4 publishes (best effort).
    pub const VEHICLE_STATUS: &str = "/fmu/out/vehicle_status";
}

/// `px4_msgs/msg/TrajectorySetpoint`: a setpoint in world NED; NaN = not controlled.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default)]
pub struct TrajectorySetpoint {
    /// Time since PX4's start (µs).
    pub timestamp: u64,
    /// m, NED.
    pub position: [f32; 3],
    /// m/s, NED.
    pub velocity: [f32; 3],
    /// m/s², NED.
    pub acceleration: [f32; 3],
    /// m/s³ (logged only).
    pub jerk: [f32; 3],
    /// rad, −π..π, from north towards east.
    pub yaw: f32,
    /// rad/s about NED z.
    pub yawspeed: f32,
}

/// `px4_msgs/msg/OffboardControlMode`: the offboard heartbeat, saying what is controlled.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize, Default)]
pub struct OffboardControlMode {
    /// Time since PX4's start (µs).
    pub timestamp: u64,
    /// Position setpoints are followed.
    pub position: bool,
    /// Velocity setpoints are followed.
    pub velocity: bool,
    /// Acceleration setpoints are followed.
    pub acceleration: bool,
    /// Attitude setpoints are followed.
    pub attitude: bool,
    /// Body-rate setpoints are followed.
    pub body_rate: bool,
    /// Thrust and torque setpoints are followed.
    pub thrust_and_torque: bool,
    /// Actuators are driven directly.
    pub direct_actuator: bool,
}

/// `px4_msgs/msg/VehicleCommand`: a MAVLink-style command.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default)]
pub struct VehicleCommand {
    /// Time since PX4's start (µs).
    pub timestamp: u64,
    /// Command parameter 1.
    pub param1: f32,
    /// Command parameter 2.
    pub param2: f32,
    /// Command parameter 3.
    pub param3: f32,
    /// Command parameter 4.
    pub param4: f32,
    /// Command parameter 5 (float64: latitudes).
    pub param5: f64,
    /// Command parameter 6 (float64: longitudes).
    pub param6: f64,
    /// Command parameter 7.
    pub param7: f32,
    /// Command id (`VEHICLE_CMD_*`).
    pub command: u32,
    /// System that should execute it.
    pub target_system: u8,
    /// Component that should execute it (0: all).
    pub target_component: u8,
    /// System sending it.
    pub source_system: u8,
    /// Component sending it.
    pub source_component: u16,
    /// 0: first transmission.
    pub confirmation: u8,
    /// Sent from outside PX4.
    pub from_external: bool,
}

impl VehicleCommand {
    /// MAV_CMD_NAV_LAND.
    pub const VEHICLE_CMD_NAV_LAND: u32 = 21;
    /// MAV_CMD_DO_SET_MODE (param1 1 = custom mode, param2 6 = offboard).
    pub const VEHICLE_CMD_DO_SET_MODE: u32 = 176;
    /// MAV_CMD_COMPONENT_ARM_DISARM (param1 1 = arm).
    pub const VEHICLE_CMD_COMPONENT_ARM_DISARM: u32 = 400;
}

/// `px4_msgs/msg/VehicleOdometry`: the estimator's pose and velocity (REP 147 for aerial vehicles).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default)]
pub struct VehicleOdometry {
    /// Time since PX4's start (µs).
    pub timestamp: u64,
    /// When the data was sampled (µs).
    pub timestamp_sample: u64,
    /// Frame of `position` and `q` (`POSE_FRAME_*`).
    pub pose_frame: u8,
    /// m in `pose_frame`; NaN if unknown.
    pub position: [f32; 3],
    /// Body FRD → `pose_frame`, `[w, x, y, z]`; first NaN if unknown.
    pub q: [f32; 4],
    /// Frame of `velocity` (`VELOCITY_FRAME_*`).
    pub velocity_frame: u8,
    /// m/s in `velocity_frame`; NaN if unknown.
    pub velocity: [f32; 3],
    /// rad/s in body FRD; NaN if unknown.
    pub angular_velocity: [f32; 3],
    /// m².
    pub position_variance: [f32; 3],
    /// rad², body frame.
    pub orientation_variance: [f32; 3],
    /// m²/s².
    pub velocity_variance: [f32; 3],
    /// Counts resets of attitude, velocity and position.
    pub reset_counter: u8,
    /// Unused by PX4.
    pub quality: i8,
}

impl VehicleOdometry {
    /// Pose frame unknown.
    pub const POSE_FRAME_UNKNOWN: u8 = 0;
    /// NED earth-fixed.
    pub const POSE_FRAME_NED: u8 = 1;
    /// FRD world-fixed, arbitrary heading.
    pub const POSE_FRAME_FRD: u8 = 2;
    /// Velocity frame unknown.
    pub const VELOCITY_FRAME_UNKNOWN: u8 = 0;
    /// NED earth-fixed.
    pub const VELOCITY_FRAME_NED: u8 = 1;
    /// FRD world-fixed, arbitrary heading.
    pub const VELOCITY_FRAME_FRD: u8 = 2;
    /// FRD body-fixed.
    pub const VELOCITY_FRAME_BODY_FRD: u8 = 3;
}

/// `px4_msgs/msg/VehicleStatus`: what commander says of the vehicle.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize, Default)]
#[allow(missing_docs)] // PX4's own field names; the ones skyground reads are documented.
pub struct VehicleStatus {
    /// Time since PX4's start (µs).
    pub timestamp: u64,
    pub armed_time: u64,
    pub takeoff_time: u64,
    /// `ARMING_STATE_*`.
    pub arming_state: u8,
    pub latest_arming_reason: u8,
    pub latest_disarming_reason: u8,
    pub nav_state_timestamp: u64,
    pub nav_state_user_intention: u8,
    /// The active mode (`NAVIGATION_STATE_*`).
    pub nav_state: u8,
    pub executor_in_charge: u8,
    pub valid_nav_states_mask: u32,
    pub can_set_nav_states_mask: u32,
    pub failure_detector_status: u16,
    pub hil_state: u8,
    pub vehicle_type: u8,
    pub failsafe: bool,
    pub failsafe_and_user_took_over: bool,
    pub failsafe_defer_state: u8,
    pub gcs_connection_lost: bool,
    pub gcs_connection_lost_counter: u8,
    pub high_latency_data_link_lost: bool,
    pub is_vtol: bool,
    pub is_vtol_tailsitter: bool,
    pub in_transition_mode: bool,
    pub in_transition_to_fw: bool,
    pub system_type: u8,
    pub system_id: u8,
    pub component_id: u8,
    pub safety_button_available: bool,
    pub safety_off: bool,
    pub power_input_valid: bool,
    pub usb_connected: bool,
    pub open_drone_id_system_present: bool,
    pub open_drone_id_system_healthy: bool,
    pub parachute_system_present: bool,
    pub parachute_system_healthy: bool,
    pub avoidance_system_required: bool,
    pub avoidance_system_valid: bool,
    pub rc_calibration_in_progress: bool,
    pub calibration_enabled: bool,
    pub pre_flight_checks_pass: bool,
}

impl VehicleStatus {
    /// Disarmed.
    pub const ARMING_STATE_DISARMED: u8 = 1;
    /// Armed.
    pub const ARMING_STATE_ARMED: u8 = 2;
    /// Auto loiter (hold).
    pub const NAVIGATION_STATE_AUTO_LOITER: u8 = 4;
    /// Offboard.
    pub const NAVIGATION_STATE_OFFBOARD: u8 = 14;
    /// Auto land.
    pub const NAVIGATION_STATE_AUTO_LAND: u8 = 18;
}

ros_message!(
    TrajectorySetpoint,
    "px4_msgs/msg/TrajectorySetpoint",
    [],
    [
        "uint64 timestamp",
        "float32[3] position",
        "float32[3] velocity",
        "float32[3] acceleration",
        "float32[3] jerk",
        "float32 yaw",
        "float32 yawspeed",
    ]
);
ros_message!(
    OffboardControlMode,
    "px4_msgs/msg/OffboardControlMode",
    [],
    [
        "uint64 timestamp",
        "bool position",
        "bool velocity",
        "bool acceleration",
        "bool attitude",
        "bool body_rate",
        "bool thrust_and_torque",
        "bool direct_actuator",
    ]
);
ros_message!(
    VehicleCommand,
    "px4_msgs/msg/VehicleCommand",
    [],
    [
        "uint64 timestamp",
        "float32 param1",
        "float32 param2",
        "float32 param3",
        "float32 param4",
        "float64 param5",
        "float64 param6",
        "float32 param7",
        "uint32 command",
        "uint8 target_system",
        "uint8 target_component",
        "uint8 source_system",
        "uint16 source_component",
        "uint8 confirmation",
        "bool from_external",
    ]
);
ros_message!(
    VehicleOdometry,
    "px4_msgs/msg/VehicleOdometry",
    [],
    [
        "uint64 timestamp",
        "uint64 timestamp_sample",
        "uint8 pose_frame",
        "float32[3] position",
        "float32[4] q",
        "uint8 velocity_frame",
        "float32[3] velocity",
        "float32[3] angular_velocity",
        "float32[3] position_variance",
        "float32[3] orientation_variance",
        "float32[3] velocity_variance",
        "uint8 reset_counter",
        "int8 quality",
    ]
);
ros_message!(
    VehicleStatus,
    "px4_msgs/msg/VehicleStatus",
    [],
    [
        "uint64 timestamp",
        "uint64 armed_time",
        "uint64 takeoff_time",
        "uint8 arming_state",
        "uint8 latest_arming_reason",
        "uint8 latest_disarming_reason",
        "uint64 nav_state_timestamp",
        "uint8 nav_state_user_intention",
        "uint8 nav_state",
        "uint8 executor_in_charge",
        "uint32 valid_nav_states_mask",
        "uint32 can_set_nav_states_mask",
        "uint16 failure_detector_status",
        "uint8 hil_state",
        "uint8 vehicle_type",
        "bool failsafe",
        "bool failsafe_and_user_took_over",
        "uint8 failsafe_defer_state",
        "bool gcs_connection_lost",
        "uint8 gcs_connection_lost_counter",
        "bool high_latency_data_link_lost",
        "bool is_vtol",
        "bool is_vtol_tailsitter",
        "bool in_transition_mode",
        "bool in_transition_to_fw",
        "uint8 system_type",
        "uint8 system_id",
        "uint8 component_id",
        "bool safety_button_available",
        "bool safety_off",
        "bool power_input_valid",
        "bool usb_connected",
        "bool open_drone_id_system_present",
        "bool open_drone_id_system_healthy",
        "bool parachute_system_present",
        "bool parachute_system_healthy",
        "bool avoidance_system_required",
        "bool avoidance_system_valid",
        "bool rc_calibration_in_progress",
        "bool calibration_enabled",
        "bool pre_flight_checks_pass",
    ]
);

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{from_cdr, to_cdr};

    /// Round trip, and the length PX4's rosidl layout gives (4-byte
    /// encapsulation header + fields with CDR alignment, counted by hand from
    /// the .msg): a field out of order or of the wrong width changes it.
    fn round_trip<M>(m: &M, len: usize) -> Vec<u8>
    where
        M: Serialize + serde::de::DeserializeOwned + PartialEq + std::fmt::Debug,
    {
        let bytes = to_cdr(m).unwrap();
        assert_eq!(bytes.len(), len, "{m:?}");
        assert_eq!(&from_cdr::<M>(&bytes).unwrap(), m);
        assert!(
            from_cdr::<M>(&bytes[..len - 1]).is_err(),
            "a cut message must not decode"
        );
        bytes
    }

    #[test]
    fn trajectory_setpoint_round_trips_in_px4_layout() {
        let m = TrajectorySetpoint {
            timestamp: 1_234_567,
            position: [1.0, -2.0, -10.0],
            velocity: [0.5; 3],
            acceleration: [0.0; 3],
            jerk: [0.0; 3],
            yaw: 1.5,
            yawspeed: -0.25,
        };
        let b = round_trip(&m, 4 + 8 + 4 * 12 + 4 + 4);
        // yaw sits right after the four vectors.
        assert_eq!(&b[4 + 8 + 48..4 + 8 + 52], &1.5f32.to_le_bytes());
    }

    #[test]
    fn offboard_control_mode_round_trips_in_px4_layout() {
        let m = OffboardControlMode {
            timestamp: 9,
            position: true,
            ..OffboardControlMode::default()
        };
        let b = round_trip(&m, 4 + 8 + 7);
        assert_eq!(&b[12..19], &[1, 0, 0, 0, 0, 0, 0]);
    }

    #[test]
    fn vehicle_command_round_trips_in_px4_layout() {
        let m = VehicleCommand {
            timestamp: 5,
            param1: 1.0,
            param2: 6.0,
            param5: 47.5,
            command: VehicleCommand::VEHICLE_CMD_DO_SET_MODE,
            target_system: 1,
            target_component: 1,
            source_system: 1,
            source_component: 1000,
            from_external: true,
            ..VehicleCommand::default()
        };
        // param5 aligned to 8 at 24; source_component (u16) aligned to 2 at 52.
        let b = round_trip(&m, 4 + 56);
        assert_eq!(&b[4 + 24..4 + 32], &47.5f64.to_le_bytes());
        assert_eq!(&b[4 + 44..4 + 48], &176u32.to_le_bytes());
        assert_eq!(&b[4 + 52..4 + 54], &1000u16.to_le_bytes());
    }

    #[test]
    fn vehicle_odometry_round_trips_in_px4_layout() {
        let m = VehicleOdometry {
            timestamp: 1,
            timestamp_sample: 2,
            pose_frame: VehicleOdometry::POSE_FRAME_NED,
            position: [3.0, 4.0, -5.0],
            q: [1.0, 0.0, 0.0, 0.0],
            velocity_frame: VehicleOdometry::VELOCITY_FRAME_NED,
            velocity: [0.1, 0.2, 0.3],
            angular_velocity: [0.0; 3],
            position_variance: [0.01; 3],
            orientation_variance: [0.02; 3],
            velocity_variance: [0.03; 3],
            reset_counter: 7,
            quality: -1,
        };
        // position aligned to 4 at 20 after the one-byte pose_frame.
        let b = round_trip(&m, 4 + 114);
        assert_eq!(b[4 + 16], 1);
        assert_eq!(&b[4 + 20..4 + 24], &3.0f32.to_le_bytes());
        assert_eq!(&b[4 + 112..4 + 114], &[7, 0xff]);
    }

    #[test]
    fn vehicle_status_round_trips_in_px4_layout() {
        let m = VehicleStatus {
            timestamp: 10,
            arming_state: VehicleStatus::ARMING_STATE_ARMED,
            nav_state: VehicleStatus::NAVIGATION_STATE_OFFBOARD,
            valid_nav_states_mask: 0xdead_beef,
            failure_detector_status: 3,
            pre_flight_checks_pass: true,
            ..VehicleStatus::default()
        };
        let b = round_trip(&m, 4 + 82);
        assert_eq!(b[4 + 24], 2);
        assert_eq!(b[4 + 41], 14);
        assert_eq!(&b[4 + 44..4 + 48], &0xdead_beefu32.to_le_bytes());
        assert_eq!(b[4 + 81], 1);
    }
}
