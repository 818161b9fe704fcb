/* Closest-approach reflection (PRE Sec. IV): "elastically reflecting the radial component
 * of velocity for approaching pairs of particles at a fixed closest-approach distance".
 * With equal masses the centre-of-mass velocity of the pair is kept and the radial
 * relative velocity reversed, so momentum and kinetic energy are unchanged. */
#include <spam/physics.h>

PetscErrorCode SpamClosestApproachReflect(SpamSim *sim, double *y, double dmin, PetscInt *nreflected)
{
  const SpamLayout *l  = &sim->model.layout;
  const int         nv = l->nvar;
  const SpamImage   im = sim->pair.nl.im;
  PetscInt          bad;

  PetscFunctionBeginUser;
  *nreflected = 0;
  PetscCall(SpamNeighboursUpdate(&sim->pair.nl, &sim->geo.box, y + l->x, nv, PETSC_FALSE, &bad));
  PetscCheck(bad < 0, sim->p.comm, PETSC_ERR_FP, "non-finite position of particle %" PetscInt_FMT, bad);
  for (int i = 0; i < sim->pair.nl.n; i++) {
    for (int p = sim->pair.nl.start[i]; p < sim->pair.nl.start[i + 1]; p++) {
      const int    j = sim->pair.nl.nbr[p];
      double       dx[2];
      const double r2 = SpamPairDelta2(&sim->pair.nl, &im, i, j, dx);
      if (r2 >= dmin * dmin || r2 == 0.0) continue;
      double      *vi = y + (size_t)i * nv + l->v, *vj = y + (size_t)j * nv + l->v;
      const double vr = ((vi[0] - vj[0]) * dx[0] + (vi[1] - vj[1]) * dx[1]) / r2; /* (v_ij.r_ij)/r^2 */
      if (vr >= 0.0) continue;
      for (int d = 0; d < 2; d++) {
        vi[d] -= vr * dx[d];
        vj[d] += vr * dx[d];
      }
      (*nreflected)++;
    }
  }
  PetscFunctionReturn(0);
}
