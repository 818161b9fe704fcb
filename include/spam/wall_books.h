/* The books of the mirror walls: what each wall gives the fluid. A ghost mirrored in a
 * wall stands for the boundary, so what its pairs did to it (its slots' accumulations,
 * not folded) is the reaction of what the wall did to the fluid: for the pair (i, g)
 * the momentum and energy exchanged cancel as between any two particles, so the wall's
 * force on the fluid is -m_g a_g, its mechanical power -m_g (v_g.a_g + de_g/dt by work)
 * and its heat -m_g de_g/dt by conduction, summed over its ghosts. A ghost mirrored in
 * two or three walls (a corner) is booked to the one whose condition sets its exchange:
 * isothermal first, then moving, else its lowest mirrored direction's (wall_books.c). */
#ifndef SPAM_WALL_BOOKS_H
#define SPAM_WALL_BOOKS_H
#include <spam/fields.h>
#include <spam/ghosts.h>
#include <spam/layout.h>

typedef struct {
  double    force[SPAM_FACES][3]; /* force of each wall on the fluid                      */
  double    work[SPAM_FACES];     /* mechanical power into the fluid                      */
  double    heat[SPAM_FACES];     /* conducted power into the fluid                       */
  PetscBool energy;               /* work and heat are booked (the energy equation's models) */
} SpamWallRates;

/* This rank's rates of the last pass into r (its mirror images' share: the rates of the
 * walls are their sum over ranks), and where the layout carries books (l->wb >= 0) each
 * ghost's share into its source's rows of ydot (work, heat, impulse), on the source's
 * owner: their sum over particles integrates to the walls' totals. f holds the pass's
 * accumulations on the ghost slots: acc always, and with the energy equation v, edot
 * (work) and qdot. Collective where the state carries books. */
PetscErrorCode SpamWallBooks(const SpamGhosts *g, const SpamFields *f, const SpamLayout *l, int n, PetscBool energy, SpamWallRates *r, double *ydot);
#endif
