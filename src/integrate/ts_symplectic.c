/* Verlet through PETSc's basicsymplectic TS. In PETSc 3.18 each stage first kicks
 * (v += c_i dt a(x)) and then drifts (x += d_i dt v). Its built-in type "2" has
 * c = {0, 1}, d = {1/2, 1/2}: drift-kick-drift (position Verlet). We register both
 * orderings under explicit names, "dkd" (the same scheme as "2") and "kdk" (c = {1/2,
 * 1/2}, d = {1, 0}: the velocity Verlet of LAMMPS fix nve, SWIFT and Phantom). The
 * second kick of a kdk step and the first kick of the next see the same positions, so
 * the kick caches the force: one force evaluation per step, plus one at the start. */
#include "ts_family.h"
#include <spam/errors.h>

PetscErrorCode SpamSymplecticRegister(void)
{
  PetscReal kdk_c[2] = {0.5, 0.5}, kdk_d[2] = {1.0, 0.0};
  PetscReal dkd_c[2] = {0.0, 1.0}, dkd_d[2] = {0.5, 0.5};

  PetscFunctionBeginUser;
  PetscCall(TSBasicSymplecticRegister("kdk", 2, 2, kdk_c, kdk_d));
  PetscCall(TSBasicSymplecticRegister("dkd", 2, 2, dkd_c, dkd_d));
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
  const size_t       len = (size_t)sim->p.n * dim;
  const PetscScalar *x;
  PetscScalar       *f;

  PetscFunctionBeginUser;
  (void)ts;
  PetscCall(VecGetArrayRead(X, &x));
  PetscCall(VecGetArrayWrite(F, &f));
  if (!(app->cache_valid && !memcmp(x, app->xcache, len * sizeof *x))) {
    PetscInt bad;
    PetscCall(SpamAccel(sim, x, dim, &bad));
    if (bad >= 0 && app->bad < 0) {
      app->bad  = bad;
      app->tbad = t;
    }
    if (bad >= 0) PetscCall(PetscArrayzero(app->acache, len));
    else PetscCall(PetscArraycpy(app->acache, sim->pair.f.acc, len)); /* same layout, a[i*dim + d] */
    PetscCall(PetscArraycpy(app->xcache, x, len));
    app->cache_valid = (PetscBool)(bad < 0);
  }
  PetscCall(PetscArraycpy(f, app->acache, len));
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
  PetscCall(PetscMalloc2((size_t)sim->p.n * sim->model.dim + 1, &app->xcache, (size_t)sim->p.n * sim->model.dim + 1, &app->acache));
  app->cache_valid = PETSC_FALSE;
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

/* Our default scheme is velocity Verlet (before the options, which may choose another),
 * and the position/momentum split. */
static PetscErrorCode CreatedSymplectic(TS ts, SpamTsApp *app)
{
  PetscFunctionBeginUser;
  PetscCall(TSBasicSymplecticSetType(ts, "kdk"));
  PetscCall(SpamSymplecticSetUp(ts, app));
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
