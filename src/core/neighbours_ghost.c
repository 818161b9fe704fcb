/* The ghost part of the neighbour list: ghost slots after the local particles in u, and
 * each local particle's ghost neighbours as a second CSR list. The local rows are the
 * half list of neighbours.c; the ghost rows are built over every adjacent cell (a ghost
 * has no row of its own that could hold the pair), and a periodic image's pair is kept
 * only in the row of the lower of its two particles, so every physical pair is listed
 * once and the fold of ghosts.h keeps the momentum exact. A remote ghost's pair is kept
 * in the local particle's row: its owner lists the same pair in its own row (newton off
 * across ranks). */
#include <spam/neighbours.h>
#include <limits.h>

PetscErrorCode SpamNeighboursSetPeriodicGhosts(SpamNeighbours *nl, const SpamBox *box, const PetscBool per[3])
{
  PetscFunctionBeginUser;
  PetscCheck(nl->builds == 0, PETSC_COMM_SELF, PETSC_ERR_ORDER, "set the ghost directions before the first build");
  nl->lbox = *box;
  for (int d = 0; d < box->dim; d++) {
    nl->ghosts.periodic[d] = (PetscBool)(per[d] && box->periodic[d]);
    if (nl->ghosts.periodic[d]) nl->lbox.periodic[d] = PETSC_FALSE;
  }
  nl->im = SpamBoxImage(&nl->lbox);
  PetscFunctionReturn(0);
}

PetscErrorCode SpamNeighboursSetComm(SpamNeighbours *nl, MPI_Comm comm)
{
  PetscFunctionBeginUser;
  PetscCheck(nl->builds == 0, PETSC_COMM_SELF, PETSC_ERR_ORDER, "set the communicator before the first build");
  PetscCall(SpamHaloSetComm(&nl->ghosts.halo, comm));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamNeighboursSetWalls(SpamNeighbours *nl, const SpamWalls *walls)
{
  PetscFunctionBeginUser;
  PetscCheck(nl->builds == 0, PETSC_COMM_SELF, PETSC_ERR_ORDER, "set the walls before the first build");
  nl->ghosts.walls  = *walls;
  nl->ghosts.mirror = SpamWallsAny(walls, nl->dim);
  PetscFunctionReturn(0);
}

/* Room for the ghost slots in u (the local part is kept). */
static PetscErrorCode GrowSlots(SpamNeighbours *nl)
{
  const int need = nl->n + nl->ghosts.n + 1;

  PetscFunctionBeginUser;
  if (need <= nl->ucap) PetscFunctionReturn(0);
  nl->ucap = need + need / 8 + 16;
  for (int d = 0; d < nl->dim; d++) PetscCall(PetscRealloc((size_t)nl->ucap * sizeof(double), &nl->u[d]));
  PetscFunctionReturn(0);
}

/* The cells whose particles may pair with a ghost: those adjacent to a cell holding one
 * (adjacency is symmetric). The ghost rows skip the others: on several ranks most of a
 * rank's particles are far from its halo, and 27 empty cells per particle took 9 % of a
 * 3D expansion's time on 2 ranks (perf). */
static PetscErrorCode MarkNearGhosts(SpamNeighbours *nl)
{
  int adj[27];

  PetscFunctionBeginUser;
  if (!nl->gcell_near) PetscCall(PetscMalloc1(nl->ncells, &nl->gcell_near));
  for (int c = 0; c < nl->ncells; c++) nl->gcell_near[c] = 0;
  for (int c = 0; c < nl->ncells; c++) {
    if (nl->gcell_start[c + 1] == nl->gcell_start[c]) continue;
    const int na = SpamNeighboursAdjacentCells(nl, &nl->lbox, c, adj);
    for (int a = 0; a < na; a++) nl->gcell_near[adj[a]] = 1;
  }
  PetscFunctionReturn(0);
}

/* Counting sort of the ghosts by the cell they fall in (clamped into the edge cells:
 * a ghost beyond a face is within the list range of that face's cells only). */
static PetscErrorCode BinGhosts(SpamNeighbours *nl)
{
  const int ng = nl->ghosts.n;

  PetscFunctionBeginUser;
  if (nl->gcell_cap < ng + 1 || !nl->gcell_start) {
    PetscCall(PetscFree2(nl->gcell_start, nl->gcell_list));
    nl->gcell_cap = ng + ng / 2 + 16;
    PetscCall(PetscMalloc2(nl->ncells + 1, &nl->gcell_start, nl->gcell_cap, &nl->gcell_list));
  }
  for (int c = 0; c <= nl->ncells; c++) nl->gcell_start[c] = 0;
  for (int k = 0; k < ng; k++) {
    const double u[3] = {nl->u[0][nl->n + k], nl->dim > 1 ? nl->u[1][nl->n + k] : 0.0, nl->dim > 2 ? nl->u[2][nl->n + k] : 0.0};
    nl->gcell_start[SpamNeighboursCellOf(nl, &nl->lbox, u) + 1]++;
  }
  for (int c = 0; c < nl->ncells; c++) nl->gcell_start[c + 1] += nl->gcell_start[c];
  for (int k = 0; k < ng; k++) {
    const double u[3] = {nl->u[0][nl->n + k], nl->dim > 1 ? nl->u[1][nl->n + k] : 0.0, nl->dim > 2 ? nl->u[2][nl->n + k] : 0.0};
    nl->gcell_list[nl->gcell_start[SpamNeighboursCellOf(nl, &nl->lbox, u)]++] = k;
  }
  for (int c = nl->ncells; c > 0; c--) nl->gcell_start[c] = nl->gcell_start[c - 1];
  nl->gcell_start[0] = 0;
  PetscCall(MarkNearGhosts(nl));
  PetscFunctionReturn(0);
}

/* How far beyond each wall the farthest particle of any rank stands (collective on several
 * ranks): a particle at -a beyond a wall pairs with the image of one at u when u + a < rc,
 * so the images of particles up to rc + a from the wall are needed. */
static PetscErrorCode WallDepths(SpamGhosts *g, const SpamBox *box, int n, double *const u[3])
{
  PetscFunctionBeginUser;
  for (int f = 0; f < SPAM_FACES; f++) g->depth[f] = 0.0;
  for (int d = 0; d < box->dim; d++)
    for (int i = 0; i < n; i++) {
      g->depth[2 * d]     = PetscMax(g->depth[2 * d], -u[d][i]);
      g->depth[2 * d + 1] = PetscMax(g->depth[2 * d + 1], u[d][i] - box->len[d]);
    }
  if (SpamHaloActive(&g->halo)) PetscCallMPI(MPIU_Allreduce(MPI_IN_PLACE, g->depth, SPAM_FACES, MPI_DOUBLE, MPI_MAX, g->halo.comm));
  PetscFunctionReturn(0);
}

/* Whether ghost k pairs with local i in i's row: a periodic image only when its source
 * is above i (the pair's other copy, in the source's row, is skipped); a mirror or a
 * remote ghost always. */
static int KeepGhostPair(const SpamGhosts *g, int i, int k)
{
  return g->kind[k] != SPAM_GHOST_PERIODIC || g->src[k] > i;
}

static PetscErrorCode AppendGhost(SpamNeighbours *nl, int j)
{
  PetscFunctionBeginUser;
  if (nl->ngpairs == nl->gcap) {
    PetscCheck(nl->gcap < (size_t)INT_MAX / 2, PETSC_COMM_SELF, PETSC_ERR_MEM, "too many ghost pairs");
    nl->gcap = nl->gcap + nl->gcap / 2 + 64;
    PetscCall(PetscRealloc(nl->gcap * sizeof(int), &nl->gnbr));
  }
  nl->gnbr[nl->ngpairs++] = j;
  PetscFunctionReturn(0);
}

static PetscErrorCode GhostRows(SpamNeighbours *nl)
{
  const SpamGhosts *g   = &nl->ghosts;
  const int         dim = nl->dim;
  int               adj[27];

  PetscFunctionBeginUser;
  nl->ngpairs = 0;
  if (!g->n) PetscFunctionReturn(0); /* no rows: gstart holds zeros (SpamNeighboursBuildGhosts) */
  nl->gstart[0] = 0;
  for (int i = 0; i < nl->n; i++) {
    const int na = g->n && nl->gcell_near[nl->cell_of[i]] ? SpamNeighboursAdjacentCells(nl, &nl->lbox, nl->cell_of[i], adj) : 0;
    for (int a = 0; a < na; a++)
      for (int q = nl->gcell_start[adj[a]]; q < nl->gcell_start[adj[a] + 1]; q++) {
        const int k = nl->gcell_list[q], j = nl->n + k;
        double    r2 = 0.0;
        if (!KeepGhostPair(g, i, k)) continue;
        for (int d = 0; d < dim; d++) {
          const double dx = SpamImageDelta(&nl->im, d, nl->u[d][i] - nl->u[d][j]);
          r2 += dx * dx;
        }
        if (r2 < nl->rc2) PetscCall(AppendGhost(nl, j));
      }
    nl->gstart[i + 1] = (int)nl->ngpairs;
  }
  PetscFunctionReturn(0);
}

PetscErrorCode SpamNeighboursBuildGhosts(SpamNeighbours *nl, const SpamBox *box)
{
  SpamGhosts     *g     = &nl->ghosts;
  const PetscBool local = (PetscBool)(g->periodic[0] || g->periodic[1] || g->periodic[2] || g->mirror);

  PetscFunctionBeginUser;
  /* gstart is zeros until a build has ghost rows (a periodic box of many cells has none:
   * its pairs across a face are minimum images), and those zeros take no memory
   * (SpamNeighboursCreate): written again only after rows. */
  if (nl->ngpairs) for (int i = 0; i <= nl->n; i++) nl->gstart[i] = 0;
  nl->ngpairs = 0;
  if (!local && !SpamHaloActive(&g->halo)) PetscFunctionReturn(0);
  /* At the build every particle is inside the box, so only an image within the list
   * range rc of a face can be within rc of a local particle. */
  g->n = 0;
  if (g->mirror) PetscCall(WallDepths(g, box, nl->n, nl->u));
  if (local) PetscCall(SpamGhostsSelect(g, box, nl->n, nl->u, sqrt(nl->rc2)));
  PetscCall(SpamGhostsSelectRemote(g, box, nl->n, nl->u, sqrt(nl->rc2)));
  PetscCall(GrowSlots(nl));
  PetscCall(SpamGhostsPositions(g, nl->dim, nl->n, nl->u));
  nl->placements++;
  PetscCall(BinGhosts(nl));
  PetscCall(GhostRows(nl));
  PetscCall(SpamNeighboursPadList(&nl->gnbr, &nl->gcap, nl->ngpairs));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamNeighboursMoveGhosts(SpamNeighbours *nl)
{
  PetscFunctionBeginUser;
  if (!nl->ghosts.n && !SpamHaloActive(&nl->ghosts.halo)) PetscFunctionReturn(0);
  PetscCall(SpamGhostsPositions(&nl->ghosts, nl->dim, nl->n, nl->u));
  nl->placements++;
  PetscFunctionReturn(0);
}
