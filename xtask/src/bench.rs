//! `cargo xtask bench`: the divan benchmarks, then the figures of merit as ratios.
use std::path::Path;

use crate::run_checked;

pub fn run(root: &Path) -> Result<bool, String> {
    let mut ok = true;
    for (package, bench) in [("talus-cone", "projection"), ("talus-ssn", "footing")] {
        println!("== cargo bench -p {package} --bench {bench}");
        let out = run_checked(
            root,
            "cargo",
            &["bench", "-q", "-p", package, "--bench", bench],
        )?;
        print!("{}", String::from_utf8_lossy(&out.stdout));
        if !out.status.success() {
            eprint!("{}", String::from_utf8_lossy(&out.stderr));
            ok = false;
        }
    }
    Ok(ok)
}
