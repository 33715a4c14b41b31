//! The C handle of `csrc/shim.c`: `DMUMPS_STRUC_C` stays opaque here, its layout in MUMPS'
//! own header.
use std::os::raw::{c_double, c_int, c_longlong};

#[repr(C)]
pub(crate) struct Struc {
    _opaque: [u8; 0],
}

extern "C" {
    pub(crate) fn talus_dmumps_init(sym: c_int, comm_fortran: c_int) -> *mut Struc;
    pub(crate) fn talus_dmumps_end(id: *mut Struc);
    pub(crate) fn talus_dmumps_set_icntl(id: *mut Struc, i: c_int, value: c_int);
    pub(crate) fn talus_dmumps_infog(id: *const Struc, i: c_int) -> c_int;
    pub(crate) fn talus_dmumps_rinfog(id: *const Struc, i: c_int) -> c_double;
    pub(crate) fn talus_dmumps_set_local_matrix(
        id: *mut Struc,
        n: c_int,
        nnz_loc: c_longlong,
        irn_loc: *mut c_int,
        jcn_loc: *mut c_int,
        a_loc: *mut c_double,
    );
    pub(crate) fn talus_dmumps_set_local_values(id: *mut Struc, a_loc: *mut c_double);
    pub(crate) fn talus_dmumps_set_rhs(id: *mut Struc, rhs: *mut c_double);
    pub(crate) fn talus_dmumps_job(id: *mut Struc, job: c_int) -> c_int;
}
