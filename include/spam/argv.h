/* The command line before PETSc reads it (core/argv_check.c). */
#ifndef SPAM_ARGV_H
#define SPAM_ARGV_H

/* Before PetscInitialize: rewrites --help and --version to -help and -version, answers
 * -version ("spam-ark VERSION"), and checks every -options_file argument (and the
 * -options_file lines inside those files) the way PETSc would read it, so that a missing,
 * unreadable or malformed file is one line of bad input, not PETSc's abort. Returns -1 to
 * go on, else the exit code (0 after -version, 2 after printing the bad input). An
 * installed spam-ark reads a relative -options_file missing from the working directory from
 * its share directory ($PREFIX/share/spam/options/...), saying so (core/argv_check.c). */
int SpamArgvCheck(int argc, char **argv);
#endif
