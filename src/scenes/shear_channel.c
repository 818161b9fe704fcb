/* The shear channels (couette, poiseuille): a viscous gas on a square
 * lattice of unit spacing between mirror walls at y = 0 and y = H = n, periodic along x
 * (and z in 3D). The rows sit at y = j + 1/2, so the mirror images of the lattice in either
 * wall continue the lattice: the summed density is as uniform at the walls as inside, and
 * the gas starts in mechanical equilibrium. */
#include <spam/scene.h>
#include <spam/errors.h>

void SpamShearChannelDefaults(const SpamCommonParams *c, SpamSolidParams *solid)
{
  SpamSolidGasDefaults(c->mass, solid); /* unit square lattice */
  solid->shear_visc      = 1.0; /* nu = 1 at unit density: Re = U H of order 1 for U = 0.1 */
}

/* The columns along x (and z): the user's, or n but at least 2 (h + skin), the shortest
 * periodic edge the neighbour list takes. */
static PetscInt Columns(const SpamCommonParams *c, const SpamShearParams *p)
{
  if (p->nx > 0) return p->nx;
  return PetscMax(p->n, (PetscInt)ceil(2.0 * (c->h + c->skin)));
}

PetscErrorCode SpamShearChannelOptions(const SpamCommonParams *c, const char *name, const char *start, const SpamSceneOption *table, SpamShearParams *p)
{
  char opt_n[40], opt_nx[40], opt_start[40], opt_speed[40], title[80], val[64], hs[32], choice[32] = "rest";

  PetscFunctionBeginUser;
  p->n     = 16;
  p->nx    = 0;
  p->speed = 0.1;
  (void)snprintf(opt_n, sizeof opt_n, "-%s_n", name);
  (void)snprintf(opt_nx, sizeof opt_nx, "-%s_nx", name);
  (void)snprintf(opt_start, sizeof opt_start, "-%s_start", name);
  (void)snprintf(opt_speed, sizeof opt_speed, "-%s_speed", name);
  (void)snprintf(title, sizeof title, "Scene %s (shear flow between mirror walls)", name);
  (void)snprintf(hs, sizeof hs, "%g", c->h); /* PETSc's %g would print 3 as "3." */
  PetscOptionsBegin(PETSC_COMM_WORLD, NULL, title, "spam-ark");
  PetscCall(SpamSceneOptionReal(PetscOptionsObject, table, opt_speed + 1, &p->speed, NULL));
  PetscCall(SpamSceneOptionInt(PetscOptionsObject, table, opt_n + 1, &p->n, NULL));
  PetscCall(SpamSceneOptionInt(PetscOptionsObject, table, opt_nx + 1, &p->nx, NULL));
  PetscCall(SpamSceneOptionString(PetscOptionsObject, table, opt_start + 1, choice, sizeof choice, NULL));
  PetscOptionsEnd();
  PetscCall(PetscSNPrintf(val, sizeof val, "%" PetscInt_FMT, p->n));
  if (p->n < 2) SPAM_BAD_INPUT(opt_n, val, "must be at least 2 rows");
  if ((double)p->n < c->h) SPAM_BAD_INPUT(opt_n, val, "the channel width n must be at least h = %s (one mirror image per wall)", hs);
  PetscCall(PetscSNPrintf(val, sizeof val, "%" PetscInt_FMT, p->nx));
  if (p->nx < 0) SPAM_BAD_INPUT(opt_nx, val, "must be 0 (automatic) or a positive number of columns");
  PetscCall(PetscSNPrintf(val, sizeof val, "%" PetscInt_FMT " x %" PetscInt_FMT, p->n, Columns(c, p)));
  PetscCall(SpamCheckParticleCount(opt_n, val, (double)p->n * pow((double)Columns(c, p), c->dim - 1)));
  if (strcmp(choice, "rest") && strcmp(choice, start)) {
    char shown[100];
    SpamClip(choice, shown, sizeof shown);
    SPAM_BAD_INPUT(opt_start, shown, "allowed: rest, %s", start);
  }
  p->steady_start = (PetscBool)!strcmp(choice, start);
  PetscFunctionReturn(0);
}

PetscErrorCode SpamShearChannelCheck(const char *name, const SpamShearParams *p, const SpamSolidParams *solid, double *nu, double *c)
{
  char opt[40], val[64];

  PetscFunctionBeginUser;
  if (solid->material == SPAM_MATERIAL_ISENTROPE) SPAM_BAD_INPUT("-material", "isentrope", "-scene %s needs a viscous model: -material gas (its default) or elastic", name);
  (void)snprintf(val, sizeof val, "%g", solid->shear_visc);
  if (!(solid->shear_visc > 0.0)) SPAM_BAD_INPUT("-viscosity_shear", val, "-scene %s needs a shear viscosity: its steady flow is set by it", name);
  *nu = solid->shear_visc / solid->rho0;
  if (solid->material == SPAM_MATERIAL_GAS) *c = sqrt(solid->gamma * (solid->gamma - 1.0) * solid->gas_e0);
  else *c = sqrt((solid->lambda + 2.0 * solid->eta) / solid->rho0);
  (void)snprintf(opt, sizeof opt, "-%s_speed", name);
  PetscCall(SpamOptionText(opt, p->speed, val, sizeof val));
  if (!isfinite(p->speed) || !(fabs(p->speed) < *c)) SPAM_BAD_INPUT(opt, val, "must be below the sound speed %g in size (a subsonic shear flow)", *c);
  PetscFunctionReturn(0);
}

PetscErrorCode SpamShearChannelBuild(const SpamCommonParams *c, const char *name, const SpamShearParams *p, SpamParticles *out)
{
  const int      dim = c->dim;
  const PetscInt nx = Columns(c, p), nz = dim == 3 ? nx : 1, n = nx * p->n * nz;

  PetscFunctionBeginUser;
  PetscCall(SpamParticlesAllocate(dim, n, out));
  out->mass    = c->mass;
  out->box.dim = dim;
  for (int d = 0; d < dim; d++) {
    out->box.lo[d]       = 0.0;
    out->box.len[d]      = (double)(d == 1 ? p->n : nx);
    out->box.periodic[d] = (PetscBool)(d != 1);
  }
  for (PetscInt k = 0, i = 0; k < nz; k++)
    for (PetscInt j = 0; j < p->n; j++)
      for (PetscInt l = 0; l < nx; l++, i++) {
        const double site[3] = {(double)l + 0.5, (double)j + 0.5, (double)k + 0.5};
        for (int d = 0; d < dim; d++) out->x[i * dim + d] = site[d];
      }
  /* No-slip walls on the y faces (2: ylo, 3: yhi) where the user gave no condition. */
  for (int f = 2; f <= 3; f++)
    if (!out->walls.slip_given[f]) out->walls.slip[f] = SPAM_WALL_NOSLIP;
  PetscCall(PetscStrncpy(out->info.name, name, sizeof out->info.name));
  PetscFunctionReturn(0);
}

/* Measured (docs/scenes/couette.md, examples/couette_rest_lattice.py): the gas's square
 * lattice at rest is unstable under Lucy at h = 3 in the plain scheme, with or without
 * walls; Wendland C2 keeps it, and so does the flow scheme (its background pressure). */
PetscErrorCode SpamShearLatticeNote(const SpamCommonParams *c, const SpamSolidParams *solid, const char *name)
{
  PetscFunctionBeginUser;
  if (c->kernel.kind == SPAM_KERNEL_LUCY && solid->material == SPAM_MATERIAL_GAS && solid->scheme == SPAM_GAS_PLAIN)
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "%s: note: under -gas_scheme plain the gas's square lattice is unstable under the Lucy kernel (it rearranges by t ~ 100 at h = 3); -kernel wendland_c2 or -gas_scheme flow keeps it\n", name));
  PetscFunctionReturn(0);
}
