/* A handle over DMUMPS_STRUC_C: the struct's layout stays in MUMPS' own header, so the Rust
 * side never mirrors it (src/ffi.rs). Arrays passed in are borrowed, not copied: the caller
 * keeps them alive and unmoved between the calls that use them (MUMPS' own rule). */
#include <stdlib.h>
#include <string.h>
#include "dmumps_c.h"

/* comm_fortran: a Fortran communicator handle, or MUMPS' code for MPI_COMM_WORLD
 * (-987654, its C examples' USE_COMM_WORLD). */
DMUMPS_STRUC_C *talus_dmumps_init(int sym, int comm_fortran) {
    DMUMPS_STRUC_C *id = calloc(1, sizeof(DMUMPS_STRUC_C));
    if (!id) return NULL;
    id->comm_fortran = comm_fortran;
    id->par = 1; /* the host works too */
    id->sym = sym;
    id->job = -1;
    dmumps_c(id);
    return id;
}

void talus_dmumps_end(DMUMPS_STRUC_C *id) {
    if (!id) return;
    id->job = -2;
    dmumps_c(id);
    free(id);
}

void talus_dmumps_set_icntl(DMUMPS_STRUC_C *id, int i, int value) { id->icntl[i - 1] = value; }
int talus_dmumps_infog(const DMUMPS_STRUC_C *id, int i) { return id->infog[i - 1]; }
double talus_dmumps_rinfog(const DMUMPS_STRUC_C *id, int i) { return id->rinfog[i - 1]; }

/* The local entries (ICNTL(18) = 3), 1-based indices. */
void talus_dmumps_set_local_matrix(DMUMPS_STRUC_C *id, int n, long long nnz_loc,
                                   int *irn_loc, int *jcn_loc, double *a_loc) {
    id->n = n;
    id->nnz_loc = nnz_loc;
    id->nz_loc = (nnz_loc <= 2147483647LL) ? (int)nnz_loc : 0;
    id->irn_loc = irn_loc;
    id->jcn_loc = jcn_loc;
    id->a_loc = a_loc;
}

void talus_dmumps_set_local_values(DMUMPS_STRUC_C *id, double *a_loc) { id->a_loc = a_loc; }

/* The centralized right-hand side, on the host only (ICNTL(20) = 0, ICNTL(21) = 0). */
void talus_dmumps_set_rhs(DMUMPS_STRUC_C *id, double *rhs) {
    id->rhs = rhs;
    id->nrhs = 1;
    id->lrhs = id->n;
}

int talus_dmumps_job(DMUMPS_STRUC_C *id, int job) {
    id->job = job;
    dmumps_c(id);
    return id->infog[0];
}
