/* Remote ghosts through PetscSF (halo.h), on any number of ranks, against brute force over
 * the whole particle set: every pair within the cutoff of a local particle is listed
 * exactly once among its local and ghost neighbours; a ghost's position is its owner's
 * box-local position plus its shift, bit for bit; a gathered field arrives in every ghost
 * slot; moves below skin/2 keep the list and the exchange keeps the ghosts right; a larger
 * move on one rank rebuilds on every rank; a non-finite position on one rank is reported on
 * every rank. Perturbed lattices in 2D and 3D, periodic directions by the minimum image and
 * by ghost images, one open direction, mirror walls (some particles a little beyond a wall,
 * as within a step; corners of two and three walls), owners by slabs and at random. A
 * partner is a particle and its image: a mirror image of a particle (its own included) is
 * a partner of its own. */
#include <spam/neighbours.h>
#include "test_util.h"

#define H    3.0
#define SKIN 0.4

typedef struct {
  const char *name;
  int         dim, side;       /* lattice of side^dim particles, spacing 1          */
  PetscBool   periodic[3];
  PetscBool   ghost_periodic;  /* periodic images as ghost slots (else min image)   */
  PetscBool   random_owner;    /* else slabs along x                                */
  PetscBool   walls[3];        /* mirror walls on both faces of the direction       */
} Case;

/* A partner's key: its global id and its mirror image (flip bits, face bits << 3). */
#define IMAGES 64
static int KeyOf(int gid, int flip, int face)
{
  return gid * IMAGES + flip + (face << 3);
}

typedef struct {
  MPI_Comm    comm;
  PetscMPIInt rank, size;
  TestCount   count;
} World;

/* The global set: every rank makes the same particles, then keeps its own. */
typedef struct {
  SpamBox box;
  int     N;          /* particles in all                           */
  double *X;          /* [N * dim] positions, the same on every rank */
  int    *owner;      /* [N]                                        */
  int     n;          /* this rank's particles                      */
  int    *gid;        /* [n] their global ids, increasing            */
  double *x;          /* [n * dim] their positions                  */
  int    *gid_at;     /* [sum n_r] gid of (rank, index): rank r's from start_of[r] */
  int    *start_of;   /* [size + 1]                                 */
  double *uall[3];    /* [sum n_r] every rank's box-local u, gathered */
} Particles;

static long SumAll(const World *w, long v)
{
  long s = 0;
  MPI_Allreduce(&v, &s, 1, MPI_LONG, MPI_SUM, w->comm);
  return s;
}

/* A check that every rank agrees on: printed once, by rank 0. */
static void Check(World *w, int ok, const char *msg)
{
  if (w->rank == 0) TestCheck(&w->count, ok, "%s", msg);
  else if (ok) w->count.passed++;
  else w->count.failed++;
}

static PetscErrorCode MakeParticles(const World *w, const Case *c, Particles *p)
{
  uint64_t seed = 20261203;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(p, sizeof *p));
  p->box.dim = c->dim;
  p->N       = 1;
  for (int d = 0; d < c->dim; d++) {
    p->box.lo[d]       = -2.0;
    p->box.len[d]      = c->side;
    p->box.periodic[d] = c->periodic[d];
    p->N *= c->side;
  }
  PetscCall(PetscMalloc3((size_t)p->N * c->dim, &p->X, p->N, &p->owner, p->N, &p->gid));
  PetscCall(PetscMalloc1((size_t)p->N * c->dim, &p->x));
  for (int g = 0; g < p->N; g++) {
    int rem = g;
    for (int d = 0; d < c->dim; d++) {
      /* lattice sites at lo + 0.5 + k, moved by up to 0.3: across the lower face of a
       * periodic direction (wrapped by the list) or a wall (up to 0.4 beyond it), inside an
       * open one */
      p->X[(size_t)g * c->dim + d] = p->box.lo[d] + 0.5 + (rem % c->side) + 0.6 * (TestUniform(&seed) - 0.5) - ((c->periodic[d] || c->walls[d]) && rem % c->side == 0 ? 0.6 : 0.0);
      rem /= c->side;
    }
    if (c->random_owner) p->owner[g] = (int)(TestUniform(&seed) * w->size);
    else p->owner[g] = PetscMin(w->size - 1, (int)(SpamBoxLocal(&p->box, 0, p->X[(size_t)g * c->dim]) / p->box.len[0] * w->size));
  }
  for (int g = 0; g < p->N; g++) {
    if (p->owner[g] != w->rank) continue;
    p->gid[p->n] = g;
    for (int d = 0; d < c->dim; d++) p->x[(size_t)p->n * c->dim + d] = p->X[(size_t)g * c->dim + d];
    p->n++;
  }
  PetscCall(PetscMalloc2(w->size + 1, &p->start_of, p->N, &p->gid_at));
  for (int d = 0; d < 3; d++) PetscCall(PetscMalloc1(p->N, &p->uall[d]));
  {
    PetscMPIInt *cnt;
    PetscCall(PetscMalloc1(w->size, &cnt));
    PetscCallMPI(MPI_Allgather(&p->n, 1, MPI_INT, cnt, 1, MPI_INT, w->comm));
    p->start_of[0] = 0;
    for (int r = 0; r < w->size; r++) p->start_of[r + 1] = p->start_of[r] + cnt[r];
    PetscCallMPI(MPI_Allgatherv(p->gid, p->n, MPI_INT, p->gid_at, cnt, p->start_of, MPI_INT, w->comm));
    PetscCall(PetscFree(cnt));
  }
  PetscFunctionReturn(0);
}

static PetscErrorCode FreeParticles(Particles *p)
{
  PetscFunctionBeginUser;
  PetscCall(PetscFree3(p->X, p->owner, p->gid));
  PetscCall(PetscFree(p->x));
  PetscCall(PetscFree2(p->start_of, p->gid_at));
  for (int d = 0; d < 3; d++) PetscCall(PetscFree(p->uall[d]));
  PetscFunctionReturn(0);
}

/* Every rank's current box-local positions (the owners' u), by (rank, index). */
static PetscErrorCode GatherU(const World *w, const SpamNeighbours *nl, Particles *p)
{
  PetscMPIInt *cnt;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc1(w->size, &cnt));
  for (int r = 0; r < w->size; r++) cnt[r] = p->start_of[r + 1] - p->start_of[r];
  for (int d = 0; d < p->box.dim; d++) PetscCallMPI(MPI_Allgatherv(nl->u[d], p->n, MPI_DOUBLE, p->uall[d], cnt, p->start_of, MPI_DOUBLE, w->comm));
  PetscCall(PetscFree(cnt));
  PetscFunctionReturn(0);
}

/* Global id of ghost slot k: a local image's source, or a remote owner's particle. */
static int GhostGid(const SpamNeighbours *nl, const Particles *p, int k)
{
  const SpamGhosts *g = &nl->ghosts;
  if (g->src[k] >= 0) return p->gid[g->src[k]];
  return p->gid_at[p->start_of[g->halo.ghost_owner[k - g->nlocal]] + g->halo.ghost_index[k - g->nlocal]];
}

/* Ghost slot k as a partner: its particle and, for a mirror image, which. */
static int GhostKey(const SpamNeighbours *nl, const Particles *p, int k)
{
  const SpamGhosts *g = &nl->ghosts;
  return KeyOf(GhostGid(nl, p, k), g->kind[k] == SPAM_GHOST_MIRROR ? g->flip[k] : 0, g->kind[k] == SPAM_GHOST_MIRROR ? g->face[k] : 0);
}

/* The slot's position the ghost must hold: its owner's u, mirrored where it is a mirror
 * image, plus its shift. */
static double GhostExpected(const SpamNeighbours *nl, const Particles *p, int k, int d)
{
  const SpamGhosts *g = &nl->ghosts;
  const double      u = g->src[k] >= 0 ? nl->u[d][g->src[k]] : p->uall[d][p->start_of[g->halo.ghost_owner[k - g->nlocal]] + g->halo.ghost_index[k - g->nlocal]];
  return ((g->flip[k] >> d) & 1 ? -u : u) + g->shift[d][k];
}

/* Squared distance from x_i to image (flip, face) of x_j: mirrored in the walls of the
 * flipped directions (box-local -u or 2L - u), the minimum image along periodic ones. */
static double Dist2(const SpamBox *b, const double *xi, const double *xj, int flip, int face)
{
  double r2 = 0.0;
  for (int d = 0; d < b->dim; d++) {
    const double ui = SpamBoxLocal(b, d, xi[d]), uj = SpamBoxLocal(b, d, xj[d]);
    const double dx = (flip >> d) & 1 ? ui - ((face >> d) & 1 ? 2.0 * b->len[d] - uj : -uj) : SpamBoxMinImage(ui - uj, b->len[d], 0.5 * b->len[d], b->periodic[d]);
    r2 += dx * dx;
  }
  return r2;
}

/* Each local particle's listed partners (global ids), from the half list (both ends),
 * the local images (both ends: a periodic image's pair sits in one row) and the remote
 * ghosts (the local end only: the owner lists its own end). CSR in *start, *part. */
static PetscErrorCode Partners(const SpamNeighbours *nl, const Particles *p, int **start, int **part)
{
  const int n = nl->n;
  int      *fill;
  size_t    total = 2 * nl->npairs + 2 * nl->ngpairs;

  PetscFunctionBeginUser;
  PetscCall(PetscCalloc1(n + 1, start));
  PetscCall(PetscCalloc1(n + 1, &fill));
  PetscCall(PetscMalloc1(total + 1, part));
  for (int pass = 0; pass < 2; pass++) {
    for (int i = 0; i < n; i++) {
      for (int q = nl->start[i]; q < nl->start[i + 1]; q++) {
        const int j = nl->nbr[q];
        if (pass) {
          (*part)[fill[i]++] = KeyOf(p->gid[j], 0, 0);
          (*part)[fill[j]++] = KeyOf(p->gid[i], 0, 0);
        } else {
          (*start)[i + 1]++;
          (*start)[j + 1]++;
        }
      }
      for (int q = nl->gstart[i]; q < nl->gstart[i + 1]; q++) {
        const int k = nl->gnbr[q] - n, s = nl->ghosts.src[k];
        if (pass) {
          (*part)[fill[i]++] = GhostKey(nl, p, k);
          if (nl->ghosts.kind[k] == SPAM_GHOST_PERIODIC) (*part)[fill[s]++] = KeyOf(p->gid[i], 0, 0);
        } else {
          (*start)[i + 1]++;
          if (nl->ghosts.kind[k] == SPAM_GHOST_PERIODIC) (*start)[s + 1]++;
        }
      }
    }
    if (!pass) {
      for (int i = 0; i < n; i++) (*start)[i + 1] += (*start)[i];
      for (int i = 0; i < n; i++) fill[i] = (*start)[i];
    }
  }
  PetscCall(PetscFree(fill));
  PetscFunctionReturn(0);
}

/* Whether image (flip, face) exists: mirrored only in walled directions. */
static int ImageExists(const Case *c, int flip, int face)
{
  for (int d = 0; d < 3; d++)
    if ((((flip >> d) & 1) && !c->walls[d]) || (((face >> d) & 1) && !((flip >> d) & 1))) return 0;
  return 1;
}

/* Every pair within the cutoff of a local particle listed exactly once; no partner listed
 * twice, no particle its own partner (its mirror images are). */
static PetscErrorCode CheckPairs(World *w, const Case *c, const char *when, const SpamNeighbours *nl, const Particles *p)
{
  const int dim = p->box.dim;
  int      *start, *part, *seen;
  long      want = 0, missing = 0, dup = 0, self = 0;
  char      msg[256];
  int       img[IMAGES][2], nimg = 0; /* the images that exist: (flip, face) */

  PetscFunctionBeginUser;
  PetscCall(Partners(nl, p, &start, &part));
  PetscCall(PetscCalloc1((size_t)p->N * IMAGES, &seen));
  for (int flip = 0; flip < 8; flip++)
    for (int face = 0; face < 8; face++)
      if (ImageExists(c, flip, face)) img[nimg][0] = flip, img[nimg++][1] = face;
  for (int i = 0; i < p->n; i++) {
    const double *xi = p->X + (size_t)p->gid[i] * dim;
    for (int q = start[i]; q < start[i + 1]; q++) {
      if (part[q] == KeyOf(p->gid[i], 0, 0)) self++;
      else if (seen[part[q]]++) dup++;
    }
    for (int j = 0; j < p->N; j++)
      for (int m = 0; m < nimg; m++) {
        const int flip = img[m][0], face = img[m][1];
        if ((j == p->gid[i] && !flip) || Dist2(&p->box, xi, p->X + (size_t)j * dim, flip, face) >= H * H) continue;
        want++;
        if (seen[KeyOf(j, flip, face)] != 1) missing++;
      }
    for (int q = start[i]; q < start[i + 1]; q++) seen[part[q]] = 0;
  }
  want = SumAll(w, want), missing = SumAll(w, missing), dup = SumAll(w, dup), self = SumAll(w, self);
  snprintf(msg, sizeof msg, "%s, %s: %ld (local particle, partner) pairs within h by brute force; missing %ld, listed twice %ld, self %ld", c->name, when, want, missing, dup, self);
  Check(w, want > 0 && missing == 0 && dup == 0 && self == 0, msg);
  PetscCall(PetscFree(seen));
  PetscCall(PetscFree(start));
  PetscCall(PetscFree(part));
  PetscFunctionReturn(0);
}

/* Ghost positions equal to the owners' u plus the shifts, bitwise. */
static PetscErrorCode CheckPositions(World *w, const char *name, const char *when, SpamNeighbours *nl, Particles *p)
{
  long bad = 0, slots = 0, remote = 0;
  char msg[256];

  PetscFunctionBeginUser;
  PetscCall(GatherU(w, nl, p));
  for (int k = 0; k < nl->ghosts.n; k++) {
    remote += nl->ghosts.src[k] < 0;
    for (int d = 0; d < p->box.dim; d++) bad += !(nl->u[d][nl->n + k] == GhostExpected(nl, p, k, d));
  }
  slots = SumAll(w, nl->ghosts.n), remote = SumAll(w, remote), bad = SumAll(w, bad);
  snprintf(msg, sizeof msg, "%s, %s: %ld ghost slots (%ld remote), %ld coordinates differ from owner u + shift", name, when, slots, remote, bad);
  Check(w, bad == 0 && (w->size == 1 || remote > 0), msg);
  PetscFunctionReturn(0);
}

/* The sign of component c of a field in a mirror image of flip bits f: a vector's mirrored
 * components, a tensor's components with exactly one mirrored index, change sign. */
static double Parity(int f, int dim, SpamGhostParity par, int c)
{
  if (par == SPAM_GHOST_SCALAR) return 1.0;
  if (par == SPAM_GHOST_VECTOR) return (f >> c) & 1 ? -1.0 : 1.0;
  return ((f >> (c / dim)) ^ (f >> (c % dim))) & 1 ? -1.0 : 1.0;
}

/* A field of ncomp values 1000 gid + c gathered into every ghost slot (signs mirrored). */
static PetscErrorCode CheckGather(World *w, const char *name, SpamNeighbours *nl, const Particles *p)
{
  const int  dim = p->box.dim, slots = SpamNeighboursSlots(nl);
  const int  ncomp[3] = {1, dim, dim * dim};
  const SpamGhostParity par[3] = {SPAM_GHOST_SCALAR, SPAM_GHOST_VECTOR, SPAM_GHOST_TENSOR};
  double    *f;
  long       bad = 0, values = 0;
  char       msg[256];

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc1((size_t)slots * dim * dim + 1, &f));
  for (int t = 0; t < 3; t++) {
    const int nc = ncomp[t];
    for (int i = 0; i < slots; i++)
      for (int c = 0; c < nc; c++) f[(size_t)i * nc + c] = i < nl->n ? 1000.0 * p->gid[i] + c : -1.0;
    PetscCall(SpamGhostsGather(&nl->ghosts, dim, nl->n, nc, par[t], f));
    for (int k = 0; k < nl->ghosts.n; k++)
      for (int c = 0; c < nc; c++, values++) bad += f[(size_t)(nl->n + k) * nc + c] != Parity(nl->ghosts.flip[k], dim, par[t], c) * (1000.0 * GhostGid(nl, p, k) + c);
  }
  bad = SumAll(w, bad), values = SumAll(w, values);
  snprintf(msg, sizeof msg, "%s: gather of 1000 gid + component (1, dim, dim^2 values): %ld of %ld ghost values wrong", name, bad, values);
  Check(w, bad == 0 && (values > 0 || SumAll(w, nl->ghosts.n) == 0), msg);
  PetscCall(PetscFree(f));
  PetscFunctionReturn(0);
}

/* The counts of the build, per rank, printed by rank 0. */
static PetscErrorCode PrintCounts(const World *w, const char *name, const SpamNeighbours *nl, const Particles *p)
{
  long mine[6] = {p->n, nl->ghosts.n, nl->ghosts.halo.nghost, nl->ghosts.halo.nitems, (long)nl->npairs, (long)nl->ngpairs}, *all;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc1(6 * (size_t)w->size, &all));
  PetscCallMPI(MPI_Gather(mine, 6, MPI_LONG, all, 6, MPI_LONG, 0, w->comm));
  for (int r = 0; w->rank == 0 && r < w->size; r++) {
    const long *a = all + 6 * r;
    printf("  %s, rank %d: %ld particles, %ld ghosts (%ld remote), %ld items sent, %ld local pairs, %ld ghost pairs\n", name, r, a[0], a[1], a[2], a[3], a[4], a[5]);
  }
  PetscCall(PetscFree(all));
  PetscFunctionReturn(0);
}

/* Moves every particle by the same global draw (each rank applies its own), each
 * component up to a. */
static void MoveAll(Particles *p, double a, uint64_t seed)
{
  const int dim = p->box.dim;
  for (int g = 0; g < p->N; g++)
    for (int d = 0; d < dim; d++) p->X[(size_t)g * dim + d] += a * (2.0 * TestUniform(&seed) - 1.0);
  for (int i = 0; i < p->n; i++)
    for (int d = 0; d < dim; d++) p->x[(size_t)i * dim + d] = p->X[(size_t)p->gid[i] * dim + d];
}

static long MinAll(const World *w, long v)
{
  long m = 0;
  MPI_Allreduce(&v, &m, 1, MPI_LONG, MPI_MIN, w->comm);
  return m;
}

static PetscErrorCode RunCase(World *w, const Case *c)
{
  Particles      p;
  SpamNeighbours nl;
  PetscInt       bad;
  long           builds;
  const int      dim  = c->dim;
  const int      last = w->size - 1;
  char           msg[256];

  PetscFunctionBeginUser;
  PetscCall(MakeParticles(w, c, &p));
  PetscCall(SpamNeighboursCreate(p.n, &p.box, H, SKIN, &nl));
  if (c->ghost_periodic) PetscCall(SpamNeighboursSetPeriodicGhosts(&nl, &p.box, c->periodic));
  if (c->walls[0] || c->walls[1] || c->walls[2]) {
    SpamWalls walls;
    PetscCall(PetscMemzero(&walls, sizeof walls));
    for (int d = 0; d < dim; d++)
      if (c->walls[d]) walls.slip[2 * d] = walls.slip[2 * d + 1] = SPAM_WALL_NOSLIP;
    PetscCall(SpamNeighboursSetWalls(&nl, &walls));
  }
  PetscCall(SpamNeighboursSetComm(&nl, w->comm));
  PetscCall(SpamNeighboursUpdate(&nl, &p.box, p.x, dim, PETSC_TRUE, &bad));
  PetscCall(PrintCounts(w, c->name, &nl, &p));
  PetscCall(CheckPairs(w, c, "at the build", &nl, &p));
  PetscCall(CheckPositions(w, c->name, "at the build", &nl, &p));
  PetscCall(CheckGather(w, c->name, &nl, &p));

  /* below skin/2 per particle: no rebuild anywhere, the exchange moves the ghosts */
  builds = nl.builds;
  MoveAll(&p, 0.95 * 0.5 * SKIN / sqrt((double)dim), 7);
  PetscCall(SpamNeighboursUpdate(&nl, &p.box, p.x, dim, PETSC_FALSE, &bad));
  snprintf(msg, sizeof msg, "%s: moves below skin/2: builds since %ld (min over ranks) to %ld (max), no non-finite flag", c->name, MinAll(w, nl.builds - builds), -MinAll(w, builds - nl.builds));
  Check(w, MinAll(w, nl.builds - builds) == 0 && MinAll(w, builds - nl.builds) == 0 && MinAll(w, bad < 0) == 1, msg);
  PetscCall(CheckPositions(w, c->name, "after moves below skin/2", &nl, &p));
  PetscCall(CheckPairs(w, c, "after moves below skin/2", &nl, &p));

  /* one particle of the last rank moves 1.5 skin (at least one skin from the last build,
   * after the move above): every rank rebuilds */
  builds = nl.builds;
  for (int d = 0; d < dim; d++) {
    p.X[(size_t)p.gid_at[p.start_of[last]] * dim + d] += 1.5 * SKIN / sqrt((double)dim);
    if (w->rank == last) p.x[d] = p.X[(size_t)p.gid[0] * dim + d];
  }
  PetscCall(SpamNeighboursUpdate(&nl, &p.box, p.x, dim, PETSC_FALSE, &bad));
  snprintf(msg, sizeof msg, "%s: one particle of rank %d moved 1.5 skin: every rank rebuilt once (%ld to %ld builds since)", c->name, last, MinAll(w, nl.builds - builds), -MinAll(w, builds - nl.builds));
  Check(w, MinAll(w, nl.builds - builds) == 1 && MinAll(w, builds - nl.builds) == -1, msg);
  PetscCall(CheckPairs(w, c, "after the rebuild", &nl, &p));
  PetscCall(CheckPositions(w, c->name, "after the rebuild", &nl, &p));

  /* a non-finite position on the last rank: every rank returns and says where */
  if (w->rank == last) p.x[dim - 1] = NAN;
  PetscCall(SpamNeighboursUpdate(&nl, &p.box, p.x, dim, PETSC_FALSE, &bad));
  {
    const int here = w->rank == last ? bad == 0 : bad == SPAM_BAD_ON_OTHER_RANK;
    snprintf(msg, sizeof msg, "%s: a NaN position on rank %d: every rank stops, names that rank (bad_rank %d on rank 0), the owner names its particle", c->name, last, nl.bad_rank);
    Check(w, MinAll(w, here && nl.bad_rank == last) == 1, msg);
  }
  PetscCall(SpamNeighboursDestroy(&nl));
  PetscCall(FreeParticles(&p));
  PetscFunctionReturn(0);
}

int main(int argc, char **argv)
{
  const Case cases[] = {
    {"2D periodic, minimum image, slabs", 2, 24, {PETSC_TRUE, PETSC_TRUE, PETSC_FALSE}, PETSC_FALSE, PETSC_FALSE, {PETSC_FALSE, PETSC_FALSE, PETSC_FALSE}},
    {"2D periodic x, open y, ghost images, slabs", 2, 24, {PETSC_TRUE, PETSC_FALSE, PETSC_FALSE}, PETSC_TRUE, PETSC_FALSE, {PETSC_FALSE, PETSC_FALSE, PETSC_FALSE}},
    {"2D periodic, ghost images, random owners", 2, 24, {PETSC_TRUE, PETSC_TRUE, PETSC_FALSE}, PETSC_TRUE, PETSC_TRUE, {PETSC_FALSE, PETSC_FALSE, PETSC_FALSE}},
    {"3D periodic x y, open z, minimum image, slabs", 3, 12, {PETSC_TRUE, PETSC_TRUE, PETSC_FALSE}, PETSC_FALSE, PETSC_FALSE, {PETSC_FALSE, PETSC_FALSE, PETSC_FALSE}},
    {"3D periodic, ghost images, slabs", 3, 12, {PETSC_TRUE, PETSC_TRUE, PETSC_TRUE}, PETSC_TRUE, PETSC_FALSE, {PETSC_FALSE, PETSC_FALSE, PETSC_FALSE}},
    {"3D periodic x y, open z, ghost images, random owners", 3, 12, {PETSC_TRUE, PETSC_TRUE, PETSC_FALSE}, PETSC_TRUE, PETSC_TRUE, {PETSC_FALSE, PETSC_FALSE, PETSC_FALSE}},
    {"2D periodic x, walls y, minimum image, slabs", 2, 24, {PETSC_TRUE, PETSC_FALSE, PETSC_FALSE}, PETSC_FALSE, PETSC_FALSE, {PETSC_FALSE, PETSC_TRUE, PETSC_FALSE}},
    {"2D periodic x, walls y, ghost images, random owners", 2, 24, {PETSC_TRUE, PETSC_FALSE, PETSC_FALSE}, PETSC_TRUE, PETSC_TRUE, {PETSC_FALSE, PETSC_TRUE, PETSC_FALSE}},
    {"2D walls on every face, random owners", 2, 16, {PETSC_FALSE, PETSC_FALSE, PETSC_FALSE}, PETSC_FALSE, PETSC_TRUE, {PETSC_TRUE, PETSC_TRUE, PETSC_FALSE}},
    {"3D walls on every face, random owners", 3, 10, {PETSC_FALSE, PETSC_FALSE, PETSC_FALSE}, PETSC_FALSE, PETSC_TRUE, {PETSC_TRUE, PETSC_TRUE, PETSC_TRUE}},
  };
  World w = {0};

  PetscCall(TestInitialize(&argc, &argv));
  w.comm = PETSC_COMM_WORLD;
  PetscCallMPI(MPI_Comm_rank(w.comm, &w.rank));
  PetscCallMPI(MPI_Comm_size(w.comm, &w.size));
  if (w.rank == 0) printf("%d ranks, h = %g, skin = %g\n", w.size, H, SKIN);
  for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) PetscCall(RunCase(&w, &cases[k]));
  {
    const int code = w.rank == 0 ? TestFinish(&w.count) : (w.count.failed ? 1 : 0);
    PetscCall(TestFinalize());
    return code;
  }
}
