/* What each kernel's file tells SpamKernelCreate (internal to src/kernels; its kind and
 * name are its row's in kernel_list.h): the dimensionless normalisation C_D, the factor cgrad of F'(s)/s = cgrad G(s), and its
 * smoothness at r = h, all for one dimension D. Every shape has F(0) = 1 (to round-off),
 * so that wnorm = w(0), which the density passes add as each particle's own term. A new
 * kernel writes one describe function; its row in kernel_list.h declares and registers it. */
#ifndef SPAM_KERNEL_REGISTRY_H
#define SPAM_KERNEL_REGISTRY_H
#include <spam/kernel.h>

#define SPAM_PI 3.14159265358979323846

typedef struct {
  double cnorm;  /* C_D: the integral of C_D F(|x|) over D-space is one */
  double cgrad;  /* F'(s)/s = cgrad G(s)                                 */
  int    smooth; /* derivatives of w continuous at r = h                 */
} SpamKernelShapeInfo;

/* Fills d for dimension dim (1..3). */
typedef PetscErrorCode (*SpamKernelDescribeFn)(int dim, SpamKernelShapeInfo *d);

/* SpamKernelPrefixDescribe of each row of kernel_list.h, defined in kernel_<name>.c. */
#define SPAM_KERNEL_DESCRIBE_DECL(ctx, KIND, name, Prefix) PetscErrorCode SpamKernel##Prefix##Describe(int dim, SpamKernelShapeInfo *d);
SPAM_KERNEL_LIST(SPAM_KERNEL_DESCRIBE_DECL, ~)
#undef SPAM_KERNEL_DESCRIBE_DECL
#endif
