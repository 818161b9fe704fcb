/* Cells of a given width over the box, and the keys that order them: the local order of
 * the particles (row by row in 1D and 2D, a Morton curve in 3D: particle_order.c says
 * why) and a Hilbert curve, whose consecutive cells are face neighbours, so that a piece
 * of it cut out for one rank is compact (decompose.c). */
#ifndef SPAM_CELL_KEYS_H
#define SPAM_CELL_KEYS_H
#include <stdint.h>
#include <spam/box.h>

#define SPAM_CELL_MAX_PER_DIM 2097152 /* 2^21: three 21-bit coordinates fill a 63-bit key */

typedef struct {
  int    dim;
  int    ncell[3]; /* cells per direction, 1 .. 2^21                                */
  int    bits;     /* Hilbert bits per direction: 2^bits >= every ncell[d]         */
} SpamCellGrid;

/* Cells of at least `width` (as many as fit, at least one) along each edge of the box. */
void SpamCellGridInit(const SpamBox *box, double width, SpamCellGrid *g);
/* Cell coordinates of point x: wrapped in periodic directions, clamped into the edge
 * cells otherwise; a non-finite coordinate gives cell 0 (callers check finiteness). */
void SpamCellOf(const SpamCellGrid *g, const SpamBox *box, const double *x, int c[3]);
/* Key of the local particle order: row-major (y, then x) in 1D and 2D, Morton in 3D. */
uint64_t SpamCellOrderKey(const SpamCellGrid *g, const int c[3]);
/* Position of the cell along a Hilbert curve through the 2^bits cube (< 2^(dim bits)). */
uint64_t SpamCellHilbertKey(const SpamCellGrid *g, const int c[3]);
#endif
