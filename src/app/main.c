/* spam-ark: smooth-particle applied mechanics on SUNDIALS ARKODE and PETSc. */
#include "program.h"

int main(int argc, char **argv) { return SpamArkProgram(argc, argv); }
