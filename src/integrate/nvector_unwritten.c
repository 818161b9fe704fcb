/* ERKStep clones its stage, work and interpolant vectors from the solution (N_VClone).
 * NVECTOR_PETSC's clone is VecDuplicate, whose array PETSc zeroes, so every page of every
 * clone is resident whether or not the integrator ever reads the vector: ERKStep 6.4.1
 * reads four of its seven work vectors, and the Hermite interpolant's third vector,
 * never in a run without dense outputs (five vectors, 160 bytes a particle in 2D). The
 * clone here takes its array from PetscMalloc unwritten, so a vector's pages become
 * resident when the integrator first writes it. SUNDIALS writes each vector before it
 * reads it (its serial vectors are not zeroed either), so the results do not change.
 * Those first writes come inside the run loop (a stage vector's inside a right-hand
 * side), so a large clone asks for huge pages (huge_pages.c). */
#include <spam/integrator.h>
#include <spam/huge_pages.h>
#include <nvector/nvector_petsc.h>

/* A Vec of w's type, layout and communicator over an array nobody has written: VECSEQ
 * and VECMPI (the solution's types); another type is duplicated as NVECTOR_PETSC does. */
static PetscErrorCode VecUnwritten(Vec w, Vec *v)
{
  PetscInt    n, N, bs;
  PetscBool   seq, mpi;
  MPI_Comm    comm;
  PetscScalar *a;

  PetscFunctionBeginUser;
  PetscCall(PetscObjectTypeCompare((PetscObject)w, VECSEQ, &seq));
  PetscCall(PetscObjectTypeCompare((PetscObject)w, VECMPI, &mpi));
  if (!seq && !mpi) {
    PetscCall(VecDuplicate(w, v));
    PetscFunctionReturn(0);
  }
  PetscCall(VecGetLocalSize(w, &n));
  PetscCall(VecGetSize(w, &N));
  PetscCall(VecGetBlockSize(w, &bs));
  PetscCall(PetscObjectGetComm((PetscObject)w, &comm));
  if (seq) PetscCall(VecCreateSeqWithArray(comm, bs, n, NULL, v));
  else PetscCall(VecCreateMPIWithArray(comm, bs, n, N, NULL, v));
  PetscCall(PetscMalloc1(n, &a));
  SpamAdviseHugePages(a, (size_t)n * sizeof *a); /* first written in the loop (huge_pages.c) */
  PetscCall(VecReplaceArray(*v, a));             /* the Vec owns a and frees it */
  PetscFunctionReturn(0);
}

/* N_VClone for NVECTOR_PETSC vectors (SUNDIALS calls it, so errors are a NULL vector). */
static N_Vector CloneUnwritten(N_Vector w)
{
  N_Vector c = N_VCloneEmpty_Petsc(w);
  Vec      v = NULL;

  if (!c) return NULL;
  if (VecUnwritten(N_VGetVector_Petsc(w), &v)) {
    N_VDestroy_Petsc(c);
    return NULL;
  }
  {
    /* what is composed on the solution follows it into its clones (ts_arkode.c's record
     * of ERKStep's copies) */
    PetscObject k = NULL;
    if (PetscObjectQuery((PetscObject)N_VGetVector_Petsc(w), "SpamArkodeCopies", &k) || (k && PetscObjectCompose((PetscObject)v, "SpamArkodeCopies", k))) {
      VecDestroy(&v);
      N_VDestroy_Petsc(c);
      return NULL;
    }
  }
  ((N_VectorContent_Petsc)c->content)->own_data = SUNTRUE; /* N_VDestroy destroys v */
  ((N_VectorContent_Petsc)c->content)->pvec     = v;
  return c;
}

/* SUNDIALS 6.4.1's N_VClone uses the clone it gets without a check: a clone that fails for
 * want of memory crashes the integrator instead of ending the run with its one-line error
 * (the first evolve allocates the interpolant's vectors). So before ERKStep makes its
 * vectors, the memory for count of them is asked for once and given back: a run that
 * cannot have them fails here, through PETSc's error path. The block is never written, so
 * where memory is overcommitted it costs no resident page. */
PetscErrorCode SpamNVectorReserve(Vec y, PetscInt count)
{
  PetscInt     n;
  PetscScalar *a;

  PetscFunctionBeginUser;
  PetscCall(VecGetLocalSize(y, &n));
  PetscCall(PetscMalloc1((size_t)n * (size_t)count + 1, &a));
  PetscCall(PetscFree(a));
  PetscFunctionReturn(0);
}

void SpamNVectorCloneUnwritten(N_Vector y)
{
  y->ops->nvclone = CloneUnwritten;
}
