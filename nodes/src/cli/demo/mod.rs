//! `skyground demo`: the whole sky–ground mission over DDS (docs/design.md
//! steps 1–9). Every node is a process of its own on one domain. This
//! process makes the prior, then works in three parts: [`launch`] starts
//! the nodes (and starts again any that exits), [`watch`] follows the
//! mission's topics and closes the loop round by round until the stop rule
//! or a limit, and [`report`] stops nothing but measures: it proves the gain
//! against ground truth (report.json, report.md, overview.png; the bag is
//! mission.mcap).

mod args;
mod console;
mod launch;
mod report;
mod resume;
mod stall;
mod uav;
mod watch;

pub use args::{DemoArgs, FieldArgs};

use std::time::Instant;

use skyground_core::cloud::write_cloud;
use skyground_core::crs::{Crs, SourceFrame};
use skyground_core::io::{SourceFootprints, load_scene_and_crs};
use skyground_core::metrics::MeasureSoFar;
use skyground_core::prior::unlabelled;
use skyground_core::scene::{Cropped, Scene};

use crate::cli::aerial::{Survey, survey_of};
use crate::cli::profile::Profile;
use crate::cli::reconstruct::ModelFootprints;
use crate::runtime::{NodeRuntime, RuntimeError};

/// Runs the demo mission.
pub async fn run(rt: &mut NodeRuntime, a: DemoArgs) -> Result<(), RuntimeError> {
    let err = |e: String| RuntimeError::Node(e);
    let t0 = Instant::now();
    let mut prof = Profile::new("prior");
    std::fs::create_dir_all(&a.out).map_err(|e| err(format!("{}: {e}", a.out.display())))?;
    let exe = std::env::current_exe().map_err(|e| err(e.to_string()))?;
    eprintln!(
        "skyground demo: scene {}, output {}",
        a.scene(),
        a.out.display()
    );
    skyground_core::explore::VoxelMerge::new(a.merge_voxel)
        .map_err(|e| err(format!("--merge-voxel: {e}")))?;
    // A footprints file that cannot be read stops the demo before the scene is.
    let given = a
        .footprints
        .read_parts(Some(&a.scene()), a.parts)
        .map_err(|e| err(format!("footprints: {e}")))?;
    // The model is read once: its CRS is kept, the scene moves into the
    // mission's (or its crop is taken and the whole dropped).
    let (full, model_crs) =
        load_scene_and_crs(&a.scene()).map_err(|e| err(format!("scene {}: {e}", a.scene())))?;
    let (scene_spec, prior, crop) = mission_prior(&a, full, model_crs.as_ref())?;
    let footprints = in_prior_frame(given.as_ref(), &prior)?;
    let detector = a.footprints.detector_params(
        footprints.as_ref().map(|f| &f.footprints[..]),
        Some(&a.scene()),
        prior.cloud.crs.as_ref(),
        prior.scene.origin,
    )?;
    // A geofence that cannot be used stops the demo here too.
    let fence = uav::fence_params(a.geofence.as_deref(), &prior)?;
    if a.geofence.is_some() && !a.uav() {
        eprintln!("  --geofence: no drone flies (--platforms without uav), so it is not used");
    }
    // Only a mission that can start clears (or takes up) what its folder holds.
    let carried = start_or_resume(&a)?;
    // The prior's measurement and models are ready before the mission ends;
    // the merged cloud is measured as its points arrive (report: only the
    // last round's points are left to measure).
    let mut before = MeasureSoFar::new(&prior.gt, prior.tau);
    before.add(&prior.scene, &prior.gt, &prior.cloud);
    let models_before = models_in_background(&a, &prior, footprints.clone());
    let aerial = a.cloud_file("aerial");
    // The classifier labels the prior itself: publish it without the simulator's labels.
    write_cloud(&aerial, &unlabelled(&prior.cloud)).map_err(|e| err(e.to_string()))?;
    say_prior(&a, &prior, &before, t0);
    let driver = if a.field.field {
        launch::field_driver()
    } else {
        let real = a.real_prior().then_some(&prior.cloud);
        launch::sim_driver(&prior.scene, &scene_spec, a.time_factor, real)?
    };
    let drone = if a.uav() {
        let start = uav::start_of(&driver.1)
            .ok_or_else(|| err("the drone's pad: no start for the ground robot".into()))?;
        let mut nodes = uav::nodes(
            &prior.scene,
            &prior.cloud,
            &scene_spec,
            start,
            a.time_factor,
            &a.scan_log(),
        )?;
        if let Some(planner) = nodes.iter_mut().find(|n| n.0 == "uav_planner") {
            planner.1.extend(fence);
        }
        nodes
    } else {
        Vec::new()
    };
    let mut procs = launch::start_all(&a, &exe, (detector, &aerial, driver), &carried, drone)?;
    prof.stage("start-up, classification, detection, first route");
    eprintln!(
        "  started {} processes: {}",
        procs.len(),
        procs.iter().map(|p| p.name).collect::<Vec<_>>().join(", ")
    );
    let outcome = watch::follow(
        rt,
        (&a, &prior, &before, carried),
        (&mut procs, &exe),
        &mut prof,
        t0,
    )
    .await?;
    let mission = (
        &prior,
        before,
        crop.as_ref(),
        model_crs,
        footprints.as_ref(),
    );
    stop_and_report(
        &a,
        mission,
        (&mut procs, outcome),
        models_before,
        (t0, &mut prof),
    )
    .await
}

/// The given footprints moved into the prior's frame. Footprints in another
/// CRS than the cloud's stop the demo here, before any node starts; in the
/// prior's frame they also shape the models (one per footprint, its id
/// kept; with `--parts`, one per BuildingPart under its Building).
fn in_prior_frame(
    given: Option<&SourceFootprints>,
    prior: &Survey,
) -> Result<Option<ModelFootprints>, RuntimeError> {
    let frame = SourceFrame::new(prior.scene.origin, prior.cloud.crs.clone());
    given
        .map(|r| ModelFootprints::in_frame(r, &frame))
        .transpose()
        .map_err(|e| RuntimeError::Node(format!("footprints: {e}")))
}

/// The mission's survey, what was measured before it, its crop, the city
/// model's CRS and the footprints its models are made on.
type Mission<'a> = (
    &'a Survey,
    MeasureSoFar,
    Option<&'a Cropped>,
    Option<Crs>,
    Option<&'a ModelFootprints>,
);

/// Stops the nodes, takes in the merge store and reports; an error when the
/// mission did not finish (the report is written all the same).
async fn stop_and_report(
    a: &DemoArgs,
    (prior, before, crop, model_crs, footprints): Mission<'_>,
    (procs, mut outcome): (&mut [launch::Proc], watch::Outcome),
    models_before: report::ModelsBefore,
    (t0, prof): (Instant, &mut Profile),
) -> Result<(), RuntimeError> {
    eprintln!("  {}; stopping the nodes", outcome.why);
    prof.stage("stopping the nodes");
    launch::stop_all(procs, prof).await;
    // The explorer wrote its last batch as it stopped.
    let merge = report::take_store((&a.merge_store(), &a.scan_log()), prior, &mut outcome)?;
    eprintln!("  {}", report::ids_line(&merge.ids));
    let (finished, why) = (outcome.finished, outcome.why.clone());
    let inputs = report::Inputs {
        a,
        prior,
        crop,
        model_crs,
        footprints,
        before: before.measured(&prior.gt),
        outcome,
        restarts: launch::restarts(procs),
        merge,
        bag: launch::bag_topics(&a.out.join("mission.mcap")),
    };
    report::report(&inputs, models_before, (t0, prof))?;
    if finished {
        Ok(())
    } else {
        Err(RuntimeError::Node(format!(
            "the mission did not finish ({why}): see the logs in {}",
            a.out.display()
        )))
    }
}

/// A new mission clears what a former one left in its folder and keeps its
/// command line; a resumed one reads what its earlier runs did.
fn start_or_resume(a: &DemoArgs) -> Result<resume::Carried, RuntimeError> {
    // A planner restarted in this run goes on from its status; a resumed
    // run finishes the round it was driving; a new run plans anew.
    let carried = if a.resume.is_some() {
        let c = resume::read(&a.out)?;
        eprintln!(
            "  resuming: {} rounds done, {:.0} m driven, {:.0} robot s, last at {:?}",
            c.rounds, c.odometer_m, c.sim_s, c.position
        );
        match resume::carry_round(&a.out) {
            Ok(Some(s)) => {
                eprintln!(
                    "  going on with the round it was driving: {} of {} stops dealt with",
                    s.visited.points.len() + s.visited.regions.len(),
                    s.target_points + s.target_regions
                );
                c.without_open_round()
            }
            Ok(None) => c.planning_anew(),
            Err(e) => {
                eprintln!("  the interrupted round cannot be read back ({e}): planning anew");
                let _ = std::fs::remove_file(a.out.join(resume::PLANNER_FILE));
                let _ = std::fs::remove_file(a.out.join(resume::ROUND_FILE));
                c.planning_anew()
            }
        }
    } else {
        let _ = std::fs::remove_file(a.out.join(resume::PLANNER_FILE));
        let _ = std::fs::remove_file(a.out.join(resume::ROUND_FILE));
        launch::remove_bag(&a.out.join("mission.mcap"));
        // A new mission starts a new merge (the explorer would go on from one left here).
        launch::remove_merge(&a.merge_store())?;
        let _ = std::fs::remove_file(a.scan_log());
        let _ = std::fs::remove_file(a.out.join(resume::PROGRESS_FILE));
        resume::Command::now()
            .write(&a.out)
            .map_err(RuntimeError::Node)?;
        resume::Carried::default()
    };
    Ok(resume::Carried {
        runs: carried.runs + 1,
        ..carried
    })
}

/// The prior's line: which prior, its points and building completeness.
fn say_prior(a: &DemoArgs, prior: &Survey, before: &MeasureSoFar, t0: Instant) {
    eprintln!(
        "  {}: {} points, building completeness {:.2} % ({:.1} s)",
        if a.real_prior() {
            "real prior"
        } else {
            "airborne prior (simulated)"
        },
        prior.cloud.len(),
        before
            .measured(&prior.gt)
            .completeness
            .overall
            .ratio
            .unwrap_or(0.0)
            * 100.0,
        t0.elapsed().as_secs_f64()
    );
}

/// The prior's LoD2 models, made on a thread of their own while the mission runs.
fn models_in_background(
    a: &DemoArgs,
    prior: &Survey,
    footprints: Option<ModelFootprints>,
) -> report::ModelsBefore {
    let (dir, scene, cloud, spacing) = (
        a.out.clone(),
        prior.scene.clone(),
        prior.cloud.clone(),
        prior.gt.spacing,
    );
    std::thread::spawn(move || {
        crate::cli::reconstruct::models_of(
            &dir,
            "models_before",
            &scene,
            &cloud,
            spacing,
            footprints.as_ref(),
        )
    })
}

/// The mission's scene and prior: the simulated airborne survey of the
/// mission's scene ([`crate::cli::crop::mission_scene`]), or the real survey
/// of `--prior` over the city model.
fn mission_prior(
    a: &DemoArgs,
    full: Scene,
    model_crs: Option<&Crs>,
) -> Result<(String, Survey, Option<Cropped>), RuntimeError> {
    if a.real_prior() {
        return crate::cli::prior::real_prior(
            &a.prior,
            (&a.scene(), &a.crop, &a.out),
            full,
            model_crs,
        );
    }
    let (scene_spec, scene, crop) =
        crate::cli::crop::mission_scene((&a.scene(), &a.crop, &a.out), full, model_crs)?;
    let mut prior = survey_of(scene, &scene_spec, None)?;
    // The city model's CRS, also when the mission runs on a crop of it
    // (written as OBJ, which names none).
    prior.cloud.crs = model_crs.cloned();
    Ok((scene_spec, prior, crop))
}
