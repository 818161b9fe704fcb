/* The state vector X over the swarm's packed field (swarm.h). PETSc's
 * DMSwarmCreateGlobalVectorFromField makes a standard vector, which allocates and zeroes
 * an array of its own, then places the field's array in it: the own array, one state
 * vector of memory, stays resident and unused for the vector's life. Made here over the
 * field's array from the start, so the state takes its memory once. */
#include <spam/swarm.h>
#include <spam/huge_pages.h>

PetscErrorCode SpamSwarmOpenState(SpamSwarm *p)
{
  PetscScalar  *s;
  PetscInt      bs, n;
  PetscDataType type;
  PetscMPIInt   size;

  PetscFunctionBeginUser;
  PetscCall(DMSwarmGetLocalSize(p->swarm, &n));
  PetscCall(DMSwarmGetField(p->swarm, SPAM_STATE_FIELD, &bs, &type, (void **)&s));
  PetscCheck(type == PETSC_REAL, p->comm, PETSC_ERR_SUP, "the state field must hold reals");
  PetscCallMPI(MPI_Comm_size(p->comm, &size));
  /* DMSwarm has zeroed the field: its pages are small until gathered (huge_pages.c) */
  SpamCollapseHugePages(s, (size_t)n * bs * sizeof *s);
  if (size == 1) PetscCall(VecCreateSeqWithArray(p->comm, bs, n * bs, s, &p->X));
  else PetscCall(VecCreateMPIWithArray(p->comm, bs, n * bs, PETSC_DETERMINE, s, &p->X));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamSwarmCloseState(SpamSwarm *p)
{
  PetscScalar *s = NULL;

  PetscFunctionBeginUser;
  if (!p->X) PetscFunctionReturn(0);
  PetscCall(VecDestroy(&p->X));
  PetscCall(DMSwarmRestoreField(p->swarm, SPAM_STATE_FIELD, NULL, NULL, (void **)&s)); /* the access SpamSwarmOpenState opened */
  PetscFunctionReturn(0);
}
