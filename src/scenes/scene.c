/* Scene registry: common options, the choice of scene, and filling the swarm. */
#include <spam/scene.h>
#include <spam/errors.h>

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
  PetscFunctionReturn(0);
}

static PetscErrorCode CheckPositive(const char *opt, double v)
{
  char val[64];
  PetscFunctionBeginUser;
  (void)snprintf(val, sizeof val, "%g", v);
  if (!(v > 0.0) || !isfinite(v)) SPAM_BAD_INPUT(opt, val, "must be a positive number");
  PetscFunctionReturn(0);
}

static PetscErrorCode CommonOptions(SpamCommonParams *c)
{
  PetscInt  nd = 3, nl = 3, np = 3, nt = 3, dim = 2;
  PetscBool set;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(c, sizeof *c));
  for (int d = 0; d < 3; d++) c->periodic[d] = PETSC_TRUE;
  c->h    = 3.0;
  c->mass = 1.0;
  PetscOptionsBegin(PETSC_COMM_WORLD, NULL, "Particles, kernel and gas", "spam-ark");
  PetscCall(PetscOptionsInt("-dim", "Space dimension (1, 2 or 3)", "README", dim, &dim, NULL));
  PetscCall(PetscOptionsReal("-h", "Kernel range h (Lucy's kernel vanishes at r = h)", "README", c->h, &c->h, NULL));
  PetscCall(PetscOptionsReal("-mass", "Particle mass m", "README", c->mass, &c->mass, NULL));
  c->skin = 0.1 * c->h;
  PetscCall(PetscOptionsReal("-neighbour_skin", "Verlet-list skin (default 0.1 h)", "README", c->skin, &c->skin, NULL));
  c->gamma = 1.0 + 2.0 / (double)PetscClipInterval(dim, 1, 3);
  PetscCall(PetscOptionsReal("-eos_gamma", "Isentrope exponent gamma in P = kappa rho^gamma (default 1 + 2/D)", "README", c->gamma, &c->gamma, NULL));
  c->kappa = 1.0 / c->gamma;
  PetscCall(PetscOptionsReal("-eos_kappa", "Isentrope constant kappa (default 1/gamma: sound speed 1 at rho = 1)", "README", c->kappa, &c->kappa, NULL));
  PetscCall(PetscOptionsRealArray("-box_lo", "Lower corner of the box (file scene; default 0)", "README", c->box_lo, &nd, NULL));
  PetscCall(PetscOptionsRealArray("-box_len", "Box edge lengths (file scene: required)", "README", c->box_len, &nl, &c->box_len_set));
  PetscCall(PetscOptionsBoolArray("-periodic", "Periodic in each direction (default true)", "README", c->periodic, &np, NULL));
  c->threads = 1;
  PetscCall(PetscOptionsInt("-threads", "OpenMP threads of the pair passes (1: none; results are the same run to run for a given count)", "README", c->threads, &c->threads, NULL));
  PetscCall(PetscOptionsRealArray("-scene_translate", "Shift particles and box by this vector (a test of translation invariance)", "README", c->translate, &nt, &set));
  PetscOptionsEnd();
  c->dim = (int)dim;
  {
    char val[32];
    PetscCall(PetscSNPrintf(val, sizeof val, "%" PetscInt_FMT, dim));
    if (dim < 1 || dim > 3) SPAM_BAD_INPUT("-dim", val, "allowed: 1, 2 or 3");
  }
  {
    char val[32];
    PetscCall(PetscSNPrintf(val, sizeof val, "%" PetscInt_FMT, c->threads));
    if (c->threads < 1 || c->threads > SPAM_MAX_THREADS) SPAM_BAD_INPUT("-threads", val, "must be from 1 to %d", SPAM_MAX_THREADS);
  }
  PetscCall(CheckPositive("-h", c->h));
  PetscCall(CheckPositive("-mass", c->mass));
  PetscCall(CheckPositive("-eos_kappa", c->kappa));
  {
    char val[64];
    (void)snprintf(val, sizeof val, "%g", c->skin);
    if (!(c->skin >= 0.0) || !isfinite(c->skin)) SPAM_BAD_INPUT("-neighbour_skin", val, "must be zero or positive");
    (void)snprintf(val, sizeof val, "%g", c->gamma);
    if (!(c->gamma > 1.0) || !isfinite(c->gamma)) SPAM_BAD_INPUT("-eos_gamma", val, "must be greater than 1");
  }
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

  PetscFunctionBeginUser;
  if (help || s == SCENE_EXPANSION) PetscCall(SpamExpansionOptions(c, &ep));
  if (help || s == SCENE_FILE) PetscCall(SpamFileOptions(&fp));
  if (help || s == SCENE_CHAIN) PetscCall(SpamChainOptions(c, &ch));
  if (help || s == SCENE_PLANEWAVE) PetscCall(SpamPlanewaveOptions(c, &pw));
  if (help || s == SCENE_ROTOR) PetscCall(SpamRotorOptions(c, PETSC_FALSE, &ro));
  if (help || s == SCENE_ROTOR_PAIR) PetscCall(SpamRotorOptions(c, PETSC_TRUE, &rp));
  if (help || s == SCENE_ROTOR_MD) PetscCall(SpamRotorMdOptions(c, &md));
  if (help || s == SCENE_TENSILE) PetscCall(SpamTensileOptions(c, &te));
  switch (s) {
  case SCENE_EXPANSION: PetscCall(SpamExpansionBuild(c, &ep, p)); break;
  case SCENE_FILE: PetscCall(SpamFileBuild(c, &fp, p)); break;
  case SCENE_CHAIN: PetscCall(SpamChainBuild(c, &ch, p)); break;
  case SCENE_PLANEWAVE: PetscCall(SpamPlanewaveBuild(c, &pw, p)); break;
  case SCENE_ROTOR: PetscCall(SpamRotorBuild(c, &ro, p)); break;
  case SCENE_ROTOR_PAIR: PetscCall(SpamRotorBuild(c, &rp, p)); break;
  case SCENE_ROTOR_MD: PetscCall(SpamRotorMdBuild(c, &md, p)); break;
  default: PetscCall(SpamTensileBuild(c, &te, p)); break;
  }
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

PetscErrorCode SpamSceneCreateSim(MPI_Comm comm, SpamSim *sim)
{
  SpamCommonParams c;
  SpamParticles    p;
  SpamModel        model;
  PetscInt         scene = 0;
  PetscBool        help  = PETSC_FALSE, sort;
  PetscMPIInt      size;
  char             val[64];

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_size(comm, &size));
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
  PetscCall(BuildScene(&c, (int)scene, help, &p));
  PetscCall(PetscSNPrintf(val, sizeof val, "%d", size));
  if (size > 1) SPAM_BAD_INPUT("mpiexec -n", val, "this version runs on one rank; multi-rank halo exchange is not written yet");
  Translate(c.translate, &p);
  PetscCall(SpamBoxValidate(&p.box, c.h, scene == SCENE_EXPANSION ? "2 x -expansion_n" : scene == SCENE_FILE ? "-box_len" : "the lattice size"));
  for (int d = 0; d < p.box.dim; d++) { /* the list's minimum image corrects by one edge at most */
    PetscCall(PetscSNPrintf(val, sizeof val, "%g", c.skin));
    if (p.box.periodic[d] && !(c.skin < 0.5 * p.box.len[d])) SPAM_BAD_INPUT("-neighbour_skin", val, "must be below half the periodic box edge (%g)", p.box.len[d]);
  }
  if (p.model_set) model = p.model;
  else PetscCall(SpamModelIsentropeSetUp(c.dim, c.h, p.mass, c.gamma, c.kappa, &model));
  PetscCall(SpamSimCreate(comm, &model, &p.box, p.n, c.skin, sim));
  sim->scene   = p.info;
  sim->threads = (int)c.threads;
  PetscCall(SortOption(comm, scene == SCENE_FILE, &sort));
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
