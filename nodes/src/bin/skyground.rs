//! `skyground`: the command-line entry to every tool of the project.

use std::process::ExitCode;

use clap::{Parser, Subcommand};
use skyground_nodes::cli::{
    self, aerial, bench, classify, demo, detect, echo, eval, footprints, info, plan, play,
    reconstruct, record, sink,
};
use skyground_nodes::netns;
use skyground_nodes::runtime::{RosArgs, run_with};

/// Sky–ground building point-cloud completion over ROS 2.
#[derive(Debug, Parser)]
#[command(name = "skyground", version, about)]
struct Cli {
    #[command(subcommand)]
    cmd: Cmd,
}

#[derive(Debug, Subcommand)]
enum Cmd {
    /// Run the default mission (re-runs itself inside a loopback-only network namespace).
    Demo(demo::DemoArgs),
    /// Run a node: skyground node NAME [--ros-args ...] (see `skyground node --help`; e.g. scene_classifier).
    Node {
        /// The node's name.
        name: String,
    },
    /// Simulate the airborne LiDAR survey of a scene; print its completeness.
    Aerial(aerial::AerialArgs),
    /// Classify a cloud: ground (CSF), vegetation and buildings (Random Forest); scores against its own labels.
    Classify(classify::ClassifyArgs),
    /// Train the classifier's model on labelled surveys, forests and simulated scenes.
    Train(classify::TrainArgs),
    /// What a file holds: points or objects, extent, CRS and unit, density, classes, returns.
    Info(info::InfoArgs),
    /// Find where buildings' walls are missing and make ground targets (with a PNG).
    Detect(detect::DetectArgs),
    /// Derive building footprints from a classified cloud (GeoJSON); with --truth, score them.
    Footprints(footprints::FootprintsArgs),
    /// Build the ground graph and route over the targets of `skyground detect`.
    Plan(plan::PlanArgs),
    /// Measure an aerial cloud and a merged cloud against a scene's buildings.
    Eval(eval::EvalArgs),
    /// Reconstruct LoD2 building models (CityJSON 2.0, OBJ); with --gt, their accuracy.
    Reconstruct(reconstruct::ReconstructArgs),
    /// Republish a recorded bag with its timing (like `ros2 bag play`).
    Play(play::PlayArgs),
    /// Record topics into a rosbag2-compatible MCAP file.
    Record(record::RecordArgs),
    /// Print a topic's messages as JSON lines.
    Echo(echo::EchoArgs),
    /// Receive whole clouds and print one JSON line each.
    CloudSink(sink::SinkArgs),
    /// Benchmarks (run inside a loopback-only network namespace; re-runs itself in one).
    Bench {
        /// Run here even if other network interfaces exist.
        #[arg(long)]
        no_netns: bool,
        #[command(subcommand)]
        which: bench::BenchCmd,
    },
    /// Message types: list, definitions, CDR samples.
    Msgs {
        #[command(subcommand)]
        which: MsgsCmd,
    },
    /// Run a command in a fresh loopback-only network namespace.
    Netns {
        /// The command and its arguments.
        #[arg(required = true, trailing_var_arg = true, allow_hyphen_values = true)]
        command: Vec<std::ffi::OsString>,
    },
}

#[derive(Debug, Subcommand)]
enum MsgsCmd {
    /// Every known message type.
    List,
    /// The ros2msg schema text (with dependencies) of a type.
    Show {
        /// pkg/msg/Type
        type_name: String,
    },
    /// One JSON line per type: a sample's fields and its CDR bytes (for interop tests).
    Samples,
}

fn main() -> ExitCode {
    let argv: Vec<String> = std::env::args().collect();
    let (own, ros) = match RosArgs::split(argv.get(1..).unwrap_or_default()) {
        Ok(v) => v,
        Err(e) => {
            eprintln!("skyground: {e}");
            return ExitCode::from(2);
        }
    };
    let cli = Cli::parse_from(std::iter::once("skyground".to_string()).chain(own));
    match cli.cmd {
        Cmd::Msgs { which } => msgs(which),
        Cmd::Netns { command } => match command.split_first() {
            Some((prog, args)) => exec_failed(netns::exec_isolated(prog, args)),
            None => ExitCode::from(2),
        },
        Cmd::Demo(a) => {
            let a = match a.resumed() {
                Ok(a) => a,
                Err(e) => {
                    eprintln!("skyground demo: {e}");
                    return ExitCode::from(2);
                }
            };
            // Field mode talks to a robot on the real network: no namespace.
            if !a.no_netns && !a.field.field && !netns::is_isolated() {
                eprintln!("skyground demo: re-running inside a loopback-only network namespace");
                return exec_failed(netns::exec_self_isolated());
            }
            // A resumed mission's relative paths mean what they meant when it started.
            if let Some(cwd) = &a.started_in
                && let Err(e) = std::env::set_current_dir(cwd)
            {
                eprintln!(
                    "skyground demo: --resume: the mission ran in {}: {e}",
                    cwd.display()
                );
                return ExitCode::from(2);
            }
            if !a.field.field && std::env::var_os("ROS_AUTOMATIC_DISCOVERY_RANGE").is_none() {
                // The demo is a local mission: keep discovery on this host.
                // SAFETY: no other thread exists yet.
                unsafe { std::env::set_var("ROS_AUTOMATIC_DISCOVERY_RANGE", "LOCALHOST") };
            }
            run_with(
                cli::tool_spec("skyground_demo"),
                ros,
                vec![],
                async |rt, _| demo::run(rt, a).await,
            )
        }
        Cmd::Aerial(a) => offline("aerial", a.json, true, aerial::run(&a)),
        Cmd::Eval(a) => offline("eval", a.json, false, eval::run(&a)),
        Cmd::Reconstruct(a) => offline("reconstruct", a.json, false, reconstruct::run(&a)),
        Cmd::Classify(a) => offline("classify", a.json, false, classify::run(&a)),
        Cmd::Train(a) => offline("train", a.json, true, classify::run_train(&a)),
        Cmd::Info(a) => offline("info", a.json, false, info::run(&a)),
        Cmd::Detect(a) => offline("detect", a.json, false, detect::run(&a)),
        Cmd::Footprints(a) => offline("footprints", a.json, false, footprints::run(&a)),
        Cmd::Plan(a) => offline("plan", a.json, false, plan::run(&a)),
        Cmd::Node { name } => skyground_nodes::node::run_by_name(&name, ros).unwrap_or_else(|| {
            eprintln!(
                "skyground: unknown node `{name}` (nodes: {})",
                skyground_nodes::node::NAMES.join(", ")
            );
            ExitCode::from(2)
        }),
        Cmd::Record(a) => run_with(
            cli::tool_spec("skyground_record"),
            ros,
            vec![],
            async |rt, _| record::run(rt, a).await,
        ),
        Cmd::Play(a) => run_with(
            cli::tool_spec("skyground_play"),
            ros,
            vec![],
            async |rt, _| play::run(rt, a).await,
        ),
        Cmd::Echo(a) => run_with(
            cli::tool_spec("skyground_echo"),
            ros,
            vec![],
            async |rt, _| echo::run(rt, a).await,
        ),
        Cmd::CloudSink(a) => run_with(
            cli::tool_spec("skyground_cloud_sink"),
            ros,
            vec![],
            async |rt, _| sink::run(rt, a).await,
        ),
        Cmd::Bench {
            which: bench::BenchCmd::Lidar(a),
            ..
        } => bench::lidar(&a),
        Cmd::Bench { no_netns, which } => {
            if !no_netns && !netns::is_isolated() {
                eprintln!("skyground bench: re-running inside a loopback-only network namespace");
                return exec_failed(netns::exec_self_isolated());
            }
            run_with(
                cli::tool_spec("skyground_bench"),
                ros,
                vec![],
                async |rt, _| match which {
                    bench::BenchCmd::Transport(a) => bench::transport(rt, a).await,
                    bench::BenchCmd::Lidar(_) => Ok(()),
                },
            )
        }
    }
}

/// Ends an offline command: its JSON on stdout with `--json` (else on
/// stderr when `echo` is set), or its error.
fn offline(
    name: &str,
    json: bool,
    echo: bool,
    result: Result<serde_json::Value, skyground_nodes::runtime::RuntimeError>,
) -> ExitCode {
    match result {
        Ok(v) => {
            if json {
                println!("{v}");
            } else if echo {
                eprintln!("{v:#}");
            }
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("skyground {name}: {e}");
            ExitCode::FAILURE
        }
    }
}

/// What is left when exec into the isolated command failed.
fn exec_failed(e: std::io::Error) -> ExitCode {
    eprintln!("skyground: cannot start the isolated command (needs `unshare` and `ip`): {e}");
    ExitCode::FAILURE
}

fn msgs(which: MsgsCmd) -> ExitCode {
    match which {
        MsgsCmd::List => {
            for t in skyground_msgs::known_types() {
                println!("{t}");
            }
            ExitCode::SUCCESS
        }
        MsgsCmd::Show { type_name } => match skyground_msgs::full_definition(&type_name) {
            Some(text) => {
                print!("{text}");
                ExitCode::SUCCESS
            }
            None => {
                eprintln!("skyground: unknown message type `{type_name}`");
                ExitCode::FAILURE
            }
        },
        MsgsCmd::Samples => {
            for s in skyground_msgs::samples::all() {
                println!("{}", s.to_json_line());
            }
            ExitCode::SUCCESS
        }
    }
}
