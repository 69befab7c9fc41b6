//! `skyground demo --prior FILE.laz`: a real aerial survey as the mission's
//! prior, with the city model (`--scene`) as the world the vehicle drives
//! and scans in and the ground truth completeness is measured against.

use std::path::{Path, PathBuf};

use skyground_core::cloud::{Cloud, read_cloud};
use skyground_core::crs::Crs;
use skyground_core::graph::GraphParams;
use skyground_core::lidar::Caster;
use skyground_core::prior::{
    CrsCheck, check_crs, extent_xy, join_tiles, mission_window, overlap, to_frame,
};
use skyground_core::scene::{Cropped, Scene, Window};
use skyground_core::vehicle::start_on_classes;

use super::aerial::{Survey, survey_of_real};
use super::crop::{CropArg, CropArgs};
use crate::runtime::RuntimeError;

/// The prior options of `skyground demo`.
#[derive(Debug, Clone, clap::Args)]
pub struct PriorArgs {
    /// A real aerial survey (LAS/LAZ/PLY) as the prior instead of the
    /// simulated one; several tiles (repeated, or joined by commas as
    /// --scene's) load as one prior. Its horizontal CRS must be the city
    /// model's (--scene).
    #[arg(long = "prior", value_delimiter = ',')]
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

/// Where the vehicle starts on a real prior: the spot whose ground graph
/// on the producer's classes (as the planner will build it on the
/// classifier's) is largest ([`start_on_classes`]).
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
    let s = start_on_classes(caster, &prior.xyz, labels, &extent, &params)
        .map_err(|e| err(format!("no start for the vehicle: {e}")))?;
    eprintln!(
        "  vehicle starts at ({:.1}, {:.1}): its ground graph on the prior's classes has {} nodes, the largest of {} spots tried",
        s.at[0], s.at[1], s.nodes, s.tried
    );
    Ok(s.at)
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
