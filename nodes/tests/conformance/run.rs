//! Running the jobs: a few at a time, each under a memory limit (`prlimit
//! --as`, so a runaway allocation aborts instead of taking the machine) and
//! a time limit, its stdout and stderr kept beside its outputs.

use std::path::{Path, PathBuf};
use std::process::{Command as Process, Stdio};
use std::sync::Mutex;
use std::time::{Duration, Instant};

use super::plan::{Command, DEMO_TIMEOUT_S, EARLIER, Layout};
use super::verdict::{Outcome, Verdict, judge};

/// Address space one run may take: a command whose input needs more must
/// say so, not abort when it runs out.
const MEMORY_LIMIT: u64 = 4 << 30;
/// Wall seconds one run may take (the machine may be shared).
const TIME_LIMIT_S: u64 = 300;

/// One command on one file.
#[derive(Debug, Clone)]
pub struct Job {
    pub file: PathBuf,
    pub command: Command,
}

/// A job and how it ended.
pub struct Done {
    pub job: Job,
    pub verdict: Verdict,
    pub seconds: f64,
}

/// Runs every job, as many at once as there are cores; results in job order.
pub fn all(bin: &Path, root: &Path, jobs: Vec<Job>) -> Vec<Done> {
    let workers = std::thread::available_parallelism().map_or(2, |n| n.get());
    let queue = Mutex::new(jobs.into_iter().enumerate().collect::<Vec<_>>());
    let done = Mutex::new(Vec::new());
    std::thread::scope(|s| {
        for _ in 0..workers {
            s.spawn(|| {
                loop {
                    let next = queue.lock().expect("queue").pop();
                    let Some((i, job)) = next else { break };
                    let d = one(bin, root, job, i);
                    done.lock().expect("results").push((i, d));
                }
            });
        }
    });
    let mut done = done.into_inner().expect("results");
    done.sort_by_key(|(i, _)| *i);
    done.into_iter().map(|(_, d)| d).collect()
}

fn one(bin: &Path, root: &Path, job: Job, index: usize) -> Done {
    let layout = Layout::new(root, &job.file, job.command);
    std::fs::create_dir_all(&layout.outputs).expect("run directory");
    if let Some(seed) = &layout.seeded {
        std::fs::write(seed, EARLIER).expect("seed an earlier output");
    }
    let started = Instant::now();
    let outcome = launch(bin, &layout, &job, index);
    let seconds = started.elapsed().as_secs_f64();
    let verdict = judge(&job.file, job.command, &layout, &outcome);
    Done {
        job,
        verdict,
        seconds,
    }
}

/// The process, under the memory limit, killed at the time limit. The demo
/// gets a network namespace of its own (`skyground netns`) and a domain id
/// of its own, so demos run side by side never meet.
fn launch(bin: &Path, layout: &Layout, job: &Job, index: usize) -> Outcome {
    let (out, err) = (layout.dir.join("stdout"), layout.dir.join("stderr"));
    let mut p = Process::new("prlimit");
    p.arg(format!("--as={MEMORY_LIMIT}")).arg("--").arg(bin);
    if job.command == Command::Demo {
        p.arg("netns").arg(bin);
        p.env("ROS_DOMAIN_ID", (100 + index % 100).to_string());
    }
    p.args(layout.args(&job.file, job.command))
        .current_dir(&layout.dir)
        .stdin(Stdio::null())
        .stdout(std::fs::File::create(&out).expect("stdout file"))
        .stderr(std::fs::File::create(&err).expect("stderr file"));
    let mut child = p.spawn().expect("prlimit and the binary start");
    let limit = match job.command {
        Command::Demo => TIME_LIMIT_S + u64::from(DEMO_TIMEOUT_S),
        _ => TIME_LIMIT_S,
    };
    let end = Instant::now() + Duration::from_secs(limit);
    let (status, timed_out) = loop {
        if let Some(s) = child.try_wait().expect("wait") {
            break (Some(s), false);
        }
        if Instant::now() > end {
            let _ = child.kill();
            break (child.wait().ok(), true);
        }
        std::thread::sleep(Duration::from_millis(50));
    };
    let read = |p: &Path| String::from_utf8_lossy(&std::fs::read(p).unwrap_or_default()).into();
    Outcome {
        code: status.and_then(|s| s.code()),
        timed_out,
        stdout: read(&out),
        stderr: read(&err),
    }
}
