/* Standing elastic plane waves (PRE Sec. V, Fig. 3): a periodic triangular crystal of
 * nx x ny particles (24 x 24, N = 576, density sqrt(4/3)) at rest, displaced by
 * u = A sin(k y) along x (transverse) or y (longitudinal), k = 2 pi / (ny sqrt(3)/2), with
 * the matching stress sigma_xy = eta k A cos(ky) (transverse) or sigma_yy = (lambda + 2 eta)
 * k A cos(ky), sigma_xx = lambda k A cos(ky) (longitudinal). The elastic energy per unit
 * mass W/rho0, W = sigma:epsilon/2, starts in e, so KE + IE is the total energy. The
 * period predicted by the linearised SPAM equations (dispersion_lucy.c) is printed.
 * That is -planewave_stress continuum; the default, spam, replaces the stress, density
 * and energy by those of SPAM's own strain of the displaced lattice (planewave_stress.c),
 * which starts the wave at a turning point of the discrete dynamics. */
#include <spam/scene.h>
#include <spam/physics.h>
#include <spam/errors.h>
#include <spam/planewave_stress.h>

typedef struct {
  PetscInt  nx, ny;     /* lattice columns and rows (ny even: periodic)            */
  PetscBool longitudinal;
  double    amplitude;
  PetscBool continuum_stress; /* -planewave_stress continuum: Hooke(grad u), not SPAM's */
  SpamSolidParams solid;
} SpamPlanewaveParams;

static const SpamSceneOption Table[] = {
  {"planewave_nx", SPAM_SCENE_OPTION_INT, "Particles per lattice row", NULL},
  {"planewave_ny", SPAM_SCENE_OPTION_INT, "Lattice rows (even; the wavelength is ny sqrt(3)/2)", NULL},
  {"planewave_mode", SPAM_SCENE_OPTION_STRING, "Polarisation: transverse (u_x) or longitudinal (u_y)", NULL},
  {"planewave_amplitude", SPAM_SCENE_OPTION_REAL, "Displacement amplitude A (lattice units)", NULL},
  {"planewave_stress", SPAM_SCENE_OPTION_STRING, "Initial stress: spam (Hooke's law of SPAM's strain of the displaced lattice) or continuum (of grad u)", NULL},
  {NULL, SPAM_SCENE_OPTION_INT, NULL, NULL},
};

static PetscErrorCode SpamPlanewaveOptions(const SpamCommonParams *c, SpamPlanewaveParams *p)
{
  char val[64], mode[32] = "transverse", stress[32] = "spam";

  PetscFunctionBeginUser;
  p->nx        = 24;
  p->ny        = 24;
  p->amplitude = 0.25;
  SpamSolidDefaults(&p->solid);
  p->solid.rho0 = c->mass * sqrt(4.0 / 3.0); /* unit triangular lattice */
  PetscOptionsBegin(PETSC_COMM_WORLD, NULL, "Scene planewave (Hoover, Hoover & Merritt 2004, Sec. V)", "spam-ark");
  PetscCall(SpamSceneOptionInt(PetscOptionsObject, Table, "planewave_nx", &p->nx, NULL));
  PetscCall(SpamSceneOptionInt(PetscOptionsObject, Table, "planewave_ny", &p->ny, NULL));
  PetscCall(SpamSceneOptionString(PetscOptionsObject, Table, "planewave_mode", mode, sizeof mode, NULL));
  PetscCall(SpamSceneOptionReal(PetscOptionsObject, Table, "planewave_amplitude", &p->amplitude, NULL));
  PetscCall(SpamSceneOptionString(PetscOptionsObject, Table, "planewave_stress", stress, sizeof stress, NULL));
  PetscOptionsEnd();
  if (strcmp(mode, "transverse") && strcmp(mode, "longitudinal")) SPAM_BAD_INPUT("-planewave_mode", mode, "allowed: transverse, longitudinal");
  p->longitudinal = (PetscBool)!strcmp(mode, "longitudinal");
  if (strcmp(stress, "spam") && strcmp(stress, "continuum")) SPAM_BAD_INPUT("-planewave_stress", stress, "allowed: spam, continuum");
  p->continuum_stress = (PetscBool)!strcmp(stress, "continuum");
  PetscCall(PetscSNPrintf(val, sizeof val, "%" PetscInt_FMT, p->ny));
  if (p->ny < 2 || p->ny % 2) SPAM_BAD_INPUT("-planewave_ny", val, "must be an even number of rows >= 2 (periodic triangular lattice)");
  PetscCall(PetscSNPrintf(val, sizeof val, "%" PetscInt_FMT, p->nx));
  if (p->nx < 1) SPAM_BAD_INPUT("-planewave_nx", val, "must be positive");
  PetscCall(PetscSNPrintf(val, sizeof val, "%" PetscInt_FMT " x %" PetscInt_FMT, p->nx, p->ny));
  PetscCall(SpamCheckParticleCount("-planewave_nx x -planewave_ny", val, (double)p->nx * (double)p->ny));
  (void)snprintf(val, sizeof val, "%g", p->amplitude);
  if (!isfinite(p->amplitude) || fabs(p->amplitude) >= 0.5) SPAM_BAD_INPUT("-planewave_amplitude", val, "allowed: |A| < 0.5 lattice spacings");
  PetscFunctionReturn(0);
}

/* Stress, density and energy of SPAM's strain of the displaced lattice out->x; the pair
 * density is the one the model's density choice gives on the reference lattice. */
static PetscErrorCode LatticeStress(const SpamCommonParams *c, const SpamPlanewaveParams *p, SpamParticles *out)
{
  const SpamSolidParams *s = &p->solid;
  const PetscInt         n = p->nx * p->ny;
  SpamKernel             ker;
  double                *x0, *u, rho_ref = s->rho0;

  PetscFunctionBeginUser;
  ker = c->kernel; /* the run's kernel (-kernel) */
  PetscCall(PetscMalloc2(2 * n, &x0, 2 * n, &u));
  SpamLatticeTriangular(p->nx, p->ny, 1.0, x0);
  for (PetscInt k = 0; k < 2 * n; k++) u[k] = out->x[k] - x0[k];
  {
    const SpamDisplacedLattice L = {p->nx, p->ny, 1.0, x0, u, c->mass, s->lambda, s->eta};
    if (s->density == SPAM_DENSITY_SUMMATION || s->density_initial == SPAM_DENSITY_INITIAL_SUMMED) rho_ref = SpamLatticeSummedDensity(&ker, &L);
    SpamPlanewaveStressSpam(&ker, &L, rho_ref, out->sigma, out->rho, out->e);
  }
  PetscCall(PetscFree2(x0, u));
  PetscFunctionReturn(0);
}

static PetscErrorCode SpamPlanewaveBuild(const SpamCommonParams *c, const SpamPlanewaveParams *p, SpamParticles *out)
{
  const SpamSolidParams *s  = &p->solid;
  const PetscInt         n  = p->nx * p->ny;
  const double           ly = 0.5 * sqrt(3.0) * (double)p->ny, k = 2.0 * PETSC_PI / ly;
  const double           mod = p->longitudinal ? s->lambda + 2.0 * s->eta : s->eta;
  const double           kvec[2] = {0.0, k};
  double                 wt, wl;
  char                   line[256];

  PetscFunctionBeginUser;
  PetscCall(SpamParticlesAllocate(2, n, out));
  PetscCall(SpamParticlesAllocateFields(out));
  out->mass = c->mass;
  SpamLatticeTriangular(p->nx, p->ny, 1.0, out->x);
  for (PetscInt i = 0; i < n; i++) {
    const double y0 = out->x[2 * i + 1], strain = k * p->amplitude * cos(k * y0);
    out->x[2 * i + (p->longitudinal ? 1 : 0)] += p->amplitude * sin(k * y0);
    if (p->longitudinal) {
      out->sigma[3 * i]     = s->lambda * strain;
      out->sigma[3 * i + 2] = (s->lambda + 2.0 * s->eta) * strain;
      out->rho[i]           = s->rho0 / (1.0 + strain);
    } else {
      out->sigma[3 * i + 1] = s->eta * strain;
      out->rho[i]           = s->rho0;
    }
    out->e[i] = 0.5 * mod * strain * strain / s->rho0;
  }
  if (!p->continuum_stress) PetscCall(LatticeStress(c, p, out));
  out->box = (SpamBox){2, {0, 0, 0}, {(double)p->nx, ly, 0}, {PETSC_TRUE, PETSC_TRUE, PETSC_FALSE}};
  SpamDispersionLucy(c->h, 1.0, c->mass, s->rho0, s->lambda, s->eta, kvec, &wt, &wl);
  {
    const double w = p->longitudinal ? wl : wt, cs = sqrt(mod / s->rho0);
    (void)snprintf(line, sizeof line, "planewave: %s, wavelength %.6g, predicted period %.10g (linearised SPAM), continuum period %.10g\n", p->longitudinal ? "longitudinal" : "transverse", ly, 2.0 * PETSC_PI / w, ly / cs);
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "%s", line));
    PetscCall(PetscStrncpy(out->info.name, "planewave", sizeof out->info.name));
    out->info.sound_traversal_time = ly / cs;
    out->info.t_end_default        = 2.0 * 2.0 * PETSC_PI / w;
  }
  PetscFunctionReturn(0);
}

static PetscErrorCode Options(const SpamCommonParams *c, void *p, SpamSolidParams *solid)
{
  PetscFunctionBeginUser;
  PetscCall(SpamPlanewaveOptions(c, p));
  *solid = ((const SpamPlanewaveParams *)p)->solid;
  PetscFunctionReturn(0);
}

static PetscErrorCode Build(const SpamCommonParams *c, const void *p, const SpamSolidParams *solid, SpamParticles *out)
{
  SpamPlanewaveParams q = *(const SpamPlanewaveParams *)p;

  PetscFunctionBeginUser;
  q.solid = *solid;
  PetscCall(SpamPlanewaveBuild(c, &q, out));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamScenePlanewave(SpamSceneOps *ops)
{
  PetscFunctionBeginUser;
  *ops = (SpamSceneOps){"planewave", 4, PETSC_FALSE, Table, sizeof(SpamPlanewaveParams), PETSC_FALSE, NULL, Options, Build};
  PetscFunctionReturn(0);
}
