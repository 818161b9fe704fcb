/* The halo's choice of items at a build (halo_select.c), for halo.c. */
#ifndef SPAM_HALO_SELECT_H
#define SPAM_HALO_SELECT_H
#include <spam/halo.h>

/* Collective. Fills h->nitems, item_src, item_shift (in (rank, particle, code) order) and
 * scount[r] for the n local particles at box-local u, with list range rc. */
PetscErrorCode SpamHaloChooseItems(SpamHalo *h, const SpamBox *box, const PetscBool gper[3], int n, double *const u[3], double rc);
/* Room for `need` items, the ones chosen so far kept (at builds only; grows by half). */
PetscErrorCode SpamHaloGrowItems(SpamHalo *h, int need);
/* Frees what the choice keeps between builds. */
PetscErrorCode SpamHaloCellsDestroy(SpamHaloCells *c);
#endif
