/* Ghost slots: selection of periodic and mirror images, their positions, gather (with
 * the walls' conditions) and fold. */
#include <spam/ghosts.h>

PetscErrorCode SpamGhostsDestroy(SpamGhosts *g)
{
  PetscFunctionBeginUser;
  PetscCall(PetscFree(g->src));
  for (int d = 0; d < 3; d++) PetscCall(PetscFree(g->shift[d]));
  PetscCall(PetscFree(g->flip));
  PetscCall(PetscFree(g->kind));
  PetscCall(PetscFree(g->face));
  PetscCall(PetscFree(g->rbook));
  PetscCall(SpamHaloDestroy(&g->halo));
  g->n = g->cap = g->nlocal = g->bcap = 0;
  PetscFunctionReturn(0);
}

static PetscErrorCode Grow(SpamGhosts *g, int need)
{
  PetscFunctionBeginUser;
  if (need <= g->cap) PetscFunctionReturn(0);
  g->cap = need + need / 2 + 16;
  PetscCall(PetscRealloc((size_t)g->cap * sizeof(int), &g->src));
  for (int d = 0; d < 3; d++) PetscCall(PetscRealloc((size_t)g->cap * sizeof(double), &g->shift[d]));
  PetscCall(PetscRealloc((size_t)g->cap, &g->flip));
  PetscCall(PetscRealloc((size_t)g->cap, &g->kind));
  PetscCall(PetscRealloc((size_t)g->cap, &g->face));
  PetscFunctionReturn(0);
}

/* The images of a particle along one direction: itself, a periodic image one edge away
 * (shift +-L), or its mirror in the lower (x -> -x) or upper (x -> 2L - x) wall. */
typedef enum { IMG_SELF, IMG_PERIODIC_UP, IMG_PERIODIC_DOWN, IMG_MIRROR_LO, IMG_MIRROR_HI } Image;

/* The images a particle at box-local u needs along direction d: a periodic image when
 * it lies within range of a face of a ghost-periodic direction (beyond the other face),
 * a mirror image in each wall it lies within range of. Returns how many (1: only itself). */
static int ImagesAlong(const SpamGhosts *g, const SpamBox *box, int d, double u, double range, Image img[3])
{
  int k = 0;
  img[k++] = IMG_SELF;
  if (d >= box->dim) return k;
  if (g->periodic[d]) {
    if (u < range) img[k++] = IMG_PERIODIC_UP;
    if (u > box->len[d] - range) img[k++] = IMG_PERIODIC_DOWN; /* both, in an edge below 2 range */
    return k;
  }
  if (SpamWallOn(&g->walls, 2 * d) && u < range + g->depth[2 * d]) img[k++] = IMG_MIRROR_LO;
  if (SpamWallOn(&g->walls, 2 * d + 1) && u > box->len[d] - range - g->depth[2 * d + 1]) img[k++] = IMG_MIRROR_HI;
  return k;
}

/* Appends the ghost of particle i made of one image per direction. */
static void AddGhost(SpamGhosts *g, const SpamBox *box, int i, const Image o[3])
{
  const int k = g->n++;
  g->src[k]   = i;
  g->flip[k] = g->face[k] = 0;
  for (int d = 0; d < 3; d++) {
    const double L = d < box->dim ? box->len[d] : 0.0;
    g->shift[d][k] = o[d] == IMG_PERIODIC_UP ? L : o[d] == IMG_PERIODIC_DOWN ? -L : o[d] == IMG_MIRROR_HI ? 2.0 * L : 0.0;
    if (o[d] == IMG_MIRROR_LO || o[d] == IMG_MIRROR_HI) g->flip[k] |= (unsigned char)(1u << d);
    if (o[d] == IMG_MIRROR_HI) g->face[k] |= (unsigned char)(1u << d);
  }
  /* A ghost mirrored in any wall stands for the boundary, not for its source. */
  g->kind[k] = g->flip[k] ? SPAM_GHOST_MIRROR : SPAM_GHOST_PERIODIC;
}

PetscErrorCode SpamGhostsSelect(SpamGhosts *g, const SpamBox *box, int n, double *const u[3], double range)
{
  PetscFunctionBeginUser;
  g->n = 0;
  for (int i = 0; i < n; i++) {
    Image img[3][3];
    int   no[3];
    for (int d = 0; d < 3; d++) no[d] = ImagesAlong(g, box, d, d < box->dim ? u[d][i] : 0.0, range, img[d]);
    if (no[0] * no[1] * no[2] == 1) continue;
    PetscCall(Grow(g, g->n + 27));
    for (int a = 0; a < no[0]; a++)
      for (int b = 0; b < no[1]; b++)
        for (int c = 0; c < no[2]; c++) {
          const Image o[3] = {img[0][a], img[1][b], img[2][c]};
          if (o[0] == IMG_SELF && o[1] == IMG_SELF && o[2] == IMG_SELF) continue; /* the particle itself */
          AddGhost(g, box, i, o);
        }
  }
  g->nlocal = g->n;
  PetscFunctionReturn(0);
}

/* The faces with a mirror wall as bits (halo.h). */
static unsigned WallBits(const SpamWalls *w)
{
  unsigned bits = 0;
  for (int f = 0; f < SPAM_FACES; f++)
    if (SpamWallOn(w, f)) bits |= 1u << f;
  return bits;
}

/* Remote slot k from the halo's image codes s: x_g = flip x_owner + shift as for a local
 * ghost; mirrored in some wall, it stands for the boundary (SPAM_GHOST_MIRROR), otherwise
 * for the owner's particle. */
static void DescribeRemote(SpamGhosts *g, int k, const signed char s[3], const double len[3])
{
  g->src[k]  = -1;
  g->flip[k] = g->face[k] = 0;
  for (int d = 0; d < 3; d++) {
    const PetscBool mirror = (PetscBool)(s[d] == SPAM_HALO_MIRROR_LO || s[d] == SPAM_HALO_MIRROR_HI);
    g->shift[d][k]         = mirror ? (s[d] == SPAM_HALO_MIRROR_HI ? 2.0 * len[d] : 0.0) : s[d] * len[d];
    if (mirror) g->flip[k] |= (unsigned char)(1u << d);
    if (s[d] == SPAM_HALO_MIRROR_HI) g->face[k] |= (unsigned char)(1u << d);
  }
  g->kind[k] = g->flip[k] ? SPAM_GHOST_MIRROR : SPAM_GHOST_REMOTE;
}

PetscErrorCode SpamGhostsSelectRemote(SpamGhosts *g, const SpamBox *box, int n, double *const u[3], double range)
{
  SpamHalo *h = &g->halo;

  PetscFunctionBeginUser;
  g->nlocal = g->n;
  if (!h->active) PetscFunctionReturn(0);
  h->walls = WallBits(&g->walls);
  for (int f = 0; f < SPAM_FACES; f++) h->depth[f] = g->depth[f];
  PetscCall(SpamHaloSelect(h, box, g->periodic, n, u, range));
  PetscCall(Grow(g, g->nlocal + h->nghost));
  for (int q = 0; q < h->nghost; q++) DescribeRemote(g, g->nlocal + q, h->ghost_shift[q], h->len);
  g->n = g->nlocal + h->nghost;
  if (g->mirror && h->nghost > g->bcap) { /* the walls' books of remote images (wall_books.c) */
    g->bcap = h->nghost + h->nghost / 2 + 16;
    PetscCall(PetscFree(g->rbook));
    PetscCall(PetscMalloc1((size_t)g->bcap * (2 + 3), &g->rbook));
  }
  PetscFunctionReturn(0);
}

PetscErrorCode SpamGhostsPositions(const SpamGhosts *g, int dim, int n, double *const u[3])
{
  double *remote[3] = {NULL, NULL, NULL};

  PetscFunctionBeginUser;
  for (int d = 0; d < dim; d++) remote[d] = u[d] + n + g->nlocal;
  for (int d = 0; d < dim; d++)
    for (int k = 0; k < g->nlocal; k++) {
      const double s = u[d][g->src[k]];
      u[d][n + k]    = ((g->flip[k] >> d) & 1 ? -s : s) + g->shift[d][k];
    }
  PetscCall(SpamHaloForwardPositions(&g->halo, dim, u, remote));
  PetscFunctionReturn(0);
}

/* Sign of component c of a field under ghost k's mirror. */
static double Sign(const SpamGhosts *g, int k, int dim, int ncomp, SpamGhostParity parity, int c)
{
  const unsigned f = g->flip[k];
  if (!f || parity == SPAM_GHOST_SCALAR) return 1.0;
  if (parity == SPAM_GHOST_VECTOR) return (f >> (c % dim)) & 1 ? -1.0 : 1.0;
  { /* D x D tensor: component (a, b) flips when exactly one of a, b is mirrored */
    const int a = (c / dim) % dim, b = c % dim;
    (void)ncomp;
    return (((f >> a) ^ (f >> b)) & 1) ? -1.0 : 1.0;
  }
}

PetscErrorCode SpamGhostsGather(const SpamGhosts *g, int dim, int n, int ncomp, SpamGhostParity parity, double *field)
{
  PetscFunctionBeginUser;
  for (int k = 0; k < g->nlocal; k++) {
    const double *s = field + (size_t)g->src[k] * ncomp;
    double       *t = field + (size_t)(n + k) * ncomp;
    for (int c = 0; c < ncomp; c++) t[c] = Sign(g, k, dim, ncomp, parity, c) * s[c];
  }
  PetscCall(SpamHaloForward(&g->halo, ncomp, field, field + (size_t)(n + g->nlocal) * ncomp));
  if (g->mirror && parity != SPAM_GHOST_SCALAR) /* other ranks' mirror images arrive as their sources */
    for (int k = g->nlocal; k < g->n; k++) {
      double *t = field + (size_t)(n + k) * ncomp;
      if (!g->flip[k]) continue;
      for (int c = 0; c < ncomp; c++) t[c] *= Sign(g, k, dim, ncomp, parity, c);
    }
  PetscFunctionReturn(0);
}

void SpamGhostsFold(const SpamGhosts *g, int dim, int n, int ncomp, SpamGhostParity parity, double *field)
{
  for (int k = 0; k < g->nlocal; k++) {
    double *t = field + (size_t)(n + k) * ncomp;
    if (g->kind[k] != SPAM_GHOST_PERIODIC) continue;
    double *s = field + (size_t)g->src[k] * ncomp;
    for (int c = 0; c < ncomp; c++) {
      s[c] += Sign(g, k, dim, ncomp, parity, c) * t[c];
      t[c] = 0.0;
    }
  }
}

/* One wall's condition on the values t[] of a ghost mirrored in face f (normal d). */
static void WallRule(const SpamWalls *w, int f, int dim, SpamWallField what, double *t)
{
  const int d = f / 2;
  switch (what) {
  case SPAM_WALL_FIELD_VELOCITY:
    if (w->slip[f] == SPAM_WALL_NOSLIP)
      for (int c = 0; c < dim; c++) t[c] = 2.0 * w->velocity[f][c] - t[c];
    else t[d] = -t[d];
    break;
  case SPAM_WALL_FIELD_DRIFT:
    if (w->slip[f] == SPAM_WALL_NOSLIP)
      for (int c = 0; c < dim; c++) t[c] = -t[c];
    else t[d] = -t[d];
    break;
  case SPAM_WALL_FIELD_TEMPERATURE:
    t[0] = SpamWallGhostTemperature(w, f, t[0]);
    break;
  case SPAM_WALL_FIELD_HEAT_FLUX:
    for (int c = 0; c < dim; c++)
      if ((c == d) != (PetscBool)w->isothermal[f]) t[c] = -t[c];
    break;
  case SPAM_WALL_FIELD_STRESS:
    if (w->slip[f] == SPAM_WALL_NOSLIP) break;
    for (int a = 0; a < dim; a++)
      for (int b = 0; b < dim; b++)
        if ((a == d) != (b == d)) t[a * dim + b] = -t[a * dim + b];
    break;
  }
}

/* Every wall that mirrors ghost k, in turn: a corner ghost is mirrored twice. */
static void WallRules(const SpamGhosts *g, int k, int dim, SpamWallField what, double *t)
{
  for (int d = 0; d < dim; d++)
    if ((g->flip[k] >> d) & 1) WallRule(&g->walls, 2 * d + ((g->face[k] >> d) & 1), dim, what, t);
}

PetscErrorCode SpamGhostsGatherWall(const SpamGhosts *g, int dim, int n, SpamWallField what, double *field)
{
  const int ncomp = what == SPAM_WALL_FIELD_TEMPERATURE ? 1 : what == SPAM_WALL_FIELD_STRESS ? dim * dim : dim;

  PetscFunctionBeginUser;
  for (int k = 0; k < g->nlocal; k++) {
    const double *s = field + (size_t)g->src[k] * ncomp;
    double       *t = field + (size_t)(n + k) * ncomp;
    for (int c = 0; c < ncomp; c++) t[c] = s[c];
    WallRules(g, k, dim, what, t);
  }
  PetscCall(SpamHaloForward(&g->halo, ncomp, field, field + (size_t)(n + g->nlocal) * ncomp));
  if (g->mirror) /* other ranks' mirror images arrive as their sources */
    for (int k = g->nlocal; k < g->n; k++)
      if (g->flip[k]) WallRules(g, k, dim, what, field + (size_t)(n + k) * ncomp);
  PetscFunctionReturn(0);
}
