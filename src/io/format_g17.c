/* "%.17g" of a double without printf: the particle CSV files write every value so, and
 * glibc's printf takes about 3000 instructions a value (its multi-precision digit
 * generation), the larger part of a short run's start-up and end. The 17 significant
 * digits here come from exact 128-bit integer arithmetic: x = m 2^e (m < 2^53) scaled by a
 * power of ten into [10^16, 10^17), rounded to nearest with ties to even, as glibc does;
 * the text then follows %g's rules (fixed or exponent form, trailing zeros dropped). Values
 * whose scaling does not fit 128 bits (|x| far from 1: below about 1e-6 or above about
 * 1e38), and non-finite ones, go to snprintf, so every value prints exactly as before. */
#include <spam/decimal.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

typedef unsigned __int128 U128;

/* 10^k, k = 0..38 (10^38 < 2^127): a table of 64-bit powers, the larger as a product. */
static U128 Pow10(int k)
{
  static const uint64_t p19[20] = {1ULL, 10ULL, 100ULL, 1000ULL, 10000ULL, 100000ULL, 1000000ULL, 10000000ULL, 100000000ULL, 1000000000ULL, 10000000000ULL, 100000000000ULL, 1000000000000ULL, 10000000000000ULL, 100000000000000ULL, 1000000000000000ULL, 10000000000000000ULL, 100000000000000000ULL, 1000000000000000000ULL, 10000000000000000000ULL};
  return k <= 19 ? (U128)p19[k] : (U128)p19[19] * p19[k - 19];
}

/* The 17 digits of m 2^e at decimal exponent E (x = q 10^(E-16)), rounded; 0 when the
 * scaling does not fit. */
static int Digits(uint64_t m, int e, int E, U128 *q)
{
  const int s = 16 - E; /* q ~ x 10^s */
  U128      num, den, rem;

  if (s >= 0) {
    if (s > 22) return 0; /* 10^s m < 2^128 */
    num = (U128)m * Pow10(s);
    if (e >= 0) {
      if (e > 10) return 0;
      *q = num << e; /* exact */
      return 1;
    }
    if (-e > 126) return 0;
    *q  = num >> -e;
    den = (U128)1 << -e;
    rem = num & (den - 1);
  } else {
    if (-s > 38 || e > 74 || e < 0) return 0;
    num = (U128)m << e;
    den = Pow10(-s);
    *q  = num / den;
    rem = num % den;
  }
  if (2 * rem > den || (2 * rem == den && (*q & 1))) *q += 1;
  return 1;
}

/* Digits of q (17 of them, q < 10^17 < 2^64) into d, the trailing zeros dropped; returns
 * their count. */
static int Significant(uint64_t q, char d[17])
{
  int n = 17;
  for (int k = 16; k >= 0; k--) {
    d[k] = (char)('0' + (int)(q % 10));
    q /= 10;
  }
  while (n > 1 && d[n - 1] == '0') n--;
  return n;
}

int SpamFormatG17(double x, char *buf)
{
  static const U128 lo = (U128)10000000000000000ULL, hi = (U128)100000000000000000ULL;
  char              d[17], *p = buf;
  int               e2, E, n;
  uint64_t          m;
  U128              q = 0;

  if (x == 0.0) return (int)strlen(strcpy(buf, signbit(x) ? "-0" : "0"));
  if (!isfinite(x)) return snprintf(buf, 32, "%.17g", x);
  m = (uint64_t)ldexp(fabs(frexp(x, &e2)), 53); /* exact: 53 bits */
  E = (int)floor((e2 - 1) * 0.30102999566398120); /* 10^E <= |x| to within one */
  for (int tries = 0;; tries++) {
    if (tries > 3 || !Digits(m, e2 - 53, E, &q)) return snprintf(buf, 32, "%.17g", x);
    if (q >= hi) {
      if (q == hi) { /* rounded up to the next power of ten */
        q = lo;
        E++;
        break;
      }
      E++;
    } else if (q < lo) E--;
    else break;
  }
  n = Significant((uint64_t)q, d);
  if (signbit(x)) *p++ = '-';
  if (E < -4 || E >= 17) {
    *p++ = d[0];
    if (n > 1) {
      *p++ = '.';
      memcpy(p, d + 1, (size_t)n - 1);
      p += n - 1;
    }
    p += snprintf(p, 8, "e%c%02d", E < 0 ? '-' : '+', E < 0 ? -E : E);
  } else if (E >= 0) {
    memcpy(p, d, (size_t)E + 1);
    p += E + 1;
    if (n > E + 1) {
      *p++ = '.';
      memcpy(p, d + E + 1, (size_t)(n - E - 1));
      p += n - E - 1;
    }
  } else {
    *p++ = '0';
    *p++ = '.';
    for (int k = 0; k < -E - 1; k++) *p++ = '0';
    memcpy(p, d, (size_t)n);
    p += n;
  }
  *p = 0;
  return (int)(p - buf);
}
