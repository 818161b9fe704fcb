/* Spring bonds across ranks. The springs model makes its bonds once, at set-up, on rank 0
 * (springs_md.c BuildBonds), by local index; a migration (the first distribution, and any
 * later one) changes which rank holds a particle and its local index, so the bonds are
 * carried by global id:
 *   - Depart: each bond becomes one record (holder gid, partner gid) per particle of the
 *     pair that this rank holds (two for a local pair, one for a pair with a remote
 *     partner, whose other record is on the partner's rank), and the record travels to
 *     its holder's destination in a swarm of records (DMSwarmMigrate of a DMSWARM_BASIC
 *     swarm, as the particles travel: any destination, count kept).
 *   - Arrive: each rank keeps one entry per local pair (newton on) and one per bond with a
 *     remote partner (newton off: the partner's rank keeps the same bond and adds the
 *     opposite force to its own particle), and matches the remote partners' gids to their
 *     owners with PetscSFCreateByMatchingIndices.
 * Nothing here runs on one rank: there the set-up's bonds are kept as they are, bit for bit. */
#include <spam/physics.h>
#include <spam/errors.h>

#define BOND_RECORD_FIELD "spam_bond" /* (holder gid, partner gid) */

PetscErrorCode SpamBondHaloDestroy(SpamBondHalo *bh)
{
  PetscFunctionBeginUser;
  if (bh->sf) PetscCallMPI(MPI_Type_free(&bh->unit));
  PetscCall(PetscSFDestroy(&bh->sf));
  PetscCall(PetscFree(bh->gid));
  PetscCall(PetscFree2(bh->xlocal, bh->xremote));
  PetscCall(DMDestroy(&bh->carrier));
  bh->nremote = 0;
  PetscFunctionReturn(0);
}

static PetscErrorCode CreateCarrier(SpamSim *sim, DM *carrier)
{
  PetscFunctionBeginUser;
  PetscCall(DMCreate(sim->p.comm, carrier));
  PetscCall(DMSetType(*carrier, DMSWARM));
  PetscCall(DMSetDimension(*carrier, sim->model.dim));
  PetscCall(DMSwarmSetType(*carrier, DMSWARM_BASIC));
  PetscCall(DMSwarmInitializeFieldRegister(*carrier));
  PetscCall(DMSwarmRegisterPetscDatatypeField(*carrier, BOND_RECORD_FIELD, 2, PETSC_INT64));
  PetscCall(DMSwarmFinalizeFieldRegister(*carrier));
  PetscCall(DMSwarmSetLocalSizes(*carrier, 0, 0));
  PetscFunctionReturn(0);
}

typedef struct {
  SpamSim        *sim;
  const PetscInt *dest;
} PackCtx;

static void PutRecord(PetscInt64 *rec, PetscInt *rank, PetscInt k, PetscInt64 holder, PetscInt64 partner, PetscInt to)
{
  rec[2 * k]     = holder;
  rec[2 * k + 1] = partner;
  rank[k]        = to;
}

/* The records of this rank's bonds into the carrier, each addressed to its holder's
 * destination (local phase). */
static PetscErrorCode Pack(void *ctx)
{
  SpamSim            *sim = ((PackCtx *)ctx)->sim;
  const PetscInt     *dest = ((PackCtx *)ctx)->dest;
  SpamPhysicsScratch *ps = sim->ps;
  DM                  carrier = ps->bond_halo.carrier;
  PetscInt64         *rec;
  PetscInt           *rank, nrec = 0, k = 0;

  PetscFunctionBeginUser;
  for (PetscInt i = 0; i < sim->p.n; i++)
    for (int b = ps->bond_start[i]; b < ps->bond_start[i + 1]; b++) nrec += ps->bond_nbr[b] < sim->p.n ? 2 : 1;
  PetscCall(DMSwarmSetLocalSizes(carrier, nrec, 0));
  PetscCall(DMSwarmGetField(carrier, BOND_RECORD_FIELD, NULL, NULL, (void **)&rec));
  PetscCall(DMSwarmGetField(carrier, DMSwarmField_rank, NULL, NULL, (void **)&rank));
  for (PetscInt i = 0; i < sim->p.n; i++)
    for (int b = ps->bond_start[i]; b < ps->bond_start[i + 1]; b++) {
      const int j = ps->bond_nbr[b];
      if (j < sim->p.n) {
        PutRecord(rec, rank, k++, sim->p.gid[i], sim->p.gid[j], dest[i]);
        PutRecord(rec, rank, k++, sim->p.gid[j], sim->p.gid[i], dest[j]);
      } else PutRecord(rec, rank, k++, sim->p.gid[i], ps->bond_halo.gid[j - sim->p.n], dest[i]);
    }
  PetscCall(DMSwarmRestoreField(carrier, DMSwarmField_rank, NULL, NULL, (void **)&rank));
  PetscCall(DMSwarmRestoreField(carrier, BOND_RECORD_FIELD, NULL, NULL, (void **)&rec));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamBondsDepart(SpamSim *sim, const PetscInt *dest)
{
  PackCtx ctx = {sim, dest};

  PetscFunctionBeginUser;
  if (!SpamBondsAny(sim)) PetscFunctionReturn(0); /* before the set-up made them */
  PetscCall(DMDestroy(&sim->ps->bond_halo.carrier));
  PetscCall(CreateCarrier(sim, &sim->ps->bond_halo.carrier));
  PetscCall(SpamRunAgreed(sim->p.comm, PETSC_FALSE, Pack, &ctx));
  /* Sent records stay (as the particles do: local_order.c says why PETSc's removal is
   * slow); Arrive keeps only those addressed to this rank. */
  PetscCall(DMSwarmMigrate(sim->ps->bond_halo.carrier, PETSC_FALSE));
  PetscFunctionReturn(0);
}

/* The local particle of gid g (binary search in gid order), or -1. */
static PetscInt LocalOf(const SpamSim *sim, PetscInt64 g)
{
  PetscInt lo = 0, hi = sim->p.n - 1;

  while (lo <= hi) {
    const PetscInt   mid = lo + (hi - lo) / 2, i = SpamSimAtRow(sim, mid);
    const PetscInt64 gm  = sim->p.gid[i];
    if (gm == g) return i;
    if (gm < g) lo = mid + 1;
    else hi = mid - 1;
  }
  return -1;
}

/* A bond this rank keeps: its local particle, the partner's gid and local index (-1:
 * remote). */
typedef struct {
  PetscInt   i, j;
  PetscInt64 partner;
} Entry;

static int CompareEntries(const void *a, const void *b)
{
  const Entry *p = a, *q = b;
  if (p->i != q->i) return p->i < q->i ? -1 : 1;
  return (p->partner > q->partner) - (p->partner < q->partner);
}

static int CompareGids(const void *a, const void *b)
{
  const PetscInt64 p = *(const PetscInt64 *)a, q = *(const PetscInt64 *)b;
  return (p > q) - (p < q);
}

/* The slot of remote gid g among the sorted gids of the bond halo. */
static PetscInt SlotOf(const SpamBondHalo *bh, PetscInt64 g)
{
  const PetscInt64 *hit = bsearch(&g, bh->gid, (size_t)bh->nremote, sizeof g, CompareGids);
  return (PetscInt)(hit - bh->gid);
}

/* The kept entries of the arrived records: those addressed to this rank, one per local
 * pair (from its lower local index) and one per bond with a remote partner. */
static PetscErrorCode Entries(SpamSim *sim, Entry **entry, PetscInt *nentry)
{
  DM          carrier = sim->ps->bond_halo.carrier;
  PetscMPIInt me;
  PetscInt64 *rec;
  PetscInt   *rank, nrec, m = 0;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(sim->p.comm, &me));
  PetscCall(DMSwarmGetLocalSize(carrier, &nrec));
  PetscCall(PetscMalloc1(nrec + 1, entry));
  PetscCall(DMSwarmGetField(carrier, BOND_RECORD_FIELD, NULL, NULL, (void **)&rec));
  PetscCall(DMSwarmGetField(carrier, DMSwarmField_rank, NULL, NULL, (void **)&rank));
  for (PetscInt k = 0; k < nrec; k++) {
    Entry e;
    if (rank[k] != me) continue; /* sent away */
    e.i       = LocalOf(sim, rec[2 * k]);
    e.partner = rec[2 * k + 1];
    e.j       = LocalOf(sim, e.partner);
    PetscCheck(e.i >= 0, PETSC_COMM_SELF, PETSC_ERR_PLIB, "a spring bond of particle %" PetscInt64_FMT " arrived where the particle is not", rec[2 * k]);
    if (e.j < 0 || e.i < e.j) (*entry)[m++] = e;
  }
  PetscCall(DMSwarmRestoreField(carrier, DMSwarmField_rank, NULL, NULL, (void **)&rank));
  PetscCall(DMSwarmRestoreField(carrier, BOND_RECORD_FIELD, NULL, NULL, (void **)&rec));
  qsort(*entry, (size_t)m, sizeof **entry, CompareEntries);
  *nentry = m;
  PetscFunctionReturn(0);
}

/* The remote partners' gids, once each and increasing. */
static PetscErrorCode RemoteGids(SpamBondHalo *bh, const Entry *entry, PetscInt m)
{
  int n = 0;

  PetscFunctionBeginUser;
  PetscCall(PetscFree(bh->gid));
  PetscCall(PetscMalloc1(m + 1, &bh->gid));
  for (PetscInt k = 0; k < m; k++)
    if (entry[k].j < 0) bh->gid[n++] = entry[k].partner;
  qsort(bh->gid, (size_t)n, sizeof *bh->gid, CompareGids);
  bh->nremote = 0;
  for (int k = 0; k < n; k++)
    if (!bh->nremote || bh->gid[k] != bh->gid[bh->nremote - 1]) bh->gid[bh->nremote++] = bh->gid[k];
  PetscFunctionReturn(0);
}

/* The CSR of the kept bonds in the new local order (local phase). */
static PetscErrorCode Unpack(void *ctx)
{
  SpamSim            *sim = ctx;
  SpamPhysicsScratch *ps  = sim->ps;
  SpamBondHalo       *bh  = &ps->bond_halo;
  Entry              *entry;
  PetscInt            m;

  PetscFunctionBeginUser;
  PetscCall(Entries(sim, &entry, &m));
  PetscCall(RemoteGids(bh, entry, m));
  PetscCall(PetscFree(ps->bond_start));
  PetscCall(PetscFree(ps->bond_nbr));
  PetscCall(PetscCalloc1(sim->p.n + 1, &ps->bond_start));
  PetscCall(PetscMalloc1(m + 1, &ps->bond_nbr));
  for (PetscInt k = 0; k < m; k++) {
    ps->bond_start[entry[k].i + 1]++;
    ps->bond_nbr[k] = (int)(entry[k].j >= 0 ? entry[k].j : sim->p.n + SlotOf(bh, entry[k].partner));
  }
  for (PetscInt i = 0; i < sim->p.n; i++) ps->bond_start[i + 1] += ps->bond_start[i];
  ps->nbonds = (int)m;
  PetscCall(PetscFree2(bh->xlocal, bh->xremote));
  PetscCall(PetscMalloc2((size_t)sim->p.n * sim->model.dim + 1, &bh->xlocal, (size_t)bh->nremote * sim->model.dim + 1, &bh->xremote));
  PetscCall(PetscFree(entry));
  PetscFunctionReturn(0);
}

/* The graph from the local particles (roots, by gid) to the remote slots (leaves), over
 * the gid space; every remote partner must be found (collective). */
static PetscErrorCode Connect(SpamSim *sim)
{
  SpamBondHalo *bh = &sim->ps->bond_halo;
  PetscLayout   layout;
  PetscInt     *roots, *leaves, nleaves;
  int           mine, all;

  PetscFunctionBeginUser;
  PetscCheck(sim->p.nglobal <= PETSC_MAX_INT, sim->p.comm, PETSC_ERR_SUP, "spring bonds across ranks match gids as PetscInt: at most %" PetscInt_FMT " particles", (PetscInt)PETSC_MAX_INT);
  if (bh->sf) PetscCallMPI(MPI_Type_free(&bh->unit));
  PetscCall(PetscSFDestroy(&bh->sf));
  PetscCall(PetscMalloc2(sim->p.n + 1, &roots, bh->nremote + 1, &leaves));
  for (PetscInt i = 0; i < sim->p.n; i++) roots[i] = (PetscInt)sim->p.gid[i];
  for (int k = 0; k < bh->nremote; k++) leaves[k] = (PetscInt)bh->gid[k];
  PetscCall(PetscLayoutCreate(sim->p.comm, &layout));
  PetscCall(PetscLayoutSetSize(layout, sim->p.nglobal));
  PetscCall(PetscLayoutSetUp(layout));
  PetscCall(PetscSFCreateByMatchingIndices(layout, sim->p.n, roots, NULL, 0, bh->nremote, leaves, NULL, 0, NULL, &bh->sf));
  PetscCall(PetscLayoutDestroy(&layout));
  PetscCall(PetscFree2(roots, leaves));
  PetscCallMPI(MPI_Type_contiguous(sim->model.dim, MPI_DOUBLE, &bh->unit));
  PetscCallMPI(MPI_Type_commit(&bh->unit));
  PetscCall(PetscSFGetGraph(bh->sf, NULL, &nleaves, NULL, NULL));
  mine = nleaves == bh->nremote;
  PetscCallMPI(MPIU_Allreduce(&mine, &all, 1, MPI_INT, MPI_LAND, sim->p.comm));
  PetscCheck(all, sim->p.comm, PETSC_ERR_PLIB, "a spring bond's partner is held by no rank");
  PetscFunctionReturn(0);
}

PetscErrorCode SpamBondsArrive(SpamSim *sim)
{
  PetscFunctionBeginUser;
  if (!SpamBondsAny(sim)) PetscFunctionReturn(0);
  PetscCall(SpamRunAgreed(sim->p.comm, PETSC_FALSE, Unpack, sim));
  PetscCall(DMDestroy(&sim->ps->bond_halo.carrier));
  PetscCall(Connect(sim));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamBondsGather(SpamSim *sim, const double *x, int stride)
{
  SpamBondHalo *bh  = &sim->ps->bond_halo;
  const int     dim = sim->model.dim;

  PetscFunctionBeginUser;
  if (!bh->sf) PetscFunctionReturn(0);
  for (PetscInt i = 0; i < sim->p.n; i++)
    for (int d = 0; d < dim; d++) bh->xlocal[(size_t)i * dim + d] = x[(size_t)i * stride + d];
  PetscCall(PetscSFBcastBegin(bh->sf, bh->unit, bh->xlocal, bh->xremote, MPI_REPLACE));
  PetscCall(PetscSFBcastEnd(bh->sf, bh->unit, bh->xlocal, bh->xremote, MPI_REPLACE));
  PetscFunctionReturn(0);
}
