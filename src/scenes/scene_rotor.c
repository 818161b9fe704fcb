/* Rotating elastic hexagon (PRE Sec. VI, Figs. 4-7): n shells of the stress-free unit
 * triangular lattice, N = 1 + 3n + 3n^2, free surface, rigid rotation with the vertices
 * moving at the given speed (0.1: about 10% of c_L), run for one nominal revolution,
 * t = 2 pi n / speed (20 n pi). rotor-pair: the hexagon and its mirror image, rotating
 * the other way, side by side with a gap (PRE Sec. IX): their total L is zero. */
#include <spam/scene.h>
#include <spam/errors.h>

typedef struct {
  PetscInt  n;          /* shells: N = 1 + 3n + 3n^2                                */
  double    speed;      /* speed of the vertices                                    */
  double    gap;        /* rotor-pair: gap between the two hexagons                 */
  PetscBool pair;
  SpamSolidParams solid;
} SpamRotorParams;

/* The rotor's options; the pair's add the gap. */
#define ROTOR_N     {"rotor_n", SPAM_SCENE_OPTION_INT, "Shells of the hexagon (N = 1 + 3n + 3n^2; 8 gives 217)", NULL}
#define ROTOR_SPEED {"rotor_speed", SPAM_SCENE_OPTION_REAL, "Speed of the vertices of the rigidly rotating hexagon", NULL}
static const SpamSceneOption TableOne[] = {ROTOR_N, ROTOR_SPEED, {NULL, SPAM_SCENE_OPTION_INT, NULL, NULL}};
static const SpamSceneOption TablePair[] = {
  ROTOR_N,
  ROTOR_SPEED,
  {"rotor_gap", SPAM_SCENE_OPTION_REAL, "Gap between the two hexagons' vertex circles (default h + 1: no contact)", NULL},
  {NULL, SPAM_SCENE_OPTION_INT, NULL, NULL},
};

static PetscErrorCode SpamRotorOptions(const SpamCommonParams *c, PetscBool pair, SpamRotorParams *p)
{
  const SpamSceneOption *table = pair ? TablePair : TableOne;
  char                   val[64];

  PetscFunctionBeginUser;
  p->n     = 8;
  p->speed = 0.1;
  p->gap   = c->h + 1.0;
  p->pair  = pair;
  SpamSolidDefaults(&p->solid);
  p->solid.rho0 = c->mass * sqrt(4.0 / 3.0);
  if (pair) { /* the PRE Sec. IX question is about torque scaling: on by default */
    p->solid.coords = SPAM_COORDS_R2;
    p->solid.angmom = SPAM_ANGMOM_TIJ;
  }
  PetscOptionsBegin(PETSC_COMM_WORLD, NULL, pair ? "Scene rotor-pair (Hoover, Hoover & Merritt 2004, Sec. IX)" : "Scene rotor (Hoover, Hoover & Merritt 2004, Sec. VI)", "spam-ark");
  PetscCall(SpamSceneOptionInt(PetscOptionsObject, table, "rotor_n", &p->n, NULL));
  PetscCall(SpamSceneOptionReal(PetscOptionsObject, table, "rotor_speed", &p->speed, NULL));
  if (pair) PetscCall(SpamSceneOptionReal(PetscOptionsObject, table, "rotor_gap", &p->gap, NULL));
  PetscOptionsEnd();
  PetscCall(PetscSNPrintf(val, sizeof val, "%" PetscInt_FMT, p->n));
  if (p->n < 1 || p->n > 1000) SPAM_BAD_INPUT("-rotor_n", val, "allowed: 1 to 1000 shells");
  PetscCall(SpamCheckParticleCount("-rotor_n", val, (pair ? 2.0 : 1.0) * (1.0 + 3.0 * (double)p->n * (double)(p->n + 1))));
  (void)snprintf(val, sizeof val, "%g", p->speed);
  /* The default run lasts one revolution, 2 pi n / speed: 1e-300 made it 6e300 long (and
   * 4.9e-324 infinite); 1e300 stopped as unstable at once. Both ends ran at 1e-6 and 10. */
  if (!(p->speed >= 1e-6 && p->speed <= 10.0)) SPAM_BAD_INPUT("-rotor_speed", val, "must be a positive speed from 1e-6 to 10 (the vertex speed; the longitudinal sound speed of the default solid is about 1.06)");
  (void)snprintf(val, sizeof val, "%g", p->gap);
  /* The gap is the distance between the facing vertices: at 0 two particles coincide,
   * and below about 1e-15 n they coincide in floating point (1e-300 ran as unstable).
   * 1e-6 is the smallest gap tried that ran (rotor_n 4). Beyond h the hexagons never
   * meet, and a wider gap only widens the box: 1e4 keeps its cells countable. */
  if (!(p->gap >= 1e-6 && p->gap <= 1e4)) SPAM_BAD_INPUT("-rotor_gap", val, "allowed: 1e-6 to 1e4 lattice spacings (at 0 the facing vertices of the two hexagons coincide; beyond h they never meet)");
  PetscFunctionReturn(0);
}

/* Hexagon of n shells centred at cx, rotating with angular velocity omega (counter-
 * clockwise if positive), into x, v from index k0; returns the count. */
static PetscInt Hexagon(PetscInt n, double cx, double omega, PetscBool mirror, double *x, double *v)
{
  const PetscInt m = SpamLatticeHexagon(n, 1.0, x);
  for (PetscInt i = 0; i < m; i++) {
    if (mirror) x[2 * i] = -x[2 * i];
    v[2 * i]     = -omega * x[2 * i + 1];
    v[2 * i + 1] = omega * x[2 * i];
    x[2 * i] += cx;
  }
  return m;
}

static PetscErrorCode SpamRotorBuild(const SpamCommonParams *c, const SpamRotorParams *p, SpamParticles *out)
{
  const PetscInt one   = 1 + 3 * p->n + 3 * p->n * p->n;
  const double   omega = p->speed / (double)p->n, half = (double)p->n + 0.5 * p->gap;

  PetscFunctionBeginUser;
  PetscCall(SpamParticlesAllocate(2, p->pair ? 2 * one : one, out));
  PetscCall(SpamParticlesAllocateFields(out));
  out->mass = c->mass;
  if (p->pair) {
    (void)Hexagon(p->n, -half, omega, PETSC_FALSE, out->x, out->v);
    (void)Hexagon(p->n, half, -omega, PETSC_TRUE, out->x + 2 * one, out->v + 2 * one);
  } else (void)Hexagon(p->n, 0.0, omega, PETSC_FALSE, out->x, out->v);
  for (PetscInt i = 0; i < out->n; i++) out->rho[i] = p->solid.rho0;
  /* Room to deform: the list's edge cells also hold anything that leaves the box. */
  SpamParticlesOpenBox(out, c->h + 0.25 * (double)p->n + 1.0);
  PetscCall(PetscStrncpy(out->info.name, p->pair ? "rotor-pair" : "rotor", sizeof out->info.name));
  out->info.sound_traversal_time = 2.0 * (double)p->n / sqrt((p->solid.lambda + 2.0 * p->solid.eta) / p->solid.rho0);
  out->info.t_end_default        = 2.0 * PETSC_PI / omega;
  PetscFunctionReturn(0);
}

static PetscErrorCode OptionsOne(const SpamCommonParams *c, void *p, SpamSolidParams *solid)
{
  SpamRotorParams *q = p;

  PetscFunctionBeginUser;
  PetscCall(SpamRotorOptions(c, PETSC_FALSE, q));
  *solid = q->solid;
  PetscFunctionReturn(0);
}

static PetscErrorCode OptionsPair(const SpamCommonParams *c, void *p, SpamSolidParams *solid)
{
  SpamRotorParams *q = p;

  PetscFunctionBeginUser;
  PetscCall(SpamRotorOptions(c, PETSC_TRUE, q));
  *solid = q->solid;
  PetscFunctionReturn(0);
}

static PetscErrorCode Build(const SpamCommonParams *c, const void *p, const SpamSolidParams *solid, SpamParticles *out)
{
  SpamRotorParams r = *(const SpamRotorParams *)p;

  PetscFunctionBeginUser;
  r.solid = *solid;
  PetscCall(SpamRotorBuild(c, &r, out));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamSceneRotor(SpamSceneOps *ops)
{
  PetscFunctionBeginUser;
  *ops = (SpamSceneOps){"rotor", 4, PETSC_FALSE, TableOne, sizeof(SpamRotorParams), PETSC_FALSE, NULL, OptionsOne, Build};
  PetscFunctionReturn(0);
}

PetscErrorCode SpamSceneRotorPair(SpamSceneOps *ops)
{
  PetscFunctionBeginUser;
  *ops = (SpamSceneOps){"rotor-pair", 4, PETSC_FALSE, TablePair, sizeof(SpamRotorParams), PETSC_FALSE, NULL, OptionsPair, Build};
  PetscFunctionReturn(0);
}
