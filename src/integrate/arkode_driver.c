/* Time loop on ARKODE ERKStep. The PETSc state Vec is wrapped as an N_Vector (no copy);
 * the loop takes one step at a time with a stop time at the next output, so it can
 * monitor every step, write outputs at exact times, and stop cleanly when the state
 * goes bad. */
#include <spam/run.h>
#include <spam/errors.h>
#include <spam/weights.h>
#include <arkode/arkode_erkstep.h>
#include <nvector/nvector_petsc.h>

int SpamArkodeAdaptMethod(const char *name);

/* The weights context comes first: ARKODE hands the same user data to the RHS and to the
 * error-weight function, which reads it as a SpamWeightsCtx. */
typedef struct {
  SpamWeightsCtx w;
  SpamSim       *sim;
  PetscInt       bad;     /* particle with a non-finite position, or -1            */
  double         tbad;    /* stage time at which it was seen                        */
  PetscErrorCode perr;    /* a PETSc failure inside the RHS                         */
  char           msg[256];/* ARKODE's last error message                            */
} ArkCtx;

static int Rhs(realtype t, N_Vector y, N_Vector ydot, void *data)
{
  ArkCtx            *c = (ArkCtx *)data;
  const PetscScalar *ya;
  PetscScalar       *fa;
  if ((c->perr = VecGetArrayRead(N_VGetVector_Petsc(y), &ya))) return -1;
  if ((c->perr = VecGetArrayWrite(N_VGetVector_Petsc(ydot), &fa))) return -1;
  c->perr = SpamRhs(c->sim, ya, fa, &c->bad);
  VecRestoreArrayWrite(N_VGetVector_Petsc(ydot), &fa);
  VecRestoreArrayRead(N_VGetVector_Petsc(y), &ya);
  if (c->perr) return -1;
  if (c->bad >= 0) c->tbad = t;
  return c->bad >= 0 ? 1 : 0;
}

static void ErrHandler(int code, const char *module, const char *function, char *msg, void *data)
{
  ArkCtx *c = (ArkCtx *)data;
  (void)code;
  (void)module;
  snprintf(c->msg, sizeof c->msg, "%s: %s", function, msg);
}

static PetscErrorCode Configure(void *mem, const SpamRunOptions *o, ArkCtx *ctx)
{
  PetscFunctionBeginUser;
  PetscCallARK(ERKStepSetUserData(mem, ctx));
  PetscCallARK(ERKStepSetErrHandlerFn(mem, ErrHandler, ctx));
  PetscCallARK(ERKStepSetTableName(mem, o->table));
  if (o->classic_weights) PetscCallARK(ERKStepSStolerances(mem, o->rtol, o->atol));
  else PetscCallARK(ERKStepWFtolerances(mem, SpamErrorWeights));
  PetscCallARK(ERKStepSetMaxNumSteps(mem, -1)); /* the loop counts steps itself */
  if (o->fixed_step > 0) PetscCallARK(ERKStepSetFixedStep(mem, o->fixed_step));
  else {
    realtype params[3] = {0, 0, 0};
    PetscCallARK(ERKStepSetAdaptivityMethod(mem, SpamArkodeAdaptMethod(o->adapt), 1, 0, params));
    if (o->dt_first > 0) PetscCallARK(ERKStepSetInitStep(mem, o->dt_first));
    if (o->safety > 0) PetscCallARK(ERKStepSetSafetyFactor(mem, o->safety));
    if (o->max_growth > 0) PetscCallARK(ERKStepSetMaxGrowth(mem, o->max_growth));
  }
  PetscFunctionReturn(0);
}

/* First particle with a non-finite entry in state y, or -1. */
static PetscInt FirstNonFinite(const SpamSim *sim, const double *y)
{
  const int nv = sim->model.layout.nvar;
  for (PetscInt i = 0; i < sim->n; i++)
    for (int k = 0; k < nv; k++)
      if (!isfinite(y[(size_t)i * nv + k])) return i;
  return -1;
}

static PetscErrorCode Progress(void *mem, const ArkCtx *ctx, PetscLogDouble wall0, SpamProgress *p)
{
  long           expsteps, accsteps, attempts, nfe, netf, nsteps;
  realtype       hlast, t;
  PetscLogDouble now;

  PetscFunctionBeginUser;
  (void)ctx;
  PetscCallARK(ERKStepGetTimestepperStats(mem, &expsteps, &accsteps, &attempts, &nfe, &netf));
  PetscCallARK(ERKStepGetNumSteps(mem, &nsteps));
  PetscCallARK(ERKStepGetLastStep(mem, &hlast));
  PetscCallARK(ERKStepGetCurrentTime(mem, &t));
  PetscCall(PetscTime(&now));
  p->t         = t;
  p->steps     = nsteps;
  p->rejected  = netf;
  p->rhs_evals = nfe;
  p->dt        = hlast;
  p->wall      = now - wall0;
  PetscFunctionReturn(0);
}

/* Diagnostics row (and snapshot when due) at the current state. */
static PetscErrorCode Output(SpamSim *sim, const SpamRunOptions *o, SpamOutput *out, const double *y, const SpamProgress *p, PetscBool snapshot, SpamRunResult *r)
{
  SpamDiagnostics d;

  PetscFunctionBeginUser;
  PetscCall(SpamDiagnosticsCompute(sim, &o->diag, p->t, y, &d));
  if (p->steps == 0 && p->t == 0.0) r->first = d;
  r->last = d;
  SpamRunUpdateDrifts(&d, r);
  PetscCall(SpamTimeseriesAppend(out, sim, p, &d, &r->first));
  if (snapshot) PetscCall(SpamSnapshotWrite(out, sim, y, p->t, NULL));
  PetscCall(SpamMonitorProgress(sim, o, p, r));
  PetscFunctionReturn(0);
}

static double NextMultiple(double t, double interval, double t_end)
{
  if (interval <= 0) return t_end;
  double k = floor(t / interval + 1e-9) + 1.0;
  return PetscMin(k * interval, t_end);
}

static PetscErrorCode Unstable(SpamSim *sim, SpamOutput *out, const ArkCtx *ctx, Vec Xgood, double tgood, SpamRunResult *r, const char *why)
{
  const PetscScalar *g;
  PetscInt           bad;

  PetscFunctionBeginUser;
  r->status = SPAM_STATUS_UNSTABLE;
  PetscCall(PetscStrncpy(r->reason, why, sizeof r->reason));
  /* Keep the last good state as a snapshot tagged last_good. */
  PetscCall(VecGetArrayRead(Xgood, &g));
  PetscCall(SpamDensitySummation(sim, g, &bad));
  if (bad < 0) PetscCall(SpamSnapshotWrite(out, sim, g, tgood, "last_good"));
  PetscCall(VecRestoreArrayRead(Xgood, &g));
  (void)ctx;
  PetscCall(PetscPrintf(sim->comm, "spam-ark: unstable: %s\n", r->reason));
  PetscFunctionReturn(0);
}

/* Sound speed at the mean summed density of the state whose density was just computed. */
static PetscErrorCode InitialSoundSpeed(const SpamSim *sim, double *c)
{
  double loc = 0.0, sum;

  PetscFunctionBeginUser;
  for (PetscInt i = 0; i < sim->n; i++) loc += sim->rho[i];
  PetscCallMPI(MPIU_Allreduce(&loc, &sum, 1, MPI_DOUBLE, MPI_SUM, sim->comm));
  *c = SpamEosSoundSpeed(&sim->model.eos, sum / (double)PetscMax(sim->nglobal, 1));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamRunArkode(SpamSim *sim, const SpamRunOptions *o, SpamOutput *out, SpamRunResult *r)
{
  SUNContext     sunctx;
  N_Vector       y;
  void          *mem;
  ArkCtx         ctx;
  Vec            Xgood;
  PetscLogDouble wall0;
  SpamProgress   p = {0};
  double         t = 0.0, next_out, next_snap;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(r, sizeof *r));
  PetscCall(PetscMemzero(&ctx, sizeof ctx));
  ctx.w.sim  = sim;
  ctx.w.rtol = o->rtol;
  ctx.w.atol = o->atol;
  ctx.sim    = sim;
  ctx.bad    = -1;
  PetscCall(PetscTime(&wall0));
  PetscCallARK(SUNContext_Create((void *)&sim->comm, &sunctx));
  y = N_VMake_Petsc(sim->X, sunctx);
  PetscCheck(y, sim->comm, PETSC_ERR_LIB, "N_VMake_Petsc failed");
  mem = ERKStepCreate(Rhs, 0.0, y, sunctx);
  PetscCheck(mem, sim->comm, PETSC_ERR_LIB, "ERKStepCreate failed");
  PetscCall(Configure(mem, o, &ctx));
  PetscCall(VecDuplicate(sim->X, &Xgood));
  PetscCall(VecCopy(sim->X, Xgood));
  {
    const PetscScalar *ya;
    PetscCall(VecGetArrayRead(sim->X, &ya));
    PetscCall(Output(sim, o, out, ya, &p, o->snapshot_interval > 0, r));
    PetscCall(VecRestoreArrayRead(sim->X, &ya));
    PetscCall(InitialSoundSpeed(sim, &ctx.w.vscale));
  }
  next_out  = NextMultiple(0.0, o->output_interval, o->t_end);
  next_snap = NextMultiple(0.0, o->snapshot_interval, o->t_end);
  while (t < o->t_end && p.steps < o->max_steps) {
    const double tstop = PetscMin(next_out, next_snap);
    realtype     tret;
    int          flag;
    PetscInt     bad;

    PetscCallARK(ERKStepSetStopTime(mem, tstop));
    flag = ERKStepEvolve(mem, tstop, y, &tret, ARK_ONE_STEP);
    PetscCall(ctx.perr);
    if (flag < 0) {
      char why[256], *name = ERKStepGetReturnFlagName(flag);
      if (ctx.bad >= 0) PetscCall(PetscSNPrintf(why, sizeof why, "non-finite position of particle %" PetscInt_FMT " at stage time t = %.6g, step %ld (%s)", ctx.bad, ctx.tbad, p.steps + 1, name));
      else PetscCall(PetscSNPrintf(why, sizeof why, "ERKStepEvolve returned %s at t = %.6g: %s", name, t, ctx.msg));
      free(name);
      PetscCall(Unstable(sim, out, &ctx, Xgood, t, r, why));
      break;
    }
    t = tret;
    PetscCall(Progress(mem, &ctx, wall0, &p));
    {
      const PetscScalar *ya;
      PetscCall(VecGetArrayRead(sim->X, &ya));
      bad = FirstNonFinite(sim, ya);
      PetscCall(VecRestoreArrayRead(sim->X, &ya));
    }
    if (bad >= 0) {
      char why[256];
      PetscCall(PetscSNPrintf(why, sizeof why, "non-finite state of particle %" PetscInt_FMT " at t = %.6g (step %ld)", bad, t, p.steps));
      PetscCall(Unstable(sim, out, &ctx, Xgood, r->t, r, why));
      break;
    }
    PetscCall(VecCopy(sim->X, Xgood));
    r->t = t;
    PetscCall(SpamStepsAppend(out, &p));
    if (o->monitor) PetscCall(SpamMonitorStep(sim, &p));
    if (t >= tstop * (1.0 - 1e-14) || t >= o->t_end || p.steps >= o->max_steps) {
      const PetscBool snap = (PetscBool)(o->snapshot_interval > 0 && (t >= next_snap * (1.0 - 1e-14) || t >= o->t_end || p.steps >= o->max_steps));
      const PetscScalar *ya;
      PetscCall(VecGetArrayRead(sim->X, &ya));
      PetscCall(Output(sim, o, out, ya, &p, snap, r));
      PetscCall(VecRestoreArrayRead(sim->X, &ya));
      if (t >= next_out * (1.0 - 1e-14)) next_out = NextMultiple(t, o->output_interval, o->t_end);
      if (t >= next_snap * (1.0 - 1e-14)) next_snap = NextMultiple(t, o->snapshot_interval, o->t_end);
    }
  }
  if (r->status != SPAM_STATUS_UNSTABLE && t < o->t_end) r->status = SPAM_STATUS_MAX_STEPS;
  PetscCall(Progress(mem, &ctx, wall0, &p));
  {
    long attempts, expsteps, accsteps, nfe, netf;
    PetscCallARK(ERKStepGetTimestepperStats(mem, &expsteps, &accsteps, &attempts, &nfe, &netf));
    r->attempts = attempts;
  }
  r->steps     = p.steps;
  r->rejected  = p.rejected;
  r->rhs_evals = p.rhs_evals;
  r->wall      = p.wall;
  PetscCall(VecDestroy(&Xgood));
  ERKStepFree(&mem);
  N_VDestroy(y);
  PetscCallARK(SUNContext_Free(&sunctx));
  PetscFunctionReturn(0);
}
