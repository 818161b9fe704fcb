/* Torque scaling (PRE Sec. VIII). The pair forces of SPAM are not central, so each pair
 * exerts a spurious torque Ldot_ij = x_ij F^y_ij - y_ij F^x_ij. With R^2 the sum of the
 * positive torques over minus the sum of the negative ones, dividing the positive torques
 * by R and multiplying the negative ones by R makes their sum vanish exactly:
 *   T_ij: on each pair's Ldot_ij;
 *   T_i : on the particle torques Ldot_i = 1/2 sum_j Ldot_ij, each pair then using the
 *         mean (f_i + f_j)/2 of its two particles' factors, which again sums to zero.
 * The sums run per connected body (local conservation, PRE Sec. IX) or over everything.
 * Where either sum is zero (at t = 0 every torque vanishes) the factor stays 1. */
#include <spam/physics.h>

/* Visits each listed pair in range with its separation and unscaled tensor force. */
#define FOR_EACH_PAIR_FORCE(sim, qs, BODY) \
  do { \
    const SpamNeighbours *nl_ = &(sim)->nl; \
    const SpamImage       im_ = SpamBoxImage(&(sim)->box); \
    for (int i = 0; i < nl_->n; i++) \
      for (int p_ = nl_->start[i]; p_ < nl_->start[i + 1]; p_++) { \
        const int    j = nl_->nbr[p_]; \
        double       dx[2], F[2]; \
        const double r2_ = SpamPairDelta2(nl_, &im_, i, j, dx); \
        if (r2_ >= (sim)->model.kernel.h2) continue; \
        SpamPairForceTensor((sim)->model.mass, (qs) + 3 * i, (qs) + 3 * j, SpamKernelDWOverR(&(sim)->model.kernel, r2_), dx, F); \
        BODY \
      } \
  } while (0)

double SpamTorqueSum(const SpamSim *sim, const double *qs)
{
  double total = 0.0;
  FOR_EACH_PAIR_FORCE(sim, qs, { total += SpamPairTorque(dx, F); });
  return total;
}

static int BodyOf(const SpamSim *sim, int i)
{
  return sim->model.solid.per_body ? sim->ps->body[i] : 0;
}

/* R = sqrt(positive / -negative) per body, or 1 where a sum vanishes. */
static PetscErrorCode BodyFactors(SpamSim *sim)
{
  SpamPhysicsScratch *ps = sim->ps;
  const int           nb = sim->model.solid.per_body ? ps->nbody : 1;

  PetscFunctionBeginUser;
  PetscCallMPI(MPIU_Allreduce(MPI_IN_PLACE, ps->bpos, nb, MPI_DOUBLE, MPI_SUM, sim->comm));
  PetscCallMPI(MPIU_Allreduce(MPI_IN_PLACE, ps->bneg, nb, MPI_DOUBLE, MPI_SUM, sim->comm));
  for (int b = 0; b < nb; b++) ps->bfac[b] = (ps->bpos[b] > 0.0 && ps->bneg[b] < 0.0) ? sqrt(ps->bpos[b] / -ps->bneg[b]) : 1.0;
  PetscFunctionReturn(0);
}

PetscErrorCode SpamTorqueScalingFactors(SpamSim *sim, const double *qs, double *total)
{
  SpamPhysicsScratch *ps   = sim->ps;
  const PetscBool     pair = (PetscBool)(sim->model.solid.angmom == SPAM_ANGMOM_TIJ);
  double              sum  = 0.0;

  PetscFunctionBeginUser;
  for (int b = 0; b < ps->nbody; b++) ps->bpos[b] = ps->bneg[b] = 0.0;
  for (PetscInt i = 0; i < sim->n; i++) ps->ltorque[i] = 0.0;
  FOR_EACH_PAIR_FORCE(sim, qs, {
    const double L = SpamPairTorque(dx, F);
    sum += L;
    if (pair) {
      if (L > 0.0) ps->bpos[BodyOf(sim, i)] += L;
      else ps->bneg[BodyOf(sim, i)] += L;
    } else {
      ps->ltorque[i] += 0.5 * L;
      ps->ltorque[j] += 0.5 * L;
    }
  });
  if (!pair)
    for (PetscInt i = 0; i < sim->n; i++) {
      if (ps->ltorque[i] > 0.0) ps->bpos[BodyOf(sim, (int)i)] += ps->ltorque[i];
      else ps->bneg[BodyOf(sim, (int)i)] += ps->ltorque[i];
    }
  PetscCall(BodyFactors(sim));
  if (!pair)
    for (PetscInt i = 0; i < sim->n; i++) {
      const double R = ps->bfac[BodyOf(sim, (int)i)];
      ps->tfac[i]    = ps->ltorque[i] > 0.0 ? 1.0 / R : R;
    }
  PetscCallMPI(MPIU_Allreduce(&sum, total, 1, MPI_DOUBLE, MPI_SUM, sim->comm));
  PetscFunctionReturn(0);
}
