/* Outputs on several ranks: a snapshot written by P ranks is the file
 * one rank writes. Run on 1, 2 and 3 ranks. For a 2D and a 3D gas and a 3D elastic solid
 * (energy, carried density and six stresses in the state), particles of a jittered
 * lattice filling a periodic box (some just outside its lower faces, wrapped by the
 * writer), whose state, mass and density are functions of their gid:
 *   - reference: rank 0 alone holds all of them in a sim of its own (PETSC_COMM_SELF),
 *     re-sorted by a migration as a run sorts them, and writes a snapshot (HDF5, CSV,
 *     XDMF index, manifest, grid fields as HDF5, CSV and XDMF) and a particle CSV;
 *   - the same particles on the P ranks (SpamSimCreate on rank 0 + SpamSimMigrate), the
 *     same outputs from all ranks together.
 * Compared: every HDF5 dataset and attribute of the snapshot bitwise (read back with the
 * HDF5 C API), the text files byte for byte, the rows in gid order (ids 0..N-1 and the
 * velocities of those gids), and the grid fields and grid entropy within a bound derived
 * below: they are sums over particles, which P ranks add in another order.
 *
 * The bounds. Every grid column is sum_j t_j of positive terms (the test's velocities,
 * energies and stresses are positive), each computed by the same arithmetic on any rank
 * count; only the order of the additions differs (and the ranks' partial sums are added
 * by the reduction). Any order of adding K positive terms is within (K - 1) u of the exact
 * sum (u = 2^-53), so two orders differ by at most 2 (K - 1) u relative, K the largest
 * number of particles within h of a grid point (counted here by brute force). The grid
 * entropy is sum_p T_p with T_p = (rho/m) dV [(D/2) ln(e(rho) + dv^2/2) - ln rho] of the
 * point's three sums rho, sum w v, sum w v^2; each carries that relative error eps, and
 * the first-order change of T_p is eps times the sum of |x dT/dx| over the three (computed
 * here from the exact formula), plus the rounding of evaluating T_p (16 u of its parts)
 * and of adding the points (2 n_p u sum |T_p|). With these sizes the bound is about 1e-13
 * of S.
 * Controls (on 2 and 3 ranks), so that the comparisons are seen to fail: the grid fields
 * and the grid entropy of each rank's particles without the reduction (the entropy of the
 * parts summed, as before this change) differ from the one-rank values by far more than
 * the bounds; a snapshot whose one velocity differs in its last bit is found by the
 * HDF5 and CSV comparisons as exactly one value and a different text.
 * The outputs are held as a run holds them: rank 0 owns the directory, the other ranks an
 * output with no open file. Last, an HDF5 write failing on every rank returns the error
 * on every rank (none is left waiting) and leaves no file.
 * With -time_n N (not in ctest) it prints the time of writing one HDF5 snapshot of N 3D
 * particles on the ranks it runs on, after their migration. */
#define _XOPEN_SOURCE 700 /* nftw: POSIX, not C11 */
#define _DEFAULT_SOURCE   /* mkdtemp */
#include <spam/decompose.h>
#include <spam/entropy.h>
#include <spam/grid.h>
#include <spam/kernel.h>
#include <spam/scene.h>
#include <hdf5.h>
#include <float.h>
#include <dirent.h>
#include <ftw.h>
#include <stdarg.h>
#include <unistd.h>
#include "test_util.h"
#include "../src/io/particle_rows.h"

#define U_ROUND (DBL_EPSILON / 2)

typedef struct {
  TestCount   count;
  MPI_Comm    comm;
  PetscMPIInt rank, size;
  char        dir[PETSC_MAX_PATH_LEN];
} Ctx;

/* A check that holds on every rank (ok_here is this rank's part), printed once by rank 0. */
#define Check(t, ok_here, ...) TestCheckAll((t)->comm, &(t)->count, (ok_here), __VA_ARGS__)

/* ---- The particles: functions of the gid. */
typedef struct {
  const char *name;
  int         dim, side;
  PetscBool   solid;
  double      h, spacing; /* kernel range; spacing of the grid fields and entropy grid */
  PetscInt    N;
  SpamBox     box;
} Case;

static double Uniform(PetscInt64 gid, int k)
{
  uint64_t s = (uint64_t)gid * 7919u + (uint64_t)k * 104729u;
  return TestUniform(&s);
}
/* Lattice site + up to 0.3; site 0 of each direction moved down by 0.6 more, so that some
 * particles lie below the box's lower face (periodic: the writer wraps them). */
static double PositionOf(const Case *c, PetscInt64 gid, int d)
{
  PetscInt64 site = gid;
  for (int k = 0; k < d; k++) site /= c->side;
  site %= c->side;
  return c->box.lo[d] + 0.5 + (double)site + 0.6 * (Uniform(gid, d) - 0.5) - (site == 0 ? 0.6 : 0.0);
}
static double VelocityOf(PetscInt64 gid, int d) { return 0.5 + 0.5 * Uniform(gid, 3 + d); }
static double MassOf(PetscInt64 gid) { return 1.0 + (double)(gid % 7) / 8.0; }
static double DensityOf(PetscInt64 gid) { return 0.8 + 0.4 * Uniform(gid, 7); }
static double EnergyOf(PetscInt64 gid) { return 0.01 + 0.01 * Uniform(gid, 8); }
static double StressOf(PetscInt64 gid, int k) { return 0.1 + 0.1 * Uniform(gid, 9 + k); }

static PetscErrorCode MakeModel(const Case *c, SpamModel *m)
{
  SpamKernel kern;

  PetscFunctionBeginUser;
  if (c->solid) {
    SpamSolidParams sp;
    SpamSolidDefaults(&sp);
    sp.material = SPAM_MATERIAL_ELASTIC;
    sp.density  = SPAM_DENSITY_CONTINUITY; /* the density in the state: written as carried */
    PetscCall(SpamTestModelSolid(c->dim, c->h, &sp, m));
  } else {
    PetscCall(SpamKernelLucyInit(c->dim, c->h, &kern));
    PetscCall(SpamModelIsentropeSetUp(c->dim, &kern, 1.0, 2.0, 0.5, m));
  }
  PetscFunctionReturn(0);
}

/* The state beyond x and v, and the summed density of a gas, from each particle's gid. */
static PetscErrorCode SetValues(SpamSim *sim)
{
  const SpamLayout *l = &sim->model.layout;
  PetscScalar      *y;

  PetscFunctionBeginUser;
  PetscCall(VecGetArray(sim->p.X, &y));
  for (PetscInt i = 0; i < sim->p.n; i++) {
    const PetscInt64 g = SpamSimRowOf(sim, i);
    double          *p = y + (size_t)i * l->nvar;
    if (l->rho >= 0) p[l->rho] = DensityOf(g);
    else sim->pair.f.rho[i] = DensityOf(g);
    if (l->e >= 0) p[l->e] = EnergyOf(g);
    for (int k = 0; l->s >= 0 && k < sim->model.dim * (sim->model.dim + 1) / 2; k++) p[l->s + k] = StressOf(g, k);
  }
  PetscCall(VecRestoreArray(sim->p.X, &y));
  PetscFunctionReturn(0);
}

/* All N particles on rank 0 of comm, then distributed (or, on one rank, re-sorted) by a
 * migration, as a run's set-up does. */
static PetscErrorCode MakeSim(MPI_Comm comm, const Case *c, SpamSim *sim)
{
  SpamModel       model;
  SpamDecomp      dec;
  SpamMigrateInfo info;
  PetscMPIInt     rank;
  PetscInt        n;
  double         *x, *v, *m;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  n = rank ? 0 : c->N;
  PetscCall(MakeModel(c, &model));
  PetscCall(SpamSimCreate(comm, &model, &c->box, n, 0.1 * c->h, sim));
  PetscCall(PetscMalloc3((size_t)n * c->dim + 1, &x, (size_t)n * c->dim + 1, &v, n + 1, &m));
  for (PetscInt i = 0; i < n; i++) {
    for (int d = 0; d < c->dim; d++) {
      x[i * c->dim + d] = PositionOf(c, i, d);
      v[i * c->dim + d] = VelocityOf(i, d);
    }
    m[i] = MassOf(i);
  }
  PetscCall(SpamSimFill(sim, x, v, m));
  PetscCall(PetscFree3(x, v, m));
  PetscCall(SpamSimSetUp(sim));
  PetscCall(SpamDecompCreate(sim->p.comm, &sim->geo.box, sim->model.kernel.h, 0.0, &dec));
  PetscCall(SpamSimMigrate(sim, &dec, &info));
  PetscCheck(info.bad < 0, comm, PETSC_ERR_PLIB, "bad position in the test's particles");
  PetscCall(SpamDecompDestroy(&dec));
  PetscCall(SetValues(sim));
  PetscFunctionReturn(0);
}

/* This rank's particles alone, in a sim of their own (PETSC_COMM_SELF): what the grid
 * sums were before they were reduced over the ranks. */
static PetscErrorCode LocalCopy(const Case *c, const SpamSim *sim, SpamSim *loc)
{
  const SpamLayout  *l = &sim->model.layout;
  const PetscScalar *y;
  PetscScalar       *z;
  double            *x, *v;

  PetscFunctionBeginUser;
  PetscCall(SpamSimCreate(PETSC_COMM_SELF, &sim->model, &c->box, sim->p.n, sim->pair.skin, loc));
  PetscCall(PetscMalloc2((size_t)sim->p.n * c->dim + 1, &x, (size_t)sim->p.n * c->dim + 1, &v));
  PetscCall(VecGetArrayRead(sim->p.X, &y));
  for (PetscInt i = 0; i < sim->p.n; i++)
    for (int d = 0; d < c->dim; d++) {
      x[i * c->dim + d] = y[(size_t)i * l->nvar + l->x + d];
      v[i * c->dim + d] = y[(size_t)i * l->nvar + l->v + d];
    }
  PetscCall(SpamSimFill(loc, x, v, sim->pair.f.m));
  PetscCall(PetscFree2(x, v));
  PetscCall(SpamSimSetUp(loc));
  PetscCall(VecGetArray(loc->p.X, &z));
  PetscCall(PetscArraycpy(z, y, (size_t)sim->p.n * l->nvar));
  PetscCall(VecRestoreArray(loc->p.X, &z));
  PetscCall(VecRestoreArrayRead(sim->p.X, &y));
  PetscCall(PetscArraycpy(loc->pair.f.rho, sim->pair.f.rho, sim->p.n));
  PetscFunctionReturn(0);
}

/* ---- Writing. */
static PetscErrorCode WriteOutputs(const Case *c, SpamSim *sim, const char *dir)
{
  SpamOutput        o;
  SpamOutputOptions opt;
  char              path[PETSC_MAX_PATH_LEN];
  const PetscScalar *y;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(&opt, sizeof opt));
  opt.grid_interval = c->spacing;
  /* as a run holds it (run_session.c): rank 0 owns the directory, the other ranks an
   * output with no open file */
  {
    PetscMPIInt rank;
    PetscCallMPI(MPI_Comm_rank(sim->p.comm, &rank));
    if (rank == 0) PetscCall(SpamOutputInit(dir, PETSC_TRUE, PETSC_TRUE, &opt, &o));
    else {
      PetscCall(PetscMemzero(&o, sizeof o));
      o.lock_fd = -1;
      o.hdf5 = o.csv = PETSC_TRUE;
      o.opt          = opt;
      PetscCall(PetscStrncpy(o.dir, dir, sizeof o.dir));
    }
    PetscCallMPI(MPI_Barrier(sim->p.comm)); /* the directory exists */
  }
  o.step = 17;
  PetscCall(VecGetArrayRead(sim->p.X, &y));
  PetscCall(SpamSnapshotWrite(&o, sim, y, 0.25, NULL));
  PetscCall(SpamSnapshotWrite(&o, sim, y, 0.5, NULL)); /* an index of two */
  PetscCall(SpamOutputPath(&o, "particles.csv", path, sizeof path));
  PetscCall(SpamParticlesCsvWrite(path, sim, y));
  PetscCall(VecRestoreArrayRead(sim->p.X, &y));
  PetscCall(PetscFree(o.snap_times));
  PetscCall(PetscFree(o.grid.times));
  PetscCall(PetscFree(o.files));
  PetscFunctionReturn(0);
}

/* ---- Reading back (rank 0). */
typedef struct {
  long   datasets, attributes, values; /* compared                                     */
  long   differ;                       /* values (or attributes, shapes) that differ  */
  double worst;                        /* largest |a - b| / (tol |a|) (0 when tol = 0) */
  char   first[160];                   /* the first difference                         */
} Diff;

static void Note(Diff *r, const char *what)
{
  if (!r->first[0]) (void)snprintf(r->first, sizeof r->first, "%s", what);
}

typedef struct {
  hid_t other;
  Diff *r;
} AttrCtx;

/* Attribute `name` of the first object against the same-named one of the other: type,
 * size and bytes. */
static herr_t CompareAttribute(hid_t loc, const char *name, const H5A_info_t *info, void *data)
{
  AttrCtx *c = data;
  hid_t    a = H5Aopen(loc, name, H5P_DEFAULT), b = H5Aopen(c->other, name, H5P_DEFAULT);
  int      same = 0;

  (void)info;
  c->r->attributes++;
  if (a >= 0 && b >= 0) {
    hid_t         ta = H5Aget_type(a), tb = H5Aget_type(b);
    const hsize_t sa = H5Aget_storage_size(a), sb = H5Aget_storage_size(b);
    if (H5Tequal(ta, tb) > 0 && sa == sb) {
      char *ba = malloc(sa + 1), *bb = malloc(sb + 1);
      same     = ba && bb && H5Aread(a, ta, ba) >= 0 && H5Aread(b, tb, bb) >= 0 && !memcmp(ba, bb, sa);
      free(ba);
      free(bb);
    }
    (void)H5Tclose(ta);
    (void)H5Tclose(tb);
  }
  if (!same) {
    char what[160];
    (void)snprintf(what, sizeof what, "attribute %s", name);
    c->r->differ++;
    Note(c->r, what);
  }
  if (a >= 0) (void)H5Aclose(a);
  if (b >= 0) (void)H5Aclose(b);
  return 0;
}

static int CountAttributes(hid_t loc)
{
  H5O_info_t info;
  return H5Oget_info2(loc, &info, H5O_INFO_NUM_ATTRS) < 0 ? -1 : (int)info.num_attrs;
}

static void CompareAttributes(hid_t a, hid_t b, Diff *r)
{
  AttrCtx c = {b, r};
  hsize_t idx = 0;
  if (CountAttributes(a) != CountAttributes(b)) {
    r->differ++;
    Note(r, "number of attributes");
  }
  (void)H5Aiterate2(a, H5_INDEX_NAME, H5_ITER_INC, &idx, CompareAttribute, &c);
}

/* Dataset name of both files: type, shape, attributes and values (bitwise when tol is 0,
 * else |a - b| <= tol |a|). */
static void CompareDataset(hid_t fa, hid_t fb, const char *name, double tol, Diff *r)
{
  hid_t   a = H5Dopen2(fa, name, H5P_DEFAULT), b = H5Dopen2(fb, name, H5P_DEFAULT);
  hid_t   ta, tb, sa, sb;
  hsize_t da[4] = {0}, db[4] = {0}, count = 1;
  int     ra, rb;
  char    what[160];

  r->datasets++;
  if (a < 0 || b < 0) {
    (void)snprintf(what, sizeof what, "dataset %s missing", name);
    r->differ++;
    Note(r, what);
    if (a >= 0) (void)H5Dclose(a);
    if (b >= 0) (void)H5Dclose(b);
    return;
  }
  ta = H5Dget_type(a);
  tb = H5Dget_type(b);
  sa = H5Dget_space(a);
  sb = H5Dget_space(b);
  ra = H5Sget_simple_extent_dims(sa, da, NULL);
  rb = H5Sget_simple_extent_dims(sb, db, NULL);
  if (H5Tequal(ta, tb) <= 0 || ra != rb || memcmp(da, db, sizeof da)) {
    (void)snprintf(what, sizeof what, "dataset %s: type or shape", name);
    r->differ++;
    Note(r, what);
  } else {
    const int is_float = H5Tget_class(ta) == H5T_FLOAT;
    double   *va, *vb;
    for (int k = 0; k < ra; k++) count *= da[k];
    va = calloc(count + 1, sizeof *va);
    vb = calloc(count + 1, sizeof *vb);
    /* integers read as 64-bit integers into the same bytes: compared bitwise */
    if (H5Dread(a, is_float ? H5T_NATIVE_DOUBLE : H5T_NATIVE_LLONG, H5S_ALL, H5S_ALL, H5P_DEFAULT, va) < 0 || H5Dread(b, is_float ? H5T_NATIVE_DOUBLE : H5T_NATIVE_LLONG, H5S_ALL, H5S_ALL, H5P_DEFAULT, vb) < 0) {
      r->differ++;
      Note(r, "unreadable dataset");
    } else
      for (hsize_t k = 0; k < count; k++) {
        int bad;
        r->values++;
        if (tol == 0.0 || !is_float) bad = memcmp(va + k, vb + k, sizeof *va) != 0;
        else {
          const double e = fabs(va[k] - vb[k]), lim = tol * fabs(va[k]);
          bad            = !(e <= lim);
          if (lim > 0) r->worst = PetscMax(r->worst, e / lim);
        }
        if (bad) {
          (void)snprintf(what, sizeof what, "%s[%llu]: %.17g vs %.17g", name, (unsigned long long)k, va[k], vb[k]);
          r->differ++;
          Note(r, what);
        }
      }
    free(va);
    free(vb);
  }
  CompareAttributes(a, b, r);
  (void)H5Tclose(ta);
  (void)H5Tclose(tb);
  (void)H5Sclose(sa);
  (void)H5Sclose(sb);
  (void)H5Dclose(a);
  (void)H5Dclose(b);
}

/* Two HDF5 files: the same objects in the root group, each dataset as above, and the
 * root's attributes. */
static void CompareH5(const char *pa, const char *pb, double tol, Diff *r)
{
  hid_t      fa = H5Fopen(pa, H5F_ACC_RDONLY, H5P_DEFAULT), fb = H5Fopen(pb, H5F_ACC_RDONLY, H5P_DEFAULT);
  H5G_info_t ia, ib;

  memset(r, 0, sizeof *r);
  if (fa < 0 || fb < 0 || H5Gget_info(fa, &ia) < 0 || H5Gget_info(fb, &ib) < 0 || ia.nlinks != ib.nlinks) {
    r->differ++;
    Note(r, "file missing or different objects");
  } else {
    for (hsize_t k = 0; k < ia.nlinks; k++) {
      char name[256] = "/";
      if (H5Lget_name_by_idx(fa, ".", H5_INDEX_NAME, H5_ITER_INC, k, name + 1, sizeof name - 1, H5P_DEFAULT) < 0) continue;
      CompareDataset(fa, fb, name, tol, r);
    }
    CompareAttributes(fa, fb, r);
  }
  if (fa >= 0) (void)H5Fclose(fa);
  if (fb >= 0) (void)H5Fclose(fb);
}

static PetscErrorCode SameText(const char *pa, const char *pb, PetscBool *same)
{
  char  *a, *b;
  size_t na, nb;

  PetscFunctionBeginUser;
  PetscCall(SpamReadWholeFile(pa, &a, &na));
  PetscCall(SpamReadWholeFile(pb, &b, &nb));
  *same = (PetscBool)(a && b && na == nb && !memcmp(a, b, na));
  PetscCall(PetscFree(a));
  PetscCall(PetscFree(b));
  PetscFunctionReturn(0);
}

/* Two grid CSV files: the two comment and header lines equal, then every number within
 * tol relative. */
static PetscErrorCode CompareGridCsv(const char *pa, const char *pb, double tol, Diff *r)
{
  char  *a, *b, *sa, *sb;
  size_t na, nb;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(r, sizeof *r));
  PetscCall(SpamReadWholeFile(pa, &a, &na));
  PetscCall(SpamReadWholeFile(pb, &b, &nb));
  sa = a ? strchr(a, '\n') : NULL;
  sb = b ? strchr(b, '\n') : NULL;
  sa = sa ? strchr(sa + 1, '\n') : NULL;
  sb = sb ? strchr(sb + 1, '\n') : NULL;
  if (!sa || !sb || sa - a != sb - b || memcmp(a, b, (size_t)(sa - a))) {
    r->differ++;
    Note(r, "header lines");
  } else {
    while (*sa && *sb) {
      char        *ea, *eb;
      const double x = strtod(sa + 1, &ea), y = strtod(sb + 1, &eb);
      if (ea == sa + 1 || eb == sb + 1) break;
      r->values++;
      if (!(fabs(x - y) <= tol * fabs(x))) {
        r->differ++;
        Note(r, "a value");
      } else if (tol * fabs(x) > 0) r->worst = PetscMax(r->worst, fabs(x - y) / (tol * fabs(x)));
      sa = ea;
      sb = eb;
      if (*sa != *sb) {
        r->differ++;
        Note(r, "layout");
        break;
      }
    }
    if (strcmp(sa, sb)) { /* what follows the last number: the same in both */
      r->differ++;
      Note(r, "length");
    }
  }
  PetscCall(PetscFree(a));
  PetscCall(PetscFree(b));
  PetscFunctionReturn(0);
}

/* ---- Brute force (rank 0, the case's exact particles): the largest count of particles
 * within h of a grid point, and the grid entropy's bound. */
static void GridPoint(const Case *c, PetscInt ng[3], double g[3], PetscInt k, double u[3])
{
  for (int d = 0, rem = (int)k; d < 3; d++) {
    u[d] = d < c->dim ? (rem % ng[d] + 0.5) * g[d] : 0.0;
    if (d < c->dim) rem /= (int)ng[d];
  }
}

static double Delta(const Case *c, int d, double du)
{
  const double L = c->box.len[d];
  du -= L * round(du / L);
  return du;
}

/* Box-local position of particle gid. */
static void LocalPosition(const Case *c, PetscInt64 gid, double u[3])
{
  for (int d = 0; d < 3; d++) u[d] = d < c->dim ? PositionOf(c, gid, d) - c->box.lo[d] : 0.0;
}

typedef struct {
  int    kmax;     /* most particles within h of a point                         */
  double S, bound; /* the entropy evaluated here, and the bound of a rank change */
  double sum_abs;  /* sum |T_p|                                                  */
} Brute;

static PetscErrorCode BruteForce(const Case *c, const SpamModel *m, Brute *b)
{
  const int    D = c->dim, np1 = D + 2;
  PetscInt     ng[3] = {1, 1, 1}, total = 1;
  double       g[3] = {1, 1, 1}, cv = 1.0, *mom;
  const double h2 = c->h * c->h, gm1 = m->eos.gamma - 1.0;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(b, sizeof *b));
  for (int d = 0; d < D; d++) {
    ng[d] = (PetscInt)PetscMax(1.0, ceil(c->box.len[d] / c->spacing));
    g[d]  = c->box.len[d] / ng[d];
    cv *= g[d];
    total *= ng[d];
  }
  PetscCall(PetscCalloc1((size_t)np1 * total, &mom));
  for (PetscInt k = 0; k < total; k++) {
    double u[3], *p = mom + (size_t)np1 * k;
    int    count = 0;
    GridPoint(c, ng, g, k, u);
    for (PetscInt j = 0; j < c->N; j++) {
      double uj[3], r2 = 0.0, v2 = 0.0;
      LocalPosition(c, j, uj);
      for (int d = 0; d < D; d++) r2 += Delta(c, d, u[d] - uj[d]) * Delta(c, d, u[d] - uj[d]);
      if (r2 >= h2) continue;
      count++;
      const double w = m->mass * SpamKernelW(&m->kernel, r2);
      for (int d = 0; d < D; d++) v2 += VelocityOf(j, d) * VelocityOf(j, d);
      p[0] += w;
      for (int d = 0; d < D; d++) p[1 + d] += w * VelocityOf(j, d);
      p[1 + D] += w * v2;
    }
    b->kmax = PetscMax(b->kmax, count);
  }
  /* T_p and its first-order sensitivity to relative changes eps of its three sums */
  {
    const double eps = 2.0 * (b->kmax - 1) * U_ROUND;
    double       dsum = 0.0;
    for (PetscInt k = 0; k < total; k++) {
      const double *p = mom + (size_t)np1 * k, rho = p[0], A = p[1 + D] / rho, cr = cv * rho / m->mass;
      double        B2 = 0.0;
      for (int d = 0; d < D; d++) B2 += (p[1 + d] / rho) * (p[1 + d] / rho);
      const double e = SpamEosEnergy(&m->eos, rho), E = e + 0.5 * (A - B2);
      const double T = cr * (0.5 * D * log(E) - log(rho));
      const double dV2 = cr * 0.5 * D * A / (2.0 * E), dVm = cr * 0.5 * D * B2 / E;
      const double drho = T + cr * (0.5 * D * (gm1 * e - 0.5 * A + B2) / E - 1.0);
      b->S += T;
      b->sum_abs += fabs(T);
      b->bound += eps * (fabs(drho) + dVm + dV2);
      /* evaluating T: the cancellation in A - B2, the logarithms */
      dsum += 16.0 * U_ROUND * (cr * 0.5 * D * (A + B2) / E + cr * 0.5 * D * fabs(log(E)) + cr * fabs(log(rho)));
    }
    b->bound += dsum + 2.0 * (double)total * U_ROUND * b->sum_abs;
  }
  PetscCall(PetscFree(mom));
  PetscFunctionReturn(0);
}

/* The case's files under dir/name/sub. */
static void CasePath(const Ctx *t, const Case *c, const char *sub, const char *file, char *path, size_t len)
{
  const int k = snprintf(path, len, "%s/%s/%s%s%s", t->dir, c->name, sub, file ? "/" : "", file ? file : "");
  if (k < 0 || (size_t)k >= len) path[0] = 0; /* too long: no file (the comparison fails) */
}

/* ---- The comparisons of one case. */
static PetscErrorCode CompareFiles(Ctx *t, const Case *c, const Brute *b)
{
  static const char *text[] = {"particles_00000.csv", "particles_00001.csv", "particles.csv", "snapshots.xmf", "grid.xmf", "manifest.json"};
  const double       tol    = 2.0 * b->kmax * U_ROUND * 1.01;
  char               pa[PETSC_MAX_PATH_LEN], pb[PETSC_MAX_PATH_LEN];
  Diff               r = {0}, g = {0}, gc = {0};
  long               text_differ = 0;
  char               text_first[64] = "";

  PetscFunctionBeginUser;
  if (t->rank == 0) {
    for (int s = 0; s < 2; s++) {
      Diff one;
      char name[32];
      (void)snprintf(name, sizeof name, "snap_%05d.h5", s);
      CasePath(t, c, "ref", name, pa, sizeof pa);
      CasePath(t, c, "ranks", name, pb, sizeof pb);
      CompareH5(pa, pb, 0.0, &one);
      r.datasets += one.datasets;
      r.attributes += one.attributes;
      r.values += one.values;
      r.differ += one.differ;
      if (!r.first[0]) (void)snprintf(r.first, sizeof r.first, "%s", one.first);
    }
    for (size_t k = 0; k < sizeof text / sizeof *text; k++) {
      PetscBool same;
      CasePath(t, c, "ref", text[k], pa, sizeof pa);
      CasePath(t, c, "ranks", text[k], pb, sizeof pb);
      PetscCall(SameText(pa, pb, &same));
      if (!same && !text_differ++) (void)snprintf(text_first, sizeof text_first, "%s", text[k]);
    }
    CasePath(t, c, "ref", "grid_00001.h5", pa, sizeof pa);
    CasePath(t, c, "ranks", "grid_00001.h5", pb, sizeof pb);
    CompareH5(pa, pb, tol, &g);
    CasePath(t, c, "ref", "grid_00001.csv", pa, sizeof pa);
    CasePath(t, c, "ranks", "grid_00001.csv", pb, sizeof pb);
    PetscCall(CompareGridCsv(pa, pb, tol, &gc));
  }
  PetscCall(Check(t, t->rank || (r.differ == 0 && r.datasets == 2 * (c->solid ? 7 : 5) && r.values > 0),
                  "%s on %d ranks: the two HDF5 snapshots equal to the one-rank files bitwise (%ld datasets, %ld attributes, %ld values compared; %ld differ%s%s)", c->name, t->size, r.datasets, r.attributes, r.values, r.differ, r.differ ? ": first " : "", r.first));
  PetscCall(Check(t, t->rank || text_differ == 0, "%s on %d ranks: the snapshot and particle CSV files, both XDMF indexes and the manifest equal byte for byte (%ld differ%s%s)", c->name, t->size, text_differ, text_differ ? ": first " : "", text_first));
  PetscCall(Check(t, t->rank || (g.differ == 0 && g.values > 0), "%s on %d ranks: grid_00001.h5: attributes bitwise, %ld field values within 2 K u = %.2e relative (K = %d particles at most within h of a point), worst at %.3f of it%s%s", c->name, t->size, g.values, tol, b->kmax, g.worst, g.differ ? "; first difference " : "", g.first));
  PetscCall(Check(t, t->rank || (gc.differ == 0 && gc.values > 0), "%s on %d ranks: grid_00001.csv: header lines equal, %ld numbers within the same bound (worst at %.3f of it)%s%s", c->name, t->size, gc.values, gc.worst, gc.differ ? "; first difference " : "", gc.first));
  PetscFunctionReturn(0);
}

/* The rows of the P-rank file are in gid order: id r and the velocity of gid r in row r. */
static PetscErrorCode RowsInGidOrder(Ctx *t, const Case *c)
{
  char    path[PETSC_MAX_PATH_LEN];
  long    wrong = -1;
  hsize_t N     = (hsize_t)c->N;

  PetscFunctionBeginUser;
  if (t->rank == 0) {
    long long *id = calloc(N + 1, sizeof *id);
    double    *v  = calloc(3 * N + 3, sizeof *v);
    hid_t      f, a, b;
    CasePath(t, c, "ranks", "snap_00000.h5", path, sizeof path);
    f = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT);
    a = f < 0 ? -1 : H5Dopen2(f, "/id", H5P_DEFAULT);
    b = f < 0 ? -1 : H5Dopen2(f, "/velocities", H5P_DEFAULT);
    if (a >= 0 && b >= 0 && H5Dread(a, H5T_NATIVE_LLONG, H5S_ALL, H5S_ALL, H5P_DEFAULT, id) >= 0 && H5Dread(b, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v) >= 0) {
      wrong = 0;
      for (hsize_t r = 0; r < N; r++) {
        int ok = id[r] == (long long)r;
        for (int d = 0; d < c->dim; d++) ok = ok && v[3 * r + d] == VelocityOf((PetscInt64)r, d);
        wrong += !ok;
      }
    }
    if (a >= 0) (void)H5Dclose(a);
    if (b >= 0) (void)H5Dclose(b);
    if (f >= 0) (void)H5Fclose(f);
    free(id);
    free(v);
  }
  PetscCall(Check(t, t->rank || wrong == 0, "%s on %d ranks: row r of the file holds gid r (ids 0..%ld, velocities those of the gids): %ld rows wrong", c->name, t->size, (long)c->N - 1, wrong));
  PetscFunctionReturn(0);
}

/* Largest |a - b| / (tol |a|) over the grid fields. */
static double GridExcess(const SpamGridFields *a, const SpamGridFields *b, PetscInt npoints, double tol)
{
  double worst = 0.0;
  for (int col = 0; col < a->ncol; col++)
    for (PetscInt p = 0; p < npoints; p++) {
      const double e = fabs(a->col[col][p] - b->col[col][p]), lim = tol * fabs(a->col[col][p]);
      worst          = PetscMax(worst, lim > 0 ? e / lim : (e > 0 ? PETSC_INFINITY : 0.0));
    }
  return worst;
}

/* Grid fields and entropy in memory: the ranks' against rank 0's reference; then the
 * controls without the reduction. */
static PetscErrorCode CompareSums(Ctx *t, const Case *c, SpamSim *ref, SpamSim *sim, const Brute *b)
{
  const double       tol = 2.0 * b->kmax * U_ROUND * 1.01;
  SpamGrid           g;
  SpamGridFields     fr = {0}, fp = {0}, fl = {0};
  const PetscScalar *y;
  double             Sref = 0.0, Sp, Sloc, Sparts, worst = 0.0, worst_loc = 0.0;
  SpamSim            loc;

  PetscFunctionBeginUser;
  PetscCall(SpamGridSetUp(&c->box, c->spacing, &g));
  if (t->rank == 0) {
    PetscCall(VecGetArrayRead(ref->p.X, &y));
    PetscCall(SpamGridFieldsEvaluate(ref, y, &g, &fr));
    if (!c->solid) PetscCall(SpamEntropyGrid(ref, y, c->spacing, &Sref));
    PetscCall(VecRestoreArrayRead(ref->p.X, &y));
  }
  PetscCall(VecGetArrayRead(sim->p.X, &y));
  PetscCall(SpamGridFieldsEvaluate(sim, y, &g, &fp));
  if (!c->solid) PetscCall(SpamEntropyGrid(sim, y, c->spacing, &Sp));
  PetscCall(VecRestoreArrayRead(sim->p.X, &y));
  if (t->rank == 0) worst = GridExcess(&fr, &fp, g.npoints, tol);
  PetscCall(Check(t, t->rank || worst <= 1.0, "%s on %d ranks: grid fields (%d columns, %ld points) equal the one-rank sums within 2 K u = %.2e relative: worst at %.3f of the bound", c->name, t->size, fp.ncol, (long)g.npoints, tol, worst));
  if (!c->solid) {
    double agree[2] = {Sp, -Sp};
    PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, agree, 2, MPI_DOUBLE, MPI_MAX, t->comm));
    PetscCall(Check(t, agree[0] == -agree[1], "%s on %d ranks: every rank gets the same grid entropy %.17g", c->name, t->size, Sp));
    PetscCall(Check(t, t->rank || fabs(Sref - b->S) <= b->bound, "%s: one-rank grid entropy %.15g against this test's evaluation %.15g: |difference| %.2e within the bound %.2e (%.1e of S): the bound's model of the sum holds", c->name, Sref, b->S, fabs(Sref - b->S), b->bound, b->bound / fabs(b->S)));
    if (c->dim == 2) TestReading(t->comm, "entropy_bound_rel_2d", b->bound / fabs(b->S));
    PetscCall(Check(t, t->rank || fabs(Sp - Sref) <= b->bound, "%s on %d ranks: grid entropy %.17g, one rank %.17g: |difference| %.2e within the bound %.2e (%.1e of S)", c->name, t->size, Sp, Sref, fabs(Sp - Sref), b->bound, b->bound / fabs(Sref)));
  }
  if (t->size > 1) { /* controls: the sums of this rank's particles only */
    PetscCall(LocalCopy(c, sim, &loc));
    PetscCall(VecGetArrayRead(loc.p.X, &y));
    PetscCall(SpamGridFieldsEvaluate(&loc, y, &g, &fl));
    Sloc = 0.0;
    if (!c->solid) PetscCall(SpamEntropyGrid(&loc, y, c->spacing, &Sloc));
    PetscCall(VecRestoreArrayRead(loc.p.X, &y));
    PetscCallMPI(MPI_Allreduce(&Sloc, &Sparts, 1, MPI_DOUBLE, MPI_SUM, t->comm));
    if (t->rank == 0) worst_loc = GridExcess(&fr, &fl, g.npoints, tol);
    PetscCall(Check(t, t->rank || worst_loc > 1e6, "%s on %d ranks, control: rank 0's grid fields without the reduction are off by %.3g times the bound", c->name, t->size, worst_loc));
    if (!c->solid) PetscCall(Check(t, t->rank || fabs(Sparts - Sref) > 1e6 * b->bound, "%s on %d ranks, control: the ranks' grid entropies added (each of its own particles, as before the reduction) give %.6g against %.6g: off by %.3g times the bound", c->name, t->size, Sparts, Sref, fabs(Sparts - Sref) / b->bound));
    PetscCall(SpamGridFieldsFree(&fl));
    PetscCall(SpamSimDestroy(&loc));
  }
  PetscCall(SpamGridFieldsFree(&fr));
  PetscCall(SpamGridFieldsFree(&fp));
  PetscFunctionReturn(0);
}

/* Control of the bitwise comparisons (rank 0): one velocity one ulp off. */
static PetscErrorCode UlpControl(Ctx *t, const Case *c, SpamSim *ref)
{
  const SpamLayout *l = ref ? &ref->model.layout : NULL; /* the reference exists on rank 0 only */
  char              pa[PETSC_MAX_PATH_LEN], pb[PETSC_MAX_PATH_LEN], dir[PETSC_MAX_PATH_LEN];
  Diff              r = {0};
  PetscBool         same = PETSC_TRUE;
  PetscScalar      *y;
  double            keep;

  PetscFunctionBeginUser;
  if (t->rank == 0) {
    CasePath(t, c, "ulp", NULL, dir, sizeof dir);
    PetscCall(SpamOutputMakeDirs(dir));
    PetscCall(VecGetArray(ref->p.X, &y));
    keep           = y[l->v];
    y[l->v]        = nextafter(keep, 2.0);
    CasePath(t, c, "ulp", "snap_00000.h5", pb, sizeof pb);
    PetscCall(SpamSnapshotHdf5Write(pb, ref, y, 0.25, 17));
    CasePath(t, c, "ulp", "particles_00000.csv", pb, sizeof pb);
    PetscCall(SpamSnapshotCsvWrite(pb, ref, y, 0.25));
    y[l->v] = keep;
    PetscCall(VecRestoreArray(ref->p.X, &y));
    CasePath(t, c, "ref", "snap_00000.h5", pa, sizeof pa);
    CasePath(t, c, "ulp", "snap_00000.h5", pb, sizeof pb);
    CompareH5(pa, pb, 0.0, &r);
    CasePath(t, c, "ref", "particles_00000.csv", pa, sizeof pa);
    CasePath(t, c, "ulp", "particles_00000.csv", pb, sizeof pb);
    PetscCall(SameText(pa, pb, &same));
  }
  PetscCall(Check(t, t->rank || (r.differ == 1 && !same), "%s, control: a velocity one ulp off is found: %ld HDF5 value differs (%s), CSV text %s", c->name, r.differ, r.first, same ? "equal" : "differs"));
  PetscFunctionReturn(0);
}

/* A periodic box of side^dim lattice sites, lower corner at -2. */
static void CaseBox(Case *c)
{
  c->N = 1;
  for (int d = 0; d < 3; d++) {
    c->box.lo[d]       = d < c->dim ? -2.0 : 0.0;
    c->box.len[d]      = d < c->dim ? c->side : 1.0;
    c->box.periodic[d] = d < c->dim ? PETSC_TRUE : PETSC_FALSE;
    if (d < c->dim) c->N *= c->side;
  }
  c->box.dim = c->dim;
}

/* Lock files and temporaries in dir. */
static long Leftovers(const char *dir)
{
  DIR           *dp = opendir(dir);
  struct dirent *e;
  long           n = 0;
  if (!dp) return -1;
  while ((e = readdir(dp))) {
    const size_t len = strlen(e->d_name);
    n += strstr(e->d_name, "lock") != NULL || (len > 4 && !strcmp(e->d_name + len - 4, ".tmp"));
  }
  closedir(dp);
  return n;
}

/* A write of an HDF5 snapshot that fails (SPAM_TEST_FAIL_WRITE: the third dataset
 * write, on every rank since they write together) returns the file-write error on every
 * rank and leaves neither the file nor its temporary. */
static PetscErrorCode SnapshotFailure(Ctx *t)
{
  Case           c = {"fail", 2, 6, PETSC_FALSE, 3.0, 1.0, 0, {0}};
  SpamSim        sim;
  char           dir[PETSC_MAX_PATH_LEN], path[PETSC_MAX_PATH_LEN];
  long           leftover;
  PetscErrorCode ierr;
  int            codes[2];

  PetscFunctionBeginUser;
  CaseBox(&c);
  PetscCall(MakeSim(t->comm, &c, &sim));
  PetscCall(PetscSNPrintf(dir, sizeof dir, "%s/snap_fail", t->dir));
  if (t->rank == 0) PetscCall(SpamOutputMakeDirs(dir));
  PetscCall(PetscSNPrintf(path, sizeof path, "%s/fail.h5", dir));
  setenv("SPAM_TEST_FAIL_WRITE", "fail.h5:3", 1);
  {
    const PetscScalar *y;
    PetscCall(VecGetArrayRead(sim.p.X, &y));
    PetscCall(PetscPushErrorHandler(PetscReturnErrorHandler, NULL));
    ierr = SpamSnapshotHdf5Write(path, &sim, y, 0.0, 0);
    PetscCall(PetscPopErrorHandler());
    PetscCall(VecRestoreArrayRead(sim.p.X, &y));
  }
  unsetenv("SPAM_TEST_FAIL_WRITE");
  codes[0] = (int)ierr;
  codes[1] = -(int)ierr;
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, codes, 2, MPI_INT, MPI_MAX, t->comm));
  leftover = t->rank ? 0 : Leftovers(dir) + (access(path, F_OK) == 0);
  PetscCall(Check(t, codes[0] == PETSC_ERR_FILE_WRITE && codes[0] == -codes[1] && leftover == 0, "HDF5 snapshot on %d ranks: a failed dataset write returns the file-write error on every rank (codes %d..%d), neither the file nor its temporary left (%ld)", t->size, -codes[1], codes[0], leftover));
  PetscCall(SpamSimDestroy(&sim));
  PetscFunctionReturn(0);
}

static PetscErrorCode RunCase(Ctx *t, Case *c)
{
  SpamSim   ref, sim;
  SpamModel m;
  Brute     b;
  char      dir[PETSC_MAX_PATH_LEN];

  PetscFunctionBeginUser;
  CaseBox(c);
  PetscCall(MakeModel(c, &m));
  if (t->rank == 0) {
    PetscCall(BruteForce(c, &m, &b));
    PetscCall(MakeSim(PETSC_COMM_SELF, c, &ref));
    CasePath(t, c, "ref", NULL, dir, sizeof dir);
    PetscCall(WriteOutputs(c, &ref, dir));
  }
  PetscCallMPI(MPI_Bcast(&b, (int)sizeof b, MPI_BYTE, 0, t->comm));
  PetscCall(MakeSim(t->comm, c, &sim));
  {
    PetscInt n = sim.p.n, nmin;
    PetscCallMPI(MPI_Allreduce(&n, &nmin, 1, MPIU_INT, MPI_MIN, t->comm));
    PetscCall(Check(t, nmin > 0, "%s on %d ranks: %ld particles distributed, every rank holds some (fewest %ld)", c->name, t->size, (long)c->N, (long)nmin));
  }
  CasePath(t, c, "ranks", NULL, dir, sizeof dir);
  PetscCall(WriteOutputs(c, &sim, dir));
  PetscCall(CompareFiles(t, c, &b));
  PetscCall(RowsInGidOrder(t, c));
  PetscCall(CompareSums(t, c, t->rank ? NULL : &ref, &sim, &b));
  if (t->rank == 0) PetscCall(UlpControl(t, c, &ref));
  else PetscCall(UlpControl(t, c, NULL));
  PetscCall(SpamSimDestroy(&sim));
  if (t->rank == 0) PetscCall(SpamSimDestroy(&ref));
  PetscFunctionReturn(0);
}

/* -time_n N: one HDF5 snapshot of N particles of a 3D gas (a cube lattice filling its
 * box, as the expansion's set-up), written after the migration; the slowest rank's time,
 * best of 3. */
static PetscErrorCode TimeWrite(Ctx *t, PetscInt N)
{
  Case        c = {"timing", 3, 1, PETSC_FALSE, 2.0, 1.0, 0, {0}};
  SpamSim     sim;
  char        path[PETSC_MAX_PATH_LEN];
  double      best = PETSC_INFINITY, best_rows = PETSC_INFINITY;
  const PetscScalar *y;

  PetscFunctionBeginUser;
  while ((PetscInt)c.side * c.side * c.side < N) c.side++;
  CaseBox(&c);
  PetscCall(MakeSim(t->comm, &c, &sim));
  PetscCall(PetscSNPrintf(path, sizeof path, "%s/timing.h5", t->dir));
  PetscCall(VecGetArrayRead(sim.p.X, &y));
  for (int k = 0; k < 3; k++) {
    double t0;
    PetscCallMPI(MPI_Barrier(t->comm));
    t0 = MPI_Wtime();
    PetscCall(SpamSnapshotHdf5Write(path, &sim, y, 0.0, 0));
    t0 = MPI_Wtime() - t0;
    PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &t0, 1, MPI_DOUBLE, MPI_MAX, t->comm));
    best = PetscMin(best, t0);
  }
  for (int k = 0; k < 3; k++) { /* the peer: moving the rows to their blocks alone */
    SpamRows rows;
    double   t0;
    PetscCallMPI(MPI_Barrier(t->comm));
    t0 = MPI_Wtime();
    PetscCall(SpamRowsGather(&sim, y, SPAM_ROWS_BLOCKS, &rows));
    t0 = MPI_Wtime() - t0;
    PetscCall(SpamRowsFree(&rows));
    PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &t0, 1, MPI_DOUBLE, MPI_MAX, t->comm));
    best_rows = PetscMin(best_rows, t0);
  }
  PetscCall(VecRestoreArrayRead(sim.p.X, &y));
  if (t->rank == 0)
    printf("timing: one HDF5 snapshot of %ld 3D particles on %d ranks: %.4f s (best of 3, slowest rank); of which moving the rows to their gid blocks %.4f s (%.2f of the write)\n", (long)c.N, t->size, best, best_rows, best_rows / best);
  PetscCall(SpamSimDestroy(&sim));
  PetscFunctionReturn(0);
}

static int RemoveEntry(const char *path, const struct stat *sb, int flag, struct FTW *ftw)
{
  (void)sb;
  (void)flag;
  (void)ftw;
  return remove(path);
}

int main(int argc, char **argv)
{
  Ctx       t = {{0, 0}, MPI_COMM_NULL, 0, 1, ""};
  Case      cases[] = {
    {"gas2d", 2, 20, PETSC_FALSE, 3.0, 1.0, 0, {0}},
    {"gas3d", 3, 8, PETSC_FALSE, 2.5, 1.0, 0, {0}},
    {"solid3d", 3, 7, PETSC_TRUE, 2.5, 1.0, 0, {0}},
  };
  PetscInt  time_n = 0;
  PetscBool keep   = PETSC_FALSE;

  PetscCall(TestInitialize(&argc, &argv));
  t.comm = PETSC_COMM_WORLD;
  PetscCallMPI(MPI_Comm_rank(t.comm, &t.rank));
  PetscCallMPI(MPI_Comm_size(t.comm, &t.size));
  PetscCall(PetscOptionsGetInt(NULL, NULL, "-time_n", &time_n, NULL));
  PetscCall(PetscOptionsGetBool(NULL, NULL, "-keep", &keep, NULL));
  if (t.rank == 0) {
    const char *tmp = getenv("TMPDIR");
    (void)snprintf(t.dir, sizeof t.dir, "%s/output_ranksXXXXXX", tmp && tmp[0] ? tmp : "/tmp");
    PetscCheck(mkdtemp(t.dir), PETSC_COMM_SELF, PETSC_ERR_FILE_OPEN, "cannot create %s", t.dir);
  }
  PetscCallMPI(MPI_Bcast(t.dir, (int)sizeof t.dir, MPI_CHAR, 0, t.comm));
  if (time_n > 0) PetscCall(TimeWrite(&t, time_n));
  else {
    for (size_t k = 0; k < sizeof cases / sizeof *cases; k++) PetscCall(RunCase(&t, &cases[k]));
    PetscCall(SnapshotFailure(&t));
  }
  PetscCallMPI(MPI_Barrier(t.comm));
  if (t.rank == 0 && !keep && !t.count.failed) (void)nftw(t.dir, RemoveEntry, 16, FTW_DEPTH | FTW_PHYS);
  PetscCall(TestFinalize());
  if (t.rank == 0) return TestFinish(&t.count);
  return t.count.failed ? 1 : 0;
}
