/* Ghost slots: selection of periodic images, their positions, gather and fold. */
#include <spam/ghosts.h>

PetscErrorCode SpamGhostsDestroy(SpamGhosts *g)
{
  PetscFunctionBeginUser;
  PetscCall(PetscFree(g->src));
  for (int d = 0; d < 3; d++) PetscCall(PetscFree(g->shift[d]));
  PetscCall(PetscFree(g->flip));
  PetscCall(PetscFree(g->kind));
  g->n = g->cap = 0;
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
  PetscFunctionReturn(0);
}

/* The image offsets (-1, 0, +1 edges per direction) a particle at u needs: along each
 * ghost-periodic direction, +1 when it lies within range of the lower face (its image
 * sits beyond the upper one), -1 near the upper face. Returns how many offsets exist in
 * each direction (1: only 0). */
static void ImageOffsets(const SpamGhosts *g, const SpamBox *box, const double *u, double range, int off[3][2], int no[3])
{
  for (int d = 0; d < 3; d++) {
    no[d]     = 1;
    off[d][0] = 0;
    if (d >= box->dim || !g->periodic[d]) continue;
    if (u[d] < range) off[d][no[d]++] = 1;
    else if (u[d] > box->len[d] - range) off[d][no[d]++] = -1;
  }
}

PetscErrorCode SpamGhostsSelect(SpamGhosts *g, const SpamBox *box, int n, double *const u[3], double range)
{
  PetscFunctionBeginUser;
  g->n = 0;
  for (int i = 0; i < n; i++) {
    const double ui[3] = {u[0][i], box->dim > 1 ? u[1][i] : 0.0, box->dim > 2 ? u[2][i] : 0.0};
    int          off[3][2], no[3];
    ImageOffsets(g, box, ui, range, off, no);
    if (no[0] * no[1] * no[2] == 1) continue;
    PetscCall(Grow(g, g->n + 8));
    for (int a = 0; a < no[0]; a++)
      for (int b = 0; b < no[1]; b++)
        for (int c = 0; c < no[2]; c++) {
          const int o[3] = {off[0][a], off[1][b], off[2][c]};
          if (!o[0] && !o[1] && !o[2]) continue; /* the particle itself */
          g->src[g->n]  = i;
          g->flip[g->n] = 0;
          g->kind[g->n] = SPAM_GHOST_PERIODIC;
          for (int d = 0; d < 3; d++) g->shift[d][g->n] = d < box->dim ? o[d] * box->len[d] : 0.0;
          g->n++;
        }
  }
  PetscFunctionReturn(0);
}

void SpamGhostsPositions(const SpamGhosts *g, int dim, int n, double *const u[3])
{
  for (int d = 0; d < dim; d++)
    for (int k = 0; k < g->n; k++) {
      const double s = u[d][g->src[k]];
      u[d][n + k]    = ((g->flip[k] >> d) & 1 ? -s : s) + g->shift[d][k];
    }
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

void SpamGhostsGather(const SpamGhosts *g, int dim, int n, int ncomp, SpamGhostParity parity, double *field)
{
  for (int k = 0; k < g->n; k++) {
    const double *s = field + (size_t)g->src[k] * ncomp;
    double       *t = field + (size_t)(n + k) * ncomp;
    for (int c = 0; c < ncomp; c++) t[c] = Sign(g, k, dim, ncomp, parity, c) * s[c];
  }
}

void SpamGhostsFold(const SpamGhosts *g, int dim, int n, int ncomp, SpamGhostParity parity, double *field)
{
  for (int k = 0; k < g->n; k++) {
    double *t = field + (size_t)(n + k) * ncomp;
    if (g->kind[k] != SPAM_GHOST_PERIODIC) continue;
    double *s = field + (size_t)g->src[k] * ncomp;
    for (int c = 0; c < ncomp; c++) {
      s[c] += Sign(g, k, dim, ncomp, parity, c) * t[c];
      t[c] = 0.0;
    }
  }
}
