//! A spinning multi-beam LiDAR on a ground vehicle (VLP-16-like by default).

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use super::bvh::PACKET;
use super::caster::Caster;
use super::intensity::return_intensity;
use super::pose::{Pose, rotate};
use super::ray::{Hit, Ray, dot};
use crate::cloud::Cloud;
use crate::params::{Checks, ParamError};
use crate::rng::{Rng, combine};

/// Spinning LiDAR parameters; every field has a default (a Velodyne VLP-16
/// at 10 Hz), so a config file names only what differs.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct LidarConfig {
    /// Number of beams (rings), evenly spread over the vertical field of view.
    pub beams: u32,
    /// Elevation of the lowest beam, degrees (negative: below horizontal).
    pub fov_min_deg: f32,
    /// Elevation of the highest beam, degrees.
    pub fov_max_deg: f32,
    /// Horizontal angle between firings, degrees (0.2 at 10 Hz for a VLP-16).
    pub azimuth_step_deg: f32,
    /// Farthest return, metres; longer ranges give no point.
    pub max_range: f32,
    /// Nearest return, metres; closer ones (e.g. the vehicle itself) are dropped.
    pub min_range: f32,
    /// Revolutions per second; sets each point's time stamp.
    pub rate_hz: f32,
    /// Standard deviation of the range error along the beam, metres
    /// (Gaussian, truncated at 4σ).
    pub range_noise_sigma: f32,
    /// Probability that a return is lost, 0–1.
    pub dropout: f32,
    /// Base seed of the noise; combined with each scan's own seed.
    pub seed: u64,
}

impl Default for LidarConfig {
    fn default() -> Self {
        Self {
            beams: 16,
            fov_min_deg: -15.0,
            fov_max_deg: 15.0,
            azimuth_step_deg: 0.2,
            max_range: 100.0,
            min_range: 0.5,
            rate_hz: 10.0,
            range_noise_sigma: 0.02,
            dropout: 0.0,
            seed: 0,
        }
    }
}

impl LidarConfig {
    /// Checks every field's range.
    pub fn validate(&self) -> Result<(), ParamError> {
        let c = Checks("LiDAR");
        c.within("beams", self.beams, 1, 1024)?;
        let fov_ok = (-90.0..=90.0).contains(&self.fov_min_deg)
            && (-90.0..=90.0).contains(&self.fov_max_deg)
            && self.fov_min_deg <= self.fov_max_deg;
        c.that(
            fov_ok,
            "fov_max_deg",
            self.fov_max_deg,
            "fov_min_deg ≤ fov_max_deg, both within ±90",
        )?;
        c.within("azimuth_step_deg", self.azimuth_step_deg, 0.001, 360.0)?;
        c.positive("max_range", self.max_range)?;
        c.that(
            self.min_range >= 0.0 && self.min_range < self.max_range,
            "min_range",
            self.min_range,
            "must be ≥ 0 and < max_range",
        )?;
        c.positive("rate_hz", self.rate_hz)?;
        c.non_negative("range_noise_sigma", self.range_noise_sigma)?;
        c.within("dropout", self.dropout, 0.0, 1.0)
    }

    /// Firings per revolution (columns of the range image).
    pub fn columns(&self) -> usize {
        ((360.0 / self.azimuth_step_deg).round() as usize).max(1)
    }

    /// Elevation of beam `ring`, radians (ring 0 lowest).
    pub fn elevation(&self, ring: u32) -> f32 {
        let frac = if self.beams > 1 {
            ring as f32 / (self.beams - 1) as f32
        } else {
            0.0
        };
        (self.fov_min_deg + frac * (self.fov_max_deg - self.fov_min_deg)).to_radians()
    }
}

/// One revolution's returns, one entry per point in every column.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ScanPoints {
    /// Positions in the map frame, metres.
    pub xyz: Vec<[f32; 3]>,
    /// Measured range (with noise), metres.
    pub range: Vec<f32>,
    /// Return intensity, 0–65535 (reflectance × |cos incidence|).
    pub intensity: Vec<f32>,
    /// LAS class of the object hit (2 ground, 5 vegetation, 6 building).
    pub label: Vec<u8>,
    /// Building id of the object hit (0 = not a building).
    pub building: Vec<u32>,
    /// Beam index, 0 = lowest.
    pub ring: Vec<u16>,
    /// Seconds after the start of the revolution.
    pub time: Vec<f32>,
}

impl ScanPoints {
    /// Number of points.
    pub fn len(&self) -> usize {
        self.xyz.len()
    }

    /// True when nothing was hit.
    pub fn is_empty(&self) -> bool {
        self.xyz.is_empty()
    }

    /// The points as a [`Cloud`] (xyz, intensity, label, building) with `origin`.
    pub fn to_cloud(&self, origin: [f64; 3]) -> Cloud {
        Cloud {
            xyz: self.xyz.clone(),
            intensity: Some(self.intensity.clone()),
            label: Some(self.label.clone()),
            building: Some(self.building.clone()),
            return_number: None,
            number_of_returns: None,
            origin,
            crs: None,
        }
    }
}

/// One return before it is stored.
struct Return {
    xyz: [f32; 3],
    range: f32,
    intensity: f32,
    label: u8,
    building: u32,
}

/// Scans one full revolution from `pose`: firing columns counter-clockwise
/// from the sensor's +x axis, all beams per column. Noise and dropout are
/// drawn from `(config.seed, rng_seed, ray index)`, so the same inputs give
/// the same points on any number of threads; give every scan its own
/// `rng_seed` (e.g. its sequence number).
pub fn scan(
    caster: &Caster,
    config: &LidarConfig,
    pose: &Pose,
    rng_seed: u64,
) -> Result<ScanPoints, ParamError> {
    config.validate()?;
    let beams = config.beams as usize;
    let rays = revolution_rays(config, pose);
    let seed = combine(config.seed, rng_seed);
    let sigma = config.range_noise_sigma;
    let fire = |(i, (ray, hit)): (usize, (&Ray, Option<Hit>))| -> Option<Return> {
        let hit = hit?;
        let mut rng = Rng::keyed(seed, i as u64);
        if config.dropout > 0.0 && rng.unit() < f64::from(config.dropout) {
            return None;
        }
        let range = if sigma > 0.0 {
            hit.t + sigma * rng.normal_truncated_f32(4.0)
        } else {
            hit.t
        };
        if !(config.min_range..=config.max_range).contains(&range) {
            return None;
        }
        let object = caster.object(hit.object)?;
        let (p, dir) = (ray.origin, ray.dir);
        Some(Return {
            xyz: std::array::from_fn(|k| p[k] + range * dir[k]),
            range,
            intensity: return_intensity(object.kind, dot(hit.normal, dir)),
            label: object.kind.las_class(),
            building: object.building,
        })
    };
    let hits = cast_revolution(caster, config, &rays);
    let returns: Vec<Option<Return>> = rays
        .par_iter()
        .zip(hits)
        .enumerate()
        .with_min_len(512)
        .map(fire)
        .collect();
    let mut out = ScanPoints::default();
    let dt = 1.0 / (config.rate_hz * config.columns() as f32);
    for (i, r) in returns.into_iter().enumerate() {
        let Some(r) = r else { continue };
        out.xyz.push(r.xyz);
        out.range.push(r.range);
        out.intensity.push(r.intensity);
        out.label.push(r.label);
        out.building.push(r.building);
        // At most 1024 beams, checked by validate().
        out.ring.push((i % beams) as u16);
        out.time.push((i / beams) as f32 * dt);
    }
    Ok(out)
}

/// The rays of one revolution from `pose`, column by column (counter-clockwise
/// from the sensor's +x axis), beams bottom to top within a column; unit
/// directions, `max_t` = `config.max_range`. Call on a validated config.
pub fn revolution_rays(config: &LidarConfig, pose: &Pose) -> Vec<Ray> {
    let rot = pose.rotation();
    let elevations: Vec<(f32, f32)> = (0..config.beams)
        .map(|r| config.elevation(r).sin_cos())
        .collect();
    let step = config.azimuth_step_deg.to_radians();
    let columns = config.columns();
    let mut rays = Vec::with_capacity(columns * elevations.len());
    for col in 0..columns {
        let (sa, ca) = (col as f32 * step).sin_cos();
        for &(se, ce) in &elevations {
            let dir = rotate(&rot, [ce * ca, ce * sa, se]);
            rays.push(Ray::new(pose.position, dir, config.max_range));
        }
    }
    rays
}

/// Columns of one packet block: 16 columns × 4 beams = 64 rays, 3.2° × 6°
/// of a VLP-16 revolution, the most compact block of its range image.
const BLOCK_COLUMNS: usize = 32;
/// Beams of one packet block.
const BLOCK_BEAMS: usize = 2;

/// Casts one revolution's rays (`rays` as [`revolution_rays`] makes them for
/// `config`) in coherent packets of [`BLOCK_COLUMNS`] × [`BLOCK_BEAMS`]
/// rays; result `i` belongs to `rays[i]`, the same hit as
/// [`Caster::cast_ray`] gives.
pub fn cast_revolution(caster: &Caster, config: &LidarConfig, rays: &[Ray]) -> Vec<Option<Hit>> {
    cast_blocks(caster, config, rays, BLOCK_COLUMNS, BLOCK_BEAMS)
}

/// [`cast_revolution`] with blocks of `block_columns` × `block_beams` rays
/// (at most [`PACKET`] in all).
pub(crate) fn cast_blocks(
    caster: &Caster,
    config: &LidarConfig,
    rays: &[Ray],
    block_columns: usize,
    block_beams: usize,
) -> Vec<Option<Hit>> {
    let beams = config.beams as usize;
    if rays.len() != config.columns() * beams {
        return caster.cast_many(rays);
    }
    let block_columns = block_columns.clamp(1, PACKET);
    let block_beams = block_beams.clamp(1, PACKET / block_columns);
    let mut out = vec![None; rays.len()];
    // A run of whole columns is contiguous in both slices: each task takes
    // one and casts it block by block.
    let span = block_columns * beams;
    out.par_chunks_mut(span)
        .zip(rays.par_chunks(span))
        .for_each(|(out, rays)| {
            let columns = rays.len() / beams;
            let mut packet = [Ray::new([0.0; 3], [0.0; 3], 0.0); PACKET];
            let mut found = [None; PACKET];
            let mut index = [0usize; PACKET];
            for b0 in (0..beams).step_by(block_beams) {
                // Beam by beam, so neighbouring rays are neighbouring columns.
                let mut n = 0;
                for b in b0..(b0 + block_beams).min(beams) {
                    for c in 0..columns {
                        index[n] = c * beams + b;
                        packet[n] = rays[index[n]];
                        n += 1;
                    }
                }
                caster.cast_packet(&packet[..n], &mut found[..n]);
                for (&i, hit) in index[..n].iter().zip(&found[..n]) {
                    out[i] = *hit;
                }
            }
        });
    out
}
