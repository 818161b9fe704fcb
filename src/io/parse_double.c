/* strtod without its multi-precision path (decimal.h): a number of at most 19 significant
 * digits, D 10^k with D < 10^19, is rounded to the nearest double (ties to even, as glibc's
 * strtod in the default rounding mode) from exact 128-bit integers: D 10^k itself for
 * 0 <= k <= 19; for -21 <= k < 0, the quotient of D 2^s by 10^-k with at least 55 bits and
 * its remainder deciding the rounding. Anything else (blanks before the number, more
 * digits, larger exponents, hexadecimal, inf and nan) goes to strtod. */
#include <spam/decimal.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>

typedef unsigned __int128 U128;

static U128 Pow10(int k)
{
  static const uint64_t p19[20] = {1ULL, 10ULL, 100ULL, 1000ULL, 10000ULL, 100000ULL, 1000000ULL, 10000000ULL, 100000000ULL, 1000000000ULL, 10000000000ULL, 100000000000ULL, 1000000000000ULL, 10000000000000ULL, 100000000000000ULL, 1000000000000000ULL, 10000000000000000ULL, 100000000000000000ULL, 1000000000000000000ULL, 10000000000000000000ULL};
  return k <= 19 ? (U128)p19[k] : (U128)p19[19] * p19[k - 19];
}

static int BitLength(U128 v)
{
  const uint64_t hi = (uint64_t)(v >> 64), lo = (uint64_t)v;
  return hi ? 128 - __builtin_clzll(hi) : lo ? 64 - __builtin_clzll(lo) : 0;
}

/* (q + sticky) 2^e2, sticky in [0, 1) nonzero when more, rounded to 53 bits. */
static double Round(U128 q, int sticky, int e2)
{
  const int L = BitLength(q);
  uint64_t  mant;
  if (L <= 53) return ldexp((double)(uint64_t)q, e2); /* exact: sticky is 0 here */
  {
    const int  sh   = L - 53;
    const U128 low  = q & (((U128)1 << sh) - 1), half = (U128)1 << (sh - 1);
    mant            = (uint64_t)(q >> sh);
    if (low > half || (low == half && (sticky || (mant & 1)))) mant++; /* 2^53 stays exact */
    return ldexp((double)mant, e2 + sh);
  }
}

static int Digit(char c) { return c >= '0' && c <= '9'; }

double SpamParseDouble(const char *s, char **end)
{
  const char *p = s;
  uint64_t    D = 0;
  int         nd = 0, k = 0, any = 0, neg = 0;
  double      v;

  if (*p == '-' || *p == '+') neg = *p++ == '-';
  for (; Digit(*p); p++, any = 1) {
    if (D == 0 && *p == '0') continue;
    if (nd++ == 19) return strtod(s, end);
    D = 10 * D + (uint64_t)(*p - '0');
  }
  if (*p == '.')
    for (p++; Digit(*p); p++, any = 1) {
      k--;
      if (D == 0 && *p == '0') continue;
      if (nd++ == 19) return strtod(s, end);
      D = 10 * D + (uint64_t)(*p - '0');
    }
  if (!any || *p == 'x' || *p == 'X') return strtod(s, end);
  if (*p == 'e' || *p == 'E') {
    const char *q = p + 1;
    int         eneg = 0, ev = 0;
    if (*q == '-' || *q == '+') eneg = *q++ == '-';
    if (Digit(*q)) { /* else the 'e' is not part of the number, as for strtod */
      for (; Digit(*q); q++)
        if (ev < 100000) ev = 10 * ev + (*q - '0');
      k += eneg ? -ev : ev;
      p = q;
    }
  }
  if (D == 0) v = 0.0;
  else if (k >= 0 && k <= 19) v = Round((U128)D * Pow10(k), 0, 0);
  else if (k < 0 && k >= -21) {
    const int  sh  = 127 - BitLength(D); /* D 2^sh < 2^127 */
    const U128 num = (U128)D << sh, den = Pow10(-k);
    v              = Round(num / den, num % den != 0, -sh);
  } else return strtod(s, end);
  *end = (char *)p;
  return neg ? -v : v;
}
