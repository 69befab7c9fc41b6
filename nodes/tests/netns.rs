//! `skyground netns CMD`: the command sees only loopback, and an ephemeral
//! port range above the DDS ports of the domains the tests use.

use std::process::Command;

fn isolated(cmd: &[&str]) -> String {
    let out = Command::new(env!("CARGO_BIN_EXE_skyground"))
        .arg("netns")
        .args(cmd)
        .output()
        .expect("skyground netns runs");
    assert!(
        out.status.success(),
        "skyground netns {cmd:?} failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

#[test]
fn only_loopback_is_up() {
    let dev = isolated(&["cat", "/proc/net/dev"]);
    let names: Vec<&str> = dev
        .lines()
        .skip(2)
        .filter_map(|l| l.split(':').next())
        .map(str::trim)
        .collect();
    assert_eq!(names, ["lo"]);
}

#[test]
fn ephemeral_ports_stay_clear_of_dds_ports() {
    let range = isolated(&["cat", "/proc/sys/net/ipv4/ip_local_port_range"]);
    let from: u32 = range
        .split_whitespace()
        .next()
        .and_then(|s| s.parse().ok())
        .unwrap_or_else(|| panic!("unreadable port range {range:?}"));
    // The highest port a participant (id < 20) of domain 214 binds.
    let highest_dds = 7400 + 250 * 214 + 10 + 2 * 20 + 1;
    assert!(
        from > highest_dds,
        "ephemeral ports from {from}, DDS ports up to {highest_dds}"
    );
}
