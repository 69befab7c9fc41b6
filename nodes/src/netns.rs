//! Keeping DDS on this machine: run a command inside a fresh network namespace
//! that has only loopback (with multicast routed to it), as docs/design.md asks.

use std::ffi::OsString;
use std::os::unix::process::CommandExt;
use std::process::Command;

/// Shell that brings loopback up with multicast, moves the ephemeral port
/// range above DDS's well-known ports, then runs the command.
///
/// Those ports are 7400 + 250 * domain + a few; for domains above ~101 they
/// fall inside Linux's default ephemeral range (32768-60999), where any socket
/// bound to port 0 may take one and a participant is then never discovered.
/// 61000-65535 stays clear of the ports of domains 0-214.
const SETUP: &str = "ip link set lo up && ip link set lo multicast on && \
                     ip route add 224.0.0.0/4 dev lo && \
                     echo '61000 65535' > /proc/sys/net/ipv4/ip_local_port_range && \
                     exec \"$@\"";

/// Set in the environment of commands this module isolated, so that they
/// never try to isolate themselves again.
pub const ISOLATED_ENV: &str = "SKYGROUND_NETNS";

/// True when this process's network namespace has no interface but `lo`.
/// (/proc/net/dev follows the caller's namespace; /sys/class/net would not.)
pub fn is_isolated() -> bool {
    if std::env::var_os(ISOLATED_ENV).is_some_and(|v| v == "1") {
        return true;
    }
    match std::fs::read_to_string("/proc/net/dev") {
        Ok(text) => text
            .lines()
            .skip(2)
            .filter_map(|l| l.split(':').next())
            .all(|name| name.trim() == "lo"),
        Err(_) => false,
    }
}

/// Replaces this process by `program args` in a new loopback-only namespace
/// (`unshare` and `sh` both exec, so the PID stays the same and a SIGINT or
/// SIGTERM sent to it reaches the isolated command). Returns only on failure.
/// As root this is `unshare --net`; otherwise an unprivileged user namespace.
pub fn exec_isolated(program: &OsString, args: &[OsString]) -> std::io::Error {
    let root = nix_is_root();
    let mut cmd = Command::new("unshare");
    if !root {
        cmd.args(["--user", "--map-root-user"]);
    }
    cmd.args(["--net", "--", "sh", "-c", SETUP, "netns"]);
    cmd.arg(program).args(args).env(ISOLATED_ENV, "1");
    cmd.exec()
}

/// Replaces this process by the current executable with the same arguments, isolated.
pub fn exec_self_isolated() -> std::io::Error {
    match std::env::current_exe() {
        Ok(exe) => {
            let args: Vec<OsString> = std::env::args_os().skip(1).collect();
            exec_isolated(&exe.into_os_string(), &args)
        }
        Err(e) => e,
    }
}

fn nix_is_root() -> bool {
    // /proc/self/status holds "Uid: real effective ..."; no libc call needed.
    std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("Uid:"))
                .and_then(|l| l.split_whitespace().nth(2).map(|u| u == "0"))
        })
        .unwrap_or(false)
}
