//! What the vehicle asks of the scene: ground height, obstacles, insides.

use crate::lidar::{Caster, Ray};
use crate::scene::ObjectKind;

/// Terrain and obstacle queries against a scene's ray caster.
pub struct Terrain<'a> {
    caster: &'a Caster,
    top: f32,
}

impl<'a> Terrain<'a> {
    /// Queries against `caster`'s scene.
    pub fn new(caster: &'a Caster) -> Self {
        let top = caster.bounds().map_or(1000.0, |(_, hi)| hi[2] + 10.0);
        Self { caster, top }
    }

    fn kind(&self, object: u32) -> Option<ObjectKind> {
        self.caster.object(object).map(|o| o.kind)
    }

    /// Height of the ground (objects of kind Ground) under `(x, y)`, looking
    /// through roofs, floors and crowns; `None` off the terrain.
    pub fn ground_height(&self, x: f32, y: f32) -> Option<f32> {
        let mut z = self.top;
        // Each non-ground surface is stepped through; a scene has few layers.
        for _ in 0..64 {
            let hit = self
                .caster
                .cast([x, y, z], [0.0, 0.0, -1.0], z - self.bottom())?;
            let hz = z - hit.t;
            if self.kind(hit.object) == Some(ObjectKind::Ground) {
                return Some(hz);
            }
            z = hz - 1e-3;
        }
        None
    }

    fn bottom(&self) -> f32 {
        self.caster.bounds().map_or(-1000.0, |(lo, _)| lo[2] - 10.0)
    }

    /// The first non-ground obstacle the vehicle body would touch moving from
    /// `from` to `to` (both on the ground), as its distance along the move.
    pub fn obstacle(
        &self,
        from: [f32; 3],
        to: [f32; 3],
        radius: f32,
        body_height: f32,
    ) -> Option<f32> {
        let d = [to[0] - from[0], to[1] - from[1]];
        let len = (d[0] * d[0] + d[1] * d[1]).sqrt();
        if len <= 1e-6 {
            return None;
        }
        let dir = [d[0] / len, d[1] / len];
        let side = [-dir[1], dir[0]];
        let mut nearest: Option<f32> = None;
        // A fan of horizontal rays at three heights and three lateral offsets
        // stands in for the body's swept volume.
        for h in [0.3, 0.5 * body_height, body_height] {
            for s in [-radius, 0.0, radius] {
                let o = [from[0] + side[0] * s, from[1] + side[1] * s, from[2] + h];
                let ray = Ray::new(o, [dir[0], dir[1], (to[2] - from[2]) / len], len + radius);
                if let Some(hit) = self.caster.cast_ray(&ray)
                    && self.kind(hit.object) != Some(ObjectKind::Ground)
                {
                    let t = (hit.t - radius).max(0.0);
                    nearest = Some(nearest.map_or(t, |n: f32| n.min(t)));
                }
            }
        }
        nearest
    }
}

/// True when `(x, y)` at `z` lies inside a closed building: the first surface
/// straight up is a building face seen from behind (its normal points up,
/// along the ray), i.e. a roof or ceiling from the inside.
pub fn goal_inside_building(caster: &Caster, p: [f32; 3]) -> bool {
    let Some(hit) = caster.cast(p, [0.0, 0.0, 1.0], 10_000.0) else {
        return false;
    };
    caster
        .object(hit.object)
        .is_some_and(|o| o.kind == ObjectKind::Building)
        && hit.normal[2] > 0.0
}
