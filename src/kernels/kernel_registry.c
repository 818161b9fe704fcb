/* Kernels by name: the list -kernel chooses from, built where it is needed (no global
 * list), and the kernel made from a name, a dimension and h. */
#include "kernel_registry.h"
#include <spam/errors.h>

/* The rows of kernel_list.h: each kernel's name for -kernel and the function that
 * describes it, in the list's order (which -help and the names keep). */
#define SPAM_KERNEL_REGISTER(list, KIND, name, Prefix) PetscCall(PetscFunctionListAdd(list, #name, SpamKernel##Prefix##Describe));
static PetscErrorCode KernelList(PetscFunctionList *list)
{
  PetscFunctionBeginUser;
  *list = NULL;
  SPAM_KERNEL_LIST(SPAM_KERNEL_REGISTER, list)
  PetscFunctionReturn(0);
}
#undef SPAM_KERNEL_REGISTER

static PetscErrorCode ListNames(PetscFunctionList list, char *buf, size_t len)
{
  const char **names;
  int          n;

  PetscFunctionBeginUser;
  PetscCall(PetscFunctionListGet(list, &names, &n)); /* n counts the closing NULL too */
  buf[0] = 0;
  for (int i = 0; i < n && names[i]; i++) {
    PetscCall(PetscStrlcat(buf, i ? ", " : "", len));
    PetscCall(PetscStrlcat(buf, names[i], len));
  }
  PetscCall(PetscFree(names));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamKernelNames(char *buf, size_t len)
{
  PetscFunctionList list;

  PetscFunctionBeginUser;
  PetscCall(KernelList(&list));
  PetscCall(ListNames(list, buf, len));
  PetscCall(PetscFunctionListDestroy(&list));
  PetscFunctionReturn(0);
}

/* The kernel of d at range h: the h-independent numbers of d scaled by powers of h. */
static PetscErrorCode KernelFromShape(const SpamKernelShapeInfo *d, int dim, double h, SpamKernel *k)
{
  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(k, sizeof *k));
  k->kind   = d->kind;
  k->name   = d->name;
  k->dim    = dim;
  k->h      = h;
  k->hinv   = 1.0 / h;
  k->h2     = h * h;
  k->wnorm  = d->cnorm * pow(h, -dim);
  k->gnorm  = d->cgrad * d->cnorm * pow(h, -(dim + 2)); /* Lucy: -12 C_D h^-(D+2), as before */
  k->smooth = d->smooth;
  PetscFunctionReturn(0);
}

static PetscErrorCode CheckRange(int dim, double h)
{
  PetscFunctionBeginUser;
  PetscCheck(dim >= 1 && dim <= 3, PETSC_COMM_SELF, PETSC_ERR_ARG_OUTOFRANGE, "kernel dimension %d not in 1..3", dim);
  PetscCheck(h > 0.0, PETSC_COMM_SELF, PETSC_ERR_ARG_OUTOFRANGE, "kernel range h = %g must be positive", h);
  PetscFunctionReturn(0);
}

PetscErrorCode SpamKernelCreate(const char *name, int dim, double h, SpamKernel *k)
{
  PetscFunctionList    list;
  SpamKernelDescribeFn describe;
  SpamKernelShapeInfo  d;
  char                 allowed[256], shown[100];

  PetscFunctionBeginUser;
  PetscCall(CheckRange(dim, h));
  PetscCall(KernelList(&list));
  PetscCall(PetscFunctionListFind(list, name, &describe));
  if (!describe) {
    PetscCall(ListNames(list, allowed, sizeof allowed));
    PetscCall(PetscFunctionListDestroy(&list));
    SpamClip(name, shown, sizeof shown);
    SPAM_BAD_INPUT("-kernel", shown, "allowed: %s", allowed);
  }
  PetscCall(PetscFunctionListDestroy(&list));
  PetscCall(describe(dim, &d));
  PetscCall(KernelFromShape(&d, dim, h, k));
  PetscFunctionReturn(0);
}

/* Lucy's kernel without the list: the models and analyses that are Lucy's alone. */
PetscErrorCode SpamKernelLucyInit(int dim, double h, SpamKernel *k)
{
  SpamKernelShapeInfo d;

  PetscFunctionBeginUser;
  PetscCall(CheckRange(dim, h));
  PetscCall(SpamKernelLucyDescribe(dim, &d));
  PetscCall(KernelFromShape(&d, dim, h, k));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamKernelOptions(int dim, double h, SpamKernel *k)
{
  PetscFunctionList list;
  char              name[64] = "lucy";

  PetscFunctionBeginUser;
  PetscCall(KernelList(&list));
  PetscOptionsBegin(PETSC_COMM_WORLD, NULL, "Kernel", "spam-ark");
  PetscCall(PetscOptionsFList("-kernel", "Smoothing kernel, zero for r >= h (docs/kernels.md)", "README", list, name, name, sizeof name, NULL));
  PetscOptionsEnd();
  PetscCall(PetscFunctionListDestroy(&list));
  PetscCall(SpamKernelCreate(name, dim, h, k));
  PetscFunctionReturn(0);
}
