//! skyground's frames (ROS REP 103/105: map ENU, body FLU) against PX4's
//! (world NED with its origin where PX4's estimator started, body FRD).
//!
//! The NED origin is PX4's home; `origin` is where that point lies in the map
//! (a parameter: where the drone took off). Vectors swap x and y and negate z
//! between ENU and NED; bodies negate y and z between FLU and FRD.
//! Quaternions are PX4's `[w, x, y, z]`, body → world.

use std::f64::consts::{FRAC_PI_2, PI};

use nalgebra::{Matrix3, Quaternion, Rotation3, UnitQuaternion, Vector3};

/// A world vector (a position difference or a velocity) ENU → NED.
pub fn enu_to_ned_vec(v: [f64; 3]) -> [f64; 3] {
    [v[1], v[0], -v[2]]
}

/// A world vector NED → ENU (the same swap: it is its own inverse).
pub fn ned_to_enu_vec(v: [f64; 3]) -> [f64; 3] {
    [v[1], v[0], -v[2]]
}

/// A map position → PX4 local NED, the NED origin lying at `origin` in the map.
pub fn map_to_ned(p: [f64; 3], origin: [f64; 3]) -> [f64; 3] {
    enu_to_ned_vec([p[0] - origin[0], p[1] - origin[1], p[2] - origin[2]])
}

/// A PX4 local NED position → the map, the NED origin lying at `origin`.
pub fn ned_to_map(p: [f64; 3], origin: [f64; 3]) -> [f64; 3] {
    let d = ned_to_enu_vec(p);
    [origin[0] + d[0], origin[1] + d[1], origin[2] + d[2]]
}

/// A body vector FLU → FRD (and back: its own inverse).
pub fn flu_to_frd(v: [f64; 3]) -> [f64; 3] {
    [v[0], -v[1], -v[2]]
}

/// A heading in ENU (from east, counter-clockwise) → PX4's NED yaw (from
/// north, clockwise), wrapped to (−π, π]; the same formula both ways.
pub fn enu_to_ned_yaw(yaw: f64) -> f64 {
    wrap(FRAC_PI_2 - yaw)
}

/// PX4's NED yaw → the ENU heading, wrapped to (−π, π].
pub fn ned_to_enu_yaw(yaw: f64) -> f64 {
    wrap(FRAC_PI_2 - yaw)
}

/// An angle in (−π, π].
pub fn wrap(a: f64) -> f64 {
    let w = a.rem_euclid(2.0 * PI);
    if w > PI { w - 2.0 * PI } else { w }
}

/// The rotation taking NED world vectors to ENU ones (a reflection-free swap).
fn enu_from_ned() -> UnitQuaternion<f64> {
    let m = Matrix3::new(0.0, 1.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, -1.0);
    UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(m))
}

/// The rotation taking FLU body vectors to FRD ones (π about x).
fn frd_from_flu() -> UnitQuaternion<f64> {
    UnitQuaternion::from_axis_angle(&Vector3::x_axis(), PI)
}

fn unit(q: [f64; 4]) -> UnitQuaternion<f64> {
    UnitQuaternion::from_quaternion(Quaternion::new(q[0], q[1], q[2], q[3]))
}

fn wxyz(q: UnitQuaternion<f64>) -> [f64; 4] {
    [q.w, q.i, q.j, q.k]
}

/// PX4's attitude (body FRD → NED, `[w, x, y, z]`) → ROS's (body FLU → ENU).
pub fn ned_frd_to_enu_flu(q: [f64; 4]) -> [f64; 4] {
    wxyz(enu_from_ned() * unit(q) * frd_from_flu())
}

/// ROS's attitude (body FLU → ENU, `[w, x, y, z]`) → PX4's (body FRD → NED).
pub fn enu_flu_to_ned_frd(q: [f64; 4]) -> [f64; 4] {
    wxyz(enu_from_ned().inverse() * unit(q) * frd_from_flu().inverse())
}

/// Rotates a world vector into the body of attitude `q` (body → world, `[w, x, y, z]`).
pub fn world_to_body(q: [f64; 4], v: [f64; 3]) -> [f64; 3] {
    let b = unit(q).inverse_transform_vector(&Vector3::from(v));
    [b.x, b.y, b.z]
}

/// Rotates a body vector into the world by attitude `q` (body → world).
pub fn body_to_world(q: [f64; 4], v: [f64; 3]) -> [f64; 3] {
    let w = unit(q).transform_vector(&Vector3::from(v));
    [w.x, w.y, w.z]
}

/// The heading (yaw about world z) of attitude `q` (body → world).
pub fn yaw_of(q: [f64; 4]) -> f64 {
    unit(q).euler_angles().2
}

/// Attitude with roll and pitch zero and heading `yaw` (rad about world z).
pub fn from_yaw(yaw: f64) -> [f64; 4] {
    wxyz(UnitQuaternion::from_euler_angles(0.0, 0.0, yaw))
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn close(a: &[f64], b: &[f64], tol: f64) -> bool {
        a.iter().zip(b).all(|(x, y)| (x - y).abs() <= tol)
    }

    /// q and −q are the same attitude.
    fn same_attitude(a: [f64; 4], b: [f64; 4]) -> bool {
        let dot: f64 = a.iter().zip(&b).map(|(x, y)| x * y).sum();
        (dot.abs() - 1.0).abs() < 1e-9
    }

    fn angle_close(a: f64, b: f64) -> bool {
        wrap(a - b).abs() < 1e-9
    }

    #[test]
    fn known_points_and_headings() {
        let origin = [100.0, 200.0, 5.0];
        // 3 m north, 4 m east, 10 m up of home.
        assert_eq!(map_to_ned([104.0, 203.0, 15.0], origin), [3.0, 4.0, -10.0]);
        assert_eq!(ned_to_map([3.0, 4.0, -10.0], origin), [104.0, 203.0, 15.0]);
        // Facing north: ENU yaw π/2, NED yaw 0; facing east: ENU 0, NED π/2.
        assert!(angle_close(enu_to_ned_yaw(FRAC_PI_2), 0.0));
        assert!(angle_close(ned_to_enu_yaw(FRAC_PI_2), 0.0));
        assert!(angle_close(ned_to_enu_yaw(PI), -FRAC_PI_2), "south");
        // PX4 level, facing north: identity in NED/FRD.
        let q = ned_frd_to_enu_flu([1.0, 0.0, 0.0, 0.0]);
        assert!(angle_close(yaw_of(q), FRAC_PI_2), "{q:?}");
        // Its nose (FLU x) points north (ENU y), its left (FLU y) west, up is up.
        assert!(close(
            &body_to_world(q, [1.0, 0.0, 0.0]),
            &[0.0, 1.0, 0.0],
            1e-12
        ));
        assert!(close(
            &body_to_world(q, [0.0, 1.0, 0.0]),
            &[-1.0, 0.0, 0.0],
            1e-12
        ));
        assert!(close(
            &body_to_world(q, [0.0, 0.0, 1.0]),
            &[0.0, 0.0, 1.0],
            1e-12
        ));
    }

    proptest! {
        #[test]
        fn positions_round_trip(p in prop::array::uniform3(-1e4f64..1e4), o in prop::array::uniform3(-1e4f64..1e4)) {
            prop_assert!(close(&ned_to_map(map_to_ned(p, o), o), &p, 1e-9));
            prop_assert!(close(&map_to_ned(ned_to_map(p, o), o), &p, 1e-9));
        }

        #[test]
        fn vectors_round_trip_and_keep_length(v in prop::array::uniform3(-100f64..100.0)) {
            prop_assert_eq!(ned_to_enu_vec(enu_to_ned_vec(v)), v);
            prop_assert_eq!(flu_to_frd(flu_to_frd(v)), v);
            let n = enu_to_ned_vec(v);
            prop_assert!((n[0].hypot(n[1]).hypot(n[2]) - v[0].hypot(v[1]).hypot(v[2])).abs() < 1e-9);
        }

        #[test]
        fn yaws_round_trip(y in -PI..PI) {
            prop_assert!(angle_close(ned_to_enu_yaw(enu_to_ned_yaw(y)), y));
            let w = enu_to_ned_yaw(y);
            prop_assert!(w > -PI - 1e-12 && w <= PI + 1e-12);
        }

        #[test]
        fn attitudes_round_trip_and_agree_with_the_yaw_formula(
            roll in -1.0f64..1.0, pitch in -1.0f64..1.0, yaw in -PI..PI,
            v in prop::array::uniform3(-10f64..10.0),
        ) {
            let ned = wxyz(UnitQuaternion::from_euler_angles(roll, pitch, yaw));
            let enu = ned_frd_to_enu_flu(ned);
            prop_assert!(same_attitude(enu_flu_to_ned_frd(enu), ned));
            // A level attitude's heading follows yaw = π/2 − yaw.
            let level = ned_frd_to_enu_flu(from_yaw(yaw));
            prop_assert!(angle_close(yaw_of(level), ned_to_enu_yaw(yaw)));
            // One body vector, said in FLU or FRD, lands on one world vector.
            let w_enu = body_to_world(enu, v);
            let w_ned = body_to_world(ned, flu_to_frd(v));
            prop_assert!(close(&ned_to_enu_vec(w_ned), &w_enu, 1e-9));
            // And back into the body.
            prop_assert!(close(&world_to_body(enu, w_enu), &v, 1e-9));
        }
    }
}
