/* The spam-ark program from its command line to its exit code (main.c calls it; so does the
 * fuzz corpus's fork server, tests/fuzz_server.c, once per case in a forked child). */
#include "program.h"
#include <spam/scene.h>
#include <spam/session.h>
#include <spam/checkpoint.h>
#include <spam/errors.h>
#include <spam/version.h>
#include <spam/options.h>
#include <spam/mpi_start.h>
#include "help_text.h"
#include "mpi_yield.h"
#include <signal.h>

static const char help[] = "spam-ark " SPAM_VERSION ": smooth-particle applied mechanics (Lucy-Monaghan SPAM/SPH)\n"
                           "on SUNDIALS ARKODE and PETSc. Example:\n"
                           "  spam-ark -options_file options/expansion.opts -output_dir out\n"
                           "Exit codes: 0 done, 1 failure, 2 bad input, 3 the run went unstable, 130/143 interrupted\n"
                           "(SIGINT/SIGTERM: the outputs are completed first).\n"
                           "An option this run does not use, or an unknown one, is refused (-version: the version).\n"
                           "Below: spam-ark's options and time stepping; -help petsc adds PETSc's general options\n"
                           "(-options_file, -log_view, viewers, solvers) in PETSc's own words.\n";

static PetscErrorCode Run(int *exit_code)
{
  SpamSim           sim;
  SpamRunOptions    o;
  SpamOutputOptions oo;
  SpamTsApp         app;
  SpamRestart       rs;
  TS                ts = NULL;
  PetscBool         help;
  PetscErrorCode    ierr;

  PetscFunctionBeginUser;
  PetscCall(PetscOptionsHasHelp(NULL, &help));
  PetscCall(SpamSceneCreateSim(PETSC_COMM_WORLD, &sim));
  PetscCall(PetscMemzero(&app, sizeof app));
  PetscCall(PetscMemzero(&rs, sizeof rs));
  /* From here on every path frees what it made: a refused option or directory and a
   * failed run (each reported already) leak nothing (the sanitizer build checks). */
  ierr = SpamRunOptionsParse(&sim, &o);
  if (!ierr) ierr = SpamOutputOptionsParse(&sim, &o, &oo);
  if (!ierr) ierr = SpamTSCreate(&sim, &o, &app, &ts); /* validates the method; lists TS options */
  /* With -help every option has been listed with its default: nothing to run. Otherwise
   * every input is valid from here on: only now touch the file system. */
  if (!ierr && !help) ierr = SpamOptionsCheckUse(&sim, &o, ts); /* no option given in vain */
  /* A checkpoint to continue is read and checked before the directory is touched. */
  if (!ierr && !help && o.restart[0]) ierr = SpamRestartLoad(&sim, &o, &oo, ts, &rs);
  if (!ierr && !help) ierr = SpamRunSession(&sim, &o, &oo, ts, &app, o.restart[0] ? &rs : NULL, exit_code);
  PetscCall(SpamRestartDestroy(&rs));
  PetscCall(TSDestroy(&ts));
  PetscCall(SpamTSAppDestroy(&app));
  PetscCall(SpamSimDestroy(&sim));
  PetscFunctionReturn(ierr);
}

/* MPI is started here, before PETSc, so that the command line and the options files can be
 * checked (SpamArgvCheck) knowing the rank: a refusal is printed once, not by every rank,
 * and PETSc never meets a file it would abort on. PETSc then leaves MPI_Finalize to us. */
static int StartMpi(int *argc, char ***argv)
{
  int provided;

  SpamMpiSingletonDefaults(); /* alone: no singleton daemon, no UCX probe, no hwloc I/O plugins (mpi_start.c) */
  (void)SpamMpiYieldDefault(); /* under mpiexec: more ranks than idle cores yield while waiting (mpi_yield.c) */
  if (SpamMpiInitThread(argc, argv, MPI_THREAD_FUNNELED, &provided) != MPI_SUCCESS) { /* mpi_start.c */
    fprintf(stderr, "spam-ark: error: MPI_Init failed\n");
    return SPAM_EXIT_ERROR;
  }
  return -1;
}

int SpamArkProgram(int argc, char **argv)
{
  PetscErrorCode ierr;
  int            code = SpamArgvEarly(argc, argv); /* -version, --help */

  if (code >= 0) return code;
  if ((code = StartMpi(&argc, &argv)) >= 0) return code;
  if ((code = SpamArgvCheck(MPI_COMM_WORLD, argc, argv)) >= 0) { /* options files */
    (void)MPI_Finalize();
    return code;
  }
  code = SPAM_EXIT_OK;
  SpamHelpTextInstall(argc, argv);
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
  (void)MPI_Finalize();
  return code;
}
