/* A spam-ark started on its own is one MPI process, yet OpenMPI's defaults start a helper
 * daemon for the singleton and probe the UCX network layer at MPI_Init: most of the start-up
 * of a short run (measured in bench/README.md "Start-up"). An isolated singleton with the
 * ob1 messaging layer needs neither and runs the same program. Its topology discovery (hwloc,
 * inside MPI_Init) needs no I/O devices either: hwloc's plugins for PCI, OpenCL and OpenGL
 * devices and its libxml2 XML reader load about a dozen more shared libraries and read the
 * PCI configuration space, 12-17 % of the CPU time of a start that is refused at option
 * parsing (perf stat, 20 starts each); the cores and caches come from hwloc's built-in
 * Linux discovery all the same. Only defaults: a variable the user set is kept, and a process
 * started by mpiexec (which sets OMPI_COMM_WORLD_SIZE or PMIX_RANK) is left to its launcher's
 * choices. The environment is the one place OpenMPI and hwloc read these from before
 * MPI_Init. */
#define _POSIX_C_SOURCE 200809L /* setenv */
#include <stdlib.h>
#include <mpi.h>
#include <spam/mpi_start.h>
#if defined(__SANITIZE_ADDRESS__)
#include <sanitizer/lsan_interface.h>
#endif

void SpamMpiSingletonDefaults(void)
{
  if (getenv("OMPI_COMM_WORLD_SIZE") || getenv("PMIX_RANK") || getenv("PMI_RANK")) return;
  (void)setenv("OMPI_MCA_ess_singleton_isolated", "1", 0);
  (void)setenv("OMPI_MCA_pml", "ob1", 0);
  (void)setenv("HWLOC_PLUGINS_BLACKLIST", "hwloc_pci,hwloc_opencl,hwloc_gl,hwloc_xml_libxml", 0);
}

/* OpenMPI's initialisation allocates a few dozen blocks it never frees. LeakSanitizer's scan
 * at exit found them in every start of the sanitizer build, and matching each one's
 * allocation stack against tests/lsan.supp (full unwinding through libraries built without
 * frame pointers, then symbols) cost more CPU than the rest of a start refused at option
 * parsing: 1.9 -> 1.1 CPU-s per start with them ignored here, against 1.0 with no leak check
 * at all (5 starts each, loaded machine). What MPI allocates later, and everything of ours,
 * is still checked. */
int SpamMpiInitThread(int *argc, char ***argv, int required, int *provided)
{
  int code;

#if defined(__SANITIZE_ADDRESS__)
  __lsan_disable();
#endif
  code = MPI_Init_thread(argc, argv, required, provided);
#if defined(__SANITIZE_ADDRESS__)
  __lsan_enable();
#endif
  return code;
}
