/* What the run loop, the outputs and the checkpoints need to know of each TS type: one row
 * per type (ts_family.c), filled by the type's own implementation (ts_arkode.c,
 * ts_arkode_imex.c, ts_cvode.c, ts_symplectic.c, ts_petsc_explicit.c, ts_block_kdk.c). The rest of the program asks a TS's row
 * (SpamTSFamilyOf) instead of comparing type names, so a new type is one row and its hooks. */
#ifndef SPAM_TS_FAMILY_H
#define SPAM_TS_FAMILY_H
#include <spam/integrator.h>
#include <spam/checkpoint_file.h>

/* Who chooses the step: the type itself (ARKODE's and CVODE's controllers, with their own
 * weighted norm), PETSc's step adaptor (which may be "none": fixed steps), or nobody (the
 * symplectic schemes take the fixed step and never consult an adaptor). */
typedef enum { SPAM_TS_STEPS_OWN, SPAM_TS_STEPS_ADAPTOR, SPAM_TS_STEPS_FIXED } SpamTSSteps;

/* How a TS follows a migration (the state vector changes its local length): resized with
 * its history (ERKStepResize), reset onto the new vector when it takes fixed steps (PETSc
 * 3.18 has no resize, and its adaptors keep a vector of the old length), by its own hook
 * (follow_carry: what it keeps per particle travels with the particles, by id), or not at
 * all. */
typedef enum { SPAM_TS_FOLLOW_RESIZE, SPAM_TS_FOLLOW_RESET_FIXED, SPAM_TS_FOLLOW_CARRY, SPAM_TS_FOLLOW_NONE } SpamTSFollow;

/* An option a type's implementation reads (name without '-'): whether it takes a value, and
 * whether it applies only when the type's steps are adaptive. */
typedef struct {
  const char *name;
  PetscBool   value, adaptive;
} SpamTSOption;

typedef struct SpamTSFamily {
  const char *type;
  /* the sub-type: its option, allowed names and our default (NULL: the type has none) */
  const char         *sub_option, *sub_default;
  const char *const  *subs;
  int                 nsubs;
  const char         *adapt_default; /* -ts_adapt_type when not given                        */
  SpamTSSteps         steps;
  SpamTSFollow        follow;
  PetscBool           bound_as_max_step; /* takes the physical step bound as its largest step */
  PetscBool           solves;            /* solves stage equations to -ts_rtol, -ts_atol, even with fixed steps */
  const char         *step_rule;         /* sets steps by a rule of its own, not an error test (NULL: none) */
  const char         *restart_inexact;   /* why a restart cannot continue bit for bit (NULL: it can) */
  const SpamTSOption *options;           /* the options only this type reads, {NULL} ended (may be NULL) */
  /* hooks, each optional */
  PetscErrorCode (*sub_type)(TS ts, const char **sub);             /* the chosen sub-type              */
  PetscErrorCode (*created)(TS ts, SpamTsApp *app);                /* after TSSetType, before X is set */
  PetscErrorCode (*on_vector)(Vec X);                              /* each vector the TS is set onto   */
  PetscErrorCode (*set_up)(TS ts, SpamTsApp *app);                 /* after TSSetUp                    */
  PetscErrorCode (*interpolates)(TS ts, PetscBool *yes);           /* has dense output (NULL: no)      */
  PetscErrorCode (*describe)(TS ts, const char **sub, char *adapt, size_t alen, double *fixed_dt); /* NULL: sub-type and PETSc's adaptor */
  PetscErrorCode (*help_other)(PetscOptionItems *PetscOptionsObject, const SpamRunOptions *o); /* -help: options when not chosen */
  /* checkpoints: what the type saves beyond the common entries, checks and applies back */
  PetscErrorCode (*ck_put)(TS ts, const SpamTsApp *app, SpamCkFile *c, PetscReal *dt);
  PetscErrorCode (*ck_check)(const SpamCkFile *c, const char *path);
  PetscErrorCode (*ck_before_setup)(TS ts);
  PetscErrorCode (*ck_apply)(TS ts, const SpamCkFile *c, double h_next, PetscBool pending);
  /* what the type keeps per particle, into and from the particles' entries (on several
   * ranks each rank's own block, in its local order; on one rank the file itself):
   * put at a checkpoint, applied after ck_apply */
  PetscErrorCode (*ck_put_particles)(TS ts, SpamCkFile *pc);
  PetscErrorCode (*ck_apply_particles)(TS ts, const SpamCkFile *pc);
  PetscErrorCode (*ck_reuses_f)(TS ts, const SpamCkFile *c, PetscBool *reused); /* NULL: evaluated anew */
  PetscErrorCode (*follow_placed)(TS ts, Vec X);                   /* onto a checkpoint's distribution */
  PetscErrorCode (*follow_carry)(TS ts, SpamTsApp *app);           /* SPAM_TS_FOLLOW_CARRY: onto sim->p.X after a migration */
  /* the state the last step started from, held by the method (good: NULL if it has none);
   * accepted: the step was accepted (else it failed) */
  PetscErrorCode (*last_good)(TS ts, PetscBool accepted, Vec *good);
  PetscErrorCode (*keeps_last_good)(TS ts, PetscBool *yes);        /* last_good will answer  */
  /* a type with a step_rule whose settings put its steps under error control (then
   * -ts_rtol, -ts_atol and -error_norm apply; NULL: never) */
  PetscBool (*error_controlled)(TS ts);
  /* a known option this type's settings make irrelevant: PETSC_TRUE and why[] says what it
   * applies to (NULL: none) */
  PetscBool (*option_off)(TS ts, const char *name, char *why, size_t len);
} SpamTSFamily;

/* The row of type name (NULL if none); the row of ts's type (an error if none). */
const SpamTSFamily *SpamTSFamilyNamed(const char *type);
PetscErrorCode      SpamTSFamilyOf(TS ts, const SpamTSFamily **f);
/* The names of the rows, in the table's order, into names[0..max-1] (-ts_type's allowed
 * values); returns how many. */
#define SPAM_TS_FAMILIES_MAX 16
int SpamTSFamilyNames(const char *names[], int max);
/* Every row, for the few questions asked of all types (-help). */
const SpamTSFamily *SpamTSFamilyAt(int k);

/* PETSc's TS internals, read in one file (ts_internals.c): whether a state jump still
 * waits to restart the method (followed: the TS followed a migration since); the
 * adaptor's weighted-norm type, read (have) and set (want), either may be NULL; the
 * adaptor monitor's viewer (NULL when -ts_adapt_monitor is off). */
PetscErrorCode SpamTSJumpPending(TS ts, PetscBool followed, PetscBool *pending);
PetscErrorCode SpamTSAdaptNormType(TS ts, NormType *have, const NormType *want);
PetscViewer    SpamTSAdaptMonitorViewer(TS ts);

/* The row of f's options that names option name (without '-'), or NULL. */
const SpamTSOption *SpamTSFamilyOption(const SpamTSFamily *f, const char *name);
/* An interpolates hook for the types whose dense output every run has (ERKStep's Hermite
 * interpolant, CVODE's Nordsieck array). */
PetscErrorCode SpamTSInterpolatesAlways(TS ts, PetscBool *yes);

/* The options prefix of arkode_imex's stage preconditioner when this TS uses it (its KSP
 * reads -imex_pc_*), else NULL. */
PetscErrorCode SpamTSARKodeImexPCPrefix(TS ts, const char **prefix);
#define SPAM_IMEX_PC_PREFIX_TEXT "imex_pc_"
/* The rows, each defined beside its type's implementation. */
extern const SpamTSFamily SpamTSFamilyARKode, SpamTSFamilyARKodeImex, SpamTSFamilyCVode, SpamTSFamilyRK, SpamTSFamilySSP, SpamTSFamilyEuler, SpamTSFamilySymplectic, SpamTSFamilyBlock;
#endif
