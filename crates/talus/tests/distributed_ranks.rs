//! `mpirun -np 2 talus run` against one rank (`docs/distributed.md`): the paper footing
//! (FEM, non-associative), the 3D slope's factor of safety and the MPM column. With two
//! ranks every Newton matrix is factorized by MUMPS over both; with one, by Talus' own
//! factorization: two independent linear solvers, so histories that agree to 1e-10 of
//! their scale check the distributed path end to end.
//!
//! Built with the cargo feature `mpi` only (Debian `libmumps-dev libopenmpi-dev
//! openmpi-bin`); `cargo xtask test` runs it when MUMPS and `mpirun` are installed.
#![cfg(feature = "mpi")]

mod common;

use std::ffi::OsStr;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

use common::{
    array, attr, history_column, history_without_seconds, replaced, target_tmp_dir, FOOTING,
};

const MPIRUN_FLAGS: &[&str] = &["--allow-run-as-root", "--oversubscribe"];

/// `talus ARGS` on `ranks` ranks (`None`: without `mpirun`), killed after `limit`: a rank
/// left waiting would otherwise hang the test.
fn talus(ranks: Option<usize>, args: &[&OsStr], limit: Duration) -> Output {
    let talus = env!("CARGO_BIN_EXE_talus");
    let mut command = match ranks {
        Some(n) => {
            let mut c = Command::new("mpirun");
            c.args(MPIRUN_FLAGS).args(["-np", &n.to_string(), talus]);
            c
        }
        None => Command::new(talus),
    };
    // MUMPS' statistics at `info`: the runs on several ranks show that MUMPS factorized.
    let child = command
        .args(args)
        .env(
            "TALUS_LOG",
            "warn,talus_ssn::newton::distributed_factor=info,talus_ssn::solver=debug",
        )
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("mpirun and talus start");
    within(child, limit, &format!("talus {args:?}"))
}

/// The output of `child`, killed after `limit` (then the test fails naming `what`).
fn within(mut child: std::process::Child, limit: Duration, what: &str) -> Output {
    let start = Instant::now();
    while child.try_wait().expect("waitable").is_none() {
        if start.elapsed() > limit {
            let _ = child.kill();
            let output = child.wait_with_output().expect("killed run's output");
            panic!(
                "{what} still running after {limit:?}: {}",
                String::from_utf8_lossy(&output.stderr)
            );
        }
        std::thread::sleep(Duration::from_millis(100));
    }
    child.wait_with_output().expect("the run's output")
}

/// `talus run scene --out out` on `ranks` ranks, into a new `out`.
fn run(ranks: Option<usize>, scene: &Path, out: &Path, limit: Duration) -> Output {
    let _ = std::fs::remove_dir_all(out);
    let args = [
        "run".as_ref(),
        scene.as_os_str(),
        "--out".as_ref(),
        out.as_os_str(),
    ];
    talus(ranks, &args, limit)
}

fn succeeded(output: Output, what: &str) -> Output {
    assert!(
        output.status.success(),
        "{what}: {}",
        String::from_utf8_lossy(&output.stderr)
    );
    output
}

/// `output` of a run on two ranks that factorized with MUMPS over both.
fn by_mumps_on_two_ranks(output: Output, what: &str) -> Output {
    two_ranks_factorized_by(
        output,
        what,
        "MUMPS factorization ranks=2 placement=AllRanks",
    )
}

/// `output` of a run on two ranks, each working on its own points, whose MUMPS logged
/// `factorization` (its ranks and placement).
fn two_ranks_factorized_by(output: Output, what: &str, factorization: &str) -> Output {
    let output = succeeded(output, what);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        stderr.contains(factorization),
        "{what}: no `{factorization}` logged: {stderr}"
    );
    // Each rank works on its own points: the first solver's two shares split its points.
    let share = |rank: usize| -> (usize, usize) {
        let line = stderr
            .lines()
            .find(|l| l.contains("this rank's points") && l.contains(&format!(" rank={rank} ")))
            .unwrap_or_else(|| panic!("{what}: no points logged by rank {rank}: {stderr}"));
        let field = |name: &str| -> usize {
            let at = line.find(&format!(" {name}=")).expect("the field") + name.len() + 2;
            line[at..]
                .split(|c: char| !c.is_ascii_digit())
                .next()
                .and_then(|v| v.parse().ok())
                .expect("a count")
        };
        (field("points"), field("of_points"))
    };
    let ((p0, n0), (p1, n1)) = (share(0), share(1));
    assert!(
        n0 == n1 && p0 + p1 == n0 && p0 > 0 && p1 > 0,
        "{what}: ranks own {p0} of {n0} and {p1} of {n1} points"
    );
    output
}

/// The largest difference of a history column between two runs over the column's
/// largest magnitude (entries near zero are compared at the column's scale).
fn column_difference(a: &Path, b: &Path, name: &str) -> f64 {
    let (x, y) = (history_column(a, name), history_column(b, name));
    assert_eq!(
        x.len(),
        y.len(),
        "{name}: the runs took different numbers of steps"
    );
    assert!(
        x.iter().any(|v| *v != 0.0),
        "{name} is zero throughout: nothing compared"
    );
    relative_difference(&x, &y)
}

/// `max |x − y|` over `max |x|` (0 when they are equal, zero throughout included).
fn relative_difference(x: &[f64], y: &[f64]) -> f64 {
    let scale = x.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let worst = x
        .iter()
        .zip(y)
        .fold(0.0f64, |m, (p, q)| m.max((p - q).abs()));
    if worst == 0.0 {
        0.0
    } else {
        worst / scale
    }
}

/// Every one of `columns` agrees between the runs in `a` and `b` to 1e-10 of its scale.
fn assert_columns_agree(a: &Path, b: &Path, columns: &[&str], what: &str) {
    for column in columns {
        let d = column_difference(a, b, column);
        assert!(
            d <= 1e-10,
            "{column}: {what} differ by {d:.2e} of its scale"
        );
    }
}

/// The files of the snapshot of `step` in `out`: `vtu/step_NNNNN.vtu` (one rank), or the
/// pieces `vtu/step_NNNNN.pvtu` lists (two ranks: `piece_0.vtu`, `piece_1.vtu`, each its
/// rank's), checked listed in `solution.pvd`.
fn snapshot_files(out: &Path, step: usize) -> Vec<String> {
    let stem = format!("step_{step:05}");
    let vtu = out.join("vtu");
    let pvd = std::fs::read_to_string(out.join("solution.pvd")).expect("solution.pvd");
    if let Ok(whole) = std::fs::read_to_string(vtu.join(format!("{stem}.vtu"))) {
        assert!(pvd.contains(&format!("vtu/{stem}.vtu")), "{pvd}");
        return vec![whole];
    }
    let pvtu =
        std::fs::read_to_string(vtu.join(format!("{stem}.pvtu"))).expect("rank 0 wrote the .pvtu");
    assert!(pvd.contains(&format!("vtu/{stem}.pvtu")), "{pvd}");
    let sources: Vec<String> = pvtu
        .lines()
        .filter_map(|l| l.trim().strip_prefix(r#"<Piece Source=""#))
        .map(|l| l[..l.find('"').unwrap()].to_string())
        .collect();
    assert_eq!(
        sources,
        [format!("{stem}/piece_0.vtu"), format!("{stem}/piece_1.vtu")]
    );
    sources
        .iter()
        .map(|s| std::fs::read_to_string(vtu.join(s)).expect("each rank's piece"))
        .collect()
}

/// The snapshot of `step` in `a` and in `b` (one file or pieces, `snapshot_files`): the
/// same cells or particles in the same order, the values of `names` within 1e-10 of
/// their largest magnitude.
fn assert_snapshots_match(a: &Path, b: &Path, step: usize, names: &[&str]) {
    let (a, b) = (snapshot_files(a, step), snapshot_files(b, step));
    let cells = |files: &[String]| -> usize {
        files
            .iter()
            .map(|f| attr(f, "NumberOfCells").parse::<usize>().unwrap())
            .sum()
    };
    assert_eq!(cells(&a), cells(&b), "step {step}: cells");
    for name in names {
        let want: Vec<f64> = a.iter().flat_map(|f| array(f, name)).collect();
        let got: Vec<f64> = b.iter().flat_map(|f| array(f, name)).collect();
        assert_eq!(got.len(), want.len(), "{name}");
        let difference = relative_difference(&want, &got);
        assert!(difference <= 1e-10, "step {step} {name}: {difference:e}");
    }
}

fn scene_file(test: &str, text: &str) -> (PathBuf, PathBuf) {
    let dir = target_tmp_dir("distributed_ranks", test);
    let scene = dir.join("scene.toml");
    std::fs::write(&scene, text).unwrap();
    (scene, dir)
}

/// The paper footing (Guillet et al. 2024, Fig. 3: φ = 27°, ψ = 14.3°, non-associative)
/// to step 80, past the plateau's start at step 49. Newton to 1e-13: the histories of two
/// runs differ by what their solves left, and at 1e-12 a step one run ended at a relative
/// residual of 7.6e-13 and the other after one more iteration gave reactions 1.03e-10
/// apart.
fn footing_scene() -> String {
    let text = replaced(FOOTING, "steps = 300", "steps = 80");
    let text = replaced(&text, "vtu_every = 30", "vtu_every = 40");
    let text = replaced(&text, "plots = true", "plots = false");
    format!("{text}\n[solver]\ntolerance = 1e-13\n")
}

#[test]
fn paper_footing_on_two_ranks_matches_one_rank() {
    let (scene, dir) = scene_file("footing", &footing_scene());
    let limit = Duration::from_secs(300);
    let one = dir.join("one");
    succeeded(run(None, &scene, &one, limit), "one rank");
    let two = dir.join("two");
    let output = by_mumps_on_two_ranks(run(Some(2), &scene, &two, limit), "two ranks");
    // Rank 0 alone reports: the run's line once.
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert_eq!(stdout.matches("80 steps in").count(), 1, "{stdout}");
    assert_columns_agree(
        &one,
        &two,
        &[
            "time",
            "reaction_force",
            "footing_displacement",
            "footing_fy",
        ],
        "one and two ranks",
    );
    // Each rank wrote its piece of the VTUs, rank 0 the .pvtu: the one-rank run's cells.
    // Stresses compared at step 40, before the plateau: past it (step 80) two runs that
    // took one Newton iteration more or less in a step differ by up to 5e-9 of the
    // stress's scale (measured), though their reactions agree to 1e-10.
    assert_eq!(snapshot_files(&two, 80).len(), 2);
    assert_snapshots_match(&one, &two, 40, &["stress", "material"]);
    assert_snapshots_match(&one, &two, 80, &["material"]);
    // A second two-rank run. MUMPS assembles the fronts' contributions in the order its
    // messages arrive, so the bits may differ (docs/distributed.md, 'Reproducibility');
    // the histories agree as closely as with one rank.
    let again = dir.join("again");
    by_mumps_on_two_ranks(run(Some(2), &scene, &again, limit), "two ranks again");
    assert_columns_agree(
        &two,
        &again,
        &["reaction_force", "footing_fy"],
        "two two-rank runs",
    );
}

/// Issue 26's test: the same two-rank run twice gives identical bits, with
/// `[solver] reproducible = true` (MUMPS on rank 0 alone, on the entries both ranks send
/// it in rank order). Compared: the checkpoint of step 80 (every point's σ, z and state in
/// serde_json's round-trip form: equal text is equal bits) and the history. Over both
/// ranks (the default) two runs differ by up to 5e-11 of the reaction's scale
/// (`docs/distributed.md`, 'Reproducibility'); here also the one-rank histories to 1e-10.
#[test]
fn the_same_two_rank_run_twice_gives_the_same_bits_when_reproducible() {
    let text = format!("{}reproducible = true\n", footing_scene());
    let (scene, dir) = scene_file("reproducible", &text);
    let limit = Duration::from_secs(300);
    let run_with_checkpoint = |name: &str| -> PathBuf {
        let out = dir.join(name);
        let _ = std::fs::remove_dir_all(&out);
        let args = [
            "run".as_ref(),
            scene.as_os_str(),
            "--checkpoint-every".as_ref(),
            "80".as_ref(),
            "--out".as_ref(),
            out.as_os_str(),
        ];
        two_ranks_factorized_by(
            talus(Some(2), &args, limit),
            name,
            "MUMPS factorization ranks=1 placement=Host",
        );
        out
    };
    let (first, second) = (run_with_checkpoint("first"), run_with_checkpoint("second"));
    // The checkpoint's state, stepper and collapse watch (its outputs' record names the
    // folder), each as serde_json writes it back.
    let checkpoint = |out: &Path| -> Vec<String> {
        let text = std::fs::read_to_string(out.join("checkpoint/last.checkpoint"))
            .expect("rank 0's checkpoint");
        let (header, payload) = text.split_once('\n').expect("a header line");
        assert!(header.contains(" step=80 "), "{header}");
        let value: serde_json::Value = serde_json::from_str(payload).expect("JSON");
        ["state", "stepper", "watch"]
            .map(|key| serde_json::to_string(&value[key]).expect("JSON"))
            .to_vec()
    };
    let (a, b) = (checkpoint(&first), checkpoint(&second));
    assert!(
        a[0].len() > 100_000,
        "a state of every point: {} bytes",
        a[0].len()
    );
    for ((x, y), key) in a.iter().zip(&b).zip(["state", "stepper", "watch"]) {
        assert!(x == y, "the checkpoints' {key} of step 80 differ");
    }
    assert_eq!(
        history_without_seconds(&first),
        history_without_seconds(&second)
    );
    let one = dir.join("one");
    succeeded(run(None, &scene, &one, limit), "one rank");
    assert_columns_agree(
        &one,
        &first,
        &["time", "reaction_force", "footing_fy"],
        "one rank and two reproducible ranks",
    );
}

#[test]
fn a_two_rank_run_resumes_from_its_checkpoint_on_two_ranks() {
    let (scene, dir) = scene_file("resume", &footing_scene());
    let limit = Duration::from_secs(300);
    let whole = dir.join("whole");
    by_mumps_on_two_ranks(run(Some(2), &scene, &whole, limit), "two ranks");
    // The same run with a checkpoint every 30 steps: its last at step 60, from which
    // the resume runs steps 61 to 80 again.
    let resumed = dir.join("resumed");
    let _ = std::fs::remove_dir_all(&resumed);
    let args = [
        "run".as_ref(),
        scene.as_os_str(),
        "--checkpoint-every".as_ref(),
        "30".as_ref(),
        "--out".as_ref(),
        resumed.as_os_str(),
    ];
    succeeded(talus(Some(2), &args, limit), "two ranks with checkpoints");
    let checkpoint = std::fs::read_to_string(resumed.join("checkpoint/last.checkpoint"))
        .expect("rank 0 wrote the checkpoint");
    assert!(checkpoint.starts_with("talus-checkpoint") && checkpoint.contains(" step=60 "));
    let args = ["resume".as_ref(), resumed.as_os_str()];
    let output = by_mumps_on_two_ranks(talus(Some(2), &args, limit), "resume on two ranks");
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(
        stderr.matches("resuming").count(),
        1,
        "rank 0 alone says so: {stderr}"
    );
    assert_columns_agree(
        &whole,
        &resumed,
        &["time", "reaction_force", "footing_fy"],
        "resumed and whole runs",
    );
    // The resumed run's snapshots: step 40's from before the checkpoint (kept by the
    // resume), step 80's written after it (stresses compared before the plateau only, as
    // in `paper_footing_on_two_ranks_matches_one_rank`).
    assert_snapshots_match(&whole, &resumed, 40, &["stress"]);
    assert_snapshots_match(&whole, &resumed, 80, &["material"]);
}

#[test]
fn column_collapse_on_two_ranks_matches_one_rank() {
    // The a = 2 column matched to Newton's implicit MPM (scenes/column_newton.toml) at
    // h = 1e-3 s for 20 steps: no step halved, so both runs take the same sub-steps.
    let text = include_str!("../../../scenes/column_newton.toml");
    let text = replaced(text, "step = 0.016666666666666666", "step = 1e-3");
    let text = replaced(&text, "steps = 60", "steps = 20");
    let (scene, dir) = scene_file("column", &format!("{text}\n[solver]\ntolerance = 1e-13\n"));
    let limit = Duration::from_secs(300);
    let one = dir.join("one");
    succeeded(run(None, &scene, &one, limit), "one rank");
    let two = dir.join("two");
    by_mumps_on_two_ranks(run(Some(2), &scene, &two, limit), "two ranks");
    assert_columns_agree(
        &one,
        &two,
        &["time", "front", "runout_normalized", "kinetic_energy"],
        "one and two ranks",
    );
    assert_snapshots_match(&one, &two, 20, &["Points", "velocity", "stress"]);
}

/// The factor of safety and its bracket from `summary.json`.
fn factor_of_safety(out: &Path) -> (f64, f64, f64) {
    let text = std::fs::read_to_string(out.join("summary.json")).expect("summary.json");
    let v: serde_json::Value = serde_json::from_str(&text).unwrap();
    let fos = &v["factor_of_safety"];
    let number = |x: &serde_json::Value| x.as_f64().unwrap_or_else(|| panic!("{text}"));
    (
        number(&fos["value"]),
        number(&fos["bracket"][0]),
        number(&fos["bracket"][1]),
    )
}

#[test]
fn slope_3d_factor_of_safety_on_two_ranks_matches_one_rank() {
    // scenes/slope_3d.toml (Sysala et al.'s 45° slope, 20k unknowns) as shipped: one rank
    // uses its f32 factor with GMRES; two ranks, MUMPS' f64 LDLᵀ.
    let text = include_str!("../../../scenes/slope_3d.toml");
    let mesh = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/slope_3d.msh");
    let text = replaced(
        text,
        "path = \"slope_3d.msh\"",
        &format!("path = {:?}", mesh.to_str().unwrap()),
    );
    let (scene, dir) = scene_file("slope_3d", &text);
    let limit = Duration::from_secs(900);
    let one = dir.join("one");
    succeeded(run(None, &scene, &one, limit), "one rank");
    let two = dir.join("two");
    by_mumps_on_two_ranks(run(Some(2), &scene, &two, limit), "two ranks");
    let (f1, stable1, fails1) = factor_of_safety(&one);
    let (f2, stable2, fails2) = factor_of_safety(&two);
    assert!(
        (stable1..=fails1).contains(&f2) && (stable2..=fails2).contains(&f1),
        "one rank F = {f1} [{stable1}, {fails1}], two ranks F = {f2} [{stable2}, {fails2}]"
    );
}

#[test]
fn a_bad_scene_stops_every_rank_with_the_error_on_rank_0() {
    let text = replaced(FOOTING, "poisson_ratio = 0.3", "poisson_ratio = 0.7");
    let (scene, dir) = scene_file("bad", &text);
    let start = Instant::now();
    let output = run(Some(2), &scene, &dir.join("out"), Duration::from_secs(60));
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(!output.status.success(), "a bad scene ran: {stderr}");
    assert!(
        stderr.contains("error:") && stderr.contains("material.poisson_ratio"),
        "the error names the field: {stderr}"
    );
    assert!(
        start.elapsed() < Duration::from_secs(30),
        "{:?} to stop",
        start.elapsed()
    );
}

/// Two ranks that see different folders under one name (OpenMPI's `-wdir` per rank, as on
/// nodes without a shared file system, `out` relative): the run is refused on every rank,
/// rank 0 saying that rank 1 does not see its folder, instead of a `.pvtu` whose pieces
/// are elsewhere.
#[test]
fn ranks_that_do_not_share_the_output_folder_are_refused() {
    let (scene, dir) = scene_file("unshared", &footing_scene());
    let (a, b) = (dir.join("a"), dir.join("b"));
    for d in [&a, &b] {
        let _ = std::fs::remove_dir_all(d);
        std::fs::create_dir_all(d).unwrap();
    }
    let talus = env!("CARGO_BIN_EXE_talus");
    let rank = |wdir: &Path| -> Vec<String> {
        [
            "-np",
            "1",
            "-wdir",
            &wdir.display().to_string(),
            talus,
            "run",
        ]
        .iter()
        .map(|s| s.to_string())
        .chain([scene.display().to_string(), "--out".into(), "out".into()])
        .collect()
    };
    let mut args: Vec<String> = MPIRUN_FLAGS.iter().map(|s| s.to_string()).collect();
    args.extend(rank(&a));
    args.push(":".into());
    args.extend(rank(&b));
    let child = Command::new("mpirun")
        .args(&args)
        .env("TALUS_LOG", "warn")
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("mpirun runs");
    let output = within(child, Duration::from_secs(60), "ranks in two folders");
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(!output.status.success(), "the run went on: {stderr}");
    assert!(
        stderr.contains("rank 1 of 2 does not see rank 0's output folder"),
        "rank 0 names the rank that does not see its folder: {stderr}"
    );
    assert!(!a.join("out/vtu").exists(), "no snapshot written");
}

/// `talus -v` under `mpirun`: rank 0 logs at debug, the other ranks errors only. No rank
/// may reach a reduction the others skip because of its log filter (a collective inside a
/// log line would leave the ranks waiting for each other).
#[test]
fn a_verbose_run_on_two_ranks_finishes() {
    let text = replaced(&footing_scene(), "steps = 80", "steps = 20");
    let (scene, dir) = scene_file("verbose", &text);
    let out = dir.join("out");
    let _ = std::fs::remove_dir_all(&out);
    let talus = env!("CARGO_BIN_EXE_talus");
    let child = Command::new("mpirun")
        .args(MPIRUN_FLAGS)
        .args(["-np", "2", talus, "-v", "run"])
        .arg(&scene)
        .arg("--out")
        .arg(&out)
        .env_remove("TALUS_LOG")
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("mpirun starts");
    let output = within(child, Duration::from_secs(120), "a verbose two-rank run");
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    assert_eq!(history_column(&out, "time").len(), 21);
}
