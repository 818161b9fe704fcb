/* Work on several ranks that fails on one of them only: a text file rank 0 writes alone, an
 * HDF5 call or an allocation that fails on one rank. That rank's error must end every rank
 * (the others would wait for it in the next collective, for ever) and be printed once. */
#include <spam/errors.h>

typedef struct {
  PetscErrorCode code;
  char           mess[1024];
} Caught;

/* Keeps the first report of an error in fn (PETSc calls the handler again at each level
 * of the stack as the error travels up) and prints nothing: the error is raised again,
 * with this message, on every rank. */
static PetscErrorCode Catch(MPI_Comm comm, int line, const char *fun, const char *file, PetscErrorCode n, PetscErrorType p, const char *mess, void *ctx)
{
  Caught *c = ctx;

  (void)comm;
  (void)line;
  (void)file;
  if (p == PETSC_ERROR_INITIAL && !c->code) {
    /* Raised again from SpamRunAgreed, an allocator's failure would no longer be known
     * as one: keep it as out of memory, with its line. */
    if (SpamErrorIsOutOfMemory(n, fun)) {
      c->code = PETSC_ERR_MEM;
      SpamOutOfMemoryText(fun, mess, c->mess, sizeof c->mess);
    } else {
      c->code = n;
      (void)snprintf(c->mess, sizeof c->mess, "%s", mess ? mess : "error");
    }
  }
  return n;
}

PetscErrorCode SpamRunAgreed(MPI_Comm comm, PetscBool root_only, PetscErrorCode (*fn)(void *), void *ctx)
{
  PetscMPIInt    rank, size, failed;
  Caught         c = {0, ""};
  PetscErrorCode ierr = 0;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCallMPI(MPI_Comm_size(comm, &size));
  if (!root_only || rank == 0) {
    PetscCall(PetscPushErrorHandler(Catch, &c));
    ierr = fn(ctx);
    PetscCall(PetscPopErrorHandler());
    if (ierr && !c.code) { /* an error code without a report */
      c.code = ierr;
      (void)snprintf(c.mess, sizeof c.mess, "error %d", (int)ierr);
    }
  }
  /* the lowest rank that failed speaks for all */
  failed = c.code ? rank : size;
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &failed, 1, MPI_INT, MPI_MIN, comm));
  if (failed == size) PetscFunctionReturn(0);
  PetscCallMPI(MPI_Bcast(&c, (int)sizeof c, MPI_BYTE, failed, comm));
  SETERRQ(comm, c.code, "%s", c.mess);
}

PetscErrorCode SpamAgreeOnFailure(MPI_Comm comm, PetscErrorCode local, const char *what)
{
  int mine = local != 0, any = 0;

  PetscFunctionBeginUser;
  PetscCallMPI(MPIU_Allreduce(&mine, &any, 1, MPI_INT, MPI_MAX, comm));
  PetscCall(local);
  PetscCheck(!any, PETSC_COMM_SELF, PETSC_ERR_LIB, "%s failed on another rank", what);
  PetscFunctionReturn(0);
}
