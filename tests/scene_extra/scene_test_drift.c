/* A test-only scene, added from outside the program by its file and one row
 * (scene_list_extra.h): the isentropic gas on the unit square lattice of n^D points
 * filling the periodic box of edge n, every particle moving at the same velocity U along x.
 * The lattice is uniform, so the pressure forces cancel on every particle and the gas keeps
 * its velocity: a Galilean drift, exact up to round-off. */
#include <spam/scene.h>
#include <spam/errors.h>

typedef struct {
  PetscInt n;     /* lattice points per direction: the box edge */
  double   speed; /* U along x                                  */
} DriftParams;

static const SpamSceneOption Table[] = {
  {"testdrift_n", SPAM_SCENE_OPTION_INT, "Lattice points per direction of the drifting gas (N = n^D)", NULL},
  {"testdrift_speed", SPAM_SCENE_OPTION_REAL, "Velocity U of every particle along x", NULL},
  {NULL, SPAM_SCENE_OPTION_INT, NULL, NULL},
};

static PetscErrorCode Options(const SpamCommonParams *c, void *params, SpamSolidParams *solid)
{
  DriftParams *p = params;
  char         val[64];

  PetscFunctionBeginUser;
  SpamSolidDefaults(solid);
  solid->material = SPAM_MATERIAL_ISENTROPE;
  solid->density  = SPAM_DENSITY_SUMMATION;
  solid->rho0     = c->mass;
  p->n            = 8;
  p->speed        = 0.25;
  PetscOptionsBegin(PETSC_COMM_WORLD, NULL, "Scene test-drift (test only)", "spam-ark");
  PetscCall(SpamSceneOptionInt(PetscOptionsObject, Table, "testdrift_n", &p->n, NULL));
  PetscCall(SpamSceneOptionReal(PetscOptionsObject, Table, "testdrift_speed", &p->speed, NULL));
  PetscOptionsEnd();
  PetscCall(PetscSNPrintf(val, sizeof val, "%" PetscInt_FMT, p->n));
  /* the periodic edge n must exceed twice the list range (minimum image) */
  if (!((double)p->n > 2.0 * (c->h + c->skin))) SPAM_BAD_INPUT("-testdrift_n", val, "the box edge n must exceed 2 (h + skin)");
  PetscCall(SpamCheckParticleCount("-testdrift_n", val, pow((double)p->n, c->dim)));
  PetscFunctionReturn(0);
}

static PetscErrorCode Build(const SpamCommonParams *c, const void *params, const SpamSolidParams *solid, SpamParticles *out)
{
  const DriftParams *p = params;
  const int          dim = c->dim;
  PetscInt           n;

  PetscFunctionBeginUser;
  (void)solid;
  PetscCall(SpamLatticeCube(dim, p->n, c->mass, out));
  n = out->n;
  for (PetscInt i = 0; i < n; i++) out->v[i * dim] = p->speed;
  out->box.dim = dim;
  for (int d = 0; d < dim; d++) {
    out->box.lo[d]       = 0.0;
    out->box.len[d]      = (double)p->n;
    out->box.periodic[d] = PETSC_TRUE;
  }
  PetscCall(PetscStrncpy(out->info.name, "test-drift", sizeof out->info.name));
  out->info.sound_traversal_time = (double)p->n;
  out->info.t_end_default        = (double)p->n;
  PetscFunctionReturn(0);
}

PetscErrorCode SpamSceneTestDrift(SpamSceneOps *ops)
{
  PetscFunctionBeginUser;
  *ops = (SpamSceneOps){"test-drift", 2 | 4 | 8, PETSC_FALSE, Table, sizeof(DriftParams), PETSC_FALSE, NULL, Options, Build};
  PetscFunctionReturn(0);
}
