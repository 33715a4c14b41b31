//! `talus reduced FILE --json --solution PATH` on a Siconos problem: the JSON keys, the
//! exit status, and a solution file that satisfies the problem (checked here from the file).
use std::process::Command;

use talus_ssn::siconos::SiconosProblem;

const FILE: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../data/siconos-plasticity/plasticity_2d_footing_10.dat"
);

#[test]
fn reduced_prints_json_and_writes_the_solution() {
    let out_path = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("footing_10.sol");
    let out = Command::new(env!("CARGO_BIN_EXE_talus"))
        .args(["reduced", FILE, "--json", "--tol", "1e-12", "--solution"])
        .arg(&out_path)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(json["status"], "converged");
    assert!(json["iterations"].as_u64().unwrap() >= 1);
    assert!(
        json["residual"].as_f64().unwrap() <= 1e-12 * json["sigma_inf"].as_f64().unwrap().max(1.0)
    );
    assert!(json["seconds"].as_f64().unwrap() > 0.0);

    let problem = SiconosProblem::from_path(std::path::Path::new(FILE)).unwrap();
    let sigma: Vec<f64> = std::fs::read_to_string(&out_path)
        .unwrap()
        .lines()
        .map(|l| l.trim().parse().unwrap())
        .collect();
    assert_eq!(sigma.len(), problem.n());
    // Each cone's stress is feasible, ‖σ_T‖ ≤ η σ_0, and some cone is loaded.
    let talus_ssn::siconos::SiconosModel::DruckerPrager { eta, .. } = &problem.model else {
        panic!()
    };
    let scale = sigma.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    assert!(scale > 0.0);
    for (c, e) in eta.iter().enumerate() {
        let s = &sigma[3 * c..3 * c + 3];
        assert!((s[1] * s[1] + s[2] * s[2]).sqrt() <= e * s[0] + 1e-10 * scale);
    }
}

#[test]
fn reduced_reports_non_convergence_with_exit_code_3() {
    let out = Command::new(env!("CARGO_BIN_EXE_talus"))
        .args(["reduced", FILE, "--json", "--max-iterations", "1"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(3));
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(json["status"], "max_iterations");
}

/// `talus reduced` on `text` written to `name`: the file's path and the error, after
/// checking the exit code is 1 (invalid input).
fn refused(name: &str, text: impl AsRef<[u8]>) -> (std::path::PathBuf, String) {
    let path = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(name);
    std::fs::write(&path, text).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_talus"))
        .arg("reduced")
        .arg(&path)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    (path, String::from_utf8_lossy(&out.stderr).into_owned())
}

#[test]
fn reduced_names_a_bad_file() {
    let (path, err) = refused("bad.dat", "3\n1\n1\n0\n3\n3\n3\t3\n1 2 x\n");
    assert!(
        err.contains(&format!("error: {}: line 8:", path.display())),
        "{err}"
    );
}

/// A wrong size line is named as such, with the file (it used to read "line 3: expected
/// model type 1 (Drucker-Prager) or 2 (von Mises), found `0`", without the file).
#[test]
fn reduced_names_a_wrong_size_line_and_the_file() {
    let text = std::fs::read_to_string(FILE).unwrap();
    let text = text.replacen("3\n10\n", "3\n11\n", 1);
    let (path, err) = refused("wrong_n_c.dat", text);
    assert!(
        err.contains(&format!(
            "error: {}: line 2: declares n_c = 11 cones, so n = d * n_c = 3 * 11 = 33",
            path.display()
        )),
        "{err}"
    );
}

/// A file the solver cannot take (d = 2) is named too.
#[test]
fn reduced_names_the_file_of_an_unsolvable_problem() {
    let (path, err) = refused("d2.dat", "2\n1\n1\n0\n2\n2\n2\t2\n1 0\n0 1\n0 0\n0.5\n0\n");
    assert!(
        err.contains(&format!("error: {}: ", path.display())),
        "{err}"
    );
    assert!(err.contains("cone_dimension"), "{err}");
}

#[test]
fn reduced_reports_the_round_off_floor_with_exit_code_6() {
    // 1e-18 is below what floating point allows on this problem (docs/solver.md).
    let out = Command::new(env!("CARGO_BIN_EXE_talus"))
        .args(["reduced", FILE, "--json", "--tol", "1e-18"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(6));
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(json["status"], "round_off_floor");
    let reached = json["round_off_floor"]["reached"].as_f64().unwrap();
    let estimate = json["round_off_floor"]["estimate"].as_f64().unwrap();
    assert_eq!(reached, json["residual"].as_f64().unwrap());
    assert!(reached > 1e-18 * json["sigma_inf"].as_f64().unwrap().max(1.0));
    assert!(reached <= 1e3 * estimate);
}
