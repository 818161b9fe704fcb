/* Plane Poiseuille flow: a viscous gas between no-slip walls at rest at
 * y = 0 and y = H, periodic along x, driven by a uniform body force g along x (the scene's
 * default gravity; -gravity overrides it). From rest it reaches, over the time H^2/nu, the
 * exact steady profile v_x = g / (2 nu) y (H - y), peak g H^2 / (8 nu) at mid-channel; the
 * walls then hold the whole body force: their drag sums to -g M. -poiseuille_speed sets
 * that peak, so g = 8 nu U / H^2 keeps the Mach number at any resolution. The start-up
 * follows the series v_x = g/(2 nu) y (H - y) - sum over odd k of
 * 4 g H^2 / (nu k^3 pi^3) sin(k pi y / H) exp(-k^2 pi^2 nu t / H^2). */
#include <spam/scene.h>
#include <spam/errors.h>

/* The channel's options (shear_channel.c reads them). */
static const SpamSceneOption Table[] = {
  {"poiseuille_speed", SPAM_SCENE_OPTION_REAL, "Steady peak speed U: the driving g = 8 nu U / H^2 along x is the default of -gravity; below the sound speed", NULL},
  {"poiseuille_n", SPAM_SCENE_OPTION_INT, "Lattice rows across the channel: its width H = n (unit spacing)", NULL},
  {"poiseuille_nx", SPAM_SCENE_OPTION_INT, "Lattice columns along the periodic x (and z) (0: n, at least 2 (h + skin))", NULL},
  {"poiseuille_start", SPAM_SCENE_OPTION_STRING, "Initial velocity: rest, or parabolic (the exact steady profile)", NULL},
  {NULL, SPAM_SCENE_OPTION_INT, NULL, NULL},
};

static PetscErrorCode Options(const SpamCommonParams *c, void *p, SpamSolidParams *solid)
{
  SpamShearParams *q = p;

  PetscFunctionBeginUser;
  SpamShearChannelDefaults(c, solid);
  PetscCall(SpamShearChannelOptions(c, "poiseuille", "parabolic", Table, q));
  PetscFunctionReturn(0);
}

static PetscErrorCode Build(const SpamCommonParams *c, const void *p, const SpamSolidParams *solid, SpamParticles *out)
{
  const SpamShearParams *q   = p;
  const int              dim = c->dim;
  const double           H   = (double)q->n;
  double                 nu, cs, g;
  char                   line[320], val[64];
  PetscBool              speed_set;

  PetscFunctionBeginUser;
  PetscCall(PetscOptionsHasName(NULL, NULL, "-poiseuille_speed", &speed_set));
  PetscCall(SpamOptionText("-poiseuille_speed", q->speed, val, sizeof val));
  if (speed_set && c->gravity_given) SPAM_BAD_INPUT("-poiseuille_speed", val, "-gravity is given too and sets the driving force: give one of them");
  PetscCall(SpamShearChannelCheck("poiseuille", q, solid, &nu, &cs));
  PetscCall(SpamShearChannelBuild(c, "poiseuille", q, out));
  PetscCall(SpamShearLatticeNote(c, solid, "poiseuille"));
  out->gravity[0]  = 8.0 * nu * q->speed / (H * H);
  out->gravity_set = PETSC_TRUE;
  g                = c->gravity_given ? c->gravity[0] : out->gravity[0];
  if (q->steady_start)
    for (PetscInt i = 0; i < out->n; i++) {
      const double y = out->x[i * dim + 1];
      out->v[i * dim] = 0.5 * g / nu * y * (H - y);
    }
  (void)snprintf(line, sizeof line, "poiseuille: H = %g, g = %.6g, nu = %g, peak speed g H^2/(8 nu) = %.6g, Re = U H / nu = %.4g, Mach U / c = %.4g, diffusion time H^2/nu = %.6g\n", H, g, nu, g * H * H / (8.0 * nu), g * H * H * H / (8.0 * nu * nu), fabs(g * H * H / (8.0 * nu)) / cs, H * H / nu);
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "%s", line));
  out->info.sound_traversal_time = H / cs;
  out->info.t_end_default        = H * H / nu; /* the slowest transient is down to exp(-pi^2) */
  PetscFunctionReturn(0);
}

PetscErrorCode SpamScenePoiseuille(SpamSceneOps *ops)
{
  PetscFunctionBeginUser;
  *ops = (SpamSceneOps){"poiseuille", 4 | 8, PETSC_FALSE, Table, sizeof(SpamShearParams), PETSC_FALSE, NULL, Options, Build};
  PetscFunctionReturn(0);
}
