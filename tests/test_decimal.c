/* SpamFormatG17 (format_g17.c) against snprintf's "%.17g", byte for byte, and
 * SpamParseDouble (parse_double.c) against strtod, bit for bit and to the same end: for
 * values drawn over every binary exponent a run's state can take and beyond (both sides of
 * the 128-bit fast paths' edges, where they hand over to the library or, for the formatter,
 * to its wide path below about 1e-6, down to the subnormals), the values next to
 * powers of ten (where the decimal exponent and the rounding carry change), exact decimal
 * ties at the 17th digit (rounded to even), zeros, subnormals and non-finite values; for
 * the parser also decimal strings of 1 to 22 digits with any point and exponent, halfway
 * cases between two doubles, and strings that are not (only) numbers. */
#include <spam/decimal.h>
#include <float.h>
#include <string.h>
#include "test_util.h"

static int Same(double x, long *bad)
{
  char a[64], b[64];
  (void)SpamFormatG17(x, a);
  (void)snprintf(b, sizeof b, "%.17g", x);
  if (strcmp(a, b) == 0) return 1;
  if ((*bad)++ < 5) printf("  %a: %s, snprintf %s\n", x, a, b);
  return 0;
}

/* SpamParseDouble(s) == strtod(s), bits and end. */
static int SameParse(const char *s, long *bad)
{
  char  *e1, *e2;
  double a = SpamParseDouble(s, &e1), b = strtod(s, &e2);
  if (memcmp(&a, &b, sizeof a) == 0 && e1 == e2) return 1;
  if ((*bad)++ < 5) printf("  \"%s\": %a (end %d), strtod %a (end %d)\n", s, a, (int)(e1 - s), b, (int)(e2 - s));
  return 0;
}

/* A random decimal string: sign, 1 to 22 digits, maybe a point among them, maybe an exponent. */
static void RandomDecimal(uint64_t *seed, char *s)
{
  const int nd = 1 + (int)(22 * TestUniform(seed)), point = (int)((nd + 2) * TestUniform(seed)) - 1;
  char     *p  = s;
  if (TestUniform(seed) < 0.3) *p++ = TestUniform(seed) < 0.5 ? '-' : '+';
  for (int k = 0; k < nd; k++) {
    if (k == point) *p++ = '.';
    *p++ = (char)('0' + (int)(10 * TestUniform(seed)));
  }
  if (TestUniform(seed) < 0.5) p += sprintf(p, "e%d", (int)(60 * TestUniform(seed)) - 30);
  *p = 0;
}

int main(void)
{
  TestCount c      = {0, 0};
  uint64_t  seed   = 7;
  long      bad    = 0, n = 0, ties = 0;
  const double special[] = {0.0, -0.0, 1.0, -1.0, 0.1, 0.5, 1e-5, 1e-4, 9.9999999999999995e-5, 1e16, 1e17, 99999999999999999.0,
                            123456789012345678.0, 1e22, 1e23, 1e38, 1e39, DBL_MAX, DBL_MIN, DBL_TRUE_MIN, 5e-324, INFINITY, -INFINITY, NAN,
                            0.30000000000000004, 2.5, 1.0 / 3.0, 2.0 / 3.0, 255.99999999999997, 4503599627370497.5, 9007199254740993.0};

  for (size_t k = 0; k < sizeof special / sizeof *special; k++, n++) Same(special[k], &bad);
  /* random mantissas at every binary exponent from 2^-60 to 2^140, both signs */
  for (int e = -60; e <= 140; e++)
    for (int k = 0; k < 2000; k++, n++) {
      const double m = 1.0 + TestUniform(&seed);
      Same((k & 1 ? -1.0 : 1.0) * ldexp(m, e), &bad);
    }
  /* every smaller binary exponent down to the subnormals (the wide path), fewer values each */
  for (int e = -1074; e < -60; e++)
    for (int k = 0; k < 60; k++, n++) {
      const double m = 1.0 + TestUniform(&seed);
      Same((k & 1 ? -1.0 : 1.0) * ldexp(m, e), &bad); /* rounded to the subnormals below 2^-1022 */
    }
  /* small odd multiples of 2^-sh, among them the exact ties of the wide path (3 2^-25 =
   * 8.94069671630859375e-08 rounds its 17th digit up to even), and their neighbours */
  for (int sh = 16; sh <= 40; sh++)
    for (int k = 1; k < 64; k += 2, n += 3) {
      const double x = ldexp((double)k, -sh);
      Same(x, &bad);
      Same(nextafter(x, 0.0), &bad);
      Same(nextafter(x, 1.0), &bad);
    }
  /* the neighbours of powers of ten, and of their halfway points at 17 digits */
  for (int p = -323; p <= 40; p++) {
    double x = pow(10.0, p);
    for (int k = 0; k < 40; k++, n += 2) {
      Same(x, &bad);
      Same(nextafter(x, 0.0), &bad);
      x = nextafter(x, INFINITY);
    }
  }
  /* exact ties at the 17th digit: short binary fractions m 2^-k whose decimal expansion
   * ends at its 18th significant digit with a 5 (found by snprintf's %.40e) */
  for (long k = 0; k < 400000 && ties < 200; k++) {
    const int    bits = 20 + (int)(34 * TestUniform(&seed)), sh = 1 + (int)(40 * TestUniform(&seed));
    const double x    = ldexp(floor(ldexp(TestUniform(&seed), bits)) * 2 + 1, -sh);
    char         e[64];
    (void)snprintf(e, sizeof e, "%.40e", x); /* d.ddd...e+XX: significant digits at 0, 2.. */
    if (e[18] == '5' && strspn(e + 19, "0") == 23) {
      ties++;
      n++;
      Same(x, &bad);
    }
  }
  TestCheck(&c, ties > 0, "%ld values with a tie at the 17th digit among those", ties);
  TestCheck(&c, bad == 0, "SpamFormatG17 equals snprintf %%.17g for %ld values (%ld differ)", n, bad);

  /* the parser: the printed values read back, random decimals, halfway cases, odd strings */
  {
    const char *odd[] = {"", "-", "+", ".", "-.", "1.", ".5", "-0", "+0", "0.000", "1e", "1e+", "1e-x", "2E3", "0x1p3", "0X10", " 1", "inf", "-Infinity", "nan", "1,2", "3.5 ", "00012.5000",
                         "9007199254740993", "9007199254740995", "4503599627370496.5", "4503599627370497.5", "1e19", "1e20", "1e-21", "1e-22", "12345678901234567890", "1234567890123456789",
                         "0.30000000000000004", "2.2250738585072014e-308", "4.9e-324", "1.7976931348623157e308", "1e400", "123456789012345678e-30", "9999999999999999999e-21"};
    long pbad = 0, pn = 0;
    char s1[64];
    seed = 13;
    for (size_t k = 0; k < sizeof odd / sizeof *odd; k++, pn++) SameParse(odd[k], &pbad);
    for (int e = -80; e <= 80; e++)
      for (int k = 0; k < 1000; k++, pn++) {
        (void)SpamFormatG17(ldexp(1.0 + TestUniform(&seed), e), s1);
        SameParse(s1, &pbad);
      }
    for (int k = 0; k < 200000; k++, pn++) {
      RandomDecimal(&seed, s1);
      SameParse(s1, &pbad);
    }
    /* halfway between two doubles with at most 19 digits: (2m + 1) 2^-j, m in [2^(52-j),
     * 2^(53-j)), is midway between neighbours spaced 2^(1-j) apart, and as a decimal it is
     * the integer (2m + 1) 5^j with the point j places from its right */
    for (int k = 0; k < 40000; k++)
      for (int j = 0; j <= 3; j++, pn++) {
        const uint64_t m = (1ULL << (52 - j)) + (uint64_t)ldexp(TestUniform(&seed), 52 - j), t = (2 * m + 1) * (j == 0 ? 1 : j == 1 ? 5 : j == 2 ? 25 : 125);
        char           d[32];
        const int      len = snprintf(d, sizeof d, "%llu", (unsigned long long)t);
        (void)snprintf(s1, sizeof s1, "%.*s.%s", len - j, d, d + len - j);
        SameParse(s1, &pbad);
      }
    TestCheck(&c, pbad == 0, "SpamParseDouble equals strtod (value and end) for %ld strings (%ld differ)", pn, pbad);
  }
  return TestFinish(&c);
}
