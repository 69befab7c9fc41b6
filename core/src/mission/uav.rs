//! The drone's statuses: `/uav/planner_status` (what the sortie planner
//! gave it: gaps, viewpoints, sorties) and `/uav/flight_status` (how far
//! it got: sorties flown, flight time, distance, closest approach to the
//! scene). Typed, read and written only here.

use super::protocol::{OK, ProtocolError, WARN, Wire};

/// What the sortie planner made of a detection's gaps.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct UavPlan {
    /// Gaps in the detection.
    pub gaps: u32,
    /// Of those, the drone's: no ground stop sees them.
    pub drone_gaps: u32,
    /// Drone gaps a kept viewpoint sees.
    pub seen: u32,
    /// Viewpoints kept.
    pub viewpoints: u32,
    /// Sorties planned.
    pub sorties: u32,
    /// Viewpoints no sortie reaches.
    pub unreachable: u32,
    /// Planned flight time, s (every sortie).
    pub flight_s: f64,
    /// Why no plan was made ("" when one was).
    pub refused: String,
}

impl UavPlan {
    /// As it goes on the wire.
    pub fn to_wire(&self) -> Wire {
        let mut w = if self.refused.is_empty() {
            Wire::new(OK, "uav_planner", "planned")
        } else {
            Wire::new(WARN, "uav_planner", format!("refused: {}", self.refused))
        };
        w.put("gaps", self.gaps);
        w.put("drone_gaps", self.drone_gaps);
        w.put("seen", self.seen);
        w.put("viewpoints", self.viewpoints);
        w.put("sorties", self.sorties);
        w.put("unreachable", self.unreachable);
        w.put("flight_s", self.flight_s);
        w
    }

    /// Read from the wire.
    pub fn from_wire(w: &Wire) -> Result<Self, ProtocolError> {
        let refused = match w.message.strip_prefix("refused: ") {
            Some(r) => r.to_string(),
            None if w.message == "planned" => String::new(),
            None => {
                return Err(ProtocolError::State {
                    name: w.name.clone(),
                    message: w.message.clone(),
                    expected: "planned, refused: REASON",
                });
            }
        };
        Ok(Self {
            gaps: w.get("gaps")?,
            drone_gaps: w.get("drone_gaps")?,
            seen: w.get("seen")?,
            viewpoints: w.get("viewpoints")?,
            sorties: w.get("sorties")?,
            unreachable: w.get("unreachable")?,
            flight_s: w.get("flight_s")?,
            refused,
        })
    }
}

/// Where the drone's work stands.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum UavState {
    /// No path yet.
    Waiting,
    /// Sorties to fly.
    Flying,
    /// Every sortie given is flown (or it cannot go on: landed away from home).
    Done,
}

impl UavState {
    fn word(self) -> &'static str {
        match self {
            UavState::Waiting => "waiting",
            UavState::Flying => "flying",
            UavState::Done => "done",
        }
    }
}

/// uav_sim's (or a bridge's) account of the flight.
#[derive(Debug, Clone, PartialEq)]
pub struct UavStatus {
    /// The node speaking.
    pub name: String,
    /// Waiting, flying or done.
    pub state: UavState,
    /// Sorties begun.
    pub sorties: u32,
    /// Sorties given and not begun.
    pub waiting: u32,
    /// Sorties cut short (a way-point blocked by what the prior did not show).
    pub cut: u32,
    /// Seconds in the air.
    pub flight_s: f64,
    /// Robot time, s (flying or waiting).
    pub time_s: f64,
    /// Metres flown.
    pub odometer_m: f64,
    /// The body centre's closest approach to the true scene, m (a
    /// simulator's check; NaN from a real drone).
    pub closest_m: f64,
}

impl UavStatus {
    /// As it goes on the wire.
    pub fn to_wire(&self) -> Wire {
        let mut w = Wire::new(OK, &self.name, self.state.word());
        w.put("sorties", self.sorties);
        w.put("waiting", self.waiting);
        w.put("cut", self.cut);
        w.put("flight_s", self.flight_s);
        w.put("time_s", self.time_s);
        w.put("odometer_m", self.odometer_m);
        w.put("closest_m", self.closest_m);
        w
    }

    /// Read from the wire.
    pub fn from_wire(w: &Wire) -> Result<Self, ProtocolError> {
        let state = [UavState::Waiting, UavState::Flying, UavState::Done]
            .into_iter()
            .find(|s| s.word() == w.message)
            .ok_or_else(|| ProtocolError::State {
                name: w.name.clone(),
                message: w.message.clone(),
                expected: "waiting, flying, done",
            })?;
        Ok(Self {
            name: w.name.clone(),
            state,
            sorties: w.get("sorties")?,
            waiting: w.get("waiting")?,
            cut: w.get("cut")?,
            flight_s: w.get("flight_s")?,
            time_s: w.get("time_s")?,
            odometer_m: w.get("odometer_m")?,
            closest_m: w.get("closest_m")?,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn both_statuses_read_back_as_written_and_a_foreign_state_is_an_error() {
        let plan = UavPlan {
            gaps: 900,
            drone_gaps: 120,
            seen: 118,
            viewpoints: 14,
            sorties: 2,
            unreachable: 1,
            flight_s: 640.5,
            refused: String::new(),
        };
        assert_eq!(UavPlan::from_wire(&plan.to_wire()), Ok(plan.clone()));
        let refused = UavPlan {
            refused: "no /classified_cloud".into(),
            ..plan
        };
        assert_eq!(UavPlan::from_wire(&refused.to_wire()), Ok(refused));
        let s = UavStatus {
            name: "uav_sim".into(),
            state: UavState::Flying,
            sorties: 1,
            waiting: 1,
            cut: 0,
            flight_s: 300.25,
            time_s: 310.5,
            odometer_m: 1200.0,
            closest_m: 3.5,
        };
        assert_eq!(UavStatus::from_wire(&s.to_wire()), Ok(s.clone()));
        let mut w = s.to_wire();
        w.message = "landed".into();
        assert!(matches!(
            UavStatus::from_wire(&w),
            Err(ProtocolError::State { .. })
        ));
    }
}
