//! Whether this machine can build and run the cargo feature `mpi` (`docs/distributed.md`):
//! `mpirun` on the path and MUMPS' C header (Debian `libmumps-dev`, or
//! `MUMPS_INCLUDE_DIR`). `cargo xtask test` and `bench` skip the distributed stages
//! without them, saying so.
use std::path::PathBuf;
use std::process::Command;

/// `None` when the distributed stages can run, else what is missing and how to install it.
pub(crate) fn missing() -> Option<String> {
    let header = std::env::var_os("MUMPS_INCLUDE_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| "/usr/include".into())
        .join("dmumps_c.h");
    let mpirun = Command::new("mpirun").arg("--version").output().is_ok();
    (!(mpirun && header.exists())).then(|| {
        format!(
            "no mpirun or {}; Debian: apt-get install libmumps-dev libopenmpi-dev openmpi-bin \
             libclang-dev",
            header.display()
        )
    })
}
