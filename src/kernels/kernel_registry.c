/* Kernels by name: the rows of kernel_list.h as a constant table (indexed by kind, the
 * enum's order), the list -kernel chooses from built from it where it is needed (no
 * global mutable list), and the kernel made from a name, a dimension and h. Each kernel's
 * kind and name are its row's; its header gives only its numbers (SpamPrefixInfo). */
#include <spam/kernel.h>
#include <spam/errors.h>

/* A kernel's numbers in dimension dim (SpamPrefixInfo in its header). */
typedef SpamKernelShapeInfo (*KernelInfoFn)(int dim);

typedef struct {
  SpamKernelKind       kind;
  const char          *name; /* as given to -kernel */
  KernelInfoFn         info;
} KernelRow;

#define SPAM_KERNEL_ROW(ctx, KIND, name, Prefix) {SPAM_KERNEL_##KIND, #name, Spam##Prefix##Info},
static const KernelRow Rows[SPAM_KERNEL_KINDS] = {SPAM_KERNEL_LIST(SPAM_KERNEL_ROW, ~)};
#undef SPAM_KERNEL_ROW

/* The names for -kernel and -help, in the list's order. */
static PetscErrorCode KernelList(PetscFunctionList *list)
{
  PetscFunctionBeginUser;
  *list = NULL;
  for (int i = 0; i < SPAM_KERNEL_KINDS; i++) PetscCall(PetscFunctionListAdd(list, Rows[i].name, Rows[i].info));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamKernelNames(char *buf, size_t len)
{
  PetscFunctionBeginUser;
  buf[0] = 0;
  for (int i = 0; i < SPAM_KERNEL_KINDS; i++) {
    PetscCall(PetscStrlcat(buf, i ? ", " : "", len));
    PetscCall(PetscStrlcat(buf, Rows[i].name, len));
  }
  PetscFunctionReturn(0);
}

static PetscErrorCode CheckRange(int dim, double h)
{
  PetscFunctionBeginUser;
  PetscCheck(dim >= 1 && dim <= 3, PETSC_COMM_SELF, PETSC_ERR_ARG_OUTOFRANGE, "kernel dimension %d not in 1..3", dim);
  PetscCheck(h > 0.0, PETSC_COMM_SELF, PETSC_ERR_ARG_OUTOFRANGE, "kernel range h = %g must be positive", h);
  PetscFunctionReturn(0);
}

/* The kernel of row r at range h: the h-independent numbers of its header, scaled by
 * powers of h. */
static PetscErrorCode KernelFromRow(const KernelRow *r, int dim, double h, SpamKernel *k)
{
  const SpamKernelShapeInfo d = r->info(dim);

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(k, sizeof *k));
  k->kind   = r->kind;
  k->name   = r->name;
  k->dim    = dim;
  k->h      = h;
  k->hinv   = 1.0 / h;
  k->h2     = h * h;
  k->wnorm  = d.cnorm * pow(h, -dim);
  k->gnorm  = d.cgrad * d.cnorm * pow(h, -(dim + 2)); /* Lucy: -12 C_D h^-(D+2), as before */
  k->smooth = d.smooth;
  k->fourier_positive = d.fourier_positive;
  PetscFunctionReturn(0);
}

PetscErrorCode SpamKernelCreate(const char *name, int dim, double h, SpamKernel *k)
{
  char allowed[256], shown[100];

  PetscFunctionBeginUser;
  PetscCall(CheckRange(dim, h));
  for (int i = 0; i < SPAM_KERNEL_KINDS; i++) {
    PetscBool same;
    PetscCall(PetscStrcmp(name, Rows[i].name, &same));
    if (same) {
      PetscCall(KernelFromRow(&Rows[i], dim, h, k));
      PetscFunctionReturn(0);
    }
  }
  PetscCall(SpamKernelNames(allowed, sizeof allowed));
  SpamClip(name, shown, sizeof shown);
  SPAM_BAD_INPUT("-kernel", shown, "allowed: %s", allowed);
}

/* Lucy's kernel without a name: the models and analyses that are Lucy's alone. */
PetscErrorCode SpamKernelLucyInit(int dim, double h, SpamKernel *k)
{
  PetscFunctionBeginUser;
  PetscCall(CheckRange(dim, h));
  PetscCall(KernelFromRow(&Rows[SPAM_KERNEL_LUCY], dim, h, k));
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
