/* Error weights for ERKStep. A relative tolerance applied to |x| would make the step
 * depend on where the origin is, so positions are weighed against the kernel range h:
 * 1/(rtol h + atol), the same for every particle and every translation. Velocities are
 * weighed against the particle's speed |v_i| (rotation invariant), floored at the sound
 * speed: 1/(rtol max(|v_i|, c0) + atol). Other fields against their declared scales.
 * The norm of error times weight that the method holds to 1 is -error_norm's (error_norm.c).
 *
 * At a fixed step ERKStep makes no error test; it still calls this function once a step
 * and reads the weights once, for its "too much accuracy" check (uround times the norm
 * of y above 1), which zero weights pass as they pass any others a run can have. So the
 * weights are then zeros that take no memory (zero_pages.c), set once per array: a state
 * vector of memory (32 bytes a particle in 2D) and a pass over the state per step less. */
#include <spam/weights.h>
#include <spam/zero_pages.h>
#include <nvector/nvector_petsc.h>

static int ZeroWeights(SpamWeightsCtx *w, N_Vector ewt)
{
  PetscScalar *wa;
  PetscInt     n;

  if (VecGetLocalSize(N_VGetVector_Petsc(ewt), &n)) return -1;
  if (VecGetArrayWrite(N_VGetVector_Petsc(ewt), &wa)) return -1;
  if (w->zeroed != (const void *)wa) SpamZeroPages(wa, (size_t)n * sizeof *wa);
  w->zeroed = wa;
  if (VecRestoreArrayWrite(N_VGetVector_Petsc(ewt), &wa)) return -1;
  return 0;
}

int SpamErrorWeights(N_Vector y, N_Vector ewt, void *ctx)
{
  const SpamWeightsCtx *w = (const SpamWeightsCtx *)ctx;
  const SpamModel      *m = &w->sim->model;
  const SpamLayout     *l = &m->layout;
  const double          wx = 1.0 / (w->rtol * m->kernel.h + w->atol);
  const PetscScalar    *ya;
  PetscScalar          *wa;

  if (w->fixed_step) return ZeroWeights((SpamWeightsCtx *)ctx, ewt);
  if (VecGetArrayRead(N_VGetVector_Petsc(y), &ya)) return -1;
  if (VecGetArrayWrite(N_VGetVector_Petsc(ewt), &wa)) return -1;
  for (PetscInt i = 0; i < w->sim->p.n; i++) {
    const PetscScalar *p = ya + (size_t)i * l->nvar;
    PetscScalar       *q = wa + (size_t)i * l->nvar;
    double             v2 = 0.0;
    for (int d = 0; d < m->dim; d++) v2 += p[l->v + d] * p[l->v + d];
    for (int d = 0; d < m->dim; d++) {
      q[l->x + d] = wx;
      q[l->v + d] = 1.0 / (w->rtol * PetscMax(sqrt(v2), w->vscale) + w->atol);
    }
    SpamLayoutFieldWeights(l, p, w->rtol, w->atol, q); /* e, rho, stress: their own scales */
  }
  if (VecRestoreArrayWrite(N_VGetVector_Petsc(ewt), &wa)) return -1;
  if (VecRestoreArrayRead(N_VGetVector_Petsc(y), &ya)) return -1;
  return 0;
}
