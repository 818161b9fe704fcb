/* What a snapshot writes for one particle, the same in HDF5 and CSV: the position, the
 * density the model uses (the carried one under continuity, else the summed one), the
 * energy per unit mass and the stress when the state holds them. */
#include <spam/output.h>

/* The state's coordinate where it lies in the box, so that a file read back (the file
 * scene) holds bitwise the state; else wrapped into the box in a periodic direction (an
 * open direction keeps it). lo + SpamBoxLocal alone would round x when lo is not 0. */
double SpamSnapshotPosition(const SpamBox *b, int d, double x)
{
  if (!b->periodic[d] || (x >= b->lo[d] && x < b->lo[d] + b->len[d])) return x;
  return b->lo[d] + SpamBoxLocal(b, d, x);
}

double SpamSnapshotDensity(const SpamSim *sim, const double *y, PetscInt i)
{
  const SpamLayout *l = &sim->model.layout;
  return l->rho >= 0 ? y[(size_t)i * l->nvar + l->rho] : sim->pair.f.rho[i];
}

/* ParaView's Tensor6 order: xx, xy, xz, yy, yz, zz. The state holds the upper triangle
 * row by row (2D: xx, xy, yy; 3D: xx, xy, xz, yy, yz, zz). */
void SpamSnapshotStress6(const SpamLayout *l, const double *y, PetscInt i, double t6[6])
{
  const double *s = y + (size_t)i * l->nvar + l->s;

  for (int k = 0; k < 6; k++) t6[k] = 0.0;
  if (l->s < 0) return;
  if (l->dim == 2) {
    t6[0] = s[0];
    t6[1] = s[1];
    t6[3] = s[2];
  } else if (l->dim == 3)
    for (int k = 0; k < 6; k++) t6[k] = s[k];
  else t6[0] = s[0];
}
