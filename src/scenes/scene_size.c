/* The largest particle count a run can hold, and the check every scene makes of the
 * count its options ask for. Counts are computed in double by the callers, so that a
 * product of large option values is compared, never overflowed. */
#include <spam/scene.h>
#include <spam/errors.h>
#include <unistd.h>

/* Values per particle in the state vector, rounded up: at most 14 (3D solid: x, v, e,
 * rho and six stresses). The vector is indexed by PetscInt (32-bit in this build). */
#define SPAM_MAX_VALUES_PER_PARTICLE 16
/* Memory per particle, a lower bound: the maximum RSS of expansion runs grew by 958 bytes
 * per particle in 2D (65536 -> 262144 particles) and by 1547 in 3D, with the default
 * ARKODE method; a count whose bytes at this rate exceed the physical memory cannot run. */
#define SPAM_BYTES_PER_PARTICLE 900.0

/* Physical memory in bytes, or 0 if the system does not say. */
static double PhysicalMemory(void)
{
  const long pages = sysconf(_SC_PHYS_PAGES), size = sysconf(_SC_PAGESIZE);
  return pages > 0 && size > 0 ? (double)pages * (double)size : 0.0;
}

double SpamMaxParticles(void)
{
  const double index = (double)PETSC_MAX_INT / SPAM_MAX_VALUES_PER_PARTICLE, mem = PhysicalMemory() / SPAM_BYTES_PER_PARTICLE;
  return mem > 0.0 && mem < index ? floor(mem) : floor(index);
}

PetscErrorCode SpamCheckParticleCount(const char *opt, const char *val, double count)
{
  const double mem = PhysicalMemory();

  PetscFunctionBeginUser;
  if (count <= SpamMaxParticles()) PetscFunctionReturn(0);
  SPAM_BAD_INPUT(opt, val, "the scene would hold %.3g particles; at most %.4g here: the smaller of %.4g (%d-bit PetscInt state indices, %d values per particle) and %.4g (%.3g GB of physical memory at %.0f bytes per particle)", count, SpamMaxParticles(), (double)PETSC_MAX_INT / SPAM_MAX_VALUES_PER_PARTICLE, (int)(8 * sizeof(PetscInt)), SPAM_MAX_VALUES_PER_PARTICLE, mem / SPAM_BYTES_PER_PARTICLE, mem / 1e9, SPAM_BYTES_PER_PARTICLE);
}
