/* Plane Couette flow: a viscous gas between a no-slip wall at rest at
 * y = 0 and one at y = H moving at (U, 0), periodic along x. From rest the flow diffuses
 * in over the time H^2/nu to the exact steady profile v_x = U y / H, whose shear stress
 * eta U / H is uniform: the wall at y = H is dragged back by eta U L / H, the one at y = 0
 * forward by as much. The steady profile does not depend on the temperature (eta is
 * constant), so the walls may stay adiabatic: the viscous heating raises e by
 * eta (U/H)^2 t / rho, about 2 U^2 of e per diffusion time H^2/nu (1% at U = 0.1). */
#include <spam/scene.h>
#include <spam/errors.h>

/* The channel's options (shear_channel.c reads them). */
static const SpamSceneOption Table[] = {
  {"couette_speed", SPAM_SCENE_OPTION_REAL, "Speed U of the upper wall along x (the default of -wall_yhi_velocity U,0); below the sound speed", NULL},
  {"couette_n", SPAM_SCENE_OPTION_INT, "Lattice rows across the channel: its width H = n (unit spacing)", NULL},
  {"couette_nx", SPAM_SCENE_OPTION_INT, "Lattice columns along the periodic x (and z) (0: n, at least 2 (h + skin))", NULL},
  {"couette_start", SPAM_SCENE_OPTION_STRING, "Initial velocity: rest, or linear (the exact steady profile)", NULL},
  {NULL, SPAM_SCENE_OPTION_INT, NULL, NULL},
};

static PetscErrorCode Options(const SpamCommonParams *c, void *p, SpamSolidParams *solid)
{
  SpamShearParams *q = p;

  PetscFunctionBeginUser;
  SpamShearChannelDefaults(c, solid);
  PetscCall(SpamShearChannelOptions(c, "couette", "linear", Table, q));
  PetscFunctionReturn(0);
}

static PetscErrorCode Build(const SpamCommonParams *c, const void *p, const SpamSolidParams *solid, SpamParticles *out)
{
  const SpamShearParams *q   = p;
  const int              dim = c->dim, yhi = 3;
  const double           H   = (double)q->n;
  double                 nu, cs, U;
  char                   line[320], val[64];
  PetscBool              speed_set;

  PetscFunctionBeginUser;
  PetscCall(PetscOptionsHasName(NULL, NULL, "-couette_speed", &speed_set));
  PetscCall(SpamOptionText("-couette_speed", q->speed, val, sizeof val));
  if (speed_set && c->walls.velocity_given[yhi]) SPAM_BAD_INPUT("-couette_speed", val, "-wall_yhi_velocity is given too and sets the upper wall's velocity: give one of them");
  PetscCall(SpamShearChannelCheck("couette", q, solid, &nu, &cs));
  PetscCall(SpamShearChannelBuild(c, "couette", q, out));
  PetscCall(SpamShearLatticeNote(c, solid, "couette"));
  if (!c->walls.velocity_given[yhi]) out->walls.velocity[yhi][0] = q->speed;
  U = c->walls.velocity_given[yhi] ? c->walls.velocity[yhi][0] : q->speed;
  if (q->steady_start)
    for (PetscInt i = 0; i < out->n; i++) out->v[i * dim] = U * out->x[i * dim + 1] / H;
  (void)snprintf(line, sizeof line, "couette: H = %g, U = %g, nu = %g, Re = U H / nu = %.4g, Mach U / c = %.4g, diffusion time H^2/nu = %.6g, wall shear stress eta U / H = %.6g\n", H, U, nu, U * H / nu, fabs(U) / cs, H * H / nu, solid->shear_visc * U / H);
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "%s", line));
  out->info.sound_traversal_time = H / cs;
  out->info.t_end_default        = H * H / nu; /* the slowest transient is down to exp(-pi^2) */
  PetscFunctionReturn(0);
}

PetscErrorCode SpamSceneCouette(SpamSceneOps *ops)
{
  PetscFunctionBeginUser;
  *ops = (SpamSceneOps){"couette", 4 | 8, PETSC_FALSE, Table, sizeof(SpamShearParams), PETSC_FALSE, NULL, Options, Build};
  PetscFunctionReturn(0);
}
