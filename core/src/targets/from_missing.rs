//! Targets from what travels on the topics: missing points (with their
//! skeleton point and normal rebuilt by the receiver) and, per building,
//! the strategy and ground height the detector reported.

use std::collections::BTreeMap;

use geo::MultiPolygon;

use super::generate::{Dropped, generate};
use super::params::TargetParams;
use super::site::{Site, SiteError};
use super::types::TargetSet;
use crate::cloud::{Cloud, ColumnLength};
use crate::missing::{BuildingDetection, Detection, MissingPoint, Strategy};
use crate::params::ParamError;

impl Site {
    /// The site of a classified cloud with the cell and clearance of `params`.
    pub fn from_classified(cloud: &Cloud, params: &TargetParams) -> Result<Site, SiteError> {
        let labels = cloud.label.as_deref().ok_or(ColumnLength {
            column: "labels",
            expected: cloud.len(),
            got: 0,
        })?;
        Site::from_cloud(&cloud.xyz, labels, params.cell, params.clearance)
    }
}

/// What the detector said of one building.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BuildingPlan {
    /// Point- or region-based.
    pub strategy: Strategy,
    /// Its ground height, metres.
    pub ground_z: f32,
}

/// [`generate`] from missing points and per-building plans; buildings
/// without a plan are point-based at the lowest missing point's height.
pub fn generate_from_missing(
    missing: &[MissingPoint],
    plans: &BTreeMap<u32, BuildingPlan>,
    site: &Site,
    params: &TargetParams,
) -> Result<(TargetSet, Dropped), ParamError> {
    let mut per: BTreeMap<u32, Vec<MissingPoint>> = BTreeMap::new();
    for m in missing {
        per.entry(m.building).or_default().push(*m);
    }
    let buildings = per
        .into_iter()
        .map(|(id, pts)| {
            let low = pts.iter().map(|m| m.xyz[2]).fold(f32::INFINITY, f32::min);
            let plan = plans.get(&id).copied().unwrap_or(BuildingPlan {
                strategy: Strategy::PointBased,
                ground_z: low,
            });
            let mut b = BuildingDetection::skipped(
                id,
                0,
                crate::missing::SkipReason::TooFewPoints { points: 0, min: 0 },
            );
            b.skipped = None;
            b.global_contour = MultiPolygon(vec![]);
            b.ground_z = plan.ground_z;
            b.strategy = plan.strategy;
            b.missing = pts;
            b
        })
        .collect();
    let detection = Detection {
        buildings,
        ..Detection::default()
    };
    generate(&detection, site, params)
}
