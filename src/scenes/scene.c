/* Scene registry: common options, the choice of scene, and filling the swarm. */
#include <spam/scene.h>
#include <spam/errors.h>
#include <float.h>

static const char *const SceneNames[] = {"expansion", "file", "chain", "planewave", "rotor", "rotor-pair", "rotor-md", "tensile"};
enum { SCENE_EXPANSION, SCENE_FILE, SCENE_CHAIN, SCENE_PLANEWAVE, SCENE_ROTOR, SCENE_ROTOR_PAIR, SCENE_ROTOR_MD, SCENE_TENSILE, NSCENES };

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

static PetscErrorCode CheckPositive(const char *opt, double v)
{
  char val[128];
  PetscFunctionBeginUser;
  PetscCall(SpamOptionText(opt, v, val, sizeof val));
  if (!(v > 0.0) || !isfinite(v)) SPAM_BAD_INPUT(opt, val, "must be a positive finite number");
  if (v < DBL_MIN) SPAM_BAD_INPUT(opt, val, "too small (subnormal): must be at least %g", DBL_MIN);
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

/* Lucy's kernel at this h: its normalisation C_D h^-D and that of its derivatives,
 * C_D h^-(D+2), must be normal finite numbers, or every density and force is 0 or inf. */
static PetscErrorCode CheckKernelRange(int dim, double h)
{
  SpamKernel k;
  char       val[128], w[32], g[32];

  PetscFunctionBeginUser;
  PetscCall(SpamOptionText("-h", h, val, sizeof val));
  PetscCall(SpamKernelLucyInit(dim, h, &k));
  (void)snprintf(w, sizeof w, "%.3g", k.wnorm);
  (void)snprintf(g, sizeof g, "%.3g", fabs(k.gnorm));
  if (!(isnormal(k.wnorm) && isnormal(k.gnorm))) SPAM_BAD_INPUT("-h", val, "out of range: the kernel's normalisations C_D h^-%d = %s and C_D h^-%d = %s must be normal finite numbers", dim, w, dim + 2, g);
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
  PetscCall(PetscOptionsReal("-h", "Kernel range h (Lucy's kernel vanishes at r = h)", "README", c->h, &c->h, NULL));
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
  PetscCall(CheckKernelRange(c->dim, c->h));
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

/* Reads the options of scene s (of every scene with -help) and builds its particles. */
static PetscErrorCode BuildScene(const SpamCommonParams *c, int s, PetscBool help, SpamParticles *p)
{
  SpamExpansionParams ep;
  SpamFileParams      fp;
  SpamPlanewaveParams pw;
  SpamRotorParams     ro, rp;
  SpamRotorMdParams   md;
  SpamTensileParams   te;
  SpamChainParams     ch;
  PetscErrorCode      ierr;

  PetscFunctionBeginUser;
  if (help || s == SCENE_EXPANSION) PetscCall(SpamExpansionOptions(c, &ep));
  if (help || s == SCENE_FILE) PetscCall(SpamFileOptions(&fp));
  if (help || s == SCENE_CHAIN) PetscCall(SpamChainOptions(c, &ch));
  if (help || s == SCENE_PLANEWAVE) PetscCall(SpamPlanewaveOptions(c, &pw));
  if (help || s == SCENE_ROTOR) PetscCall(SpamRotorOptions(c, PETSC_FALSE, &ro));
  if (help || s == SCENE_ROTOR_PAIR) PetscCall(SpamRotorOptions(c, PETSC_TRUE, &rp));
  if (help || s == SCENE_ROTOR_MD) PetscCall(SpamRotorMdOptions(c, &md));
  if (help || s == SCENE_TENSILE) PetscCall(SpamTensileOptions(c, &te));
  PetscCall(PetscMemzero(p, sizeof *p));
  switch (s) {
  case SCENE_EXPANSION: ierr = SpamExpansionBuild(c, &ep, p); break;
  case SCENE_FILE: ierr = SpamFileBuild(c, &fp, p); break;
  case SCENE_CHAIN: ierr = SpamChainBuild(c, &ch, p); break;
  case SCENE_PLANEWAVE: ierr = SpamPlanewaveBuild(c, &pw, p); break;
  case SCENE_ROTOR: ierr = SpamRotorBuild(c, &ro, p); break;
  case SCENE_ROTOR_PAIR: ierr = SpamRotorBuild(c, &rp, p); break;
  case SCENE_ROTOR_MD: ierr = SpamRotorMdBuild(c, &md, p); break;
  default: ierr = SpamTensileBuild(c, &te, p); break;
  }
  if (ierr) PetscCall(SpamParticlesFree(p)); /* a scene refused after allocating: leak nothing */
  PetscCall(ierr);
  PetscFunctionReturn(0);
}

/* The file scene's rows come in any order, so it is sorted by default; the lattice scenes
 * are built row by row, which is already local. */
static PetscErrorCode SortOption(MPI_Comm comm, PetscBool file, PetscBool *sort)
{
  PetscFunctionBeginUser;
  *sort = file;
  PetscOptionsBegin(comm, NULL, "Particle order", "spam-ark");
  PetscCall(PetscOptionsBool("-sort_particles", "Reorder particles by cells of width h at set-up (row by row in 2D, Morton curve in 3D) (default: true for -scene file, false for the lattice scenes); outputs keep the input order", "README", *sort, sort, NULL));
  PetscOptionsEnd();
  PetscFunctionReturn(0);
}

/* The checks of a built scene against the common options, and its model. */
static PetscErrorCode CheckBuilt(MPI_Comm comm, const SpamCommonParams *c, int scene, SpamParticles *p, SpamModel *model)
{
  PetscMPIInt size;
  char        val[64];

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_size(comm, &size));
  PetscCall(PetscSNPrintf(val, sizeof val, "%d", size));
  if (size > 1) SPAM_BAD_INPUT("mpiexec -n", val, "this version runs on one rank; multi-rank halo exchange is not written yet");
  Translate(c->translate, p);
  PetscCall(SpamBoxValidate(&p->box, c->h, scene == SCENE_EXPANSION ? "2 x -expansion_n" : scene == SCENE_FILE ? "-box_len" : "the lattice size"));
  PetscCall(CheckNeighbourGrid(c, &p->box)); /* the translated box's range: SpamBoxValidate */
  for (int d = 0; d < p->box.dim; d++) { /* the list's minimum image corrects by one edge at most */
    PetscCall(PetscSNPrintf(val, sizeof val, "%g", c->skin)); /* tests/run_bad_input.py expects PETSc's '9.' */
    if (p->box.periodic[d] && !(c->skin < 0.5 * p->box.len[d])) SPAM_BAD_INPUT("-neighbour_skin", val, "must be below half the periodic box edge (%g)", p->box.len[d]);
  }
  if (p->model_set) *model = p->model;
  else PetscCall(SpamModelIsentropeSetUp(c->dim, c->h, p->mass, c->gamma, c->kappa, model));
  PetscCall(SpamParticlesCheckColumns(p, &model->layout)); /* a file's columns against the model */
  PetscCall(SpamParticlesCheckMasses(p));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamSceneCreateSim(MPI_Comm comm, SpamSim *sim)
{
  SpamCommonParams c;
  SpamParticles    p;
  SpamModel        model;
  PetscInt         scene = 0;
  PetscBool        help  = PETSC_FALSE, sort;
  char             val[64];

  PetscFunctionBeginUser;
  PetscCall(PetscOptionsHasHelp(NULL, &help));
  PetscCall(CommonOptions(&c));
  {
    char name[64] = "expansion";
    PetscOptionsBegin(comm, NULL, "Scene", "spam-ark");
    PetscCall(PetscOptionsString("-scene", "Scene that builds the particles: expansion, file, chain, planewave, rotor, rotor-pair, rotor-md or tensile", "README", name, name, sizeof name, NULL));
    PetscOptionsEnd();
    scene = -1;
    for (int s = 0; s < NSCENES; s++)
      if (!strcmp(name, SceneNames[s])) scene = s;
    if (scene < 0) SPAM_BAD_INPUT("-scene", name, "allowed: expansion, file, chain, planewave, rotor, rotor-pair, rotor-md, tensile");
  }
  PetscCall(PetscSNPrintf(val, sizeof val, "%d", c.dim));
  if (scene == SCENE_CHAIN && c.dim != 1) SPAM_BAD_INPUT("-dim", val, "the chain scene is one-dimensional: add -dim 1");
  if (scene >= SCENE_PLANEWAVE && c.dim != 2) SPAM_BAD_INPUT("-dim", val, "the elastic scenes (planewave, rotor, rotor-pair, rotor-md, tensile) are two-dimensional");
  PetscCall(SortOption(comm, scene == SCENE_FILE, &sort));
  PetscCall(BuildScene(&c, (int)scene, help, &p));
  {
    PetscErrorCode ierr = CheckBuilt(comm, &c, (int)scene, &p, &model);
    if (ierr) PetscCall(SpamParticlesFree(&p)); /* refused: leak nothing */
    PetscCall(ierr);
  }
  PetscCall(SpamSimCreate(comm, &model, &p.box, p.n, c.skin, sim));
  sim->scene   = p.info;
  sim->threads = (int)c.threads;
  if (sort) {
    PetscCall(PetscMalloc2(p.n + 1, &sim->row_of, p.n + 1, &sim->at_row));
    PetscCall(SpamParticlesSortByCell(&p, c.h, sim->row_of));
    for (PetscInt i = 0; i < p.n; i++) sim->at_row[sim->row_of[i]] = i;
  }
  PetscCall(SpamSimFill(sim, p.x, p.v));
  PetscCall(SpamSimFillFields(sim, &p));
  PetscCall(SpamParticlesFree(&p));
  PetscCall(SpamSimSetUp(sim));
  if (sim->model.setup) PetscCall(sim->model.setup(sim));
  PetscFunctionReturn(0);
}
