/* Scene registry: common options, the choice of scene, and filling the swarm. */
#include <spam/scene.h>
#include <spam/errors.h>
#include <float.h>


PetscErrorCode SpamParticlesAllocate(int dim, PetscInt n, SpamParticles *p)
{
  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(p, sizeof *p));
  p->dim = dim;
  p->n   = n;
  PetscCall(PetscCalloc1((size_t)n * dim + 1, &p->x));
  PetscCall(PetscCalloc1((size_t)n * dim + 1, &p->v));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamParticlesFree(SpamParticles *p)
{
  PetscFunctionBeginUser;
  PetscCall(PetscFree(p->x));
  PetscCall(PetscFree(p->v));
  if (p->e) PetscCall(PetscFree3(p->e, p->rho, p->sigma));
  PetscCall(PetscFree(p->m));
  PetscCall(PetscFree(p->id));
  PetscFunctionReturn(0);
}

/* The neighbour grid's cells of width h + skin in the box, counted in double, at most this. */
#define MAX_NEIGHBOUR_CELLS 1e8
/* Box corners and translated coordinates stay below this size (as the particle file's). */
#define MAX_COORDINATE 1e15

const char *SpamPositiveNormalProblem(double v)
{
  if (!(v > 0.0) || !isfinite(v)) return "must be a positive finite number";
  if (v < DBL_MIN) return "too small (subnormal): must be at least 2.22507e-308";
  return NULL;
}

static PetscErrorCode CheckPositive(const char *opt, double v)
{
  const char *why = SpamPositiveNormalProblem(v);
  char        val[128];

  PetscFunctionBeginUser;
  PetscCall(SpamOptionText(opt, v, val, sizeof val));
  if (why) SPAM_BAD_INPUT(opt, val, "%s", why);
  PetscFunctionReturn(0);
}

/* An array option of the box: 1 value (the same in every direction) or dim values. n is
 * the count read with room for 16, so a longer list is seen. */
static PetscErrorCode Broadcast(const char *opt, PetscInt n, int dim, PetscBool set, double *v)
{
  char val[128];

  PetscFunctionBeginUser;
  if (!set) PetscFunctionReturn(0);
  PetscCall(SpamOptionText(opt, v[0], val, sizeof val));
  if (n != 1 && n != dim) SPAM_BAD_INPUT(opt, val, "takes 1 value (the same in every direction) or %d (one per direction, -dim %d); %" PetscInt_FMT " given", dim, dim, n);
  for (int d = 0; d < n; d++)
    if (!isfinite(v[d]) || fabs(v[d]) >= MAX_COORDINATE) SPAM_BAD_INPUT(opt, val, "every value must be a finite number below %g in size", MAX_COORDINATE);
  for (int d = n; d < 3; d++) v[d] = v[0];
  PetscFunctionReturn(0);
}

/* The kernel of -kernel at this h (into k): its normalisation C_D h^-D and that of its
 * derivatives, C_D h^-(D+2), must be normal finite numbers, or every density and force
 * is 0 or inf. */
static PetscErrorCode KernelAndRange(int dim, double h, SpamKernel *kernel)
{
  const SpamKernel *k = kernel;
  char              val[128], w[32], g[32];

  PetscFunctionBeginUser;
  PetscCall(SpamOptionText("-h", h, val, sizeof val));
  PetscCall(SpamKernelOptions(dim, h, kernel));
  (void)snprintf(w, sizeof w, "%.3g", k->wnorm);
  (void)snprintf(g, sizeof g, "%.3g", fabs(k->gnorm));
  if (!(isnormal(k->wnorm) && isnormal(k->gnorm))) SPAM_BAD_INPUT("-h", val, "out of range: the kernel's normalisations C_D h^-%d = %s and C_D h^-%d = %s must be normal finite numbers", dim, w, dim + 2, g);
  PetscFunctionReturn(0);
}

/* -dim, -h, -mass, -neighbour_skin, -threads and the gas's -eos_gamma; gamma is checked
 * before kappa's default (1/gamma) is made from it. */
static PetscErrorCode KernelOptions(SpamCommonParams *c)
{
  PetscInt dim = 2;
  char     val[128];

  PetscFunctionBeginUser;
  PetscOptionsBegin(PETSC_COMM_WORLD, NULL, "Particles, kernel and gas", "spam-ark");
  PetscCall(PetscOptionsInt("-dim", "Space dimension (1, 2 or 3)", "README", dim, &dim, NULL));
  PetscCall(PetscOptionsReal("-h", "Kernel range h (every kernel vanishes at r = h)", "README", c->h, &c->h, NULL));
  PetscCall(PetscOptionsReal("-mass", "Particle mass m", "README", c->mass, &c->mass, NULL));
  c->skin = 0.1 * c->h;
  PetscCall(PetscOptionsReal("-neighbour_skin", "Verlet-list skin (default 0.1 h)", "README", c->skin, &c->skin, NULL));
  c->threads = 1;
  PetscCall(PetscOptionsInt("-threads", "OpenMP threads of the pair passes (1: none; results are the same run to run for a given count)", "README", c->threads, &c->threads, NULL));
  c->gamma = 1.0 + 2.0 / (double)PetscClipInterval(dim, 1, 3);
  PetscCall(PetscOptionsReal("-eos_gamma", "Isentrope exponent gamma in P = kappa rho^gamma (default 1 + 2/D; -scene expansion and file)", "README", c->gamma, &c->gamma, NULL));
  PetscOptionsEnd();
  c->dim = (int)dim;
  PetscCall(PetscSNPrintf(val, sizeof val, "%" PetscInt_FMT, dim));
  if (dim < 1 || dim > 3) SPAM_BAD_INPUT("-dim", val, "allowed: 1, 2 or 3");
  PetscCall(PetscSNPrintf(val, sizeof val, "%" PetscInt_FMT, c->threads));
  if (c->threads < 1 || c->threads > SPAM_MAX_THREADS) SPAM_BAD_INPUT("-threads", val, "must be from 1 to %d", SPAM_MAX_THREADS);
  PetscCall(CheckPositive("-h", c->h));
  PetscCall(KernelAndRange(c->dim, c->h, &c->kernel));
  PetscCall(CheckPositive("-mass", c->mass));
  PetscCall(SpamOptionText("-neighbour_skin", c->skin, val, sizeof val));
  if (!(c->skin >= 0.0) || !isfinite(c->skin)) SPAM_BAD_INPUT("-neighbour_skin", val, "must be zero or positive");
  PetscCall(SpamOptionText("-eos_gamma", c->gamma, val, sizeof val));
  if (!(c->gamma > 1.0) || !isfinite(c->gamma)) SPAM_BAD_INPUT("-eos_gamma", val, "must be a finite number greater than 1");
  PetscFunctionReturn(0);
}

static PetscErrorCode CommonOptions(SpamCommonParams *c)
{
  PetscInt  nd = 16, nl = 16, np = 16, nt = 16;
  PetscReal lo[16] = {0}, len[16] = {0}, tr[16] = {0};
  PetscBool per[16], set_lo, set_tr, set_per;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(c, sizeof *c));
  for (int d = 0; d < 16; d++) per[d] = PETSC_TRUE;
  c->h    = 3.0;
  c->mass = 1.0;
  PetscCall(KernelOptions(c));
  c->kappa = 1.0 / c->gamma;
  PetscOptionsBegin(PETSC_COMM_WORLD, NULL, "Gas and box", "spam-ark");
  PetscCall(PetscOptionsReal("-eos_kappa", "Isentrope constant kappa (default 1/gamma: sound speed 1 at rho = 1)", "README", c->kappa, &c->kappa, NULL));
  PetscCall(PetscOptionsRealArray("-box_lo", "Lower corner of the box (file scene; 1 value or -dim values; default 0)", "README", lo, &nd, &set_lo));
  PetscCall(PetscOptionsRealArray("-box_len", "Box edge lengths (file scene: required; 1 value or -dim values)", "README", len, &nl, &c->box_len_set));
  PetscCall(PetscOptionsBoolArray("-periodic", "Periodic in each direction (expansion and file scenes; 1 value or -dim values; default true)", "README", per, &np, &set_per));
  PetscCall(PetscOptionsRealArray("-scene_translate", "Shift particles and box by this vector (1 value or -dim values; a test of translation invariance)", "README", tr, &nt, &set_tr));
  PetscOptionsEnd();
  PetscCall(CheckPositive("-eos_kappa", c->kappa));
  PetscCall(Broadcast("-box_lo", nd, c->dim, set_lo, lo));
  PetscCall(Broadcast("-box_len", nl, c->dim, c->box_len_set, len));
  PetscCall(Broadcast("-scene_translate", nt, c->dim, set_tr, tr));
  if (set_per) {
    char val[128];
    PetscCall(SpamOptionText("-periodic", 0.0, val, sizeof val));
    if (np != 1 && np != c->dim) SPAM_BAD_INPUT("-periodic", val, "takes 1 value (the same in every direction) or %d (one per direction, -dim %d); %" PetscInt_FMT " given", c->dim, c->dim, np);
    for (int d = (int)np; d < 3; d++) per[d] = per[0];
  }
  for (int d = 0; d < 3; d++) {
    c->box_lo[d]    = lo[d];
    c->box_len[d]   = len[d];
    c->translate[d] = tr[d];
    c->periodic[d]  = per[d];
  }
  PetscFunctionReturn(0);
}

/* The neighbour grid of cells of width h + skin stays countable. */
static PetscErrorCode CheckNeighbourGrid(const SpamCommonParams *c, const SpamBox *b)
{
  double cells = 1.0;
  char   val[128];

  PetscFunctionBeginUser;
  for (int d = 0; d < b->dim; d++) cells *= PetscMax(1.0, floor(b->len[d] / (c->h + c->skin)));
  PetscCall(SpamOptionText("-h", c->h, val, sizeof val));
  if (!(cells <= MAX_NEIGHBOUR_CELLS)) SPAM_BAD_INPUT("-h", val, "too small for the box: its neighbour grid would hold %.3g cells of width h + skin, at most %.0e", cells, MAX_NEIGHBOUR_CELLS);
  PetscFunctionReturn(0);
}

static void Translate(const double t[3], SpamParticles *p)
{
  for (int d = 0; d < p->dim; d++) {
    p->box.lo[d] += t[d];
    for (PetscInt i = 0; i < p->n; i++) p->x[i * p->dim + d] += t[d];
  }
}

/* -gravity g (1 value: along the last direction, -dim values: the vector) and
 * -periodic_images: what every scene's model and list take. */
static PetscErrorCode ModelCommonOptions(SpamCommonParams *c)
{
  PetscReal g[16] = {0};
  PetscInt  ng    = 16;
  PetscBool set;
  char      images[32] = "minimum", val[128];
  PetscBool images_set;

  PetscFunctionBeginUser;
  PetscOptionsBegin(PETSC_COMM_WORLD, NULL, "Model and list", "spam-ark");
  PetscCall(PetscOptionsRealArray("-gravity", "Uniform acceleration g: -dim values, or 1 value along the last direction (default 0)", "README", g, &ng, &set));
  PetscCall(PetscOptionsString("-periodic_images", "Periodic neighbours by the minimum image (minimum) or as ghost slots (ghost: the path of walls and halos)", "README", images, images, sizeof images, &images_set));
  PetscCall(PetscOptionsBool("-reproducible", "Bit-identical trajectories on any number of ranks and -threads: canonical pair sums (sorted full rows, periodic images as ghost slots) and a partition-independent error norm; the isentropic gas and the gas at -smoothing_length adaptive", "README", c->reproducible, &c->reproducible, NULL));
  PetscOptionsEnd();
  c->gravity_given = set;
  PetscCall(SpamWallsOptions(c->dim, &c->walls));
  PetscCall(SpamOptionText("-gravity", set ? g[0] : 0.0, val, sizeof val));
  if (set && ng != 1 && ng != c->dim) SPAM_BAD_INPUT("-gravity", val, "takes 1 value (along the last direction) or %d (-dim %d); %" PetscInt_FMT " given", c->dim, c->dim, ng);
  for (int d = 0; d < 3; d++) c->gravity[d] = 0.0;
  for (int d = 0; set && d < (int)ng; d++) {
    if (!isfinite(g[d]) || fabs(g[d]) > 1e100) SPAM_BAD_INPUT("-gravity", val, "every value must be a finite number below 1e100 in size");
    c->gravity[ng == 1 ? c->dim - 1 : d] = g[d];
  }
  if (strcmp(images, "minimum") && strcmp(images, "ghost")) SPAM_BAD_INPUT("-periodic_images", images, "allowed: minimum, ghost");
  c->periodic_ghosts = (PetscBool)!strcmp(images, "ghost");
  if (c->reproducible && images_set && !c->periodic_ghosts) SPAM_BAD_INPUT("-periodic_images", images, "-reproducible takes the periodic images as ghost slots (the same separation on every rank count): give -periodic_images ghost or leave it out");
  c->periodic_ghosts = (PetscBool)(c->periodic_ghosts || c->reproducible);
  PetscFunctionReturn(0);
}

/* The walls of the run: the scene's defaults (out->walls, set by its build), overridden
 * face by face by what the options gave. */
static void MergeWalls(const SpamWalls *given, SpamWalls *w)
{
  for (int f = 0; f < SPAM_FACES; f++) {
    if (given->slip_given[f]) w->slip[f] = given->slip[f];
    if (given->velocity_given[f])
      for (int d = 0; d < 3; d++) w->velocity[f][d] = given->velocity[f][d];
    if (given->temperature_given[f]) {
      w->isothermal[f]  = PETSC_TRUE;
      w->temperature[f] = given->temperature[f];
    }
    w->slip_given[f]        = given->slip_given[f];
    w->velocity_given[f]    = given->velocity_given[f];
    w->temperature_given[f] = given->temperature_given[f];
  }
}

/* With -help, the options of the scenes other than ops, read into scratch params. */
static PetscErrorCode OtherScenesOptions(const SpamCommonParams *c, const SpamSceneOps *ops)
{
  PetscFunctionBeginUser;
  for (int k = 0; k < SpamSceneCount(); k++) {
    SpamSceneOps    other;
    SpamSolidParams ts;
    void           *tmp;
    PetscCall(SpamSceneGet(k, &other));
    if (!strcmp(other.name, ops->name)) continue;
    PetscCall(PetscCalloc(other.params_size + 1, &tmp));
    PetscCall(other.options(c, tmp, &ts));
    PetscCall(PetscFree(tmp));
  }
  PetscFunctionReturn(0);
}

/* Reads the options of the scene (of every scene with -help) and the model's, with the
 * scene's defaults, and builds the particles; sp holds the scene's params. */
static PetscErrorCode BuildScene(const SpamCommonParams *c, const SpamSceneOps *ops, PetscBool help, void *sp, SpamSolidParams *solid, SpamParticles *p)
{
  PetscErrorCode ierr;

  PetscFunctionBeginUser;
  if (help) PetscCall(OtherScenesOptions(c, ops)); /* every scene's options, for the listing */
  PetscCall(ops->options(c, sp, solid));
  /* The ideal gas's isentrope in D dimensions, unless the scene chose its gas's gamma
   * (SpamSolidDefaults leaves 2, the 2D value; sod and sedov set 1.4 and 5/3). */
  if (c->dim != 2 && solid->gamma == 2.0) solid->gamma = 1.0 + 2.0 / c->dim;
  if (!ops->own_model || help) PetscCall(SpamSolidOptions(solid));
  PetscCall(PetscMemzero(p, sizeof *p));
  ierr = ops->build(c, sp, solid, p);
  if (ierr) PetscCall(SpamParticlesFree(p)); /* a scene refused after allocating: leak nothing */
  PetscCall(ierr);
  MergeWalls(&c->walls, &p->walls);
  PetscFunctionReturn(0);
}

/* A scene whose rows come in any order (its descriptor's sorted: the file) is sorted by default; the lattice scenes
 * are built row by row, which is already local. */
static PetscErrorCode SortOption(MPI_Comm comm, PetscBool sorted, PetscBool *sort)
{
  PetscFunctionBeginUser;
  *sort = sorted;
  PetscOptionsBegin(comm, NULL, "Particle order", "spam-ark");
  PetscCall(PetscOptionsBool("-sort_particles", "Reorder particles by cells of width h at set-up (row by row in 2D, Morton curve in 3D) (default: true for -scene file, false for the lattice scenes); outputs keep the input order", "README", *sort, sort, NULL));
  PetscOptionsEnd();
  PetscFunctionReturn(0);
}

/* The reference density of given densities: their common value, or their mean. */
static double ReferenceDensity(const SpamParticles *p)
{
  double lo = p->rho[0], hi = p->rho[0], sum = 0.0;
  for (PetscInt i = 0; i < p->n; i++) {
    lo = PetscMin(lo, p->rho[i]);
    hi = PetscMax(hi, p->rho[i]);
    sum += p->rho[i];
  }
  return lo == hi ? lo : sum / (double)p->n;
}

/* The model of the run: the scene's own (springs), or the one read from the options
 * (-material and the rest) with the scene's defaults, in the scene's dimension. */
static PetscErrorCode ModelOf(const SpamCommonParams *c, SpamParticles *p, SpamSolidParams *solid, SpamModel *model)
{
  char val[64];

  PetscFunctionBeginUser;
  PetscCall(PetscSNPrintf(val, sizeof val, "ghost"));
  if (c->periodic_ghosts && (p->model_set || solid->closest_approach > 0)) SPAM_BAD_INPUT("-periodic_images", val, "%s finds its pairs by the minimum image: use -periodic_images minimum", p->model_set ? "the spring model's bond list" : "-closest_approach");
  if (p->model_set) *model = p->model;
  else if (solid->material == SPAM_MATERIAL_ISENTROPE) PetscCall(SpamModelIsentropeSetUp(p->dim, &c->kernel, p->mass, c->gamma, c->kappa, model));
  else {
    PetscCall(PetscSNPrintf(val, sizeof val, "%s", SpamAngmomModeNames[solid->angmom]));
    if (p->dim != 2 && solid->angmom != SPAM_ANGMOM_NONE) SPAM_BAD_INPUT("-angmom", val, "the angular-momentum treatments are two-dimensional (this run: -dim %d)", p->dim);
    PetscCall(PetscSNPrintf(val, sizeof val, "%g", solid->closest_approach));
    if (p->dim != 2 && solid->closest_approach > 0) SPAM_BAD_INPUT("-closest_approach", val, "is two-dimensional (this run: -dim %d)", p->dim);
    /* A file's densities set the reference density (sound speed, error weights), as the
     * lattice scenes' ideal density does. */
    if (p->columns & SPAM_COLUMN_RHO) solid->rho0 = ReferenceDensity(p);
    /* no density given (a file without rho, the expansion): the continuity density starts summed */
    if (solid->density != SPAM_DENSITY_SUMMATION && (!p->rho || (p->columns && !(p->columns & SPAM_COLUMN_RHO)))) solid->density_initial = SPAM_DENSITY_INITIAL_SUMMED;
    PetscCall(SpamModelSolidSetUp(p->dim, &c->kernel, p->mass, solid, model));
    if (SpamWallsAny(&p->walls, p->dim)) PetscCall(SpamLayoutAddWallBooks(&model->layout));
    if (solid->material == SPAM_MATERIAL_GAS && solid->scheme == SPAM_GAS_FLOW && (solid->background != SPAM_BACKGROUND_NONE || solid->shift_coef > 0.0)) PetscCall(SpamLayoutAddFlowBook(&model->layout));
  }
  /* The spring scenes' own model takes no gravity: -gravity is then refused as unused
   * (option_use.c), so it is only set on the smooth-particle models. */
  for (int d = 0; d < 3 && !p->model_set; d++) {
    model->gravity[d] = d >= p->dim ? 0.0 : p->gravity_set && !c->gravity_given ? p->gravity[d] : c->gravity[d];
    if (model->gravity[d] != 0.0) model->gravity_on = PETSC_TRUE;
  }
  PetscFunctionReturn(0);
}

/* A direction with a mirror wall on either face is bounded there, not periodic; a wall
 * on a face of a dimension the scene does not have is bad input. */
static PetscErrorCode WallsOfBox(SpamParticles *p)
{
  char opt[40];

  PetscFunctionBeginUser;
  for (int f = 0; f < SPAM_FACES; f++) {
    if (!SpamWallOn(&p->walls, f)) continue;
    (void)snprintf(opt, sizeof opt, "-wall_%s", SpamFaceNames[f]);
    if (f / 2 >= p->dim) SPAM_BAD_INPUT(opt, SpamWallSlipNames[p->walls.slip[f]], "the run is %d-dimensional: it has no %s face", p->dim, SpamFaceNames[f]);
    p->box.periodic[f / 2] = PETSC_FALSE;
  }
  PetscFunctionReturn(0);
}

/* -reproducible: the isentropic gas's passes have canonical rows (pass_canonical.c);
 * the tensor path and the springs sum their pairs in list order with Newton updates, and
 * a mirror wall's images book forces to the wall from both particles of a pair. */
static PetscErrorCode CheckReproducible(const SpamCommonParams *c, const SpamParticles *p, const SpamSolidParams *solid)
{
  PetscFunctionBeginUser;
  if (!c->reproducible) PetscFunctionReturn(0);
  if (p->model_set) SPAM_BAD_INPUT("-reproducible", "true", "applies to the isentropic gas (-material isentrope); this scene's spring model sums its bonds in list order");
  if (solid->material != SPAM_MATERIAL_ISENTROPE && !(solid->material == SPAM_MATERIAL_GAS && solid->smoothing != SPAM_SMOOTHING_FIXED))
    SPAM_BAD_INPUT("-reproducible", "true", "applies to the isentropic gas (-material isentrope) and the gas at -smoothing_length adaptive; the %s model's tensor-path passes sum their pairs in list order", SpamMaterialNames[solid->material]);
  if (SpamWallsAny(&p->walls, p->dim)) SPAM_BAD_INPUT("-reproducible", "true", "does not take mirror walls yet (their images' forces are booked to the wall from both particles of a pair)");
  /* Its periodic images are ghost slots, one per face a particle is near: an edge below
   * twice the list range would need images on both sides of some particles. */
  for (int d = 0; d < p->dim; d++)
    if (p->box.periodic[d] && p->box.len[d] < 2.0 * (c->h + c->skin)) SPAM_BAD_INPUT("-reproducible", "true", "needs every periodic edge at least twice the list range h + skin = %g (edge %d is %g): its periodic images are ghost slots, one per face", c->h + c->skin, d, p->box.len[d]);
  PetscFunctionReturn(0);
}

/* What runs on one rank only, refused on more in one line that says why. */
static PetscErrorCode CheckSerialOnly(PetscMPIInt size, const SpamModel *model)
{
  char val[32];

  PetscFunctionBeginUser;
  PetscCall(PetscSNPrintf(val, sizeof val, "%d", size));
  if (model->post_step) SPAM_BAD_INPUT("mpiexec -n", val, "-closest_approach runs on one rank: its pair reflections change both particles of a pair, which may sit on two ranks");
  PetscFunctionReturn(0);
}

/* The checks of a built scene against the common options, and its model. */
static PetscErrorCode CheckBuilt(MPI_Comm comm, const SpamCommonParams *c, const SpamSceneOps *ops, SpamParticles *p, SpamSolidParams *solid, SpamModel *model)
{
  PetscMPIInt size;
  char        val[64];

  PetscFunctionBeginUser;
  Translate(c->translate, p);
  PetscCall(WallsOfBox(p));
  PetscCall(SpamBoxValidate(&p->box, c->h, ops->box_size ? ops->box_size : "the lattice size"));
  PetscCall(CheckNeighbourGrid(c, &p->box)); /* the translated box's range: SpamBoxValidate */
  for (int d = 0; d < p->box.dim; d++) { /* the list's minimum image corrects by one edge at most */
    PetscCall(PetscSNPrintf(val, sizeof val, "%g", c->skin)); /* tests/run_bad_input.py expects PETSc's '9.' */
    if (p->box.periodic[d] && !(c->skin < 0.5 * p->box.len[d])) SPAM_BAD_INPUT("-neighbour_skin", val, "must be below half the periodic box edge (%g)", p->box.len[d]);
  }
  PetscCall(CheckReproducible(c, p, solid)); /* before ModelOf's -periodic_images check */
  PetscCall(ModelOf(c, p, solid, model));
  PetscCall(SpamParticlesCheckColumns(p, &model->layout)); /* a file's columns against the model */
  PetscCallMPI(MPI_Comm_size(comm, &size));
  if (size > 1) PetscCall(CheckSerialOnly(size, model));
  PetscCall(SpamSmoothingCheck(c, p, solid, size));
  PetscFunctionReturn(0);
}

/* Scene names for messages: "a, b, c". */
static PetscErrorCode SceneNames(PetscFunctionList list, char *buf, size_t len)
{
  const char **names;
  int          n;

  buf[0] = 0;
  PetscFunctionBeginUser;
  PetscCall(PetscFunctionListGet(list, &names, &n));
  for (int k = 0; k < n && names[k]; k++) { /* PETSc 3.18 ends the array with NULL, counted in n */
    PetscCall(PetscStrlcat(buf, k ? ", " : "", len));
    PetscCall(PetscStrlcat(buf, names[k], len));
  }
  PetscCall(PetscFree(names));
  PetscFunctionReturn(0);
}

/* The chosen scene's operations (by default the list's first), or a bad-input error
 * listing the scenes. */
static PetscErrorCode ChooseScene(MPI_Comm comm, PetscFunctionList list, SpamSceneOps *ops)
{
  char           name[64], names[1024], help[1100];
  SpamSceneOpsFn fn;

  PetscFunctionBeginUser;
  PetscCall(SpamSceneGet(0, ops));
  PetscCall(PetscStrncpy(name, ops->name, sizeof name));
  PetscCall(SceneNames(list, names, sizeof names));
  PetscCall(PetscSNPrintf(help, sizeof help, "Scene that builds the particles: %s", names));
  PetscOptionsBegin(comm, NULL, "Scene", "spam-ark");
  PetscCall(PetscOptionsString("-scene", help, "README", name, name, sizeof name, NULL));
  PetscOptionsEnd();
  PetscCall(PetscFunctionListFind(list, name, &fn));
  if (!fn) {
    char shown[100];
    SpamClip(name, shown, sizeof shown);
    SPAM_BAD_INPUT("-scene", shown, "allowed: %s", names);
  }
  PetscCall(fn(ops));
  PetscFunctionReturn(0);
}

static PetscErrorCode CheckDimension(const SpamCommonParams *c, const SpamSceneOps *ops)
{
  static const char *const words[] = {"", "one", "two", "three"};
  char                     val[64], dims[32] = "";
  int                      count = 0, only = 0;

  PetscFunctionBeginUser;
  if (ops->dims & (1 << c->dim)) PetscFunctionReturn(0);
  for (int d = 1; d <= 3; d++)
    if (ops->dims & (1 << d)) {
      (void)snprintf(dims + strlen(dims), sizeof dims - strlen(dims), "%s%d", count++ ? ", " : "", d);
      only = d;
    }
  PetscCall(PetscSNPrintf(val, sizeof val, "%d", c->dim));
  if (count == 1) SPAM_BAD_INPUT("-dim", val, "-scene %s is %s-dimensional: add -dim %d", ops->name, words[only], only);
  SPAM_BAD_INPUT("-dim", val, "-scene %s exists in dimensions %s", ops->name, dims);
}

/* Swarm, particle order, fields and set-up of the built particles p. */
static PetscErrorCode CreateSim(MPI_Comm comm, const SpamCommonParams *c, PetscBool sort, const SpamModel *model, SpamParticles *p, SpamSim *sim)
{
  PetscMPIInt rank;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  /* Rank 0 holds the whole scene until SpamSimDistribute (sim_distribute.c says why). */
  PetscCall(SpamSimCreate(comm, model, &p->box, rank ? 0 : p->n, c->skin, sim));
  sim->out.scene           = p->info;
  sim->pair.threads         = (int)c->threads;
  sim->pair.periodic_ghosts = c->periodic_ghosts;
  sim->pair.reproducible    = c->reproducible;
  sim->geo.walls           = p->walls;
  if (sort) {
    PetscInt *row_of;
    PetscCall(PetscMalloc1(p->n + 1, &row_of));
    PetscCall(SpamParticlesSortByCell(p, c->h, row_of));
    PetscCall(SpamSwarmSetRows(&sim->p, row_of));
    PetscCall(PetscFree(row_of));
  }
  PetscCall(SpamSimFill(sim, p->x, p->v, p->m));
  PetscCall(SpamSimFillFields(sim, p));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamSceneCreateSim(MPI_Comm comm, SpamSim *sim)
{
  SpamCommonParams  c;
  SpamParticles     p;
  SpamModel         model;
  SpamSolidParams   solid;
  SpamSceneOps      ops;
  PetscFunctionList list = NULL;
  PetscBool         help = PETSC_FALSE, sort;
  void             *sp = NULL;
  PetscErrorCode    ierr;

  PetscFunctionBeginUser;
  PetscCall(PetscOptionsHasHelp(NULL, &help));
  PetscCall(CommonOptions(&c));
  PetscCall(ModelCommonOptions(&c));
  PetscCall(SpamSceneRegisterAll(&list));
  ierr = ChooseScene(comm, list, &ops);
  if (!ierr) ierr = CheckDimension(&c, &ops);
  if (!ierr) ierr = SortOption(comm, ops.sorted, &sort);
  if (!ierr) ierr = PetscCalloc(ops.params_size + 1, &sp);
  if (!ierr) ierr = BuildScene(&c, &ops, help, sp, &solid, &p);
  PetscCall(PetscFree(sp));
  PetscCall(PetscFunctionListDestroy(&list));
  PetscCall(ierr);
  ierr = CheckBuilt(comm, &c, &ops, &p, &solid, &model);
  if (ierr) PetscCall(SpamParticlesFree(&p)); /* refused: leak nothing */
  PetscCall(ierr);
  model.energy_given = (PetscBool)((p.columns & SPAM_COLUMN_E) != 0); /* a file's e column, else the gas's -gas_e0 */
  PetscCall(CreateSim(comm, &c, sort, &model, &p, sim));
  PetscCall(SpamParticlesFree(&p));
  PetscCall(SpamSimSetUp(sim));
  if (sim->model.setup) PetscCall(sim->model.setup(sim));
  PetscCall(SpamSimDistribute(sim));
  PetscFunctionReturn(0);
}
