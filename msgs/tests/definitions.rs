//! Each type's DEFINITION equals the upstream .msg file, comments and spacing aside.
//!
//! Reads the ROS 2 share directory named by `SKYGROUND_ROS_SHARE` (default
//! `.venv/share` of the repository, where pip's `ros-kilted-*` packages put their
//! .msg files); when it is absent the comparison is skipped with a note.

use std::path::PathBuf;

use skyground_msgs::{full_definition, known_types};

const PRIMITIVES: &[&str] = &[
    "bool", "byte", "char", "int8", "uint8", "int16", "uint16", "int32", "uint32", "int64",
    "uint64", "float32", "float64", "string", "wstring",
];

/// One .msg line in canonical form: no comment, single spaces, `pkg/Type`, `NAME = value`.
fn canonical(line: &str, package: &str) -> Option<String> {
    let line = line.split('#').next()?.trim();
    if line.is_empty() {
        return None;
    }
    let (type_part, rest) = line.split_once(char::is_whitespace)?;
    let base = type_part.split('[').next()?;
    let type_part = if base.contains('/') || PRIMITIVES.contains(&base) {
        type_part.to_owned()
    } else {
        format!("{package}/{type_part}")
    };
    let rest = match rest.split_once('=') {
        Some((name, value)) => format!("{} = {}", name.trim(), value.trim()),
        None => rest.split_whitespace().collect::<Vec<_>>().join(" "),
    };
    Some(format!("{type_part} {rest}"))
}

fn canonical_text(text: &str, package: &str) -> Vec<String> {
    text.lines().filter_map(|l| canonical(l, package)).collect()
}

#[test]
fn definitions_match_upstream_msg_files() {
    let share = std::env::var_os("SKYGROUND_ROS_SHARE")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../.venv/share")));
    if !share.is_dir() {
        eprintln!("skipped: no ROS share directory at {}", share.display());
        return;
    }
    // tf2_msgs ships no wheel on PyPI, so the venv has no share for it; its
    // one field is checked against rclpy's TransformStamped bytes instead.
    const NO_WHEEL: &[&str] = &["tf2_msgs"];
    for name in known_types() {
        let mut parts = name.split('/');
        let (package, _, ty) = (parts.next().unwrap(), parts.next(), parts.next().unwrap());
        if NO_WHEEL.contains(&package) && !share.join(package).is_dir() {
            eprintln!("SKIPPED {name}: {package} has no wheel on PyPI, so no upstream .msg here");
            continue;
        }
        let path = share.join(package).join("msg").join(format!("{ty}.msg"));
        let upstream = std::fs::read_to_string(&path).unwrap();
        let full = full_definition(name).unwrap();
        let own = full.split("=====").next().unwrap();
        assert_eq!(
            canonical_text(own, package),
            canonical_text(&upstream, package),
            "{name}"
        );
    }
}
