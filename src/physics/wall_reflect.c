/* Particles that crossed a mirror wall during a step are put back by reflection. Within a
 * step a particle beyond a wall still meets its own image (now inside the box) and the
 * images of its neighbours, which push it back; but a fast, sparse front (an expansion
 * reaching a wall) can end a step beyond it. Reflecting it (position mirrored in the
 * wall, normal velocity reversed) is what an elastic wall would do; the step is then a
 * jump of the state, counted in summary.json's post_step_jumps, and the integrator
 * restarts from it. Where the state carries the walls' books, the reflection's impulse
 * -2 m v_n goes into them, and so does its change of gravity's energy -m g.(x' - x) (the
 * kinetic energy is unchanged), so that E(t) - E(0) still equals what the walls gave. */
#include <spam/physics.h>

PetscErrorCode SpamWallReflect(SpamSim *sim, double *y, PetscInt *changed)
{
  const SpamLayout *l = &sim->model.layout;
  const SpamWalls  *w = &sim->geo.walls;

  PetscFunctionBeginUser;
  *changed = 0;
  for (PetscInt i = 0; i < sim->p.n; i++) {
    double *p = y + (size_t)i * l->nvar;
    for (int d = 0; d < sim->model.dim; d++) {
      const double lo = sim->geo.box.lo[d], hi = lo + sim->geo.box.len[d];
      const double x = p[l->x + d];
      if (SpamWallOn(w, 2 * d) && x < lo) p[l->x + d] = 2.0 * lo - x;
      else if (SpamWallOn(w, 2 * d + 1) && x > hi) p[l->x + d] = 2.0 * hi - x;
      else continue;
      if (l->wb >= 0) {
        p[l->wb] -= sim->pair.f.m[i] * sim->model.gravity[d] * (p[l->x + d] - x);
        p[l->wb + 2 + d] -= 2.0 * sim->pair.f.m[i] * p[l->v + d];
      }
      p[l->v + d] = -p[l->v + d];
      (*changed)++;
    }
  }
  PetscFunctionReturn(0);
}
