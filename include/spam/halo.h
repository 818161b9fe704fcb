/* Halo of a rank: the other ranks' particles (and their images) within the list range of
 * this rank's particles, as remote ghost slots, exchanged through one PetscSF (roots: the
 * ghost slots on the receiver; leaves: the (particle, image) items on the sender, one leaf
 * per root). Chosen at every list build, which is collective (halo_select.c): every rank
 * sends each other rank the cells of a grid (at least rc wide) that its particles occupy
 * near that rank's bounding box, and sends particle i as image code s per direction to rank
 * r when the image lies within rc of a cell r occupies. The codes: s in {-1,0,1} is the
 * periodic image u + s L along a direction whose periodicity is made by ghost images (0
 * along the others; along a periodic direction kept by the minimum image the distance is
 * the periodic one); SPAM_HALO_MIRROR_LO and _HI are the mirror images -u and 2L - u in a
 * wall of the lower or upper face (walls.h), for the faces in `walls`. Items in (rank,
 * particle, code) order; a receiver lays its ghost slots out by sender rank, then in the
 * sender's item order. A rank sends itself nothing: its own periodic and mirror images are
 * the local ghosts of ghosts.h.
 *
 * The exchange of fields is forward (owner -> ghost slot, PetscSFReduce with MPI_REPLACE):
 * a rank computes its own particles' pairs with remote ghosts (newton off across ranks).
 * Only the walls' per-particle books go back (SpamHaloReverseAdd): a mirror image's share
 * belongs to its source, on the owner. On one rank (or a communicator of size one) nothing
 * is set up and every call returns at once. Cost of a build: O(n) cell lookups, O(cells x
 * ranks) box tests of occupied cells, three MPI_Alltoall(v) (PetscCommBuildTwoSided would
 * scale to many ranks). */
#ifndef SPAM_HALO_H
#define SPAM_HALO_H
#include <petscsf.h>
#include <spam/box.h>

/* The widest value a forward exchange carries: a 3 x 3 tensor. */
#define SPAM_HALO_MAX_COMP 9

/* Image codes of a direction besides the periodic shifts -1, 0, 1: the mirror image in the
 * lower face's wall (-u) and in the upper face's (2L - u). */
#define SPAM_HALO_MIRROR_LO 2
#define SPAM_HALO_MIRROR_HI 3

/* The coordinate of image code s of a box-local coordinate u along an edge L. */
static inline double SpamHaloImage(int s, double u, double L)
{
  return s == SPAM_HALO_MIRROR_LO ? -u : s == SPAM_HALO_MIRROR_HI ? 2.0 * L - u : u + s * L;
}

/* What the choice of a build keeps (halo_select.c): maps over the cells of the grid,
 * -1 and 0 between builds, and the cells each rank occupies. */
typedef struct {
  long           ncells;           /* room in the maps                                    */
  int           *head;             /* [ncells] first pool entry of a cell's ranks, or -1  */
  unsigned char *near;             /* [ncells] another rank's cell is within one cell     */
  int           *pool_rank, *pool_next, poolcap; /* the received cells' (rank, next)      */
  long          *occ;              /* this rank's occupied cells                          */
  double        *obox;             /* [occcap * 6] the box of this rank's particles in each */
  int            nocc, occcap;
  double        *scells, *rcells;  /* cells sent to / received from the other ranks: key, box */
  int            skcap, rkcap;
  PetscMPIInt   *scnt, *rcnt, *soff, *rcoff; /* per rank; rcoff[size] the total           */
  long          *stamp;            /* [size] the last image sent to each rank             */
} SpamHaloCells;

typedef struct {
  PetscBool     active;      /* a communicator of two ranks or more was set               */
  MPI_Comm      comm;
  PetscMPIInt   size, rank;
  double        len[3];      /* box edges of the last build: a shift s is s * len          */
  unsigned      walls;       /* bit f: face f has a mirror wall (set before a build)       */
  double        depth[6];    /* how far beyond face f a particle may stand (ghosts.h)      */
  PetscSF       sf;          /* NULL until the first build                               */
  /* Items this rank sends, in (rank, particle, shift) order. */
  int           nitems, icap;
  int          *item_src;    /* [icap] local particle                                    */
  int          *item_rank;   /* [icap] destination (while the items are chosen)          */
  signed char (*item_shift)[3]; /* [icap] image code s per direction                     */
  double       *sendbuf;     /* [icap * SPAM_HALO_MAX_COMP] packed values of one exchange */
  /* Remote ghost slots this rank receives, by sender rank. */
  int           nghost, gcap;
  int          *ghost_owner; /* [gcap] owner rank                                        */
  int          *ghost_index; /* [gcap] the owner's local index at the build              */
  signed char (*ghost_shift)[3]; /* [gcap] image code s (the slot holds SpamHaloImage)    */
  double       *recvbuf;     /* [gcap * SPAM_HALO_MAX_COMP] positions, build data, books   */
  /* Per rank (size): bounding boxes, counts and block offsets of a build. */
  double       *boxes;       /* [size * 6] lo[3], hi[3] of every rank's particles         */
  SpamHaloCells sel;         /* the choice's cells                                       */
  PetscMPIInt  *scount, *rcount, *roff, *soff;
  MPI_Datatype  unit[SPAM_HALO_MAX_COMP + 1]; /* unit[c]: c contiguous doubles            */
  MPI_Datatype  unit_cell;   /* a cell of the choice: key and box, 7 doubles             */
  long          builds;      /* statistics                                               */
} SpamHalo;

/* Uses comm for the halo (before the first build); a communicator of one rank sets up
 * nothing. A zeroed SpamHalo is inactive. */
PetscErrorCode SpamHaloSetComm(SpamHalo *h, MPI_Comm comm);
PetscErrorCode SpamHaloDestroy(SpamHalo *h);
static inline PetscBool SpamHaloActive(const SpamHalo *h)
{
  return h->active;
}
/* Collective. Chooses the items to send and the remote ghost slots to receive for the n
 * local particles at box-local positions u[d][i] (wrapped into the box at this build),
 * with list range rc. ghost_periodic[d]: direction d's periodicity is made by ghost images
 * (shifts s = -1, 0, 1), otherwise a periodic direction of box uses the minimum image. */
PetscErrorCode SpamHaloSelect(SpamHalo *h, const SpamBox *box, const PetscBool ghost_periodic[3], int n, double *const u[3], double rc);
/* Collective. Positions of the remote ghost slots: dst[d][k] = SpamHaloImage(s_d, u_owner[d],
 * L_d) for the remote slot k (the caller passes its arrays offset to the first remote slot). */
PetscErrorCode SpamHaloForwardPositions(const SpamHalo *h, int dim, double *const u[3], double *const dst[3]);
/* Collective. ncomp values per particle (1 .. SPAM_HALO_MAX_COMP) from each owner's field
 * to the remote slots: dst[k * ncomp + c] = field_owner[i_k * ncomp + c]. */
PetscErrorCode SpamHaloForward(const SpamHalo *h, int ncomp, const double *field, double *dst);
/* Collective. The reverse: ncomp values of each remote slot k (slots[k * ncomp + c]) are
 * added on its owner to base[i_k * stride + c], in the owner's item order. */
PetscErrorCode SpamHaloReverseAdd(const SpamHalo *h, int ncomp, const double *slots, double *base, size_t stride);
#endif
