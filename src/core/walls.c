/* Mirror walls: the options of each face and their checks (walls.h). */
#include <spam/walls.h>
#include <spam/errors.h>

const char *const SpamWallSlipNames[] = {"none", "noslip", "freeslip"};
const char *const SpamFaceNames[]     = {"xlo", "xhi", "ylo", "yhi", "zlo", "zhi"};

PetscBool SpamWallsAny(const SpamWalls *w, int dim)
{
  for (int f = 0; f < 2 * dim; f++)
    if (SpamWallOn(w, f)) return PETSC_TRUE;
  return PETSC_FALSE;
}

/* -wall_F: the condition of face F. */
static PetscErrorCode FaceSlip(int f, SpamWalls *w)
{
  char opt[32], help[160], val[64] = "none", title[64];

  PetscFunctionBeginUser;
  (void)snprintf(opt, sizeof opt, "-wall_%s", SpamFaceNames[f]);
  (void)snprintf(title, sizeof title, "Mirror wall %s (CiSE 2001 Fig. 4)", SpamFaceNames[f]);
  (void)snprintf(help, sizeof help, "Mirror wall on the %s face: noslip, freeslip or none (the direction is then periodic or open as the scene has it)", SpamFaceNames[f]);
  PetscOptionsBegin(PETSC_COMM_WORLD, NULL, title, "spam-ark");
  PetscCall(PetscOptionsString(opt, help, "README", val, val, sizeof val, &w->slip_given[f]));
  PetscOptionsEnd();
  w->slip[f] = SPAM_WALL_NONE;
  for (int k = 0; k < 3; k++)
    if (!strcmp(val, SpamWallSlipNames[k])) w->slip[f] = (SpamWallSlip)k;
  if (strcmp(val, SpamWallSlipNames[w->slip[f]])) {
    char shown[80];
    SpamClip(val, shown, sizeof shown);
    SPAM_BAD_INPUT(opt, shown, "allowed: noslip, freeslip, none");
  }
  PetscFunctionReturn(0);
}

/* -wall_F_velocity and -wall_F_temperature. */
static PetscErrorCode FaceValues(int dim, int f, SpamWalls *w)
{
  char      opt[40], help[200], val[128], title[64], ttitle[64];
  PetscReal v[16] = {0};
  PetscInt  nv    = 16;

  PetscFunctionBeginUser;
  (void)snprintf(opt, sizeof opt, "-wall_%s_velocity", SpamFaceNames[f]);
  (void)snprintf(title, sizeof title, "Mirror wall %s: velocity", SpamFaceNames[f]);
  (void)snprintf(ttitle, sizeof ttitle, "Mirror wall %s: temperature", SpamFaceNames[f]);
  (void)snprintf(help, sizeof help, "Velocity of the %s wall (-dim values, along the wall; a no-slip wall drags the fluid with it) (default 0)", SpamFaceNames[f]);
  PetscOptionsBegin(PETSC_COMM_WORLD, NULL, title, "spam-ark");
  PetscCall(PetscOptionsRealArray(opt, help, "README", v, &nv, &w->velocity_given[f]));
  PetscOptionsEnd();
  if (w->velocity_given[f]) {
    PetscCall(SpamOptionText(opt, v[0], val, sizeof val));
    if (nv != dim) SPAM_BAD_INPUT(opt, val, "takes %d values (-dim %d); %" PetscInt_FMT " given", dim, dim, nv);
    for (int d = 0; d < dim; d++)
      if (!isfinite(v[d]) || fabs(v[d]) > 1e100) SPAM_BAD_INPUT(opt, val, "every value must be a finite number below 1e100 in size");
    if (v[f / 2] != 0.0) SPAM_BAD_INPUT(opt, val, "a wall moves along itself: its component %d (normal to the %s face) must be 0", f / 2 + 1, SpamFaceNames[f]);
  }
  for (int d = 0; d < 3; d++) w->velocity[f][d] = d < dim ? v[d] : 0.0;
  (void)snprintf(opt, sizeof opt, "-wall_%s_temperature", SpamFaceNames[f]);
  (void)snprintf(help, sizeof help, "Temperature T = (gamma-1) e of an isothermal %s wall (default: adiabatic, no heat crosses it)", SpamFaceNames[f]);
  w->temperature[f] = 0.0;
  PetscOptionsBegin(PETSC_COMM_WORLD, NULL, ttitle, "spam-ark");
  PetscCall(PetscOptionsReal(opt, help, "README", w->temperature[f], &w->temperature[f], &w->temperature_given[f]));
  PetscOptionsEnd();
  w->isothermal[f] = w->temperature_given[f];
  PetscCall(SpamOptionText(opt, w->temperature[f], val, sizeof val));
  if (w->isothermal[f] && !(w->temperature[f] > 0.0 && w->temperature[f] < 1e100)) SPAM_BAD_INPUT(opt, val, "must be a positive finite temperature");
  PetscFunctionReturn(0);
}

PetscErrorCode SpamWallsOptions(int dim, SpamWalls *w)
{
  PetscBool help = PETSC_FALSE;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(w, sizeof *w));
  PetscCall(PetscOptionsHasHelp(NULL, &help));
  for (int f = 0; f < (help ? SPAM_FACES : 2 * dim); f++) {
    PetscCall(FaceSlip(f, w));
    PetscCall(FaceValues(help ? 3 : dim, f, w));
  }
  PetscFunctionReturn(0);
}
