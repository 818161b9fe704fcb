/* ERKStep's step controller as spam-ark's own ARKAdaptFn, so that a restarted run can
 * continue bit for bit. ARKODE 6.4.1 keeps the error and step history of its built-in
 * controllers (ehist, hhist) where no setter reaches, and a new or re-initialised ERKStep
 * starts them blank (ehist = 1, hhist = 0). ERKStepSetAdaptivityFn hands that history to
 * this function at every step attempt (h2 = hhist[0], h3 = hhist[1], e2 = ehist[0],
 * e3 = ehist[1]); while ARKODE's own is still blank (h2 = 0 until a step has been accepted
 * since the (re)start, h3 = 0 until two have), the values saved at the checkpoint stand in
 * for it. The formulas are arkAdaptPID, arkAdaptPI, arkAdaptI, arkAdaptExpGus and
 * arkAdaptImpGus of SUNDIALS 6.4.1 (src/arkode/arkode_adapt.c), operation for operation,
 * so that a run with this controller takes the very steps of the built-in one (checked by
 * tests/test_erk_restart.c). Everything after the controller (safety factor, growth and
 * reduction bounds, CFL bound) stays ARKODE's. A SUNDIALS upgrade must re-check them
 * (6.7 replaces this interface by SUNAdaptController). */
#include <spam/integrator.h>
#include <spam/errors.h>
#include <math.h>

/* Constants of SUNDIALS 6.4.1 (arkode_impl.h, arkode_adapt_impl.h): they are not exported. */
#define ARK641_TINY   1.0e-10 /* floor of an error estimate in the controllers          */
#define ARK641_BIAS   1.5     /* error bias: e1 = BIAS dsm (spam-ark never changes it)   */
#define ARK641_GROWTH 20.0    /* ERKStep's default largest growth after a step          */
#define ARK641_MAX(a, b) ((a) > (b) ? (a) : (b)) /* SUNMAX: a NaN estimate gives b */

/* The gains ARKODE's SetAdaptivityMethod(idefault = 1) gives each controller, in the
 * order of SpamArkodeAdaptMethod (pid, pi, i, expgus, impgus). */
static const double DefaultGains[5][3] = {
  {0.58, 0.21, 0.1}, {0.8, 0.31, 0.0}, {1.0, 0.0, 0.0}, {0.367, 0.268, 0.0}, {0.98, 0.95, 0.0}
};

static void BlankHistory(SpamArkodeHistory *h)
{
  h->h_next   = 0.0;
  h->ehist[0] = h->ehist[1] = 1.0; /* ARKODE's values before any accepted step */
  h->hhist[0] = h->hhist[1] = 0.0;
  h->accepted = 0;
}

/* The Gustafsson controllers take a first-step form while fewer than two steps (counting
 * the one being judged if it passes) have been accepted in the whole run. ARKODE passes
 * that count to its own controllers but not to an ARKAdaptFn: it is rebuilt from ERKStep's
 * count since the (re)start, the checkpoint's count and the verdict dsm <= 1, which is
 * e1 <= BIAS exactly (e1 = BIAS dsm rounds monotonically, and 1.5 (1 + 2^-52) rounds above
 * 1.5). */
static long AcceptedCount(const SpamArkodeController *c, double e1)
{
  long nst = 0;

  if (ERKStepGetNumSteps(c->mem, &nst) != ARK_SUCCESS) nst = 0;
  return c->saved.accepted + nst + (e1 <= ARK641_BIAS ? 1 : 0);
}

static double StepOf(const SpamArkodeController *c, int k, double h1, double h2, double e1, double e2, double e3)
{
  switch (c->method) {
  case 0: { /* arkAdaptPID */
    const double k1 = -c->k[0] / k, k2 = c->k[1] / k, k3 = -c->k[2] / k;
    e1 = ARK641_MAX(e1, ARK641_TINY);
    e2 = ARK641_MAX(e2, ARK641_TINY);
    e3 = ARK641_MAX(e3, ARK641_TINY);
    return h1 * pow(e1, k1) * pow(e2, k2) * pow(e3, k3);
  }
  case 1: { /* arkAdaptPI */
    const double k1 = -c->k[0] / k, k2 = c->k[1] / k;
    e1 = ARK641_MAX(e1, ARK641_TINY);
    e2 = ARK641_MAX(e2, ARK641_TINY);
    return h1 * pow(e1, k1) * pow(e2, k2);
  }
  case 2: /* arkAdaptI */
    return h1 * pow(ARK641_MAX(e1, ARK641_TINY), -c->k[0] / k);
  default: { /* arkAdaptExpGus (3), arkAdaptImpGus (4) */
    double k1, k2, r;
    if (AcceptedCount(c, e1) < 2) return h1 * pow(ARK641_MAX(e1, ARK641_TINY), -1.0 / k);
    k1 = -c->k[0] / k;
    k2 = -c->k[1] / k;
    e1 = ARK641_MAX(e1, ARK641_TINY);
    r  = e1 / ARK641_MAX(e2, ARK641_TINY);
    if (c->method == 3) return h1 * pow(e1, k1) * pow(r, k2);
    return h1 * (h1 / h2) * pow(e1, k1) * pow(r, k2);
  }
  }
}

int SpamArkodeControllerAdapt(N_Vector y, realtype t, realtype h1, realtype h2, realtype h3, realtype e1, realtype e2, realtype e3, int q, int p, realtype *hnew, void *data)
{
  SpamArkodeController *c = (SpamArkodeController *)data;

  (void)y;
  (void)t;
  (void)q; /* spam-ark asks for the embedding's order p (pq = 0), as it did of ARKODE */
  (void)h3;
  if (h2 == 0.0) { /* nothing accepted since the (re)start: the saved history */
    e2 = c->saved.ehist[0];
    e3 = c->saved.ehist[1];
    h2 = c->saved.hhist[0];
  } else if (h3 == 0.0) e3 = c->saved.ehist[0]; /* one accepted: its predecessor is saved */
  /* After an accepted attempt these become ARKODE's ehist[0], ehist[1] and hhist[0],
   * hhist[1] (arkCompleteStep shifts them in): what a checkpoint needs. */
  c->last_e[0] = e1;
  c->last_e[1] = e2;
  c->last_h[0] = h1;
  c->last_h[1] = h2;
  *hnew = StepOf(c, p, h1, h2, e1, e2, e3);
  return 0;
}

PetscErrorCode SpamArkodeControllerSetUp(SpamArkodeController *c, const SpamArkodeSettings *s, void *mem)
{
  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(c, sizeof *c));
  c->method = SpamArkodeAdaptMethod(s->adapt);
  PetscCheck(c->method >= 0, PETSC_COMM_SELF, PETSC_ERR_ARG_OUTOFRANGE, "unknown ARKODE controller %s", s->adapt);
  for (int k = 0; k < 3; k++) c->k[k] = s->n_adapt_params == 0 ? DefaultGains[c->method][k] : s->adapt_params[k];
  c->growth = s->max_growth > 0 ? s->max_growth : ARK641_GROWTH;
  c->mem    = mem;
  BlankHistory(&c->saved);
  PetscCallARK(ERKStepSetAdaptivityFn(mem, SpamArkodeControllerAdapt, c));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamArkodeControllerGet(const SpamArkodeController *c, SpamArkodeHistory *h)
{
  long nst;

  PetscFunctionBeginUser;
  PetscCallARK(ERKStepGetNumSteps(c->mem, &nst));
  if (nst == 0) { /* no step since the (re)start: what it was given */
    *h = c->saved;
    PetscFunctionReturn(0);
  }
  PetscCallARK(ERKStepGetCurrentStep(c->mem, &h->h_next));
  h->ehist[0] = c->last_e[0];
  h->ehist[1] = c->last_e[1];
  h->hhist[0] = c->last_h[0];
  h->hhist[1] = c->last_h[1];
  h->accepted = c->saved.accepted + nst;
  PetscFunctionReturn(0);
}

/* On an ERKStep just created or re-initialised at the checkpoint's time and state: the
 * first step is h_next, and its growth bound the ordinary one (ARKODE allows a first step
 * of a fresh start to grow up to 10^4 times, which the uninterrupted run did not). */
PetscErrorCode SpamArkodeControllerResume(SpamArkodeController *c, const SpamArkodeHistory *h)
{
  PetscFunctionBeginUser;
  PetscCheck(h->h_next > 0 && isfinite(h->h_next), PETSC_COMM_SELF, PETSC_ERR_ARG_OUTOFRANGE, "restart step size %g is not a positive number", h->h_next);
  PetscCheck(h->accepted >= 0, PETSC_COMM_SELF, PETSC_ERR_ARG_OUTOFRANGE, "restart step count %ld is negative", h->accepted);
  c->saved = *h;
  PetscCallARK(ERKStepSetInitStep(c->mem, h->h_next));
  PetscCallARK(ERKStepSetMaxFirstGrowth(c->mem, c->growth));
  PetscFunctionReturn(0);
}
