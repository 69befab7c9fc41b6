//! What detection reports per building and over a whole cloud.

use geo::MultiPolygon;
use serde::{Deserialize, Serialize};

use crate::skeleton::Skeleton;

/// How a building's gaps should be supplemented (docs/design.md step 4).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum Strategy {
    /// R_missing < θ: stand at points that see each gap.
    PointBased,
    /// R_missing ≥ θ: explore a region around the gaps.
    RegionBased,
}

/// Why a building was not analysed.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, thiserror::Error)]
pub enum SkipReason {
    /// Too few points to outline.
    #[error("only {points} points (need {min})")]
    TooFewPoints {
        /// Points the building has.
        points: usize,
        /// Least needed.
        min: usize,
    },
    /// The given footprint has no usable area.
    #[error("footprint is degenerate (area {area} m², or non-finite coordinates)")]
    DegenerateFootprint {
        /// Its area.
        area: f64,
    },
    /// The points outline to nothing (all in a sliver or below the first slice).
    #[error("no slice contour (building {height} m tall, outline {area} m²)")]
    NoContour {
        /// Height from ground to top.
        height: f32,
        /// Area of the whole outline.
        area: f64,
    },
}

/// A sampled contour point at one slice height.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct BoundaryPoint {
    /// q_n moved onto the wall (along s→q) in xy; z = middle of the wall part tested.
    pub xyz: [f32; 3],
    /// Unit direction s_m → q_n (outward).
    pub normal: [f32; 2],
    /// s_m, the nearest skeleton point.
    pub skeleton: [f32; 2],
    /// Covered share of the strip near q_n.
    pub coverage: f32,
    /// Whether the aerial cloud holds this part of the wall.
    pub collected: bool,
    /// Index into `BuildingDetection::slices`.
    pub slice: u32,
}

/// A missing boundary point, what targets are made from.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct MissingPoint {
    /// Position: contour point in xy, z = slice height.
    pub xyz: [f32; 3],
    /// Building id (1-based).
    pub building: u32,
    /// Unit outward direction s_m → q_n.
    pub normal: [f32; 2],
    /// The skeleton point s_m the ray starts from.
    pub skeleton: [f32; 2],
}

/// One slice of a building, for drawing and counting.
#[derive(Debug, Clone)]
pub struct SliceReport {
    /// Slice centre height, metres.
    pub height: f32,
    /// Building points in its band.
    pub points: usize,
    /// Contour tested at this height.
    pub contour: MultiPolygon<f64>,
    /// Structure index of each contour part tested.
    pub structures: Vec<usize>,
    /// Boundary points tested.
    pub boundary: usize,
    /// Of which missing.
    pub missing: usize,
}

/// One structure (podium, tower, wing) of a building.
#[derive(Debug, Clone)]
pub struct StructureReport {
    /// Its lowest and highest slice heights.
    pub heights: [f32; 2],
    /// Its contour.
    pub contour: MultiPolygon<f64>,
    /// Its medial-axis skeleton.
    pub skeleton: Skeleton,
}

/// Detection result of one building.
#[derive(Debug, Clone)]
pub struct BuildingDetection {
    /// Building id (1-based).
    pub building: u32,
    /// Its footprint's own id (BAG `identificatie`, OSM id, CityObject id;
    /// `derived_N` for a derived one), empty when no footprint named it.
    pub footprint_id: String,
    /// Points it has.
    pub points: usize,
    /// Set when the building was not analysed; everything below is then empty.
    pub skipped: Option<SkipReason>,
    /// Ground height used, metres.
    pub ground_z: f32,
    /// Highest point, metres.
    pub top_z: f32,
    /// C_building: the footprint if given, else the outline of all points.
    pub global_contour: MultiPolygon<f64>,
    /// Slices from the lowest up.
    pub slices: Vec<SliceReport>,
    /// Structures.
    pub structures: Vec<StructureReport>,
    /// Every boundary point tested.
    pub boundary: Vec<BoundaryPoint>,
    /// The boundary points found missing.
    pub missing: Vec<MissingPoint>,
    /// R_missing = missing / boundary points (0 when none were tested).
    pub r_missing: f32,
    /// Point- or region-based supplementation.
    pub strategy: Strategy,
}

impl BuildingDetection {
    /// A building reported as skipped.
    pub fn skipped(building: u32, points: usize, reason: SkipReason) -> Self {
        BuildingDetection {
            building,
            footprint_id: String::new(),
            points,
            skipped: Some(reason),
            ground_z: 0.0,
            top_z: 0.0,
            global_contour: MultiPolygon(vec![]),
            slices: vec![],
            structures: vec![],
            boundary: vec![],
            missing: vec![],
            r_missing: 0.0,
            strategy: Strategy::PointBased,
        }
    }
}

/// Detection over all buildings of a cloud.
#[derive(Debug, Clone, Default)]
pub struct Detection {
    /// One entry per building id present, ascending.
    pub buildings: Vec<BuildingDetection>,
    /// The parameters used, `auto` resolved (None when not run by [`super::detect_all`]).
    pub params: Option<super::DetectParams>,
    /// The density of the building points they were resolved for.
    pub density: Option<crate::density::Density>,
}

impl Detection {
    /// All missing points of all buildings.
    pub fn missing_points(&self) -> Vec<MissingPoint> {
        self.buildings
            .iter()
            .flat_map(|b| b.missing.iter().copied())
            .collect()
    }

    /// Their positions only.
    pub fn missing_xyz(&self) -> Vec<[f32; 3]> {
        self.buildings
            .iter()
            .flat_map(|b| b.missing.iter().map(|m| m.xyz))
            .collect()
    }

    /// The outline raster's cell in use, metres: the most an outline can
    /// stand off its wall (the high-density cell when not run by
    /// [`super::detect_all`]).
    pub fn outline_cell_m(&self) -> f64 {
        self.params.as_ref().map_or_else(
            || crate::slice::SliceParams::default().cell_m(),
            |p| p.slice.cell_m(),
        )
    }

    /// Missing over boundary points of all analysed buildings.
    pub fn r_missing(&self) -> f32 {
        let (m, n) = self.buildings.iter().fold((0, 0), |(m, n), b| {
            (m + b.missing.len(), n + b.boundary.len())
        });
        if n == 0 { 0.0 } else { m as f32 / n as f32 }
    }
}
