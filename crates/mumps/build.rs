//! Compiles the C handle over `dmumps_c.h` and links Debian's MPI MUMPS (`libmumps-dev`).
fn main() {
    println!("cargo:rerun-if-changed=csrc/shim.c");
    // Debian puts dmumps_c.h in /usr/include; MUMPS_INCLUDE_DIR / MUMPS_LIB_DIR point
    // elsewhere (a cluster's module).
    let mut build = cc::Build::new();
    build.file("csrc/shim.c").warnings(true);
    if let Ok(dir) = std::env::var("MUMPS_INCLUDE_DIR") {
        build.include(dir);
    }
    build.compile("talus_dmumps_shim");
    println!("cargo:rerun-if-env-changed=MUMPS_INCLUDE_DIR");
    println!("cargo:rerun-if-env-changed=MUMPS_LIB_DIR");
    if let Ok(dir) = std::env::var("MUMPS_LIB_DIR") {
        println!("cargo:rustc-link-search=native={dir}");
    }
    println!("cargo:rustc-link-lib=dylib=dmumps");
    println!("cargo:rustc-link-lib=dylib=mumps_common");
}
