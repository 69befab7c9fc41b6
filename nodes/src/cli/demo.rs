//! `skyground demo`: the default mission, as far as the pipeline exists: every
//! node a process of its own on one DDS domain, recorded to an MCAP bag.
//!
//! Today: cloud source → cloud_inspector, with the recorder on every topic.

use std::path::{Path, PathBuf};
use std::process::Stdio;
use std::time::{Duration, Instant};

use tokio::process::{Child, Command};

use crate::bag::read_messages;
use crate::runtime::RuntimeError;

/// Demo options.
#[derive(Debug, Clone, clap::Args)]
pub struct DemoArgs {
    /// Aerial cloud to start from (LAS/LAZ/PLY). Default: the real airborne
    /// sample ../shared/data/real/sample_c.las when present, else a synthetic cloud.
    #[arg(long)]
    pub cloud: Option<PathBuf>,
    /// Output directory (bag and logs).
    #[arg(long, default_value = "out/demo")]
    pub out: PathBuf,
    /// Run here even if other network interfaces exist (default: re-run inside
    /// a loopback-only network namespace).
    #[arg(long)]
    pub no_netns: bool,
    /// Seconds before giving up on the mission.
    #[arg(long, default_value_t = 120.0)]
    pub timeout: f64,
}

struct Proc {
    name: &'static str,
    child: Child,
}

fn start(
    name: &'static str,
    program: &Path,
    args: &[String],
    out: &Path,
) -> Result<Proc, RuntimeError> {
    let log = std::fs::File::create(out.join(format!("{name}.log")))
        .map_err(|e| RuntimeError::Node(format!("cannot write {}: {e}", out.display())))?;
    let child = Command::new(program)
        .args(args)
        .stdout(Stdio::null())
        .stderr(log)
        .kill_on_drop(true)
        .spawn()
        .map_err(|e| {
            RuntimeError::Node(format!("cannot start {name} ({}): {e}", program.display()))
        })?;
    eprintln!("  started {name}");
    Ok(Proc { name, child })
}

async fn stop(p: &mut Proc) {
    if let Some(pid) = p.child.id() {
        // SIGINT, as ros2 launch does, so nodes shut down in order.
        let _ = std::process::Command::new("kill")
            .args(["-INT", &pid.to_string()])
            .status();
    }
    if tokio::time::timeout(Duration::from_secs(10), p.child.wait())
        .await
        .is_err()
    {
        let _ = p.child.kill().await;
    }
    eprintln!("  stopped {}", p.name);
}

fn default_cloud() -> Option<PathBuf> {
    let exe = std::env::current_exe().ok()?;
    // target/{debug,release}/skyground → repository root → ../shared/data/real
    let root = exe.parent()?.parent()?.parent()?;
    let p = root.join("../shared/data/real/sample_c.las");
    p.exists().then_some(p)
}

/// Runs the demo mission.
pub async fn run(a: DemoArgs) -> Result<(), RuntimeError> {
    let t0 = Instant::now();
    let exe = std::env::current_exe().map_err(|e| RuntimeError::Node(e.to_string()))?;
    std::fs::create_dir_all(&a.out)
        .map_err(|e| RuntimeError::Node(format!("{}: {e}", a.out.display())))?;
    let bag = a.out.join("mission.mcap");
    let _ = std::fs::remove_file(&bag);
    let cloud = a.cloud.clone().or_else(default_cloud);
    eprintln!(
        "skyground demo: domain {}, output {}",
        std::env::var("ROS_DOMAIN_ID").unwrap_or_else(|_| "0".into()),
        a.out.display()
    );
    let mut recorder = start(
        "recorder",
        &exe,
        &[
            "record".into(),
            "-o".into(),
            bag.display().to_string(),
            "/aerial_cloud:sensor_msgs/msg/PointCloud2".into(),
            "/cloud_stats:diagnostic_msgs/msg/DiagnosticArray".into(),
        ],
        &a.out,
    )?;
    let node = |name: &str, params: &[String]| {
        let mut v = vec![
            "node".to_string(),
            name.to_string(),
            "--ros-args".to_string(),
        ];
        for p in params {
            v.push("-p".into());
            v.push(p.clone());
        }
        v
    };
    let mut inspector = start(
        "cloud_inspector",
        &exe,
        &node("cloud_inspector", &["max_clouds:=1".into()]),
        &a.out,
    )?;
    let source = match &cloud {
        Some(p) => format!("file:={}", p.display()),
        None => "file:=".to_string(),
    };
    let mut publisher = start(
        "cloud_publisher",
        &exe,
        &node(
            "cloud_publisher",
            &[source, "wait_for_subscribers:=2".into()],
        ),
        &a.out,
    )?;
    eprintln!(
        "  source: {}",
        cloud
            .as_ref()
            .map_or("synthetic cloud".to_string(), |p| p.display().to_string())
    );
    let done =
        tokio::time::timeout(Duration::from_secs_f64(a.timeout), inspector.child.wait()).await;
    let ok = matches!(done, Ok(Ok(s)) if s.success());
    // Give the recorder a moment for the last diagnostics.
    tokio::time::sleep(Duration::from_millis(500)).await;
    stop(&mut publisher).await;
    stop(&mut recorder).await;
    stop(&mut inspector).await;
    let messages = read_messages(&bag).map_err(|e| RuntimeError::Node(e.to_string()))?;
    let count = |t: &str| messages.iter().filter(|m| m.topic == t).count();
    eprintln!(
        "skyground demo: {} in {:.1} s; bag {} holds {} message(s): /aerial_cloud {}, /cloud_stats {}; logs in {}",
        if ok {
            "mission finished"
        } else {
            "mission FAILED"
        },
        t0.elapsed().as_secs_f64(),
        bag.display(),
        messages.len(),
        count("/aerial_cloud"),
        count("/cloud_stats"),
        a.out.display()
    );
    if ok && count("/aerial_cloud") > 0 {
        Ok(())
    } else {
        Err(RuntimeError::Node(format!(
            "the mission did not finish: see the logs in {}",
            a.out.display()
        )))
    }
}
