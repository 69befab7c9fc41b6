//! `skyground bench transport`: whole-cloud delivery and MB/s between Rust and
//! rclpy peers, each a separate process, over real DDS on loopback.

use std::collections::HashMap;
use std::path::PathBuf;
use std::process::Stdio;
use std::time::{Duration, SystemTime, UNIX_EPOCH};

use crate::convert::pointcloud2::{EncodeOptions, encode};
use serde_json::{Value, json};
use skyground_core::cloud::synthetic;
use skyground_msgs::builtin_interfaces::Time;
use skyground_msgs::std_msgs::Header;
use tokio::io::{AsyncBufReadExt, BufReader, Lines};
use tokio::process::{Child, ChildStdout, Command};

use crate::runtime::{NodeRuntime, RuntimeError, qos};
use crate::transport::{CloudPublisher, TransportConfig};

/// Which benchmark.
#[derive(Debug, Clone, clap::Subcommand)]
pub enum BenchCmd {
    /// Cloud transport: Rust→rclpy, rclpy→Rust, Rust→Rust.
    Transport(TransportArgs),
    /// Ray casting of the LiDAR simulation (no DDS).
    Lidar(LidarArgs),
}

/// LiDAR benchmark options.
#[derive(Debug, Clone, clap::Args)]
pub struct LidarArgs {
    /// Print one JSON document instead of a table.
    #[arg(long)]
    pub json: bool,
    /// Scenes: reference, reference:SEED, a file, or dense:TRIANGLES (synthetic).
    #[arg(long, value_delimiter = ',', default_value = "reference,dense:1000000")]
    pub scenes: Vec<String>,
    /// Seconds of casting per scene.
    #[arg(long, default_value_t = 3.0)]
    pub seconds: f64,
}

/// Runs the LiDAR ray-casting benchmark (spinning VLP-16 scans from street poses).
pub fn lidar(a: &LidarArgs) -> std::process::ExitCode {
    use skyground_core::lidar::{bench_rays, synthetic};
    let mut rows = Vec::new();
    for spec in &a.scenes {
        let scene = match spec.strip_prefix("dense:") {
            Some(n) => match n.parse::<usize>() {
                Ok(n) => synthetic::dense_scene(n, 1),
                Err(_) => {
                    eprintln!("skyground bench lidar: bad triangle count in {spec}");
                    return std::process::ExitCode::from(2);
                }
            },
            None => match skyground_core::io::load_scene(spec) {
                Ok(s) => s,
                Err(e) => {
                    eprintln!("skyground bench lidar: scene {spec}: {e}");
                    return std::process::ExitCode::FAILURE;
                }
            },
        };
        match bench_rays(&scene, a.seconds) {
            Ok(f) => rows.push(
                json!({"scene": spec, "figures": f, "threads": rayon::current_num_threads()}),
            ),
            Err(e) => {
                eprintln!("skyground bench lidar: {spec}: {e}");
                return std::process::ExitCode::FAILURE;
            }
        }
    }
    let doc = json!({"bench": "lidar", "results": rows});
    if a.json {
        println!("{doc}");
    } else {
        println!("{doc:#}");
    }
    std::process::ExitCode::SUCCESS
}

/// Transport benchmark options.
#[derive(Debug, Clone, clap::Args)]
pub struct TransportArgs {
    /// Print one JSON document instead of a table.
    #[arg(long)]
    pub json: bool,
    /// Cloud sizes in points.
    #[arg(long, value_delimiter = ',', default_value = "100000,1000000,5000000")]
    pub points: Vec<usize>,
    /// Clouds per size and direction.
    #[arg(long, default_value_t = 3)]
    pub repeats: usize,
    /// Directions to run.
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "rust-rclpy,rclpy-rust,rust-rust"
    )]
    pub directions: Vec<String>,
    /// Python with rclpy (the test venv's).
    #[arg(long, default_value = ".venv/bin/python")]
    pub python: PathBuf,
    /// The rclpy peer script.
    #[arg(long, default_value = "tests/python/peer_cloud.py")]
    pub peer: PathBuf,
    /// Tiles in flight before waiting for acknowledgements (default: the transport's).
    #[arg(long)]
    pub window_tiles: Option<usize>,
}

/// One measured cloud.
struct Sample {
    delivered: bool,
    mb_per_s: f64,
}

fn now_ns() -> u128 {
    SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .map_or(0, |d| d.as_nanos())
}

fn spawn(mut cmd: Command) -> Result<(Child, Lines<BufReader<ChildStdout>>), RuntimeError> {
    cmd.stdout(Stdio::piped())
        .stderr(Stdio::null())
        .kill_on_drop(true);
    let mut child = cmd
        .spawn()
        .map_err(|e| RuntimeError::Node(format!("cannot start benchmark peer: {e}")))?;
    let out = child
        .stdout
        .take()
        .ok_or_else(|| RuntimeError::Node("benchmark peer has no stdout".into()))?;
    Ok((child, BufReader::new(out).lines()))
}

async fn next_json(lines: &mut Lines<BufReader<ChildStdout>>, timeout: Duration) -> Option<Value> {
    loop {
        let line = tokio::time::timeout(timeout, lines.next_line())
            .await
            .ok()?
            .ok()??;
        if let Ok(v) = serde_json::from_str::<Value>(&line) {
            return Some(v);
        }
    }
}

fn stamp_key(v: &Value) -> Option<(i64, i64)> {
    Some((v["stamp"][0].as_i64()?, v["stamp"][1].as_i64()?))
}

/// Rust publisher (this process) → sink process.
async fn from_rust(
    rt: &mut NodeRuntime,
    sink: Command,
    topic: &str,
    n: usize,
    repeats: usize,
    config: TransportConfig,
) -> Result<Vec<Sample>, RuntimeError> {
    let (mut child, mut lines) = spawn(sink)?;
    let ready = next_json(&mut lines, Duration::from_secs(60)).await;
    if ready.is_none() {
        return Err(RuntimeError::Node("cloud sink did not start".into()));
    }
    let publisher = CloudPublisher::new(rt, topic, qos::reliable(1), config)?;
    if !publisher
        .wait_for_subscriptions(1, Duration::from_secs(30))
        .await
    {
        return Err(RuntimeError::Node("cloud sink was not discovered".into()));
    }
    tokio::time::sleep(Duration::from_millis(1500)).await;
    // x, y, z and label: 16 bytes a point, as the 80 MB for 5 M points.
    let mut cloud = synthetic::tilted_plane(n);
    cloud.intensity = None;
    cloud.building = None;
    let mut starts = HashMap::new();
    for k in 0..repeats {
        let stamp = Time {
            sec: 100 + k as i32,
            nanosec: 0,
        };
        let msg = encode(
            &cloud,
            Header {
                stamp,
                frame_id: "map".into(),
            },
            &EncodeOptions::default(),
        );
        let bytes = msg.data.len();
        starts.insert((100 + k as i64, 0), (now_ns(), bytes));
        publisher.publish(msg).await?;
        tokio::time::sleep(Duration::from_millis(300)).await;
    }
    let samples = collect(&mut lines, &starts, n, repeats).await;
    let _ = child.kill().await;
    Ok(samples)
}

/// rclpy publisher process → Rust sink process.
async fn from_rclpy(
    a: &TransportArgs,
    topic: &str,
    n: usize,
    exe: &PathBuf,
) -> Result<Vec<Sample>, RuntimeError> {
    let mut sink = Command::new(exe);
    sink.args([
        "cloud-sink",
        "--topic",
        topic,
        "--check-synthetic",
        "--count",
    ])
    .arg(a.repeats.to_string());
    let (mut sink_child, mut sink_lines) = spawn(sink)?;
    if next_json(&mut sink_lines, Duration::from_secs(60))
        .await
        .is_none()
    {
        return Err(RuntimeError::Node("cloud sink did not start".into()));
    }
    let mut send = Command::new(&a.python);
    send.arg(&a.peer)
        .args([
            "send",
            "--topic",
            topic,
            "--points",
            &n.to_string(),
            "--count",
        ])
        .arg(a.repeats.to_string())
        .args(["--linger", "30"]);
    let (mut send_child, mut send_lines) = spawn(send)?;
    let mut starts = HashMap::new();
    for _ in 0..a.repeats {
        let Some(v) = next_json(&mut send_lines, Duration::from_secs(120)).await else {
            break;
        };
        if let (Some(k), Some(t), Some(b)) =
            (stamp_key(&v), v["start_ns"].as_u64(), v["bytes"].as_u64())
        {
            starts.insert(k, (u128::from(t), b as usize));
        }
    }
    let samples = collect(&mut sink_lines, &starts, n, a.repeats).await;
    let _ = send_child.kill().await;
    let _ = sink_child.kill().await;
    Ok(samples)
}

async fn collect(
    lines: &mut Lines<BufReader<ChildStdout>>,
    starts: &HashMap<(i64, i64), (u128, usize)>,
    n: usize,
    repeats: usize,
) -> Vec<Sample> {
    let mut out: Vec<Sample> = Vec::new();
    while out.len() < repeats {
        let Some(v) = next_json(lines, Duration::from_secs(60)).await else {
            break;
        };
        let Some((start, bytes)) = stamp_key(&v).and_then(|k| starts.get(&k)) else {
            continue;
        };
        let done = v["complete_ns"].as_u64().map_or(0, u128::from);
        let secs = (done.saturating_sub(*start)) as f64 / 1e9;
        out.push(Sample {
            delivered: v["valid"].as_bool() == Some(true) && v["points"].as_u64() == Some(n as u64),
            mb_per_s: *bytes as f64 / 1e6 / secs.max(1e-9),
        });
    }
    while out.len() < repeats {
        out.push(Sample {
            delivered: false,
            mb_per_s: 0.0,
        });
    }
    out
}

/// Runs the transport benchmark and prints its figures.
pub async fn transport(rt: &mut NodeRuntime, a: TransportArgs) -> Result<(), RuntimeError> {
    let exe = std::env::current_exe().map_err(|e| RuntimeError::Node(e.to_string()))?;
    let mut config = TransportConfig::default();
    if let Some(w) = a.window_tiles {
        config.window_tiles = w;
    }
    if a.directions.iter().any(|d| d.contains("rclpy")) {
        let what = "skyground bench transport (its rclpy peer)";
        crate::runtime::tools::require_python(&a.python, &["rclpy"], what)?;
        crate::runtime::tools::require_file(&a.peer, what, "--peer")?;
    }
    let mut rows = Vec::new();
    for dir in &a.directions {
        for (i, &n) in a.points.iter().enumerate() {
            let topic = format!("/bench/{}/n{i}", dir.replace('-', "_"));
            let samples = match dir.as_str() {
                "rust-rust" => {
                    let mut c = Command::new(&exe);
                    c.args([
                        "cloud-sink",
                        "--topic",
                        &topic,
                        "--check-synthetic",
                        "--count",
                    ])
                    .arg(a.repeats.to_string());
                    from_rust(rt, c, &topic, n, a.repeats, config).await?
                }
                "rust-rclpy" => {
                    let mut c = Command::new(&a.python);
                    c.arg(&a.peer)
                        .args(["sink", "--topic", &topic, "--check-synthetic", "--count"])
                        .arg(a.repeats.to_string());
                    from_rust(rt, c, &topic, n, a.repeats, config).await?
                }
                "rclpy-rust" => from_rclpy(&a, &topic, n, &exe).await?,
                other => return Err(RuntimeError::Node(format!("unknown direction {other}"))),
            };
            let delivered = samples.iter().filter(|s| s.delivered).count();
            let rates: Vec<f64> = samples
                .iter()
                .filter(|s| s.delivered)
                .map(|s| s.mb_per_s)
                .collect();
            let mean = if rates.is_empty() {
                0.0
            } else {
                rates.iter().sum::<f64>() / rates.len() as f64
            };
            let min = rates.iter().copied().fold(f64::INFINITY, f64::min);
            let row = json!({
                "direction": dir,
                "points": n,
                "mb": (n * 16) as f64 / 1e6,
                "sent": a.repeats,
                "delivered_whole": delivered,
                "mb_per_s_mean": (mean * 10.0).round() / 10.0,
                "mb_per_s_min": if min.is_finite() { (min * 10.0).round() / 10.0 } else { 0.0 },
            });
            if !a.json {
                eprintln!("{row}");
            }
            rows.push(row);
        }
    }
    if a.json {
        println!("{}", json!({"bench": "transport", "results": rows}));
    } else {
        println!(
            "{:<11} {:>9} {:>7} {:>10} {:>9} {:>9}",
            "direction", "points", "MB", "delivered", "MB/s", "min MB/s"
        );
        for r in &rows {
            println!(
                "{:<11} {:>9} {:>7.1} {:>7}/{:<2} {:>9.1} {:>9.1}",
                r["direction"].as_str().unwrap_or(""),
                r["points"],
                r["mb"].as_f64().unwrap_or(0.0),
                r["delivered_whole"],
                r["sent"],
                r["mb_per_s_mean"].as_f64().unwrap_or(0.0),
                r["mb_per_s_min"].as_f64().unwrap_or(0.0)
            );
        }
    }
    Ok(())
}
