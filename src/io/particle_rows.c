/* The particles as rows in gid order, on blocks of ranks or on rank 0 (particle_rows.h).
 * One PetscSF whose leaves are the local particles (leaf i is particle i: the state, mass
 * and density arrays are sent as they lie, no packing) and whose roots are the rows of
 * the target layout, root gid for the particle of that gid; a reduce with MPI_REPLACE
 * moves each array (every root has exactly one leaf). */
#include "particle_rows.h"

static PetscErrorCode TargetLayout(const SpamSwarm *sw, PetscInt64 N, SpamRowsTarget target, PetscLayout *layout)
{
  PetscMPIInt rank;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(sw->comm, &rank));
  PetscCall(PetscLayoutCreate(sw->comm, layout));
  if (target == SPAM_ROWS_ON_ROOT) PetscCall(PetscLayoutSetLocalSize(*layout, rank ? 0 : (PetscInt)N));
  else PetscCall(PetscLayoutSetSize(*layout, (PetscInt)N));
  PetscCall(PetscLayoutSetUp(*layout));
  PetscFunctionReturn(0);
}

/* Moves n leaf units of `unit` into the roots. */
static PetscErrorCode Move(PetscSF sf, MPI_Datatype unit, const void *leaves, void *roots)
{
  PetscFunctionBeginUser;
  PetscCall(PetscSFReduceBegin(sf, unit, leaves, roots, MPI_REPLACE));
  PetscCall(PetscSFReduceEnd(sf, unit, leaves, roots, MPI_REPLACE));
  PetscFunctionReturn(0);
}

/* Every row got the particle of its gid: a gid repeated or missing (a broken migration)
 * would otherwise write a row of zeros. Agreed by all ranks. */
static PetscErrorCode CheckRows(const SpamSwarm *sw, const SpamRows *rows)
{
  PetscInt64 wrong = -1;

  PetscFunctionBeginUser;
  for (PetscInt r = 0; r < rows->n && wrong < 0; r++)
    if (rows->gid[r] != rows->first + r) wrong = rows->first + r;
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &wrong, 1, MPIU_INT64, MPI_MAX, sw->comm));
  PetscCheck(wrong < 0, sw->comm, PETSC_ERR_PLIB, "output rows: no particle or more than one holds gid %" PetscInt64_FMT " of %" PetscInt64_FMT, wrong, rows->nglobal);
  PetscFunctionReturn(0);
}

PetscErrorCode SpamRowsGather(const SpamSim *sim, const double *y, SpamRowsTarget target, SpamRows *rows)
{
  const SpamLayout *l = &sim->model.layout;
  PetscInt64        N = sim->p.n;
  PetscLayout       layout;
  PetscSF           sf;
  PetscInt         *at, lo, hi;
  MPI_Datatype      state;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(rows, sizeof *rows));
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &N, 1, MPIU_INT64, MPI_SUM, sim->p.comm));
  PetscCheck(N <= PETSC_MAX_INT, sim->p.comm, PETSC_ERR_SUP, "output rows: %" PetscInt64_FMT " particles, more than a PetscInt indexes", N);
  PetscCall(TargetLayout(&sim->p, N, target, &layout));
  PetscCall(PetscLayoutGetRange(layout, &lo, &hi));
  rows->n       = hi - lo;
  rows->first   = lo;
  rows->nglobal = N;
  rows->nvar    = l->nvar;
  PetscCall(PetscMalloc1((size_t)rows->n * l->nvar + 1, &rows->y));
  PetscCall(PetscMalloc2(rows->n + 1, &rows->m, rows->n + 1, &rows->gid));
  if (l->rho < 0) PetscCall(PetscMalloc1(rows->n + 1, &rows->rho_sum));
  if (sim->pair.f.adaptive) PetscCall(PetscMalloc1(rows->n + 1, &rows->h));
  for (PetscInt r = 0; r < rows->n; r++) rows->gid[r] = -1;

  PetscCall(PetscMalloc1(sim->p.n + 1, &at));
  for (PetscInt i = 0; i < sim->p.n; i++) at[i] = (PetscInt)SpamSimRowOf(sim, i);
  PetscCall(PetscSFCreate(sim->p.comm, &sf));
  PetscCall(PetscSFSetGraphLayout(sf, layout, sim->p.n, NULL, PETSC_COPY_VALUES, at));
  PetscCall(PetscSFSetUp(sf));
  PetscCall(PetscFree(at));
  PetscCallMPI(MPI_Type_contiguous(l->nvar, MPI_DOUBLE, &state));
  PetscCallMPI(MPI_Type_commit(&state));
  PetscCall(Move(sf, state, y, rows->y));
  PetscCallMPI(MPI_Type_free(&state));
  PetscCall(Move(sf, MPI_DOUBLE, sim->pair.f.m, rows->m));
  if (rows->rho_sum) PetscCall(Move(sf, MPI_DOUBLE, sim->pair.f.rho, rows->rho_sum));
  if (rows->h) PetscCall(Move(sf, MPI_DOUBLE, sim->pair.f.h, rows->h));
  if (sim->p.gid) PetscCall(Move(sf, MPIU_INT64, sim->p.gid, rows->gid));
  else
    for (PetscInt r = 0; r < rows->n; r++) rows->gid[r] = rows->first + r; /* a sim without a swarm gid field (unit tests): row = index */
  PetscCall(PetscSFDestroy(&sf));
  PetscCall(PetscLayoutDestroy(&layout));
  PetscCall(CheckRows(&sim->p, rows));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamRowsFree(SpamRows *rows)
{
  PetscFunctionBeginUser;
  PetscCall(PetscFree(rows->y));
  PetscCall(PetscFree2(rows->m, rows->gid));
  PetscCall(PetscFree(rows->rho_sum));
  PetscCall(PetscFree(rows->h));
  rows->n = 0;
  PetscFunctionReturn(0);
}

double SpamRowsDensity(const SpamLayout *l, const SpamRows *rows, PetscInt r)
{
  return l->rho >= 0 ? rows->y[(size_t)r * l->nvar + l->rho] : rows->rho_sum[r];
}
