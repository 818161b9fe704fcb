/* The walls' books (wall_books.h). */
#include <spam/wall_books.h>

/* The face a mirror ghost is booked to. An image in one wall belongs to it. A corner image
 * (mirrored in two or three walls) carries every one of their conditions; it is booked to
 * the wall whose condition makes its exchange: an isothermal wall (it sets the image's
 * temperature), else a moving wall (it sets the image's velocity), else the wall of its
 * lowest mirrored direction. So a static adiabatic free-slip wall is booked nothing it
 * did not exchange itself. */
static int FaceOf(const SpamGhosts *g, int k)
{
  int best = -1, rank = -1;

  for (int d = 0; d < 3; d++) {
    const int f = 2 * d + ((g->face[k] >> d) & 1);
    int       r;
    if (!((g->flip[k] >> d) & 1)) continue;
    r = g->walls.isothermal[f] ? 2 : (g->walls.velocity[f][0] != 0.0 || g->walls.velocity[f][1] != 0.0 || g->walls.velocity[f][2] != 0.0) ? 1 : 0;
    if (r > rank) best = f, rank = r;
  }
  return best;
}

/* Sends the books of other ranks' particles' mirror images to their owners, who add them
 * to the sources' rows (collective, where the state carries books). */
static PetscErrorCode RemoteBooks(const SpamGhosts *g, const SpamLayout *l, double *ydot)
{
  const int nb = 2 + l->dim;

  PetscFunctionBeginUser;
  if (!SpamHaloActive(&g->halo)) PetscFunctionReturn(0);
  PetscCall(SpamHaloReverseAdd(&g->halo, nb, g->rbook, ydot + l->wb, (size_t)l->nvar));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamWallBooks(const SpamGhosts *g, const SpamFields *f, const SpamLayout *l, int n, PetscBool energy, SpamWallRates *r, double *ydot)
{
  const int dim = l->dim, nv = l->nvar, nb = 2 + dim;

  PetscFunctionBeginUser;
  for (int s = 0; s < SPAM_FACES; s++) {
    r->work[s] = r->heat[s] = 0.0;
    for (int d = 0; d < 3; d++) r->force[s][d] = 0.0;
  }
  r->energy = energy;
  if (l->wb >= 0)
    for (int i = 0; i < n; i++)
      for (int c = 0; c < nb; c++) ydot[(size_t)i * nv + l->wb + c] = 0.0;
  for (int k = 0; k < g->n; k++) {
    const int     j = n + k, s = FaceOf(g, k);
    const double *a = f->acc + (size_t)j * dim;
    double        work = 0.0, heat = 0.0, *b;
    if (k >= g->nlocal && l->wb >= 0) /* a remote slot's books, zero unless a mirror image */
      for (int c = 0; c < nb; c++) g->rbook[(size_t)(k - g->nlocal) * nb + c] = 0.0;
    if (g->kind[k] != SPAM_GHOST_MIRROR) continue;
    for (int d = 0; d < dim; d++) r->force[s][d] -= f->m[j] * a[d];
    if (energy) {
      for (int d = 0; d < dim; d++) work -= f->m[j] * f->v[(size_t)j * dim + d] * a[d];
      work -= f->m[j] * f->edot[j];
      heat = -f->m[j] * f->qdot[j];
      r->work[s] += work;
      r->heat[s] += heat;
    }
    if (l->wb < 0) continue;
    b = g->src[k] >= 0 ? ydot + (size_t)g->src[k] * nv + l->wb : g->rbook + (size_t)(k - g->nlocal) * nb;
    b[0] += work;
    b[1] += heat;
    for (int d = 0; d < dim; d++) b[2 + d] -= f->m[j] * a[d];
  }
  if (l->wb >= 0) PetscCall(RemoteBooks(g, l, ydot));
  PetscFunctionReturn(0);
}
