/* Verlet through PETSc's basicsymplectic TS. In PETSc 3.18 each stage first kicks
 * (v += c_i dt a(x)) and then drifts (x += d_i dt v). Its built-in type "2" has
 * c = {0, 1}, d = {1/2, 1/2}: drift-kick-drift (position Verlet). We register both
 * orderings under explicit names, "dkd" (the same scheme as "2") and "kdk" (c = {1/2,
 * 1/2}, d = {1, 0}: the velocity Verlet of LAMMPS fix nve, SWIFT and Phantom). The
 * second kick of a kdk step and the first kick of the next see the same positions, so
 * the kick caches the force: one force evaluation per step, plus one at the start.
 *
 * Our two schemes take our own step on the interleaved state (symplectic_step.c), the
 * same bits as PETSc's step at a fraction of its cost; PETSc's own schemes ("1" to "4")
 * take PETSc's step, on the position/momentum split made here. */
#include <petsc/private/tsimpl.h>
#include "ts_family.h"
#include "symplectic.h"
#include <spam/errors.h>

static const SpamSympScheme Schemes[] = {
  {"kdk", {0.5, 0.5}, {1.0, 0.0}},
  {"dkd", {0.0, 1.0}, {0.5, 0.5}},
};
#define NSCHEMES ((int)(sizeof Schemes / sizeof Schemes[0]))

const SpamSympScheme *SpamSympSchemeNamed(const char *name)
{
  for (int k = 0; name && k < NSCHEMES; k++)
    if (!strcmp(name, Schemes[k].name)) return &Schemes[k];
  return NULL;
}

PetscErrorCode SpamSymplecticRegister(void)
{
  PetscFunctionBeginUser;
  for (int k = 0; k < NSCHEMES; k++) {
    PetscReal c[2] = {Schemes[k].c[0], Schemes[k].c[1]}, d[2] = {Schemes[k].d[0], Schemes[k].d[1]};
    PetscCall(TSBasicSymplecticRegister(Schemes[k].name, 2, 2, c, d));
  }
  PetscFunctionReturn(0);
}

/* dx/dt = v: the position split gets the velocities and returns them. */
static PetscErrorCode Drift(TS ts, PetscReal t, Vec V, Vec F, void *ctx)
{
  PetscFunctionBeginUser;
  (void)ts;
  (void)t;
  (void)ctx;
  PetscCall(VecCopy(V, F));
  PetscFunctionReturn(0);
}

/* dv/dt = a(x): the momentum split gets the positions (compact, stride dim). */
static PetscErrorCode Kick(TS ts, PetscReal t, Vec X, Vec F, void *ctx)
{
  SpamTsApp         *app = (SpamTsApp *)ctx;
  SpamSim           *sim = app->sim;
  const int          dim = sim->model.dim;
  const PetscScalar *x;
  PetscScalar       *f;
  PetscBool          cached, ok;

  PetscFunctionBeginUser;
  (void)ts;
  PetscCall(VecGetArrayRead(X, &x));
  PetscCall(VecGetArrayWrite(F, &f));
  PetscCall(SpamKickCached(app, x, dim, PETSC_FALSE, &cached));
  if (!cached) {
    PetscCall(SpamKickEvaluate(app, t, x, dim, &ok));
    if (ok) PetscCall(SpamKickKeep(app, x, dim));
  }
  PetscCall(PetscArraycpy(f, app->acache, (size_t)sim->p.n * dim));
  PetscCall(VecRestoreArrayWrite(F, &f));
  PetscCall(VecRestoreArrayRead(X, &x));
  PetscFunctionReturn(0);
}

/* The entries offset..offset+dim-1 of every particle block. Both offsets of an [x, v]
 * state are multiples of dim, so the split is a blocked IS (block size dim), which PETSc
 * scatters block by block rather than entry by entry. */
static PetscErrorCode SplitIS(const SpamSim *sim, int offset, IS *is)
{
  const SpamLayout *l   = &sim->model.layout;
  const int         dim = sim->model.dim;
  PetscInt          lo, *idx;

  PetscFunctionBeginUser;
  PetscCall(VecGetOwnershipRange(sim->p.X, &lo, NULL));
  PetscCall(PetscMalloc1(sim->p.n + 1, &idx));
  for (PetscInt i = 0; i < sim->p.n; i++) idx[i] = (lo + i * l->nvar + offset) / dim;
  PetscCall(ISCreateBlock(sim->p.comm, dim, sim->p.n, idx, PETSC_OWN_POINTER, is));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamSymplecticSetUp(TS ts, SpamTsApp *app)
{
  SpamSim          *sim = app->sim;
  const SpamLayout *l   = &sim->model.layout;
  IS                isx, isv;

  PetscFunctionBeginUser;
  if (!sim->model.accel || l->nvar != 2 * sim->model.dim) {
    char fields[128];
    PetscCall(SpamLayoutDescribe(l, fields, sizeof fields));
    SPAM_BAD_INPUT("-ts_type", "basicsymplectic", "a symplectic split needs a state of positions and velocities only; model %s carries [%s]: use rk, ssp, euler, arkode or cvode", sim->model.name, fields);
  }
  PetscCall(SpamVecCacheSubVectors(sim->p.X)); /* before TSSetUp duplicates it */
  PetscCall(SplitIS(sim, l->x, &isx));
  PetscCall(SplitIS(sim, l->v, &isv));
  PetscCall(TSRHSSplitSetIS(ts, "position", isx));
  PetscCall(TSRHSSplitSetIS(ts, "momentum", isv));
  PetscCall(ISDestroy(&isx));
  PetscCall(ISDestroy(&isv));
  PetscCall(TSRHSSplitSetRHSFunction(ts, "position", NULL, Drift, app));
  PetscCall(TSRHSSplitSetRHSFunction(ts, "momentum", NULL, Kick, app));
  PetscFunctionReturn(0);
}

/* The basicsymplectic row of the table of methods (ts_family.h). */
static const char *const SympTypes[] = {"kdk", "dkd", "1", "2", "3", "4"};

static PetscErrorCode SubTypeSymplectic(TS ts, const char **sub)
{
  PetscFunctionBeginUser;
  PetscCall(TSBasicSymplecticGetType(ts, sub));
  PetscFunctionReturn(0);
}

#define SPAM_PETSC_SETUP "SpamBasicSymplecticSetUp_C"

/* TSSetUp, once the options have chosen the scheme: ours step on the state itself and
 * need neither the split's sub-vectors nor PETSc's update vector (a state's worth of
 * memory); PETSc's take PETSc's own set-up and step. */
static PetscErrorCode SetUpSymplectic(TS ts)
{
  SpamTsApp  *app;
  const char *name;

  PetscFunctionBeginUser;
  PetscCall(TSGetApplicationContext(ts, &app));
  PetscCall(TSBasicSymplecticGetType(ts, &name));
  PetscCall(SpamKickCacheCreate(app));
  if (SpamSympSchemeNamed(name)) {
    TSAdapt adapt;
    PetscCall(TSGetAdapt(ts, &adapt));
    PetscCall(TSAdaptCandidatesClear(adapt)); /* fixed steps, as PETSc's set-up makes them */
    ts->ops->step = SpamSymplecticStep;
  } else {
    PetscErrorCode (*petsc)(TS) = NULL;
    PetscCall(PetscObjectQueryFunction((PetscObject)ts, SPAM_PETSC_SETUP, &petsc));
    PetscCheck(petsc, PetscObjectComm((PetscObject)ts), PETSC_ERR_PLIB, "basicsymplectic's own set-up was not kept");
    PetscCall((*petsc)(ts));
  }
  PetscFunctionReturn(0);
}

/* Our default scheme is velocity Verlet (before the options, which may choose another),
 * and the position/momentum split PETSc's schemes step on: made here, before the TS has
 * its solution vector, so that no sub-vector is taken of it (PETSc's set-up duplicates
 * the vector with what is composed on it). The set-up, once the options have chosen the
 * scheme, decides whose step it takes. */
static PetscErrorCode CreatedSymplectic(TS ts, SpamTsApp *app)
{
  PetscFunctionBeginUser;
  PetscCall(TSBasicSymplecticSetType(ts, "kdk"));
  PetscCall(SpamSymplecticSetUp(ts, app));
  PetscCall(PetscObjectComposeFunction((PetscObject)ts, SPAM_PETSC_SETUP, ts->ops->setup));
  ts->ops->setup = SetUpSymplectic;
  PetscFunctionReturn(0);
}

/* The force of the step's last kick, when the checkpoint kept it, is the next first kick's. */
static PetscErrorCode CkReusesSymplectic(TS ts, const SpamCkFile *c, PetscBool *reused)
{
  long cached;

  PetscFunctionBeginUser;
  (void)ts;
  PetscCall(SpamCkGetLong(c, "kick_cached", &cached));
  *reused = (PetscBool)(cached != 0);
  PetscFunctionReturn(0);
}

static const SpamTSOption OptionsSymplectic[] = {{"ts_basicsymplectic_type", PETSC_TRUE, PETSC_FALSE}, {NULL, PETSC_FALSE, PETSC_FALSE}};

const SpamTSFamily SpamTSFamilySymplectic = {
  .options       = OptionsSymplectic,
  .type          = TSBASICSYMPLECTIC,
  .sub_option    = "-ts_basicsymplectic_type",
  .sub_default   = "kdk",
  .subs          = SympTypes,
  .nsubs         = (int)(sizeof SympTypes / sizeof SympTypes[0]),
  .adapt_default = TSADAPTNONE,
  .steps         = SPAM_TS_STEPS_FIXED,
  .follow        = SPAM_TS_FOLLOW_NONE,
  .sub_type      = SubTypeSymplectic,
  .created       = CreatedSymplectic,
  .ck_reuses_f   = CkReusesSymplectic,
};
