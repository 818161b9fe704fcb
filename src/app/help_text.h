/* -help for users of spam-ark: its own options and time stepping, defaults in plain words
 * (help_text.c); -help petsc prints PETSc's text whole. */
#ifndef SPAM_HELP_TEXT_H
#define SPAM_HELP_TEXT_H
#include <petscsys.h>

/* Call before PetscInitialize, which prints the first blocks: installs the printer when
 * the command line asks for -help (and not -help petsc). */
void SpamHelpTextInstall(int argc, char **argv); /* "-help petsc" becomes PETSc's "-help true" */
#endif
