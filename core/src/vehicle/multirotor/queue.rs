//! A drone working through its sorties: each begins on the home pad with a
//! fresh battery, the next when it has landed there.

use std::collections::VecDeque;

use super::body::SceneBody;
use super::flight::{FlightStep, Multirotor};

/// The sorties still to fly, and how many were begun.
#[derive(Debug, Clone, Default)]
pub struct SortieQueue {
    queue: VecDeque<Vec<[f32; 3]>>,
    /// Sorties taken from the queue.
    pub begun: u32,
    /// Sorties cut short: a way-point blocked, the rest given up, home at
    /// the transit height.
    pub cut: u32,
    /// Height to come home at when a sortie is cut short (over the scene's top).
    pub transit_z: f32,
}

impl SortieQueue {
    /// No sorties yet; a sortie cut short comes home at `transit_z`.
    pub fn new(transit_z: f32) -> Self {
        Self {
            transit_z,
            ..Self::default()
        }
    }

    /// Adds a path of sorties, home to home, cut at each return home (a
    /// path from the sortie planner or from /uav/global_path).
    pub fn push_path(&mut self, home: [f32; 3], path: &[[f32; 3]], tolerance: f32) {
        let at_home = |p: &[f32; 3]| {
            (0..3).map(|k| (p[k] - home[k]).powi(2)).sum::<f32>() <= tolerance * tolerance
        };
        let mut current = Vec::new();
        for p in path {
            if current.is_empty() && at_home(p) {
                continue;
            }
            current.push(*p);
            if at_home(p) {
                self.queue.push_back(std::mem::take(&mut current));
            }
        }
        if !current.is_empty() {
            self.queue.push_back(current);
        }
    }

    /// Sorties not begun yet.
    pub fn waiting(&self) -> usize {
        self.queue.len()
    }

    /// Advances `m` by `dt`: on the pad with nothing to do, it takes the
    /// next sortie with a fresh battery; a way-point blocked by what the
    /// prior did not show cuts the sortie short: straight up to
    /// `transit_z`, over to home, down (as a drone's return-to-home does).
    pub fn step(&mut self, m: &mut Multirotor, dt: f32, body: &SceneBody) -> FlightStep {
        if m.goal().is_none()
            && m.on_pad()
            && let Some(next) = self.queue.pop_front()
        {
            m.swap_battery();
            m.set_path(next);
            self.begun += 1;
        }
        let step = m.step(dt, body);
        if matches!(step, FlightStep::Blocked { .. }) && m.state.airborne {
            let [x, y, z] = m.state.position;
            let top = self.transit_z.max(z);
            let h = m.home;
            m.set_path([[x, y, top], [h[0], h[1], top], h]);
            self.cut += 1;
        }
        step
    }

    /// Whether every sortie is flown (or the drone is stuck away from home).
    pub fn done(&self, m: &Multirotor) -> bool {
        m.goal().is_none() && (self.queue.is_empty() || !m.on_pad())
    }
}
