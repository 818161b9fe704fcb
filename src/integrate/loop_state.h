/* Internal to src/integrate: the time loop's state between two steps. It is what a
 * checkpoint saves besides the particles and the integrator (checkpoint_save.c), and what a
 * restart puts back (restart_load.c) before the loop goes on. */
#ifndef SPAM_LOOP_STATE_H
#define SPAM_LOOP_STATE_H
#include <spam/checkpoint.h>

typedef struct {
  double         out_interval, snap_interval, next_out, next_snap;
  SpamOutputMode mode;
  Vec            Xout; /* the interpolated state of an output time (interpolated mode) */
} SpamSchedule;

typedef struct {
  SpamSchedule   s;
  SpamProgress   p;
  double         t, dt_prev;        /* time reached; last step not cut (0: none yet)    */
  double         t_row, t_snap;     /* times of the last row and snapshot written       */
  PetscLogDouble wall0;             /* wall-clock origin of the run (restarts: shifted)  */
  long           rejected_base;     /* rejections before a restart (the TS counts anew)  */
  /* checkpoints */
  double         next_ckpt;         /* simulated time of the next one (inf: none)        */
  PetscLogDouble last_ckpt_wall;    /* wall clock of the last one (or of the start)      */
  PetscBool      ckpt_due;          /* asked for, waiting for a step without a clamp     */
  int            ckpt_deferred;     /* steps it has waited                               */
  long           ckpt_count;
  double         ckpt_bytes, ckpt_seconds; /* size and write time of the last one        */
  double        *xref_keep;         /* [n*(dim+1)] the list's reference positions before */
  long           builds_keep;       /* the outputs of a step, then the adaptive range's  */
                                    /* h_i (the solve's start), and the list's build count */
  /* several ranks (loop_migrate.c) */
  Vec            Xgood;             /* the last accepted state                           */
  long           builds_migrated;   /* list builds at the last migration                 */
  long           builds_checked;    /* list builds when the halo was last looked at       */
  double         halo_migrated;     /* the largest halo after the last migration (0: unknown) */
  PetscBool      followed;          /* a migration re-made the integrator's vectors since */
                                    /* the last step: its next step evaluates f anew      */
} SpamLoop;

/* Between two steps on several ranks: when the list has been built -migrate_interval
 * times since the last migration, the particles go to the owners of their cells (a re-cut
 * when the imbalance has grown) and every vector of the loop and the integrator follows
 * them. Nothing on one rank, or for a method that cannot follow (integrator.h). */
PetscErrorCode SpamLoopMigrate(SpamSim *sim, const SpamRunOptions *o, TS ts, SpamTsApp *app, SpamLoop *L);

/* Xgood, Xout and the kept reference positions made anew for the sim's particles (after
 * a migration, or a restart's placement). */
PetscErrorCode SpamLoopRemakeVectors(SpamSim *sim, SpamLoop *L);

/* Writes OUTPUT_DIR/checkpoint.h5 of the loop at its current step boundary. exact: no
 * stop-time clamp is pending (the restart will be bitwise where the method allows). */
PetscErrorCode SpamCheckpointWrite(SpamSim *sim, const SpamRunOptions *o, TS ts, SpamTsApp *app, SpamOutput *out, const SpamRunResult *r, SpamLoop *L, PetscBool exact);
/* Puts the checkpoint's particles, list, integrator, loop and result back (after the TS
 * is made, before the first step). */
PetscErrorCode SpamRestartApply(SpamSim *sim, const SpamRunOptions *o, TS ts, SpamTsApp *app, SpamRestart *rs, SpamRunResult *r, SpamLoop *L);
#endif
