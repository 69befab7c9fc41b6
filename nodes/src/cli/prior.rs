//! `skyground demo --prior FILE.laz`: a real aerial survey as the mission's
//! prior, with the city model (`--scene`) as the world the vehicle drives
//! and scans in and the ground truth completeness is measured against.

use std::path::{Path, PathBuf};

use skyground_core::cloud::{Cloud, read_cloud};
use skyground_core::crs::Crs;
use skyground_core::graph::{GraphParams, GroundGraph};
use skyground_core::lidar::Caster;
use skyground_core::prior::{
    CrsCheck, check_crs, extent_xy, join_tiles, mission_window, overlap, to_frame,
};
use skyground_core::scene::{Cropped, Scene, Window};
use skyground_core::vehicle::free_spot;

use super::aerial::{Survey, survey_of_real};
use super::crop::{CropArg, CropArgs};
use crate::runtime::RuntimeError;

/// The prior options of `skyground demo`.
#[derive(Debug, Clone, clap::Args)]
pub struct PriorArgs {
    /// A real aerial survey (LAS/LAZ/PLY) as the prior instead of the
    /// simulated one; repeat for several tiles (they load as one prior).
    /// Its horizontal CRS must be the city model's (--scene).
    #[arg(long = "prior")]
    pub files: Vec<PathBuf>,
    /// With --prior and without --crop: the city model is cropped to the
    /// prior's extent grown by this many metres.
    #[arg(long, default_value_t = 20.0)]
    pub prior_margin: f64,
}

impl PriorArgs {
    /// The prior's files as one line (for the log and the report).
    pub fn describe(&self) -> String {
        if self.files.is_empty() {
            "simulated airborne survey".into()
        } else {
            self.files
                .iter()
                .map(|f| f.display().to_string())
                .collect::<Vec<_>>()
                .join(" + ")
        }
    }
}

/// The mission's scene and its real prior: tiles read and joined, CRS and
/// overlap checked against the city model, the model cropped to the prior's
/// extent (unless `--crop` says otherwise), the prior moved into the scene's
/// local frame and measured against it.
pub(super) fn real_prior(
    a: &PriorArgs,
    (spec, crop, out): (&str, &CropArgs, &Path),
    full: Scene,
    model_crs: Option<&Crs>,
) -> Result<(String, Survey, Option<Cropped>), RuntimeError> {
    let err = |e: String| RuntimeError::Node(e);
    let mut tiles = Vec::new();
    for f in &a.files {
        let c = read_cloud(f).map_err(|e| err(format!("prior: {e}")))?;
        tiles.push((f.display().to_string(), c));
    }
    let mut cloud = join_tiles(&tiles).map_err(|e| err(format!("prior: {e}")))?;
    let check = check_crs(cloud.crs.as_ref(), model_crs)
        .map_err(|e| err(format!("prior {}: {e}", a.describe())))?;
    eprintln!(
        "  prior {}: {} points; {}",
        a.describe(),
        cloud.len(),
        crs_line(&check)
    );
    // A survey that names no CRS is taken to be in the model's, so what the
    // mission writes from it (aerial.las, resampled.las) names that CRS.
    if cloud.crs.is_none() {
        cloud.crs = model_crs.cloned();
    }
    let (lo, hi) = full
        .bounds()
        .ok_or_else(|| err(format!("scene {spec}: empty")))?;
    let model = Window::new(
        f64::from(lo[0]),
        f64::from(lo[1]),
        f64::from(hi[0]),
        f64::from(hi[1]),
    )
    .map_err(|e| err(format!("scene {spec}: {e}")))?;
    let in_model = to_frame(&cloud, full.origin);
    let extent =
        extent_xy(&in_model).ok_or_else(|| err(format!("prior {}: no extent", a.describe())))?;
    let shared = overlap(&extent, &model, full.origin)
        .map_err(|e| err(format!("prior {}: {e}", a.describe())))?;
    eprintln!(
        "  prior covers {:.0} m × {:.0} m of the city model ({:.0} % of the prior's extent)",
        shared.size()[0],
        shared.size()[1],
        100.0 * area(&shared) / area(&extent).max(1e-9)
    );
    let mut crop = crop.clone();
    if crop.crop.is_none() {
        let w = mission_window(&extent, a.prior_margin);
        eprintln!(
            "  cropping the city model to the prior's extent + {} m (--prior-margin; --crop none keeps the whole model)",
            a.prior_margin
        );
        crop.crop = Some(CropArg::Window(w));
    }
    eprintln!(
        "  ground graph: tree crowns block only where points stand in the vehicle's height band (a multi-return survey sees under them)"
    );
    let (spec, scene, crop) = super::crop::mission_scene((spec, &crop, out), full, model_crs)?;
    let prior = to_frame(&cloud, scene.origin);
    let survey = survey_of_real(scene, prior, &a.describe())?;
    Ok((spec, survey, crop))
}

/// Where the vehicle starts on a real prior: of free spots of the model on
/// a 4 × 4 grid over the prior's extent, the one whose ground graph (built
/// on the producer's classes, as the planner will on the classifier's) is
/// largest. A real survey's ground is cut by cars, kerbs, quays and canals
/// into hundreds of pieces (AHN3 Delft 1 + 2: 772), and the middle of the
/// model stood on one of 23 nodes.
pub fn start_on_prior(caster: &Caster, prior: &Cloud) -> Result<[f32; 2], RuntimeError> {
    let err = |e: String| RuntimeError::Node(e);
    let labels = prior
        .label
        .as_deref()
        .ok_or_else(|| err("the prior has no classes to find the ground to start on".into()))?;
    let extent = extent_xy(prior).ok_or_else(|| err("the prior is empty".into()))?;
    let params = GraphParams {
        canopy_is_obstacle: false,
        ..GraphParams::default()
    };
    let mut best: Option<([f32; 2], usize)> = None;
    for i in 0..4 {
        for j in 0..4 {
            let x = extent.min[0] + extent.size()[0] * (f64::from(i) + 0.5) / 4.0;
            let y = extent.min[1] + extent.size()[1] * (f64::from(j) + 0.5) / 4.0;
            let Some(s) = free_spot(caster, x as f32, y as f32, 2.0, 30.0) else {
                continue;
            };
            let z = prior_ground_z(prior, labels, s);
            let Ok(g) = GroundGraph::build(&prior.xyz, labels, [s[0], s[1], z], &params) else {
                continue;
            };
            let n = g.report().nodes;
            if best.is_none_or(|(_, m)| n > m) {
                best = Some((s, n));
            }
        }
    }
    let (s, n) =
        best.ok_or_else(|| err("no free spot on the prior's ground to start the vehicle".into()))?;
    eprintln!(
        "  vehicle starts at ({:.1}, {:.1}): its ground graph on the prior's classes has {n} nodes, the largest of 16 spots tried",
        s[0], s[1]
    );
    Ok(s)
}

/// The mean height of the prior's ground points within 3 m of `xy` (0 when none).
fn prior_ground_z(prior: &Cloud, labels: &[u8], xy: [f32; 2]) -> f32 {
    let (mut sum, mut n) = (0.0f64, 0usize);
    for (p, &l) in prior.xyz.iter().zip(labels) {
        if l == 2 && (p[0] - xy[0]).hypot(p[1] - xy[1]) < 3.0 {
            sum += f64::from(p[2]);
            n += 1;
        }
    }
    if n > 0 { (sum / n as f64) as f32 } else { 0.0 }
}

fn area(w: &Window) -> f64 {
    w.size()[0] * w.size()[1]
}

fn crs_line(check: &CrsCheck) -> String {
    match check {
        CrsCheck::Same(h) => format!("horizontal CRS EPSG:{h}, the city model's"),
        CrsCheck::Unchecked => "CRSs named without comparable EPSG codes: taken as equal".into(),
        CrsCheck::PriorUnknown(Some(m)) => {
            format!(
                "the prior states no CRS: taken to be the city model's {m} (the overlap check below guards against a wrong guess)"
            )
        }
        CrsCheck::PriorUnknown(None) => {
            "neither the prior nor the city model states a CRS: taken as the same".into()
        }
        CrsCheck::ModelUnknown(p) => {
            format!("the city model states no CRS: taken to be the prior's {p}")
        }
    }
}
