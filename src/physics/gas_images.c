/* The gas beyond a mirror wall: the images' pressure and density at their place
 * (gas_images.h). */
#include <spam/physics.h>
#include <spam/gas_images.h>

PetscBool SpamGasImagesOfPlace(const SpamSim *sim)
{
  const SpamSolidParams *p = &sim->model.solid;
  return (PetscBool)(sim->pair.nl.ghosts.mirror && p->material == SPAM_MATERIAL_GAS && p->scheme == SPAM_GAS_FLOW);
}

/* The source's position along d of mirror ghost k: read from it on this rank, from the
 * ghost's own position (the image undone) for another rank's particle. */
static double SourcePosition(const SpamGhosts *gh, double *const u[3], int n, int k, int d)
{
  const double x = u[d][n + k];
  if (gh->src[k] >= 0) return u[d][gh->src[k]];
  return (gh->flip[k] >> d) & 1 ? gh->shift[d][k] - x : x - gh->shift[d][k]; /* another rank's: undo the image */
}

/* g.(x_g - x_i) of mirror ghost k, and its place xg and its source's xs (absolute). */
static double Descent(const SpamSim *sim, int k, double xg[3], double xs[3])
{
  const SpamGhosts *gh  = &sim->pair.nl.ghosts;
  const int         dim = sim->model.dim, n = (int)sim->p.n;
  double            dphi = 0.0;

  for (int d = 0; d < 3; d++) xg[d] = xs[d] = 0.0;
  for (int d = 0; d < dim; d++) {
    xg[d] = sim->pair.nl.u[d][n + k] + sim->geo.box.lo[d];
    xs[d] = SourcePosition(gh, sim->pair.nl.u, n, k, d) + sim->geo.box.lo[d];
    dphi += sim->model.gravity[d] * (xg[d] - xs[d]);
  }
  return dphi;
}

/* rho_g / rho_i = (T_i + g.(x_g - x_i)) / T_g of mirror ghost k, bounded to [1/2, 2]
 * (continuous in T_g, also where the rule gives T_g <= 0); 1 outside the flow scheme. */
double SpamGasImagesPlaceRatio(const SpamSim *sim, int k)
{
  const SpamFields *f = &sim->pair.f;
  const int         n = (int)sim->p.n;
  double            xg[3], xs[3];

  if (!SpamGasImagesOfPlace(sim)) return 1.0;
  const double Tg = f->T[n + k], num = (sim->model.solid.gamma - 1.0) * f->e[n + k] + Descent(sim, k, xg, xs);
  if (!(Tg > 0.5 * num)) return 2.0;
  if (!(Tg < 2.0 * num)) return 0.5;
  return num / Tg;
}

PetscErrorCode SpamGasImagesTemperatures(SpamSim *sim, const double *y)
{
  const SpamLayout *l   = &sim->model.layout;
  SpamFields       *f   = &sim->pair.f;
  const int         n   = (int)sim->p.n;

  PetscFunctionBeginUser;
  for (int i = 0; i < n; i++) {
    f->e[i] = y[(size_t)i * l->nvar + l->e];
    f->T[i] = (sim->model.solid.gamma - 1.0) * f->e[i];
  }
  PetscCall(SpamGhostsGather(&sim->pair.nl.ghosts, l->dim, n, 1, SPAM_GHOST_SCALAR, f->e));
  PetscCall(SpamGhostsGatherWall(&sim->pair.nl.ghosts, l->dim, n, SPAM_WALL_FIELD_TEMPERATURE, f->T));
  PetscFunctionReturn(0);
}

void SpamGasImagesMasses(SpamSim *sim)
{
  const SpamGhosts *gh = &sim->pair.nl.ghosts;
  SpamFields       *f  = &sim->pair.f;
  const int         n  = (int)sim->p.n;

  for (int k = 0; k < gh->n; k++) {
    if (gh->kind[k] != SPAM_GHOST_MIRROR) continue;
    f->m[n + k] *= SpamGasImagesPlaceRatio(sim, k);
    if (f->minv) f->minv[n + k] = 1.0 / f->m[n + k];
  }
  sim->pair.ghost_mass_build = -1;
}

void SpamGasImagesDensities(SpamSim *sim)
{
  const SpamGhosts *gh = &sim->pair.nl.ghosts;
  const int         n  = (int)sim->p.n;

  for (int k = 0; k < gh->n; k++)
    if (gh->kind[k] == SPAM_GHOST_MIRROR) sim->pair.f.rho[n + k] *= SpamGasImagesPlaceRatio(sim, k);
}

/* sigma_g/rho_g^2 from the gathered sigma_i/rho_i^2: sigma_g = sigma_i - rho_i g.(x_g - x_i)
 * + B(x_g) - B(x_i) on the diagonal (without the first term the image's pressure equals
 * its source's and the bottom layer lacks the push that holds up the column), over
 * rho_g^2 = (r rho_i)^2. A solid's images keep their stress. */
void SpamGasImagesStresses(SpamSim *sim, const SpamBackground *bg)
{
  const SpamGhosts *gh  = &sim->pair.nl.ghosts;
  SpamFields       *f   = &sim->pair.f;
  const int         dim = f->dim, n = (int)sim->p.n;

  for (int k = 0; k < gh->n; k++) {
    double xg[3], xs[3];
    if (gh->kind[k] != SPAM_GHOST_MIRROR) continue;
    const double dphi = Descent(sim, k, xg, xs), r = SpamGasImagesPlaceRatio(sim, k), rho = f->rho[n + k] / r;
    const double dB = SpamBackgroundAt(bg, dim, xg) - SpamBackgroundAt(bg, dim, xs);
    double      *q  = f->qs + (size_t)(n + k) * dim * dim;
    for (int a = 0; a < dim; a++) q[a * dim + a] += -dphi / rho + dB / (rho * rho);
    if (r != 1.0)
      for (int c = 0; c < dim * dim; c++) q[c] /= r * r;
  }
}
