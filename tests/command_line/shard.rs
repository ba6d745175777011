//! Scale-out (`--shard I/N`, `merge`): N shards run as separate processes and merged give the
//! bytes of one unsharded run, for every ensemble figure and for `sweep`; a missing, duplicated
//! or foreign shard is refused with a message that names it.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn rollphase(args: &[&str]) -> Output {
    Command::new(crate::cli::binary())
        .args(args)
        .output()
        .expect("runs")
}

fn ok(args: &[&str]) -> String {
    let o = rollphase(args);
    assert!(
        o.status.success(),
        "{args:?} failed: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    String::from_utf8_lossy(&o.stdout).into_owned()
}

fn fails(args: &[&str]) -> String {
    let o = rollphase(args);
    assert!(!o.status.success(), "{args:?} should fail");
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn scratch(name: &str) -> PathBuf {
    let d = crate::cli::scratch(&format!("shard-{name}"));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn same_bytes(a: &Path, b: &Path) {
    let (x, y) = (std::fs::read(a).unwrap(), std::fs::read(b).unwrap());
    assert!(
        x == y,
        "{} and {} differ ({} and {} bytes)",
        a.display(),
        b.display(),
        x.len(),
        y.len()
    );
}

/// The figure at --quick, whole and as `n` shards merged: the same data.csv, summary.json and
/// figure.png. The whole run uses 2 threads and each shard 1, so thread count is covered too.
fn figure_shards_merge_to_the_whole(name: &str, n: usize) {
    let root = scratch(name);
    let (whole, parts) = (root.join("whole"), root.join("parts"));
    let (w, p) = (whole.to_str().unwrap(), parts.to_str().unwrap());
    ok(&["figure", name, "--quick", "--threads", "2", "--out", w]);
    for i in 1..=n {
        let spec = format!("{i}/{n}");
        let said = ok(&[
            "figure",
            name,
            "--quick",
            "--threads",
            "1",
            "--out",
            p,
            "--shard",
            &spec,
        ]);
        assert!(said.contains(&format!("shard {spec} wrote")), "{said}");
        let dir = parts.join(name);
        assert!(dir.join(format!("shard-{i}-of-{n}.json")).is_file());
        assert!(
            !dir.join("data.csv").exists() && !dir.join("figure.png").exists(),
            "a shard writes no figure"
        );
    }
    let said = ok(&["merge", parts.join(name).to_str().unwrap()]);
    assert!(said.contains(&format!("from {n} shards")), "{said}");
    for f in ["data.csv", "summary.json", "figure.png"] {
        same_bytes(&whole.join(name).join(f), &parts.join(name).join(f));
    }
    let _ = std::fs::remove_dir_all(&root);
}

#[test]
#[ignore = "slow: shard byte-identity, a figure run whole and in shards"]
fn sphere_cruising_shards_merge_to_the_unsharded_bytes() {
    figure_shards_merge_to_the_whole("sphere-cruising", 3);
}

#[test]
fn sphere_poincare_shards_merge_to_the_unsharded_bytes() {
    figure_shards_merge_to_the_whole("sphere-poincare", 4);
}

#[test]
fn sphere_orbits_shards_merge_to_the_unsharded_bytes() {
    figure_shards_merge_to_the_whole("sphere-orbits", 3);
}

#[test]
#[ignore = "slow: shard byte-identity, a figure run whole and in shards"]
fn sphere_doubling_shards_merge_to_the_unsharded_bytes() {
    figure_shards_merge_to_the_whole("sphere-doubling", 3);
}

#[test]
#[ignore = "slow: shard byte-identity, a figure run whole and in shards"]
fn sphere_bifurcation_shards_merge_to_the_unsharded_bytes() {
    figure_shards_merge_to_the_whole("sphere-bifurcation", 2);
}

#[test]
#[ignore = "slow: shard byte-identity, a figure run whole and in shards"]
fn model_validity_shards_merge_to_the_unsharded_bytes() {
    figure_shards_merge_to_the_whole("model-validity", 4);
}

#[test]
#[ignore = "slow: shard byte-identity, a figure run whole and in shards"]
fn disk_transition_shards_merge_to_the_unsharded_bytes() {
    // More shards than disks would leave some empty: 7 shards of 6 disks covers that case.
    figure_shards_merge_to_the_whole("disk-transition", 7);
}

const SPEC: &str = r#"
alpha = { from = 0.12, to = 0.2, count = 3 }
mass_ratio = [0.0, 6.0]
orientations = 2
integrators = ["fast", "dop853:1e-9"]
t_max = 300.0

[bodies]
paper_seeds = [219]
seeds = [1]
files = ["body.json"]
"#;

#[test]
fn a_sweep_writes_one_row_per_run_and_its_shards_merge_to_the_same_bytes() {
    let root = scratch("sweep");
    std::fs::copy(
        concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/assets/shapes/paper-sphere.json"
        ),
        root.join("body.json"),
    )
    .unwrap();
    let spec = root.join("spec.toml");
    std::fs::write(&spec, SPEC).unwrap();
    let (whole, parts) = (root.join("whole"), root.join("parts"));
    let s = spec.to_str().unwrap();
    ok(&["sweep", s, "--out", whole.to_str().unwrap()]);
    let csv = std::fs::read_to_string(whole.join("sweep.csv")).unwrap();
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    for col in [
        "period",
        "inverse_period",
        "multiplicity",
        "cruising",
        "rhs_evals",
    ] {
        assert!(header.contains(&col), "{header:?}");
    }
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    // 3 bodies × 3 α × 2 masses × 2 orientations × 2 integrators.
    assert_eq!(rows.len(), 72);
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
    for r in &rows {
        let evals: u64 = r[col("rhs_evals")].parse().unwrap();
        assert!(evals > 0);
        // The contact force along each run: N/F in order around cos α, the friction needed
        // at least tan α's share (a viscous run needs exactly tan α), no lift-off this gently.
        let alpha: f64 = r[col("alpha")].parse().unwrap();
        let n_min: f64 = r[col("min_normal_force")].parse().unwrap();
        let n_max: f64 = r[col("max_normal_force")].parse().unwrap();
        let mu: f64 = r[col("max_friction_needed")].parse().unwrap();
        assert!(0.0 < n_min && n_min <= alpha.cos() + 1e-12 && alpha.cos() - 1e-12 <= n_max);
        assert!(mu >= alpha.tan() - 1e-12, "{r:?}");
        if r[col("mass_ratio")] == "0" {
            assert_eq!((n_min, n_max), (alpha.cos(), alpha.cos()));
            assert!((mu - alpha.tan()).abs() < 1e-15, "{mu}");
        }
        assert!(r[col("lift_off_t")].is_empty());
        match r[col("fate")] {
            "periodic" => {
                let t: f64 = r[col("period")].parse().unwrap();
                let f: f64 = r[col("inverse_period")].parse().unwrap();
                assert!(t > 0.0 && (f * t - 1.0).abs() < 1e-12);
                assert!(r[col("multiplicity")].parse::<usize>().unwrap() >= 1);
                assert_eq!(r[col("cruising")], "true");
            }
            "halted" => {
                assert_eq!(r[col("cruising")], "false");
                assert!(r[col("period")].is_empty());
            }
            other => assert_eq!(other, "undecided"),
        }
    }
    // The paper's body at α = 0.2 > α* = 0.139 has no rest point: no run there halts, and
    // "cruising" is said of those seen to close an orbit (an undecided run is not counted).
    let paper_at_02: Vec<_> = rows
        .iter()
        .filter(|r| r[0] == "paper:219" && r[col("alpha")] == "0.2")
        .collect();
    assert_eq!(paper_at_02.len(), 8);
    // The viscous runs close their orbit within t_max = 300; the heavy ones (m/m0 = 6) are
    // still on their way there.
    let fates: Vec<(&str, &str, &str)> = paper_at_02
        .iter()
        .map(|r| (r[col("mass_ratio")], r[col("fate")], r[col("cruising")]))
        .collect();
    assert!(
        fates.iter().all(|&(m, f, c)| f != "halted"
            && (c == "true") == (f == "periodic")
            && (m != "0" || f == "periodic")),
        "{fates:?}"
    );
    // The tighter tolerance costs more work on the same run.
    let work = |integrator: &str| -> u64 {
        rows.iter()
            .filter(|r| r[col("integrator")] == integrator)
            .map(|r| r[col("rhs_evals")].parse::<u64>().unwrap())
            .sum()
    };
    assert!(work("dop853:1e-9") > work("fast"));

    for i in 1..=5 {
        ok(&[
            "sweep",
            s,
            "--out",
            parts.to_str().unwrap(),
            "--shard",
            &format!("{i}/5"),
        ]);
    }
    assert!(!parts.join("sweep.csv").exists());
    ok(&["merge", parts.to_str().unwrap()]);
    same_bytes(&whole.join("sweep.csv"), &parts.join("sweep.csv"));
    same_bytes(&whole.join("summary.json"), &parts.join("summary.json"));

    // The library's scan of the same grid gives the command line's counts, run by run.
    let sweep = rollphase::figures::sweep::Sweep::load(&spec).unwrap();
    let (runs, tally) = sweep.scan.run_all().unwrap();
    assert_eq!(runs.len(), rows.len());
    for (r, row) in runs.iter().zip(&rows) {
        assert_eq!(r.rhs_evals.to_string(), row[col("rhs_evals")]);
        assert_eq!(r.cruises().to_string(), row[col("cruising")]);
    }
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(whole.join("summary.json")).unwrap())
            .unwrap();
    for (key, n) in [
        ("halts", tally.halts),
        ("periodic", tally.periodic),
        ("left_model", tally.left_model),
        ("undecided", tally.undecided),
        ("cruising", tally.cruising),
    ] {
        assert_eq!(summary[key], n as u64, "{key}");
    }
    let _ = std::fs::remove_dir_all(&root);
}

/// Issue 44: a run whose body leaves the ramp is reported as such, in the words every surface
/// uses: `left_model`, with when (lift_off_t), and no period, multiplicity or rest claimed for
/// the model's motion past it (the rows said "periodic" or "undecided", and "cruising").
#[test]
fn a_sweep_run_that_leaves_the_ramp_says_so_and_claims_no_motion() {
    let root = scratch("sweep-lift-off");
    let spec = root.join("spec.toml");
    std::fs::write(
        &spec,
        "alpha = [0.5]\nmass_ratio = [300.0]\norientations = 1\nintegrators = [\"balanced\"]\n\
         t_max = 400.0\n\n[bodies]\npaper_seeds = [219]\n",
    )
    .unwrap();
    let out = root.join("out");
    let said = ok(&[
        "sweep",
        spec.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(said.contains("1 left the model"), "{said}");
    let text = std::fs::read_to_string(out.join("sweep.csv")).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let row: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| row[header.iter().position(|h| *h == name).unwrap()];
    assert_eq!(col("fate"), "left_model");
    assert_eq!(col("cruising"), "false");
    for empty in ["period", "inverse_period", "multiplicity", "halt_time"] {
        assert!(col(empty).is_empty(), "{empty} = {:?}", col(empty));
    }
    let lift_off: f64 = col("lift_off_t").parse().unwrap();
    assert!(lift_off > 0.0 && lift_off < 400.0, "{lift_off}");
    assert!(col("min_normal_force").parse::<f64>().unwrap() < 0.0);
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(
        (
            summary["left_model"].as_u64(),
            summary["periodic"].as_u64(),
            summary["cruising"].as_u64()
        ),
        (Some(1), Some(0), Some(0))
    );
    let _ = std::fs::remove_dir_all(&root);
}

#[test]
fn merge_refuses_missing_duplicated_and_foreign_shards_by_name() {
    let root = scratch("refuse");
    let out = root.to_str().unwrap();
    let dir = root.join("sphere-orbits");
    let d = dir.to_str().unwrap();
    let shard = |i: usize, n: usize, seed: &str| {
        ok(&[
            "figure",
            "sphere-orbits",
            "--quick",
            "--seed",
            seed,
            "--out",
            out,
            "--shard",
            &format!("{i}/{n}"),
        ])
    };
    shard(1, 3, "1");
    shard(3, 3, "1");
    let e = fails(&["merge", d]);
    assert!(e.contains("missing") && e.contains("2/3"), "{e}");

    shard(2, 3, "1");
    std::fs::copy(
        dir.join("shard-2-of-3.json"),
        dir.join("shard-2-of-3-copy.json"),
    )
    .unwrap();
    let e = fails(&["merge", d]);
    assert!(
        e.contains("appears twice") && e.contains("shard-2-of-3-copy.json"),
        "{e}"
    );
    std::fs::remove_file(dir.join("shard-2-of-3-copy.json")).unwrap();

    shard(1, 2, "1");
    let e = fails(&["merge", d]);
    assert!(e.contains("two different splits"), "{e}");
    std::fs::remove_file(dir.join("shard-1-of-2.json")).unwrap();

    // A shard of another seed, dropped in place of shard 2.
    let other = root.join("other");
    ok(&[
        "figure",
        "sphere-orbits",
        "--quick",
        "--seed",
        "7",
        "--out",
        other.to_str().unwrap(),
        "--shard",
        "2/3",
    ]);
    std::fs::copy(
        other.join("sphere-orbits/shard-2-of-3.json"),
        dir.join("shard-2-of-3.json"),
    )
    .unwrap();
    let e = fails(&["merge", d]);
    assert!(
        e.contains("different options") && e.contains("seed 7"),
        "{e}"
    );

    // Now the real shard 2 again: the merge goes through.
    shard(2, 3, "1");
    ok(&["merge", d]);
    assert!(dir.join("data.csv").is_file());

    let e = fails(&["merge", root.join("nowhere").to_str().unwrap()]);
    assert!(e.contains("nowhere"), "{e}");
    let e = fails(&["figure", "disk-flow", "--shard", "1/2", "--out", out]);
    assert!(e.contains("no ensemble"), "{e}");
    let e = fails(&["figure", "sphere-orbits", "--shard", "4/3", "--out", out]);
    assert!(e.contains("I/N"), "{e}");
    let _ = std::fs::remove_dir_all(&root);
}

#[test]
fn a_bad_sweep_spec_is_refused_with_the_key_and_what_is_allowed() {
    let root = scratch("bad-sweep");
    let cases = [
        (
            "alpha = [0.0]\n[bodies]\npaper_seeds = [219]\n",
            "alpha = 0",
        ),
        ("alpha = [0.1]\n[bodies]\n", "give at least one of"),
        (
            "alpha = [0.1]\nmass = 3\n[bodies]\nseeds = [1]\n",
            "unknown field `mass`",
        ),
        (
            "alpha = [0.1]\nintegrators = [\"euler\"]\n[bodies]\nseeds = [1]\n",
            "\"euler\" is not an integrator",
        ),
        (
            "alpha = [0.1]\nintegrators = [\"rk4:1e-9\"]\n[bodies]\nseeds = [1]\n",
            "more than 1e9",
        ),
        (
            "alpha = [0.1]\norientations = 1000000\nmass_ratio = { from = 0, to = 10, count = 1000 }\n[bodies]\nseeds = [1]\n",
            "more than 10000000",
        ),
        (
            "alpha = [0.1]\nintegrators = [\"cf4:1e308\"]\n[bodies]\nseeds = [1]\n",
            "longer than the whole run",
        ),
        // Axes in plain words, not serde's enum jargon.
        (
            "alpha = { from = 0.1, to = 0.2, count = -3 }\n[bodies]\nseeds = [1]\n",
            "count = -3 is not allowed (needs a whole number from 1",
        ),
        (
            "alpha = { from = 0.1, to = 0.2, count = 3, step = 0.05 }\n[bodies]\nseeds = [1]\n",
            "\"step\" is not one of them",
        ),
        (
            "alpha = [0.1, \"x\"]\n[bodies]\nseeds = [1]\n",
            "is not a number",
        ),
        (
            "alpha = { from = 0.1, count = 3 }\n[bodies]\nseeds = [1]\n",
            "to is missing",
        ),
        // Unstable at the small mass: refused before the first run, not after all of them.
        (
            "alpha = [0.1]\nmass_ratio = [1.0, 0.01]\nintegrators = [\"rk4:0.5\"]\n[bodies]\nseeds = [1]\n",
            "unstable for m/m0 = 0.01",
        ),
    ];
    for (k, (spec, says)) in cases.iter().enumerate() {
        let path = root.join(format!("bad{k}.toml"));
        std::fs::write(&path, spec).unwrap();
        let e = fails(&[
            "sweep",
            path.to_str().unwrap(),
            "--out",
            root.join("out").to_str().unwrap(),
        ]);
        assert!(e.contains(says), "{spec}: {e}");
        assert!(
            !e.contains("untagged") && !e.contains("variant"),
            "jargon: {e}"
        );
        assert!(e.contains(&format!("bad{k}.toml")), "names the spec: {e}");
    }
    assert!(!root.join("out").join("sweep.csv").exists());
    let _ = std::fs::remove_dir_all(&root);
}

/// A small sweep spec over one body file, relative to the spec's folder.
const SMALL_SWEEP: &str = "alpha = [0.2]\norientations = 2\nintegrators = [\"fast\"]\nt_max = 50.0\n\n[bodies]\nfiles = [\"body.json\"]\n";

fn small_sweep(root: &Path, name: &str) -> PathBuf {
    let spec = root.join(name);
    std::fs::write(&spec, SMALL_SWEEP).unwrap();
    std::fs::write(
        root.join("body.json"),
        include_str!("../../assets/shapes/paper-sphere.json"),
    )
    .unwrap();
    spec
}

#[test]
fn merge_reads_regular_shards_only_and_never_writes_over_one() {
    let root = scratch("merge-hostile");
    let spec = small_sweep(&root, "spec.toml");
    let parts = root.join("parts");
    let p = parts.to_str().unwrap();
    for i in 1..=2 {
        ok(&[
            "sweep",
            spec.to_str().unwrap(),
            "--out",
            p,
            "--shard",
            &format!("{i}/2"),
        ]);
    }
    // sweep.csv links to a shard: merging would replace the shard with its own output.
    std::os::unix::fs::symlink(parts.join("shard-1-of-2.json"), parts.join("sweep.csv")).unwrap();
    let before = std::fs::read(parts.join("shard-1-of-2.json")).unwrap();
    let e = fails(&["merge", p]);
    assert!(e.contains("is also an input"), "{e}");
    assert_eq!(
        std::fs::read(parts.join("shard-1-of-2.json")).unwrap(),
        before
    );
    std::fs::remove_file(parts.join("sweep.csv")).unwrap();

    // A FIFO named like a shard is refused at once, not waited on (opened, it would block this
    // test for ever: there is no writer).
    let fifo = parts.join("shard-9-of-9.json");
    assert!(
        Command::new("mkfifo")
            .arg(&fifo)
            .status()
            .unwrap()
            .success()
    );
    let e = fails(&["merge", p]);
    assert!(e.contains("not a regular file"), "{e}");
    std::fs::remove_file(&fifo).unwrap();

    // The shards carry absolute paths: merged from another folder, the body file is found.
    let o = Command::new(crate::cli::binary())
        .args(["merge", p])
        .current_dir("/")
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(parts.join("sweep.csv").is_file());
    let _ = std::fs::remove_dir_all(&root);
}

#[test]
fn sweep_and_fit_lag_refuse_their_own_inputs_and_bad_folders_before_running() {
    let root = scratch("sweep-hostile");
    // The spec is named like the sweep's own output and --out is its folder.
    let spec = small_sweep(&root, "sweep.csv");
    let before = std::fs::read(&spec).unwrap();
    let e = fails(&[
        "sweep",
        spec.to_str().unwrap(),
        "--out",
        root.to_str().unwrap(),
    ]);
    assert!(e.contains("is also an input"), "{e}");
    assert_eq!(std::fs::read(&spec).unwrap(), before);

    // --out under a file fails before the first run.
    let afile = root.join("afile");
    std::fs::write(&afile, "x").unwrap();
    let spec = small_sweep(&root, "spec.toml");
    let before = crate::cli::listing(&root);
    let e = fails(&[
        "sweep",
        spec.to_str().unwrap(),
        "--out",
        afile.join("sub").to_str().unwrap(),
    ]);
    assert!(e.contains("not a folder"), "{e}");
    assert_eq!(
        crate::cli::listing(&root),
        before,
        "nothing staged or written before the refusal"
    );

    // fit-lag's data as its own output: lab/fit-lag/data.csv with --out lab.
    let lab = root.join("lab");
    std::fs::create_dir_all(lab.join("fit-lag")).unwrap();
    let data = lab.join("fit-lag/data.csv");
    let measured = "run_idx,alpha*,alpha,t_lag\n0,0.1,0.15,\"[10, 11]\"\n0,0.1,0.2,\"[6, 7]\"\n0,0.1,0.3,\"[4, 4.5]\"\n";
    std::fs::write(&data, measured).unwrap();
    let e = fails(&[
        "fit-lag",
        data.to_str().unwrap(),
        "--out",
        lab.to_str().unwrap(),
    ]);
    assert!(e.contains("is also an input"), "{e}");
    assert_eq!(std::fs::read_to_string(&data).unwrap(), measured);
    let _ = std::fs::remove_dir_all(&root);
}

#[test]
fn an_edited_shard_is_refused_by_its_digest_and_a_forged_one_by_record_and_field() {
    use rollphase::figures::shard::ShardFile;
    let root = scratch("digest");
    let out = root.to_str().unwrap();
    let dir = root.join("sphere-doubling");
    for i in 1..=2 {
        ok(&[
            "figure",
            "sphere-doubling",
            "--quick",
            "--out",
            out,
            "--shard",
            &format!("{i}/2"),
        ]);
    }
    let path = dir.join("shard-1-of-2.json");
    let text = std::fs::read_to_string(&path).unwrap();
    let file: ShardFile = serde_json::from_str(&text).unwrap();

    // One number edited by hand: refused by name, whatever the number.
    let mut edited = file.records.clone();
    let mut fields: Vec<String> = edited[0].split(' ').map(String::from).collect();
    fields[2] = "7e0".into();
    edited[0] = fields.join(" ");
    let hand = ShardFile {
        records: edited.clone(),
        digest: file.digest.clone(),
        ..serde_json::from_str(&text).unwrap()
    };
    std::fs::write(&path, serde_json::to_string(&hand).unwrap()).unwrap();
    let e = fails(&["merge", dir.to_str().unwrap()]);
    assert!(
        e.contains("does not match its digest") && e.contains("shard-1-of-2.json"),
        "{e}"
    );

    // The same edit with the digest recomputed (a forged shard): the record's ranges are checked
    // before the figure reduces it, so it is an error naming file, record and field, not a panic.
    for bad in ["0e0", "7e0", "1e15", "NaN", "-1e0"] {
        let mut records = file.records.clone();
        let mut fields: Vec<String> = records[0].split(' ').map(String::from).collect();
        fields[2] = bad.into();
        records[0] = fields.join(" ");
        let forged = ShardFile {
            records,
            ..serde_json::from_str(&text).unwrap()
        }
        .sealed()
        .unwrap();
        std::fs::write(&path, serde_json::to_string(&forged).unwrap()).unwrap();
        let o = rollphase(&["merge", dir.to_str().unwrap()]);
        let e = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{bad}: {e}");
        assert!(!e.contains("panicked"), "{bad}: {e}");
        assert!(
            e.contains("shard-1-of-2.json") && e.contains("record 0") && e.contains("field"),
            "{bad}: {e}"
        );
    }
    // The real shard merges.
    std::fs::write(&path, &text).unwrap();
    ok(&["merge", dir.to_str().unwrap()]);
    let _ = std::fs::remove_dir_all(&root);
}

/// Issue 33, case 2: shards are bound to their bodies. Shards of one `--shape` name run on two
/// different files never merge; a body file replaced before the merge is refused by name; a
/// shard re-sealed (with a valid file digest) to claim a digest that is not the file's is refused
/// as well, and so is one whose body digest was removed. The same for a sweep's `bodies.files`.
/// (A forgery consistent with the file cannot be told from the real thing: the digests guard
/// against accidents, not adversaries.)
#[test]
fn shards_are_bound_to_the_bodies_they_ran_on() {
    use rollphase::figures::shard::{JobId, ShardFile};
    let root = scratch("bodies");
    let out = root.join("o");
    let cur = root.join("cur.json");
    let body_a = include_str!("../../assets/shapes/paper-sphere.json");
    let body_b = include_str!("../../assets/shapes/sphere.json");
    assert_ne!(body_a, body_b);
    let shard = |i: usize| {
        rollphase(&[
            "figure",
            "sphere-poincare",
            "--quick",
            "--shape",
            cur.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--shard",
            &format!("{i}/2"),
        ])
    };
    let dir = out.join("sphere-poincare");
    let d = dir.to_str().unwrap();
    // Two bodies behind one name.
    std::fs::write(&cur, body_a).unwrap();
    assert!(shard(1).status.success());
    std::fs::write(&cur, body_b).unwrap();
    assert!(shard(2).status.success());
    let e = fails(&["merge", d]);
    assert!(
        e.contains("different options") && e.contains("body SHA-256"),
        "{e}"
    );
    // Both shards on body A, the file replaced by B before the merge.
    std::fs::write(&cur, body_a).unwrap();
    assert!(shard(2).status.success());
    std::fs::write(&cur, body_b).unwrap();
    let e = fails(&["merge", d]);
    assert!(
        e.contains(cur.to_str().unwrap()) && e.contains("changed since the shards ran"),
        "{e}"
    );
    assert!(!dir.join("data.csv").exists());
    // Forged: both shards re-sealed (valid file digests) to claim a body digest that is not the
    // file's, or none at all: refused, naming the file.
    let originals: Vec<(PathBuf, String)> = (1..=2)
        .map(|i| {
            let p = dir.join(format!("shard-{i}-of-2.json"));
            let text = std::fs::read_to_string(&p).unwrap();
            (p, text)
        })
        .collect();
    std::fs::write(&cur, body_a).unwrap();
    for (claim, needle) in [
        (Some("0".repeat(64)), "changed since the shards ran"),
        (None, "record no digest"),
    ] {
        for (p, text) in &originals {
            let mut file: ShardFile = serde_json::from_str(text).unwrap();
            let JobId::Figure { body_sha256, .. } = &mut file.job else {
                panic!("a figure's shard")
            };
            *body_sha256 = claim.clone();
            let forged = file.sealed().unwrap();
            std::fs::write(p, serde_json::to_string(&forged).unwrap()).unwrap();
        }
        let e = fails(&["merge", d]);
        assert!(
            e.contains(needle) && e.contains(cur.to_str().unwrap()),
            "{e}"
        );
        assert!(!dir.join("data.csv").exists());
    }
    // The real shards and the real body merge.
    for (p, text) in &originals {
        std::fs::write(p, text).unwrap();
    }
    std::fs::write(&cur, body_a).unwrap();
    ok(&["merge", d]);
    assert!(dir.join("summary.json").is_file());

    // A sweep over a body file: replaced before the merge, refused by name.
    let sweep_root = root.join("sweep");
    std::fs::create_dir_all(&sweep_root).unwrap();
    let spec = small_sweep(&sweep_root, "spec.toml");
    let sweep_out = sweep_root.join("out");
    for i in 1..=2 {
        ok(&[
            "sweep",
            spec.to_str().unwrap(),
            "--out",
            sweep_out.to_str().unwrap(),
            "--shard",
            &format!("{i}/2"),
        ]);
    }
    std::fs::write(sweep_root.join("body.json"), body_b).unwrap();
    let e = fails(&["merge", sweep_out.to_str().unwrap()]);
    assert!(
        e.contains("body.json") && e.contains("changed since the shards ran"),
        "{e}"
    );
    std::fs::write(sweep_root.join("body.json"), body_a).unwrap();
    ok(&["merge", sweep_out.to_str().unwrap()]);
    let _ = std::fs::remove_dir_all(&root);
}

/// Issue 33, cases 3 and 10: a re-sealed shard naming a figure without an ensemble
/// (`sphere-tube`) is refused instead of "merged", and one claiming 10¹⁵ shards is refused at
/// once, without listing the missing ones (merge grew by hundreds of MB/s before).
#[test]
fn forged_shards_naming_no_ensemble_or_a_huge_split_are_refused_at_once() {
    use rollphase::figures::shard::{JobId, ShardFile};
    let root = scratch("forged-split");
    let out = root.to_str().unwrap();
    ok(&[
        "figure",
        "sphere-orbits",
        "--quick",
        "--out",
        out,
        "--shard",
        "1/2",
    ]);
    let source = root.join("sphere-orbits/shard-1-of-2.json");
    let text = std::fs::read_to_string(&source).unwrap();

    let tube = root.join("sphere-tube");
    std::fs::create_dir_all(&tube).unwrap();
    let mut file: ShardFile = serde_json::from_str(&text).unwrap();
    let JobId::Figure { name, .. } = &mut file.job else {
        panic!("a figure's shard")
    };
    *name = "sphere-tube".into();
    file.of = 1;
    file.shard = 1;
    file.jobs = file.records.len();
    std::fs::write(
        tube.join("shard-1-of-1.json"),
        serde_json::to_string(&file.sealed().unwrap()).unwrap(),
    )
    .unwrap();
    let e = fails(&["merge", tube.to_str().unwrap()]);
    assert!(e.contains("no ensemble to merge"), "{e}");
    assert!(!tube.join("data.csv").exists());

    let huge = root.join("huge/sphere-orbits");
    std::fs::create_dir_all(&huge).unwrap();
    let mut file: ShardFile = serde_json::from_str(&text).unwrap();
    file.of = 1_000_000_000_000_000;
    std::fs::write(
        huge.join("shard-1-of-2.json"),
        serde_json::to_string(&file.sealed().unwrap()).unwrap(),
    )
    .unwrap();
    let e = fails(&["merge", huge.to_str().unwrap()]);
    assert!(e.contains("one of 1000000000000000 shards"), "{e}");
    let _ = std::fs::remove_dir_all(&root);
}

/// Issue 33, case 11: `merge .` from inside OUT/NAME merges there (it was refused, saying the
/// folder must keep the figure's name).
#[test]
fn merge_dot_from_inside_the_figures_folder_merges_there() {
    let root = scratch("merge-dot");
    ok(&[
        "figure",
        "sphere-orbits",
        "--quick",
        "--out",
        root.to_str().unwrap(),
        "--shard",
        "1/1",
    ]);
    let dir = root.join("sphere-orbits");
    let o = Command::new(crate::cli::binary())
        .args(["merge", "."])
        .current_dir(&dir)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(dir.join("data.csv").is_file() && dir.join("summary.json").is_file());
    let _ = std::fs::remove_dir_all(&root);
}

/// Issue 33, case 9: a sweep spec kept in the output folder as summary.json (or sweep.csv) is
/// not replaced by `merge`: refused, naming it.
#[test]
fn merge_refuses_to_replace_the_sweep_spec_it_ran() {
    let root = scratch("spec-in-out");
    let out = root.join("out");
    std::fs::create_dir_all(&out).unwrap();
    std::fs::write(
        out.join("body.json"),
        include_str!("../../assets/shapes/paper-sphere.json"),
    )
    .unwrap();
    let spec = out.join("summary.json");
    std::fs::write(&spec, SMALL_SWEEP).unwrap();
    ok(&[
        "sweep",
        spec.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--shard",
        "1/1",
    ]);
    let e = fails(&["merge", out.to_str().unwrap()]);
    assert!(
        e.contains("summary.json") && e.contains("holds the sweep spec"),
        "{e}"
    );
    assert_eq!(std::fs::read_to_string(&spec).unwrap(), SMALL_SWEEP);
    let _ = std::fs::remove_dir_all(&root);
}

/// Issue 33, case 11: a full disk under a sweep names the file it stopped (sweep.csv linked to
/// /dev/full, which fails every write with "No space left on device").
#[test]
fn a_full_disk_under_a_sweep_names_the_file() {
    if !Path::new("/dev/full").exists() {
        panic!("/dev/full is missing; this test needs Linux's full device");
    }
    let root = scratch("full-disk");
    let spec = small_sweep(&root, "spec.toml");
    let out = root.join("out");
    std::fs::create_dir_all(&out).unwrap();
    std::os::unix::fs::symlink("/dev/full", out.join("sweep.csv")).unwrap();
    let e = fails(&[
        "sweep",
        spec.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(
        e.contains(&out.join("sweep.csv").display().to_string()) && e.contains("No space left"),
        "{e}"
    );
    let _ = std::fs::remove_dir_all(&root);
}
