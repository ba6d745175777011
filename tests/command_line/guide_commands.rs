//! Every command the README and the user guide (`docs/guide/*.md`) show is run by this test, as
//! printed, in a fresh folder per page that holds a copy of `assets/` and `docs/sweeps/`:
//!
//! - each line of a ```` ```sh ```` block is one command (a line ending in `\` continues), run
//!   with `bash -eo pipefail` in the page's folder, in order, and must succeed; a `# → TEXT`
//!   comment on it means its output must contain TEXT;
//! - `rollphase` is found through `tests/guide/rollphase`, which runs the binary under test and
//!   shortens only what would take minutes (full-size figures, hundreds of frames) or needs a
//!   display (the app, under Xvfb for 2 s); each of its rules says why, and every rule must be
//!   used by some command here, so none lingers;
//! - `cargo run -- ARGS` is `rollphase ARGS`; the other cargo commands are in [`NOT_RUN`] with
//!   the reason;
//! - an HTML comment right before a block marks it: `<!-- guide-test: file NAME -->` writes the
//!   block to NAME in the page's folder first, `<!-- guide-test: slurm -->` is for the Slurm test
//!   below, `<!-- guide-test: not run: REASON -->` is skipped with its reason.
//!
//! The Slurm test runs `docs/guide/cluster.md`'s array job and its `afterok` merge on a
//! single-node Slurm on loopback (`tests/slurm/cluster.sh`; Debian's `slurm-wlm` and `munge`,
//! which `.ci/run` installs) and checks the merged files byte for byte against one unsharded run.
//!
//! Both need the app and renderer (the default features), so `cargo test --no-default-features`
//! skips the file rather than run the cluster twice.
#![cfg(feature = "app")]

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::{Duration, Instant};

const REPO: &str = env!("CARGO_MANIFEST_DIR");

/// Commands shown but not run here, each with the reason.
const NOT_RUN: &[(&str, &str)] = &[
    ("cargo test", "the test suite this test is part of"),
    (
        "cargo test -- --include-ignored",
        "the whole test suite, this test included",
    ),
    (
        "cargo install --path .",
        "a release build of the binary that `cargo test` built and this test runs",
    ),
];

/// A fenced block of a page.
struct Block {
    page: String,
    line: usize,
    lang: String,
    marker: Option<String>,
    text: String,
}

fn pages() -> Vec<PathBuf> {
    let mut pages: Vec<PathBuf> = std::fs::read_dir(Path::new(REPO).join("docs/guide"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "md"))
        .collect();
    pages.sort();
    pages.insert(0, Path::new(REPO).join("README.md"));
    pages
}

fn blocks(page: &Path) -> Vec<Block> {
    let text = std::fs::read_to_string(page).unwrap();
    let name = page.strip_prefix(REPO).unwrap().display().to_string();
    let mut out = Vec::new();
    let mut lines = text.lines().enumerate();
    let mut marker: Option<String> = None;
    while let Some((i, line)) = lines.next() {
        let t = line.trim();
        if let Some(m) = t
            .strip_prefix("<!-- guide-test:")
            .and_then(|m| m.strip_suffix("-->"))
        {
            marker = Some(m.trim().to_string());
            continue;
        }
        if let Some(lang) = t.strip_prefix("```") {
            let mut body = String::new();
            for (_, l) in lines.by_ref() {
                if l.trim() == "```" {
                    break;
                }
                body.push_str(l.trim_start_matches(' '));
                body.push('\n');
            }
            out.push(Block {
                page: name.clone(),
                line: i + 1,
                lang: lang.trim().to_string(),
                marker: marker.take(),
                text: body,
            });
            continue;
        }
        if !t.is_empty() {
            marker = None;
        }
    }
    out
}

/// The logical lines of a shell block: continuations joined, blank and comment lines dropped.
fn commands(block: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut current = String::new();
    for line in block.lines() {
        if let Some(head) = line.strip_suffix('\\') {
            current.push_str(head);
            current.push(' ');
            continue;
        }
        current.push_str(line);
        let command = std::mem::take(&mut current);
        let trimmed = command.trim();
        if !trimmed.is_empty() && !trimmed.starts_with('#') {
            out.push(trimmed.to_string());
        }
    }
    out
}

/// What a command's output must contain: the text after `# →` in its comment.
fn expected(command: &str) -> Option<&str> {
    command
        .split_once("# →")
        .map(|(_, e)| e.trim())
        .filter(|e| !e.is_empty())
}

/// `cargo run -- ARGS` as the installed `rollphase ARGS`; `None` for a command not run here.
fn as_run(command: &str) -> Option<String> {
    if let Some(rest) = command.strip_prefix("cargo run --") {
        return Some(format!("rollphase{rest}"));
    }
    if let Some(rest) = command.strip_prefix("cargo run")
        && (rest.is_empty() || rest.starts_with(' '))
    {
        return Some(format!("rollphase{rest}"));
    }
    let plain = command.split(" #").next().unwrap_or(command).trim();
    if plain.starts_with("cargo ") || plain.contains("&& cargo ") {
        let known = NOT_RUN.iter().any(|(c, _)| *c == plain);
        assert!(
            known,
            "`{plain}` is shown in the guide but neither run nor in NOT_RUN"
        );
        return None;
    }
    Some(command.to_string())
}

/// A fresh folder for one page, with the files its commands name.
fn workdir(tag: &str) -> PathBuf {
    let dir = crate::cli::scratch(&format!("guide-{tag}"));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(dir.join("docs")).unwrap();
    let copy = |from: &str, to: &Path| {
        let ok = Command::new("cp")
            .arg("-r")
            .arg(Path::new(REPO).join(from))
            .arg(to)
            .status()
            .unwrap()
            .success();
        assert!(ok, "copying {from}");
    };
    copy("assets", &dir);
    copy("docs/sweeps", &dir.join("docs"));
    dir
}

fn guide_env(cmd: &mut Command, log: &Path) {
    let path = format!(
        "{}:{}",
        Path::new(REPO).join("tests/guide").display(),
        std::env::var("PATH").unwrap_or_default()
    );
    cmd.env("PATH", path)
        .env("ROLLPHASE_REAL", crate::cli::binary())
        .env("ROLLPHASE_GUIDE_LOG", log)
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY");
}

/// Runs one page's commands in order; returns how many ran.
fn run_page(page: &Path, log: &Path) -> usize {
    let blocks = blocks(page);
    let tag = page
        .strip_prefix(REPO)
        .unwrap()
        .display()
        .to_string()
        .replace(['/', '.'], "-");
    let dir = workdir(&tag);
    for b in &blocks {
        if let Some(name) = b.marker.as_deref().and_then(|m| m.strip_prefix("file ")) {
            std::fs::write(dir.join(name.trim()), &b.text).unwrap();
        }
    }
    let mut ran = 0;
    for b in blocks.iter().filter(|b| b.lang == "sh") {
        match b.marker.as_deref() {
            None => {}
            Some(m) if m.starts_with("not run:") => {
                assert!(
                    m.len() > "not run:".len() + 3,
                    "{}:{}: give the reason",
                    b.page,
                    b.line
                );
                continue;
            }
            Some(m) if m == "slurm" || m.starts_with("file ") => continue,
            Some(m) => panic!("{}:{}: unknown guide-test marker {m:?}", b.page, b.line),
        }
        for command in commands(&b.text) {
            let Some(line) = as_run(&command) else {
                continue;
            };
            let mut cmd = Command::new("bash");
            cmd.args(["-eo", "pipefail", "-c", &line]).current_dir(&dir);
            guide_env(&mut cmd, log);
            let start = Instant::now();
            let out = cmd.output().unwrap();
            let text = format!(
                "{}{}",
                String::from_utf8_lossy(&out.stdout),
                String::from_utf8_lossy(&out.stderr)
            );
            assert!(
                out.status.success(),
                "{}:{}: `{command}` failed ({}):\n{text}",
                b.page,
                b.line,
                out.status
            );
            if let Some(want) = expected(&command) {
                assert!(
                    text.contains(want),
                    "{}:{}: `{command}` printed\n{text}\nwithout {want:?}",
                    b.page,
                    b.line
                );
            }
            eprintln!(
                "{}: ran `{line}` in {:.1} s",
                b.page,
                start.elapsed().as_secs_f64()
            );
            ran += 1;
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
    ran
}

#[test]
#[ignore = "slow: every command of the README and the guide (1 min)"]
fn every_command_in_the_readme_and_the_guide_runs() {
    let log = crate::cli::scratch("guide").join("guide.log");
    let _ = std::fs::remove_file(&log);
    let pages = pages();
    assert!(pages.len() >= 10, "the guide has {} pages", pages.len());
    // Two workers, each taking the next page when its last is done (the pages' times differ
    // by 50×: in pairs, a short page's worker waited for the long one, 155 s against 85 s);
    // each page's commands run in order, in its own folder.
    let next = std::sync::atomic::AtomicUsize::new(0);
    let total: usize = std::thread::scope(|s| {
        let workers: Vec<_> = (0..2)
            .map(|_| {
                s.spawn(|| {
                    let mut ran = 0;
                    while let Some(page) =
                        pages.get(next.fetch_add(1, std::sync::atomic::Ordering::Relaxed))
                    {
                        ran += run_page(page, &log);
                    }
                    ran
                })
            })
            .collect();
        workers.into_iter().map(|w| w.join().unwrap()).sum()
    });
    assert!(total >= 40, "only {total} commands ran");
    // Every rule of the wrapper was needed by some command.
    let used = std::fs::read_to_string(&log).unwrap();
    let wrapper = std::fs::read_to_string(Path::new(REPO).join("tests/guide/rollphase")).unwrap();
    let has_ffmpeg = Command::new("ffmpeg").arg("-version").output().is_ok();
    for rule in wrapper
        .lines()
        .filter_map(|l| l.trim().strip_prefix("rule "))
        .map(|r| r.trim_matches('"'))
    {
        if rule == "mp4-without-ffmpeg" && has_ffmpeg {
            continue;
        }
        assert!(
            used.lines().any(|l| l.starts_with(&format!("{rule} ::"))),
            "no command in the guide needed the wrapper's rule {rule:?}: remove it"
        );
    }
    let _ = std::fs::remove_file(&log);
}

/// A running single-node Slurm, stopped on drop.
struct Cluster(PathBuf);

impl Drop for Cluster {
    fn drop(&mut self) {
        let _ = Command::new("bash")
            .arg(Path::new(REPO).join("tests/slurm/cluster.sh"))
            .arg("stop")
            .arg(&self.0)
            .status();
    }
}

fn slurm_available() -> bool {
    let root = Command::new("id")
        .arg("-u")
        .output()
        .is_ok_and(|o| String::from_utf8_lossy(&o.stdout).trim() == "0");
    let tools = ["sbatch", "slurmctld", "slurmd", "munged", "squeue"]
        .iter()
        .all(|t| {
            Command::new("bash")
                .args(["-c", &format!("command -v {t}")])
                .output()
                .is_ok_and(|o| o.status.success())
        });
    root && tools
}

#[test]
#[ignore = "slow: a Slurm array job on a one-node Slurm"]
fn the_cluster_pages_slurm_array_job_merges_byte_identically() {
    if !slurm_available() {
        assert!(
            std::env::var_os("CI").is_none(),
            "CI must run the Slurm job: run as root with slurm-wlm and munge installed (.ci/run does)"
        );
        eprintln!("skipped: needs root and slurm-wlm + munge (apt-get install slurm-wlm munge)");
        return;
    }
    let page = Path::new(REPO).join("docs/guide/cluster.md");
    let blocks = blocks(&page);
    let dir = workdir("slurm");
    for b in &blocks {
        if let Some(name) = b.marker.as_deref().and_then(|m| m.strip_prefix("file ")) {
            std::fs::write(dir.join(name.trim()), &b.text).unwrap();
        }
    }
    let job: Vec<&Block> = blocks
        .iter()
        .filter(|b| b.marker.as_deref() == Some("slurm"))
        .collect();
    assert_eq!(job.len(), 1, "cluster.md has one block marked slurm");
    for file in ["scan.toml", "scan.sbatch"] {
        assert!(dir.join(file).exists(), "cluster.md shows no {file}");
    }
    let cluster = Cluster(dir.join("cluster"));
    let up = Command::new("bash")
        .arg(Path::new(REPO).join("tests/slurm/cluster.sh"))
        .arg("start")
        .arg(&cluster.0)
        .output()
        .unwrap();
    assert!(
        up.status.success(),
        "the test cluster did not start: {}",
        String::from_utf8_lossy(&up.stderr)
    );
    let conf = cluster.0.join("slurm.conf");
    let scratch = dir.join("scratch");
    std::fs::create_dir_all(&scratch).unwrap();
    let log = dir.join("wrapper.log");
    let mut submit = Command::new("bash");
    submit
        .args(["-eo", "pipefail", "-c", &job[0].text])
        .current_dir(&dir)
        .env("SLURM_CONF", &conf)
        .env("SCRATCH", &scratch);
    guide_env(&mut submit, &log);
    let out = submit.output().unwrap();
    assert!(
        out.status.success(),
        "submitting failed: {}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    // Wait for the array and the merge to leave the queue.
    let start = Instant::now();
    loop {
        let q = Command::new("squeue")
            .args(["-h", "-o", "%i %T"])
            .env("SLURM_CONF", &conf)
            .output()
            .unwrap();
        let queue = String::from_utf8_lossy(&q.stdout).to_string();
        if q.status.success() && queue.trim().is_empty() {
            break;
        }
        assert!(
            start.elapsed() < Duration::from_secs(600),
            "the jobs are still queued after 10 minutes:\n{queue}"
        );
        std::thread::sleep(Duration::from_millis(500));
    }
    eprintln!(
        "Slurm: 64-task array and afterok merge done in {:.1} s",
        start.elapsed().as_secs_f64()
    );
    let merged = scratch.join("scan");
    let merge_log = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .find(|p| {
            p.file_name()
                .unwrap()
                .to_string_lossy()
                .starts_with("slurm-")
        })
        .map(|p| std::fs::read_to_string(p).unwrap())
        .unwrap_or_default();
    eprintln!("merge job's log: {merge_log}");
    let task_logs = std::fs::read_dir(dir.join("logs")).unwrap().count();
    assert_eq!(task_logs, 64, "one log per array task");
    assert!(
        merged.join("sweep.csv").exists(),
        "the merge wrote no sweep.csv; its log: {merge_log}"
    );
    let whole = Command::new(crate::cli::binary())
        .args(["sweep", "scan.toml", "--out", "whole"])
        .current_dir(&dir)
        .output()
        .unwrap();
    assert!(
        whole.status.success(),
        "{}",
        String::from_utf8_lossy(&whole.stderr)
    );
    for file in ["sweep.csv", "summary.json"] {
        let a = std::fs::read(merged.join(file)).unwrap();
        let b = std::fs::read(dir.join("whole").join(file)).unwrap();
        assert!(
            a == b,
            "{file}: the Slurm merge differs from one unsharded run"
        );
    }
    drop(cluster);
    let _ = std::fs::remove_dir_all(&dir);
}
