/* "%.17g" of a double without printf: the particle CSV files write every value so, and
 * glibc's printf takes about 3000 instructions a value (its multi-precision digit
 * generation), the larger part of a short run's start-up and end. The 17 significant
 * digits here come from exact integer arithmetic: x = m 2^e (m < 2^53, read from the
 * double's bits) scaled by a power of ten into [10^16, 10^17), rounded to nearest with ties
 * to even, as glibc does; the text then follows %g's rules (fixed or exponent form,
 * trailing zeros dropped). The scaling is done in 128 bits for |x| from about 1e-6 to
 * 1e38, and in a wider integer of 64-bit limbs below that (a state's small velocities and
 * subnormals: with snprintf there, a final CSV written after one step took twice the
 * instructions). Values above about 1e38, and non-finite ones, go to snprintf, so every
 * value prints exactly as before. */
#include <spam/decimal.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

typedef unsigned __int128 U128;

static const uint64_t p19[20] = {1ULL, 10ULL, 100ULL, 1000ULL, 10000ULL, 100000ULL, 1000000ULL, 10000000ULL, 100000000ULL, 1000000000ULL, 10000000000ULL, 100000000000ULL, 1000000000000ULL, 10000000000000ULL, 100000000000000ULL, 1000000000000000ULL, 10000000000000000ULL, 100000000000000000ULL, 1000000000000000000ULL, 10000000000000000000ULL};

/* 10^k, k = 0..38 (10^38 < 2^127): a table of 64-bit powers, the larger as a product. */
static U128 Pow10(int k)
{
  return k <= 19 ? (U128)p19[k] : (U128)p19[19] * p19[k - 19];
}

/* q = m 10^s 2^e rounded to nearest, ties to even, for s > 22 and e < 0 (|x| below about
 * 1e-6): m 10^s in limbs of 64 bits (at most 1190 bits for the smallest subnormal, s =
 * 340), then shifted right by -e bits. 0 when q would not fit 64 bits (it is below 10^18
 * here) or s is out of range. */
static int DigitsWide(uint64_t m, int e, int s, U128 *q)
{
  enum { LIMBS = 20 };
  uint64_t w[LIMBS] = {m}, v, lo, hi;
  int      n = 1, r = -e, top, L, b, h;

  if (s > 345 || e >= 0) return 0;
  while (s > 0) {
    const uint64_t p = p19[s > 19 ? 19 : s];
    uint64_t       c = 0;
    for (int i = 0; i < n; i++) {
      const U128 t = (U128)w[i] * p + c;
      w[i]         = (uint64_t)t;
      c            = (uint64_t)(t >> 64);
    }
    if (c) w[n++] = c;
    s -= s > 19 ? 19 : s;
  }
  top = 64 * n - __builtin_clzll(w[n - 1]); /* the bit length of m 10^s */
  if (top - r > 64) return 0;
  if (top <= r - 1) { /* below half a unit: q = 0 (cannot happen for q near 10^16) */
    *q = 0;
    return 1;
  }
  L  = r / 64;
  b  = r % 64;
  lo = L < n ? w[L] : 0;
  hi = L + 1 < n ? w[L + 1] : 0;
  v  = b ? (lo >> b) | (hi << (64 - b)) : lo;
  /* the bits below r: the half (bit r - 1) and whether any below it is set */
  h = (int)((w[(r - 1) / 64] >> ((r - 1) % 64)) & 1);
  if (h) {
    int sticky = (w[(r - 1) / 64] & ((((uint64_t)1) << ((r - 1) % 64)) - 1)) != 0;
    for (int i = 0; i < (r - 1) / 64 && !sticky; i++) sticky = w[i] != 0;
    if (sticky || (v & 1)) v++;
  }
  *q = v;
  return 1;
}

/* The 17 digits of m 2^e at decimal exponent E (x = q 10^(E-16)), rounded; 0 when the
 * scaling does not fit. */
static int Digits(uint64_t m, int e, int E, U128 *q)
{
  const int s = 16 - E; /* q ~ x 10^s */
  U128      num, den, rem;

  if (s >= 0) {
    if (s > 22 || -e > 126) return DigitsWide(m, e, s, q);
    num = (U128)m * Pow10(s);
    if (e >= 0) {
      if (e > 10) return 0;
      *q = num << e; /* exact */
      return 1;
    }
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

/* The decimal digits of v < 10^(2 k), two at a time, into d[0 .. 2k) (leading zeros
 * kept). */
static void Pairs(uint32_t v, int k, char *d)
{
  static const char two[201] = "00010203040506070809101112131415161718192021222324252627282930313233343536373839"
                               "40414243444546474849505152535455565758596061626364656667686970717273747576777879"
                               "8081828384858687888990919293949596979899";
  for (int i = k - 1; i >= 0; i--) {
    memcpy(d + 2 * i, two + 2 * (v % 100), 2);
    v /= 100;
  }
}

/* Digits of q (17 of them, q < 10^17 < 2^64) into d, the trailing zeros dropped; returns
 * their count. Two 32-bit halves of 9 and 8 digits, two digits a division: a digit a
 * 64-bit division took half of the function's instructions. */
static int Significant(uint64_t q, char d[17])
{
  const uint32_t hi = (uint32_t)(q / 100000000), lo = (uint32_t)(q % 100000000);
  int            n  = 17;
  d[0]              = (char)('0' + hi / 100000000);
  Pairs(hi % 100000000, 4, d + 1);
  Pairs(lo, 4, d + 9);
  while (n > 1 && d[n - 1] == '0') n--;
  return n;
}

int SpamFormatG17(double x, char *buf)
{
  static const U128 lo = (U128)10000000000000000ULL, hi = (U128)100000000000000000ULL;
  char              d[17], *p = buf;
  int               e2, E, n;
  uint64_t          bits, m;
  U128              q = 0;

  memcpy(&bits, &x, sizeof bits);
  {
    const int      be   = (int)((bits >> 52) & 0x7ff);
    const uint64_t frac = bits & ((((uint64_t)1) << 52) - 1);
    if (be == 0x7ff) return snprintf(buf, 32, "%.17g", x); /* inf, nan */
    if (be == 0 && frac == 0) return (int)strlen(strcpy(buf, bits >> 63 ? "-0" : "0"));
    if (be) { /* x = (m 2^-53) 2^e2 with m in [2^52, 2^53), as frexp gives it */
      m  = frac | ((uint64_t)1 << 52);
      e2 = be - 1022;
    } else { /* subnormal: normalised */
      const int sh = __builtin_clzll(frac) - 11;
      m            = frac << sh;
      e2           = -1021 - sh;
    }
  }
  /* 10^E <= |x| to within one: floor((e2 - 1) log10 2), 78913 / 2^18 = 0.30102920... */
  E = ((e2 - 1) * 78913) >> 18;
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
  if (bits >> 63) *p++ = '-';
  if (E < -4 || E >= 17) {
    const int a = E < 0 ? -E : E;
    *p++        = d[0];
    if (n > 1) {
      *p++ = '.';
      memcpy(p, d + 1, (size_t)n - 1);
      p += n - 1;
    }
    *p++ = 'e';
    *p++ = E < 0 ? '-' : '+';
    if (a >= 100) *p++ = (char)('0' + a / 100);
    *p++ = (char)('0' + a / 10 % 10);
    *p++ = (char)('0' + a % 10);
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
