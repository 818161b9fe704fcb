/* PETSc's own explicit methods as spam-ark runs them (rk, ssp, euler): their rows of the
 * table of methods (ts_family.h). PETSc owns their implementations; what is ours is the
 * sub-type lists we accept, the deterministic sums of rk and the checks of its adaptor. */
#include "ts_family.h"
#include <spam/errors.h>

static const char *const RkTypes[]  = {"1fe", "2a", "2b", "3", "3bs", "4", "5f", "5dp", "5bs", "6vr", "7vr", "8vr"};
static const char *const SspTypes[] = {"rks2", "rks3", "rk104"};

static PetscErrorCode SubTypeRK(TS ts, const char **sub)
{
  PetscFunctionBeginUser;
  PetscCall(TSRKGetType(ts, sub));
  PetscFunctionReturn(0);
}

static PetscErrorCode SubTypeSSP(TS ts, const char **sub)
{
  PetscFunctionBeginUser;
  PetscCall(TSSSPGetType(ts, sub));
  PetscFunctionReturn(0);
}

/* Whether the rk scheme has dense-output coefficients (TSInterpolate_RK refuses a scheme
 * without). In 3.18 every scheme with an embedded estimate (2a, 3bs, 5f, 5dp, 5bs, 6vr,
 * 7vr, 8vr) has them; the others take fixed steps, which land on the outputs. */
static PetscErrorCode InterpolatesRK(TS ts, PetscBool *yes)
{
  const PetscReal *binterp;

  PetscFunctionBeginUser;
  PetscCall(TSRKGetTableau(ts, NULL, NULL, NULL, NULL, NULL, NULL, &binterp, NULL));
  *yes = (PetscBool)(binterp != NULL);
  PetscFunctionReturn(0);
}

/* An rk scheme without an embedded method cannot control its error: PETSc picks no
 * adaptor for it, but one asked for explicitly would fail in the middle of the first step.
 * An adaptive step that is rejected keeps its stage 0 derivative for the retry
 * (rk_rollback.c); a fixed step is never rejected. */
static PetscErrorCode SetUpRK(TS ts, SpamTsApp *app)
{
  TSRKType         rk;
  TSAdapt          adapt;
  TSAdaptType      atype;
  const PetscReal *bembed;

  PetscFunctionBeginUser;
  PetscCall(TSGetAdapt(ts, &adapt));
  PetscCall(TSAdaptGetType(adapt, &atype));
  PetscCall(TSRKGetType(ts, &rk));
  PetscCall(TSRKGetTableau(ts, NULL, NULL, NULL, NULL, &bembed, NULL, NULL, NULL));
  if (!bembed && strcmp(atype, TSADAPTNONE)) SPAM_BAD_INPUT("-ts_rk_type", rk, "has no embedded error estimate, so -ts_adapt_type %s cannot control its error: use -ts_adapt_type none -ts_dt <step>", atype);
  if (strcmp(atype, TSADAPTNONE)) PetscCall(SpamTSRKKeepFirstStage(ts, app));
  PetscFunctionReturn(0);
}

/* A scheme with the first-same-as-last property starts the next step from the kept f(y_n). */
static PetscErrorCode CkReusesRK(TS ts, const SpamCkFile *c, PetscBool *reused)
{
  PetscFunctionBeginUser;
  (void)c;
  PetscCall(TSRKGetTableau(ts, NULL, NULL, NULL, NULL, NULL, NULL, NULL, reused));
  PetscFunctionReturn(0);
}

/* rk's stages and solution summed term by term (det_combination.c), so that a restart
 * continues bit for bit: on every vector the TS is set onto, before TSSetUp duplicates it
 * into the stage vectors. */
static const SpamTSOption OptionsRK[]  = {{"ts_rk_type", PETSC_TRUE, PETSC_FALSE}, {NULL, PETSC_FALSE, PETSC_FALSE}};
static const SpamTSOption OptionsSSP[] = {{"ts_ssp_type", PETSC_TRUE, PETSC_FALSE}, {"ts_ssp_nstages", PETSC_TRUE, PETSC_FALSE}, {NULL, PETSC_FALSE, PETSC_FALSE}};

const SpamTSFamily SpamTSFamilyRK = {
  .options       = OptionsRK,
  .type          = TSRK,
  .sub_option    = "-ts_rk_type",
  .sub_default   = TSRK3BS,
  .subs          = RkTypes,
  .nsubs         = (int)(sizeof RkTypes / sizeof RkTypes[0]),
  .adapt_default = TSADAPTBASIC,
  .steps         = SPAM_TS_STEPS_ADAPTOR,
  .follow        = SPAM_TS_FOLLOW_RESET_FIXED,
  .sub_type      = SubTypeRK,
  .on_vector     = SpamVecDeterministicMAXPY,
  .set_up        = SetUpRK,
  .interpolates  = InterpolatesRK,
  .ck_reuses_f   = CkReusesRK,
};

const SpamTSFamily SpamTSFamilySSP = {
  .options       = OptionsSSP,
  .type          = TSSSP,
  .sub_option    = "-ts_ssp_type",
  .sub_default   = TSSSPRKS2,
  .subs          = SspTypes,
  .nsubs         = (int)(sizeof SspTypes / sizeof SspTypes[0]),
  .adapt_default = TSADAPTNONE,
  .steps         = SPAM_TS_STEPS_ADAPTOR,
  .follow        = SPAM_TS_FOLLOW_RESET_FIXED,
  .sub_type      = SubTypeSSP,
};

const SpamTSFamily SpamTSFamilyEuler = {
  .type          = TSEULER,
  .adapt_default = TSADAPTNONE,
  .steps         = SPAM_TS_STEPS_ADAPTOR,
  .follow        = SPAM_TS_FOLLOW_RESET_FIXED,
};
