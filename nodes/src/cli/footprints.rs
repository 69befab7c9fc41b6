//! `--footprints`: the building outlines a subcommand splits a cloud by,
//! instead of deriving them from its points (`skyground detect`,
//! `skyground reconstruct`, the demo's detector), read and checked before
//! anything starts; and `skyground footprints`: the outlines derived from
//! a cloud, scored against the true ones.

use std::path::PathBuf;

use skyground_core::crs::{Crs, SourceFrame};
use skyground_core::footprint::{Footprint, ReadOptions, segmentation, split};
use skyground_core::io::geojson::write::{feature, feature_collection, multipolygon};
use skyground_core::io::{SourceFootprints, read_footprints, resolve_source};
use skyground_core::missing::{SceneParams, derive_footprints};

use super::err;
use crate::runtime::RuntimeError;

/// The `--footprints` and `--footprint-id` options.
#[derive(Debug, Clone, Default, clap::Args)]
pub struct FootprintsArg {
    /// Footprints as surveys have them: GeoJSON (BAG, OSM, a municipality's), CityJSON /
    /// CityJSONSeq (LoD 0 or ground surfaces; tiles joined by commas), FlatGeobuf (.fgb) or OBJ,
    /// in the CRS they name (else the cloud's); `model`: the CityJSON scene's own buildings.
    /// Default: derived from the points.
    #[arg(long)]
    pub footprints: Option<PathBuf>,
    /// The property (GeoJSON, FlatGeobuf) or attribute (CityJSON) holding each footprint's own
    /// id, written next to our building id; default: the first of identificatie,
    /// identificatiebagpnd, footprint_id, id, @id, osm_id, else the feature's / CityObject's id.
    #[arg(long, requires = "footprints")]
    pub footprint_id: Option<String>,
}

impl FootprintsArg {
    /// Reads the footprints named (`None` without `--footprints`), so a file
    /// that cannot be used stops the command before it starts anything;
    /// `scene` is the scene spec `model` stands for.
    pub fn read(&self, scene: Option<&str>) -> Result<Option<SourceFootprints>, RuntimeError> {
        self.read_parts(scene, false)
    }

    /// As [`Self::read`]; with `parts`, CityJSON footprints one per BuildingPart.
    pub fn read_parts(
        &self,
        scene: Option<&str>,
        parts: bool,
    ) -> Result<Option<SourceFootprints>, RuntimeError> {
        let Some(spec) = &self.footprints else {
            return Ok(None);
        };
        let spec = resolve_source(&spec.display().to_string(), scene).map_err(err)?;
        let options = ReadOptions {
            id_field: self.footprint_id.clone(),
            parts,
        };
        read_footprints(&spec, &options).map(Some).map_err(err)
    }

    /// The completeness_detector params that give it these footprints
    /// (`loaded`: [`Self::read`]'s, already moved by [`in_frame`] into the
    /// cloud's frame, so a bad file or CRS has stopped the demo before any
    /// node starts) for a cloud in `crs` whose local frame starts at
    /// `origin` (metres): `footprints:=`, `footprint_id:=`, `crs:=`, `origin:=`.
    pub fn detector_params(
        &self,
        loaded: Option<&[Footprint]>,
        scene: Option<&str>,
        crs: Option<&Crs>,
        origin: [f64; 3],
    ) -> Result<Vec<String>, RuntimeError> {
        if loaded.is_none() {
            return Ok(Vec::new());
        }
        let spec = resolve_source(
            &self
                .footprints
                .as_ref()
                .map(|p| p.display().to_string())
                .unwrap_or_default(),
            scene,
        )
        .map_err(err)?;
        let mut params = vec![format!("footprints:={spec}")];
        if let Some(f) = &self.footprint_id {
            params.push(format!("footprint_id:={f}"));
        }
        params.extend(frame_params(crs, origin));
        Ok(params)
    }
}

/// A node's `origin:=` and `crs:=` (when the CRS has an EPSG code): the
/// clouds' local frame, in which it reads the polygons its params name.
pub fn frame_params(crs: Option<&Crs>, origin: [f64; 3]) -> Vec<String> {
    let mut params = vec![format!(
        "origin:=[{}, {}, {}]",
        origin[0], origin[1], origin[2]
    )];
    if let Some(code) = crs.and_then(|c| c.epsg) {
        params.push(format!("crs:=EPSG:{code}"));
    }
    params
}

/// `read` moved into the cloud's `frame` (CRS checked); the polygons the
/// file holds but cannot be used are named on stderr, and the rest load.
pub fn in_frame(
    read: &SourceFootprints,
    frame: &SourceFrame,
) -> Result<Vec<Footprint>, RuntimeError> {
    let loaded = read.in_frame(frame).map_err(err)?;
    for s in &loaded.skipped {
        eprintln!("footprints {}: {s}", read.path.display());
    }
    Ok(loaded.footprints)
}

/// Options of `skyground footprints`.
#[derive(Debug, Clone, clap::Args)]
pub struct FootprintsArgs {
    /// A classified cloud (label 6 = building, 2 = ground); several files are tiles of one survey.
    #[arg(long = "in", num_args = 1.., required = true)]
    pub inputs: Vec<PathBuf>,
    /// True footprints to score the derived ones against (any `--footprints` format).
    #[arg(long)]
    pub truth: Option<PathBuf>,
    /// A params file (section completeness_detector, key `derive`).
    #[arg(long)]
    pub params_file: Option<PathBuf>,
    /// Output directory: footprints.geojson (the derived outlines, in the cloud's CRS).
    #[arg(long, default_value = "out/footprints")]
    pub out: PathBuf,
    /// True footprints holding fewer building points are not scored (nothing to derive from).
    #[arg(long, default_value_t = 50)]
    pub min_points: usize,
    /// Print the summary as JSON on stdout.
    #[arg(long)]
    pub json: bool,
    #[command(flatten)]
    pub units: super::units::UnitsArg,
}

/// Derives footprints from a cloud as the detector does, writes them, and
/// scores them against `--truth`.
pub fn run(a: &FootprintsArgs) -> Result<serde_json::Value, RuntimeError> {
    use crate::runtime::specs::COMPLETENESS_DETECTOR as SPEC;
    let truth_arg = FootprintsArg {
        footprints: a.truth.clone(),
        footprint_id: None,
    };
    let truth_read = truth_arg.read(None)?;
    let p: SceneParams = crate::runtime::params::section(
        "completeness_detector",
        SPEC.default_params,
        a.params_file.as_deref(),
        &["derive"],
    )?;
    let cloud = a.units.read_tiles(&a.inputs)?;
    let frame = cloud.frame();
    let t0 = std::time::Instant::now();
    let derived = derive_footprints(&cloud, &p.derive).map_err(err)?;
    let seconds = t0.elapsed().as_secs_f64();
    std::fs::create_dir_all(&a.out).map_err(|e| err(format!("{}: {e}", a.out.display())))?;
    let features = derived
        .iter()
        .map(|f| {
            let props =
                serde_json::json!({"building": f.id, "footprint_id": f.name, "area_m2": f.area()});
            feature(multipolygon(&frame, &f.polygon), props)
        })
        .collect();
    let path = a.out.join("footprints.geojson");
    let doc = feature_collection(&frame, "footprints", features);
    skyground_core::file::write(&path, format!("{doc:#}\n")).map_err(err)?;
    let mut out = serde_json::json!({
        "inputs": a.inputs, "derived": derived.len(), "seconds": seconds,
        "derive_params": p.derive, "written": path,
    });
    if let Some(read) = &truth_read {
        let truth = scored_truth(&cloud, in_frame(read, &frame)?, a.min_points)?;
        let s = segmentation(&derived, &truth);
        out["truth"] = serde_json::json!(a.truth);
        out["score"] = serde_json::json!({
            "true_buildings": s.truth, "derived": s.derived, "one_to_one": s.one_to_one,
            "under_segmented": s.under, "over_segmented": s.over, "missed": s.missed,
            "iou_p10": s.iou_quantile(0.1), "iou_p25": s.iou_quantile(0.25),
            "iou_median": s.iou_quantile(0.5), "iou_p75": s.iou_quantile(0.75),
            "iou_at_least_0.5": s.share_at_least(0.5), "iou_at_least_0.7": s.share_at_least(0.7),
            "per_building": truth.iter().zip(&s.iou).map(|(t, v)| serde_json::json!({"building": t.id, "footprint_id": t.name, "iou": v})).collect::<Vec<_>>(),
        });
        if !a.json {
            eprintln!(
                "{} derived footprints for {} true buildings with points: {} one to one (IoU ≥ 0.5), {} merged with a neighbour, {} split, {} missed; IoU p25 {:.3}, median {:.3}, p75 {:.3}",
                s.derived,
                s.truth,
                s.one_to_one,
                s.under,
                s.over,
                s.missed,
                s.iou_quantile(0.25),
                s.iou_quantile(0.5),
                s.iou_quantile(0.75)
            );
        }
    } else if !a.json {
        eprintln!(
            "{} footprints derived, written to {}",
            derived.len(),
            path.display()
        );
    }
    Ok(out)
}

/// The true footprints holding at least `min_points` of the cloud's
/// building points (the rest lie outside the survey or have no roof in it).
fn scored_truth(
    cloud: &skyground_core::cloud::Cloud,
    truth: Vec<Footprint>,
    min_points: usize,
) -> Result<Vec<Footprint>, RuntimeError> {
    let pts = cloud.xyz_of_class(skyground_core::cloud::class::BUILDING);
    let ids = split(&pts, &truth, &Default::default()).map_err(err)?;
    let mut count = std::collections::HashMap::<u32, usize>::new();
    for id in ids.into_iter().filter(|&i| i > 0) {
        *count.entry(id).or_default() += 1;
    }
    Ok(truth
        .into_iter()
        .filter(|t| count.get(&t.id).copied().unwrap_or(0) >= min_points)
        .collect())
}
