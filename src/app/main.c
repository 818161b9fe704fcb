/* spam-ark: smooth-particle applied mechanics on SUNDIALS ARKODE and PETSc. */
#include <spam/scene.h>
#include <spam/integrator.h>
#include <spam/errors.h>
#include <spam/version.h>
#include <spam/options.h>
#include <signal.h>

static const char help[] = "spam-ark " SPAM_VERSION ": smooth-particle applied mechanics (Lucy-Monaghan SPAM/SPH)\n"
                           "on SUNDIALS ARKODE and PETSc. Example:\n"
                           "  spam-ark -options_file options/expansion.opts -output_dir out\n"
                           "Exit codes: 0 done, 1 failure, 2 bad input, 3 the run went unstable.\n"
                           "An option this run does not use, or an unknown one, is refused (-version: the version).\n\n";

static PetscErrorCode Run(int *exit_code)
{
  SpamSim        sim;
  SpamRunOptions o;
  SpamRunResult  r;
  SpamOutput     out;
  SpamTsApp      app;
  TS             ts;
  PetscBool      help;

  PetscFunctionBeginUser;
  PetscCall(PetscOptionsHasHelp(NULL, &help));
  PetscCall(SpamSceneCreateSim(PETSC_COMM_WORLD, &sim));
  PetscCall(SpamRunOptionsParse(&sim, &o));
  PetscCall(SpamTSCreate(&sim, &o, &app, &ts)); /* validates the method; lists TS options */
  if (!help) PetscCall(SpamOptionsCheckUse(&sim, &o, ts)); /* no option given in vain */
  if (help) { /* every option has been listed with its default: nothing to run */
    PetscCall(TSDestroy(&ts));
    PetscCall(SpamTSAppDestroy(&app));
    PetscCall(SpamSimDestroy(&sim));
    PetscFunctionReturn(0);
  }
  /* Every input is valid from here on: only now touch the file system. */
  PetscCall(SpamOutputOpen(o.output_dir, o.hdf5, o.csv, &out));
  if (o.initial_csv[0]) {
    const PetscScalar *y;
    PetscCall(VecGetArrayRead(sim.X, &y));
    PetscCall(SpamParticlesCsvWrite(o.initial_csv, &sim, y));
    PetscCall(VecRestoreArrayRead(sim.X, &y));
  }
  PetscCall(SpamRun(&sim, &o, ts, &app, &out, &r));
  PetscCall(TSDestroy(&ts));
  PetscCall(SpamTSAppDestroy(&app));
  if (o.final_csv[0] && r.status != SPAM_STATUS_UNSTABLE) {
    const PetscScalar *y;
    PetscCall(VecGetArrayRead(sim.X, &y));
    PetscCall(SpamParticlesCsvWrite(o.final_csv, &sim, y));
    PetscCall(VecRestoreArrayRead(sim.X, &y));
  }
  PetscCall(SpamSummaryWrite(&out, &sim, &o, &r));
  PetscCall(SpamOutputClose(&out));
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "spam-ark: %s after %ld steps (%ld rejected), %ld RHS evaluations, %.2f s; energy drift %.3e; results in %s\n", r.status == SPAM_STATUS_UNSTABLE ? "unstable" : "done", r.steps, r.rejected, r.rhs_evals, r.wall, r.energy_drift_max, o.output_dir));
  *exit_code = r.status == SPAM_STATUS_UNSTABLE ? SPAM_EXIT_UNSTABLE : SPAM_EXIT_OK;
  PetscCall(SpamSimDestroy(&sim));
  PetscFunctionReturn(0);
}

int main(int argc, char **argv)
{
  PetscErrorCode ierr;
  int            code = SpamArgvCheck(argc, argv); /* -version, --help, options files */

  if (code >= 0) return code;
  code = SPAM_EXIT_OK;
  PetscCall(PetscInitialize(&argc, &argv, NULL, help));
  /* A reader that closes the pipe early (spam-ark -monitor | head) ends our output, not the
   * program with PETSc's signal trace: writes to it then fail quietly. (PETSc's own help
   * text, printed inside PetscInitialize under its handler, is not covered.) */
  (void)signal(SIGPIPE, SIG_IGN);
  PetscCall(SpamInstallErrorHandler());
  PetscCall(SpamIntegratorsRegister());
  ierr = SpamOptionsCheckValues();
  if (!ierr) ierr = Run(&code);
  /* Bad input exits 2; file-system failures (one line) and every other failure exit 1. */
  if (ierr) code = ierr == PETSC_ERR_USER_INPUT ? SPAM_EXIT_BAD_INPUT : SPAM_EXIT_ERROR;
  /* Finalize quietly after an error: the message has been printed already. */
  PetscFinalize();
  return code;
}
