/* Particles as CSV: file-scene input format, and the snapshots the chart scripts read. */
#include <spam/output.h>

PetscErrorCode SpamParticlesCsvWrite(const char *path, const SpamSim *sim, const double *y)
{
  static const char *ax[3] = {"x", "y", "z"};
  const SpamLayout  *l     = &sim->model.layout;
  const int          dim   = sim->model.dim;
  SpamFile           f;

  PetscFunctionBeginUser;
  PetscCall(SpamFileBegin(path, &f));
  for (int d = 0; d < dim; d++) SpamFilePrintf(&f, "%s%s", d ? "," : "", ax[d]);
  for (int d = 0; d < dim; d++) SpamFilePrintf(&f, ",v%s", ax[d]);
  SpamFilePrintf(&f, ",m\n");
  for (PetscInt r = 0; r < sim->n; r++) {
    const double *p = y + (size_t)SpamSimAtRow(sim, r) * l->nvar;
    for (int d = 0; d < dim; d++) SpamFilePrintf(&f, "%s%.17g", d ? "," : "", p[l->x + d]);
    for (int d = 0; d < dim; d++) SpamFilePrintf(&f, ",%.17g", p[l->v + d]);
    SpamFilePrintf(&f, ",%.17g\n", sim->model.mass);
  }
  PetscCall(SpamFileCommit(&f));
  PetscFunctionReturn(0);
}

/* Snapshot for charts: positions wrapped into the box, padded to three components. */
PetscErrorCode SpamSnapshotCsvWrite(const char *path, const SpamSim *sim, const double *y, double t)
{
  const SpamLayout *l   = &sim->model.layout;
  const int         dim = sim->model.dim;
  SpamFile          f;

  PetscFunctionBeginUser;
  PetscCall(SpamFileBegin(path, &f));
  SpamFilePrintf(&f, "# t=%.10g\nx,y,z,vx,vy,vz,rho%s%s\n", t, l->e >= 0 ? ",e" : "", l->s >= 0 ? ",sxx,sxy,sxz,syy,syz,szz" : "");
  for (PetscInt r = 0; r < sim->n; r++) {
    const PetscInt i = SpamSimAtRow(sim, r);
    const double  *p = y + (size_t)i * l->nvar;
    double         x[3] = {0, 0, 0}, v[3] = {0, 0, 0};
    for (int d = 0; d < dim; d++) {
      x[d] = sim->box.lo[d] + SpamBoxLocal(&sim->box, d, p[l->x + d]);
      v[d] = p[l->v + d];
    }
    /* Full precision: studies measure integrator errors from these snapshots. */
    SpamFilePrintf(&f, "%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g", x[0], x[1], x[2], v[0], v[1], v[2], SpamSnapshotDensity(sim, y, i));
    if (l->e >= 0) SpamFilePrintf(&f, ",%.17g", p[l->e]);
    if (l->s >= 0) {
      double t6[6];
      SpamSnapshotStress6(sim, y, i, t6);
      for (int k = 0; k < 6; k++) SpamFilePrintf(&f, ",%.17g", t6[k]);
    }
    SpamFilePrintf(&f, "\n");
  }
  PetscCall(SpamFileCommit(&f));
  PetscFunctionReturn(0);
}
