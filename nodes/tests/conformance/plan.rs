//! Which commands apply to a file, with what arguments, and what each leaves
//! where: decided from the file's extension and, for the demo, its content,
//! so a file dropped into the folder needs no code.

use std::path::{Path, PathBuf};

/// A `skyground` subcommand the suite runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Command {
    Info,
    Classify,
    Detect,
    Reconstruct,
    Aerial,
    Demo,
}

/// Every command, in the table's column order.
pub const COMMANDS: [Command; 6] = [
    Command::Info,
    Command::Classify,
    Command::Detect,
    Command::Reconstruct,
    Command::Aerial,
    Command::Demo,
];

impl Command {
    /// The subcommand's name.
    pub fn name(self) -> &'static str {
        match self {
            Command::Info => "info",
            Command::Classify => "classify",
            Command::Detect => "detect",
            Command::Reconstruct => "reconstruct",
            Command::Aerial => "aerial",
            Command::Demo => "demo",
        }
    }
}

/// City models up to this size also go through a (short) demo.
const DEMO_MAX_BYTES: u64 = 16 * 1024;
/// The demo's own `--timeout` (wall seconds).
pub const DEMO_TIMEOUT_S: u32 = 10;

/// The file's extension, lower case (`x.city.json` → `json`).
pub fn extension(path: &Path) -> String {
    path.extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
        .unwrap_or_default()
}

/// The commands that apply to `path`: every cloud command for a point cloud
/// (PLY may also be a mesh, so it is a scene too), `aerial` for a scene,
/// `demo` for a small city model with a building, `info` for anything.
pub fn commands_for(path: &Path) -> Vec<Command> {
    use Command::*;
    match extension(path).as_str() {
        "las" | "laz" => vec![Info, Classify, Detect, Reconstruct],
        "ply" => vec![Info, Classify, Detect, Reconstruct, Aerial],
        "json" | "jsonl" if small_city_model(path) => vec![Info, Aerial, Demo],
        "json" | "jsonl" | "obj" => vec![Info, Aerial],
        _ => vec![Info],
    }
}

/// A CityJSON (or CityJSONSeq) file small enough for a short demo that has
/// at least one building.
fn small_city_model(path: &Path) -> bool {
    let small = std::fs::metadata(path).is_ok_and(|m| m.len() <= DEMO_MAX_BYTES);
    let text = small
        .then(|| std::fs::read_to_string(path).ok())
        .flatten()
        .unwrap_or_default();
    text.contains("\"CityJSON") && text.contains("\"Building\"")
}

/// Where one run writes: its own directory, and the output path it is given.
pub struct Layout {
    /// The run's directory (stdout, stderr and the output live under it).
    pub dir: PathBuf,
    /// The path given as `--out` (a file for classify, a directory otherwise).
    pub out: PathBuf,
    /// The directory every output goes to.
    pub outputs: PathBuf,
    /// An output file of the command that holds an earlier run's content
    /// before the run: a failure must leave it as it was.
    pub seeded: Option<PathBuf>,
}

impl Layout {
    /// The layout of `command` on `file` under `root`.
    pub fn new(root: &Path, file: &Path, command: Command) -> Layout {
        let name = file.file_name().map(|n| n.to_string_lossy().into_owned());
        let dir = root.join(format!("{}.{}", name.unwrap_or_default(), command.name()));
        let out = match command {
            Command::Classify => dir.join(format!("out/classified.{}", extension(file))),
            _ => dir.join("out"),
        };
        let seeded = match command {
            Command::Info | Command::Demo => None,
            Command::Classify => Some(out.clone()),
            Command::Detect => Some(out.join("detection.json")),
            Command::Reconstruct => Some(out.join("reconstruct.json")),
            Command::Aerial => Some(out.join("summary.json")),
        };
        Layout {
            outputs: dir.join("out"),
            dir,
            out,
            seeded,
        }
    }

    /// The arguments after the binary.
    pub fn args(&self, file: &Path, command: Command) -> Vec<String> {
        let f = file.display().to_string();
        let out = self.out.display().to_string();
        let v = |a: &[&str]| a.iter().map(|s| (*s).to_string()).collect::<Vec<_>>();
        match command {
            Command::Info => v(&["info", "--json", &f]),
            Command::Classify => v(&["classify", "--in", &f, "--out", &out]),
            Command::Detect => v(&["detect", "--in", &f, "--out", &out]),
            Command::Reconstruct => v(&["reconstruct", "--in", &f, "--out", &out]),
            Command::Aerial => v(&["aerial", "--scene", &f, "--out", &out]),
            Command::Demo => {
                let t = DEMO_TIMEOUT_S.to_string();
                v(&["demo", "--scene", &f, "--out", &out, "--timeout", &t])
            }
        }
    }
}

/// The text an earlier run left in a seeded output.
pub const EARLIER: &[u8] = b"an earlier run's output\n";
