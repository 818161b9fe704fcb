/* Every kernel of -kernel in 1, 2 and 3D: normalisation, derivatives against differences,
 * smoothness at the edge of the support, the inline shapes against the evaluators, and the
 * registry (names, refusal of an unknown one, Lucy's numbers unchanged). */
#include <spam/kernel.h>
#include <float.h>
#include "test_util.h"

/* The names from the program's one list (kernels/kernel_list.h), not a copy of it. */
#define NAME_ROW(ctx, KIND, name, Prefix) #name,
static const char *const Names[SPAM_KERNEL_KINDS] = {SPAM_KERNEL_LIST(NAME_ROW, ~)};
#undef NAME_ROW

#define GAUSS_POINTS 8
/* Nodes and weights of GAUSS_POINTS-point Gauss-Legendre on [-1, 1] by Newton's method on
 * the Legendre polynomial (converged to round-off). */
static void GaussLegendre(double x[GAUSS_POINTS], double w[GAUSS_POINTS])
{
  const int n = GAUSS_POINTS;
  for (int i = 0; i < n; i++) {
    double z = cos(3.14159265358979323846 * (i + 0.75) / (n + 0.5)), dp = 1.0;
    for (int it = 0; it < 100; it++) {
      double p0 = 1.0, p1 = z;
      for (int k = 2; k <= n; k++) {
        const double p2 = ((2.0 * k - 1.0) * z * p1 - (k - 1.0) * p0) / k;
        p0              = p1;
        p1              = p2;
      }
      dp             = n * (z * p1 - p0) / (z * z - 1.0);
      const double dz = p1 / dp;
      z -= dz;
      if (fabs(dz) < 1e-16) break;
    }
    x[i] = z;
    w[i] = 2.0 / ((1.0 - z * z) * dp * dp);
  }
}

/* Integral of w over D-space as a radial integral, Gauss-Legendre on 12 panels. The panel
 * edges include the splines' joints (h/3, h/2, 2h/3), so the integrand is one polynomial of
 * degree at most 13 (Wendland C6 in 3D) on each panel, which 8 points integrate exactly:
 * the error is round-off, some 100 eps. */
static double Normalisation(const SpamKernel *k)
{
  double       xg[GAUSS_POINTS], wg[GAUSS_POINTS], sum = 0.0;
  const int    panels = 12;
  const double a      = k->h / panels, pi = 3.14159265358979323846;
  GaussLegendre(xg, wg);
  for (int p = 0; p < panels; p++)
    for (int g = 0; g < GAUSS_POINTS; g++) {
      const double r     = a * (p + 0.5 * (xg[g] + 1.0));
      const double shell = k->dim == 1 ? 2.0 : k->dim == 2 ? 2.0 * pi * r : 4.0 * pi * r * r;
      sum += 0.5 * a * wg[g] * shell * SpamKernelW(k, r * r);
    }
  return sum;
}

/* Central differences of w and w' against w' and w'' at s = (i - 1/2)/100, which keeps
 * every difference off the splines' joints. Truncation error delta^2/6 |f'''| with f''' estimated
 * from differences of the analytic w'' on a coarser step; round-off 8 eps max|f| / delta. */
static void CheckDerivatives(TestCount *c, const SpamKernel *k)
{
  const double delta = 1e-5 * k->h, a = 1e-3 * k->h;
  double       e1 = 0, e2 = 0, e3 = 0, m3 = 0, m4 = 0, wmax = 0, gmax = 0, d2max = 0;
  for (int i = 1; i <= 100; i++) {
    const double r   = k->h * (i - 0.5) / 100.0;
    const double fd1 = (SpamKernelW(k, (r + delta) * (r + delta)) - SpamKernelW(k, (r - delta) * (r - delta))) / (2.0 * delta);
    const double fd2 = (SpamKernelDW(k, r + delta) - SpamKernelDW(k, r - delta)) / (2.0 * delta);
    e1               = PetscMax(e1, PetscMax(fabs(fd1 - SpamKernelDW(k, r)), fabs(fd1 - SpamKernelDWOverR(k, r * r) * r)));
    e2               = PetscMax(e2, fabs(fd2 - SpamKernelD2W(k, r)));
    e3               = PetscMax(e3, fabs(k->gnorm * SpamKernelShapeG(k->kind, k->dim, r * k->hinv) * r - SpamKernelDW(k, r)));
    m3               = PetscMax(m3, fabs(SpamKernelD2W(k, r + a) - SpamKernelD2W(k, r - a)) / (2.0 * a));
    m4               = PetscMax(m4, fabs(SpamKernelD2W(k, r + a) - 2.0 * SpamKernelD2W(k, r) + SpamKernelD2W(k, r - a)) / (a * a));
    wmax             = PetscMax(wmax, SpamKernelW(k, r * r));
    gmax             = PetscMax(gmax, fabs(SpamKernelDW(k, r)));
    d2max            = PetscMax(d2max, fabs(SpamKernelD2W(k, r)));
  }
  /* factor 2 on each bound: m3, m4 are estimates of the maxima from a finite grid */
  const double tol1 = 2.0 * (delta * delta / 6.0 * m3 + 8.0 * DBL_EPSILON * wmax / delta);
  const double tol2 = 2.0 * (delta * delta / 6.0 * m4 + 8.0 * DBL_EPSILON * gmax / delta);
  TestCheck(c, e1 <= tol1, "%s D=%d h=%g: w' (and (w'/r) r) vs central difference of w: max err %.2e <= %.2e (max |w'| %.2e)", k->name, k->dim, k->h, e1, tol1, gmax);
  TestCheck(c, e2 <= tol2, "%s D=%d h=%g: w'' vs central difference of w': max err %.2e <= %.2e (max |w''| %.2e)", k->name, k->dim, k->h, e2, tol2, d2max);
  TestCheck(c, e3 <= 4.0 * DBL_EPSILON * gmax, "%s D=%d h=%g: gnorm G(s) r = w' to round-off (max err %.2e)", k->name, k->dim, k->h, e3);
  TestCheck(c, SpamKernelDW(k, 0.0) == 0.0 && isfinite(SpamKernelDWOverR(k, 0.0)), "%s D=%d h=%g: w'(0) = 0 (no self force), w'/r finite there (%.3e)", k->name, k->dim, k->h, SpamKernelDWOverR(k, 0.0));
}

/* n-th backward difference of w at r = h with step delta, over delta^n: w^(n)(h-) + O(delta). */
static double EdgeDifference(const SpamKernel *k, int n, double delta)
{
  double sum = 0.0, binom = 1.0;
  for (int j = 0; j <= n; j++) {
    const double r = k->h - j * delta;
    sum += (j % 2 ? -binom : binom) * SpamKernelW(k, r * r);
    binom = binom * (n - j) / (j + 1);
  }
  return sum / pow(delta, n);
}

/* How many derivatives of w are continuous at r = h, where w and all its derivatives are
 * zero outside: w^(n)(h-) must vanish. Near h, w ~ c (h - r)^m, so the n-th one-sided
 * difference scales as delta^(m - n): halving delta halves it (p = 1) or better while
 * n < m, and leaves it (p = 0) at n = m, the first derivative that jumps. */
static void CheckSmoothness(TestCount *c, const SpamKernel *k)
{
  const double delta = k->h / 1024.0;
  double       p[12] = {0}, jump = 0.0;
  int          measured = -1;
  for (int n = 0; n <= k->smooth + 1 && n < 12; n++) {
    const double d1 = EdgeDifference(k, n, delta), d2 = EdgeDifference(k, n, 0.5 * delta);
    p[n] = log2(fabs(d1) / fabs(d2));
    if (measured < 0 && fabs(p[n]) < 0.5) {
      measured = n - 1;
      jump     = d2 * pow(k->h, k->dim + n) / (k->wnorm * pow(k->h, k->dim)); /* w^(n)(h-) h^n / C_D h^-D */
    }
  }
  const int n = k->smooth + 1;
  TestCheck(c, measured == k->smooth && p[n] > -0.2 && p[n] < 0.2 && (n == 0 || p[n - 1] > 0.8),
            "%s D=%d h=%g: C^%d at r = h measured (expected %d): halving the step scales the one-sided w^(%d) by 2^%+.3f, w^(%d) by 2^%+.3f (jump %.4g C_D h^-(D+%d))", k->name, k->dim, k->h, measured, k->smooth,
            n - 1, n > 0 ? -p[n - 1] : 0.0, n, -p[n], jump, n);
}

/* The inline shapes equal the evaluators, and F = G = H = 0 exactly for s >= 1. */
static void CheckShapes(TestCount *c, const SpamKernel *k)
{
  static const double beyond[] = {1.0, 1.0 + DBL_EPSILON, 1.0001, 1.5, 2.0, 3.0, 10.0, 1e6, 1e30};
  int                 same = 1, close = 1, zero = 1;
  for (int i = 0; i <= 1200; i++) {
    const double r = k->h * i / 1000.0, r2 = r * r, s = sqrt(r2) * k->hinv;
    if (r2 < k->h2) {
      same &= SpamKernelShapeScaledF(k->kind, k->dim, k->wnorm, s) == SpamKernelW(k, r2) && SpamKernelShapeScaledG(k->kind, k->dim, k->gnorm, s) == SpamKernelDWOverR(k, r2);
      close &= fabs(k->wnorm * SpamKernelShapeF(k->kind, k->dim, s) - SpamKernelW(k, r2)) <= 4.0 * DBL_EPSILON * k->wnorm && fabs(k->gnorm * SpamKernelShapeG(k->kind, k->dim, s) - SpamKernelDWOverR(k, r2)) <= 4.0 * DBL_EPSILON * fabs(k->gnorm) * SpamKernelShapeG(k->kind, k->dim, 0.0);
    } else same &= SpamKernelW(k, r2) == 0.0 && SpamKernelDWOverR(k, r2) == 0.0;
  }
  for (size_t i = 0; i < sizeof beyond / sizeof beyond[0]; i++)
    zero &= SpamKernelShapeF(k->kind, k->dim, beyond[i]) == 0.0 && SpamKernelShapeG(k->kind, k->dim, beyond[i]) == 0.0 && SpamKernelShapeH(k->kind, k->dim, beyond[i]) == 0.0 && SpamKernelShapeScaledF(k->kind, k->dim, 7.0, beyond[i]) == 0.0 && SpamKernelShapeScaledG(k->kind, k->dim, 7.0, beyond[i]) == 0.0;
  TestCheck(c, fabs(SpamKernelShapeF(k->kind, k->dim, 0.0) - 1.0) <= 2.0 * DBL_EPSILON, "%s D=%d h=%g: F(0) = 1 (%.17g): wnorm is w(0), the density's self term", k->name, k->dim, k->h, SpamKernelShapeF(k->kind, k->dim, 0.0));
  TestCheck(c, same && close, "%s D=%d h=%g: ScaledF(wnorm, s), ScaledG(gnorm, s) of kernel_shape.h equal SpamKernelW, SpamKernelDWOverR bit for bit; wnorm F, gnorm G to 4 eps", k->name, k->dim, k->h);
  TestCheck(c, zero && SpamKernelW(k, k->h2) == 0.0 && SpamKernelDW(k, k->h) == 0.0 && SpamKernelD2W(k, k->h) == 0.0, "%s D=%d h=%g: F = G = H = 0 exactly for 1 <= s <= 1e30", k->name, k->dim, k->h);
}

/* Lucy's numbers are those every test and the gas benchmark were made with: the shapes,
 * the normalisations and the evaluators' arithmetic (that of the pair loops and of the
 * former kernel_lucy.c) bit for bit. Its force is only C^1 at r = h: smooth = 2. */
static void CheckLucyUnchanged(TestCount *c, int dim, double h)
{
  const double cd[3] = {5.0 / 4.0, 5.0 / 3.14159265358979323846, 105.0 / (16.0 * 3.14159265358979323846)};
  SpamKernel   k, l;
  int          same = 1;
  (void)SpamKernelLucyInit(dim, h, &l);
  (void)SpamKernelCreate("lucy", dim, h, &k);
  for (int i = 0; i < 1000; i++) {
    const double s = i / 1000.0, t = 1.0 - s, r = s * h, r2 = r * r, sr = sqrt(r2) * k.hinv, tr = 1.0 - sr, c3 = 0.37;
    same &= SpamKernelShapeF(SPAM_KERNEL_LUCY, dim, s) == (1.0 + 3.0 * s) * t * t * t && SpamKernelShapeG(SPAM_KERNEL_LUCY, dim, s) == t * t;
    same &= SpamKernelShapeScaledF(SPAM_KERNEL_LUCY, dim, c3, s) == c3 * (1.0 + 3.0 * s) * t * t * t && SpamKernelShapeScaledG(SPAM_KERNEL_LUCY, dim, c3, s) == c3 * t * t;
    same &= SpamKernelW(&k, r2) == k.wnorm * (1.0 + 3.0 * sr) * tr * tr * tr && SpamKernelDWOverR(&k, r2) == k.gnorm * tr * tr;
    same &= SpamKernelDW(&k, r) == k.gnorm * k.h * (r * k.hinv) * (1.0 - r * k.hinv) * (1.0 - r * k.hinv) && SpamKernelD2W(&k, r) == k.gnorm * (1.0 - r * k.hinv) * (1.0 - 3.0 * (r * k.hinv));
  }
  TestCheck(c, same && k.wnorm == cd[dim - 1] * pow(h, -dim) && k.gnorm == -12.0 * cd[dim - 1] * pow(h, -(dim + 2)) && l.wnorm == k.wnorm && l.gnorm == k.gnorm && l.kind == SPAM_KERNEL_LUCY && l.smooth == 2,
            "lucy D=%d h=%g: F = (1+3s)t^3, G = t^2, wnorm = C_D h^-D, gnorm = -12 C_D h^-(D+2), w, w'/r, w', w'' as before, bit for bit; smooth 2 (force C^1 at h); LucyInit = Create(\"lucy\")", dim, h);
}

static PetscErrorCode CheckRegistry(TestCount *c)
{
  SpamKernel     k;
  PetscErrorCode ierr;
  char           names[256], listed[256] = "";
  int            ok = 1;

  PetscFunctionBeginUser;
  for (int kind = 0; kind < SPAM_KERNEL_KINDS; kind++) {
    PetscCall(SpamKernelCreate(Names[kind], 2, 1.0, &k));
    ok &= (int)k.kind == kind && !strcmp(k.name, Names[kind]);
    PetscCall(PetscStrlcat(listed, kind ? ", " : "", sizeof listed));
    PetscCall(PetscStrlcat(listed, Names[kind], sizeof listed));
  }
  PetscCall(SpamKernelNames(names, sizeof names));
  TestCheck(c, ok && !strcmp(names, listed) && !strcmp(Names[SPAM_KERNEL_LUCY], "lucy"), "every name makes its own kind, the registry lists the list's rows in order (names: %s)", names);
  PetscCall(PetscPushErrorHandler(PetscReturnErrorHandler, NULL));
  ierr = SpamKernelCreate("wendland", 2, 1.0, &k);
  PetscCall(PetscPopErrorHandler());
  TestCheck(c, ierr == PETSC_ERR_USER_INPUT, "an unknown name is bad input (error %d)", (int)ierr);
  PetscFunctionReturn(0);
}

int main(int argc, char **argv)
{
  TestCount c = {0, 0};
  PetscCall(TestInitialize(&argc, &argv));
  for (int kind = 0; kind < SPAM_KERNEL_KINDS; kind++)
    for (int dim = 1; dim <= 3; dim++)
      for (double h = 1.5; h <= 6.0; h *= 2.0) {
        SpamKernel k;
        PetscCall(SpamKernelCreate(Names[kind], dim, h, &k));
        const double norm = Normalisation(&k);
        TestCheck(&c, fabs(norm - 1.0) < 200.0 * DBL_EPSILON, "%s D=%d h=%g: integral of w dV = %.16f (|err| %.1e < 200 eps: exact quadrature)", k.name, dim, h, norm, fabs(norm - 1.0));
        CheckDerivatives(&c, &k);
        CheckSmoothness(&c, &k);
        CheckShapes(&c, &k);
        if (kind == SPAM_KERNEL_LUCY) CheckLucyUnchanged(&c, dim, h);
      }
  PetscCall(CheckRegistry(&c));
  PetscCall(TestFinalize());
  return TestFinish(&c);
}
