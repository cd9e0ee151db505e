/* exp in double for the range the pair force laws reach, without the special-case branches of a library exp (C99
 * subset, no include guard): the OpenCL double builds' pair exp with `backend.pair_exp: ranged` (docs/engine.md "Pair
 * exp"); tests/engine/physics/test_exp.cpp holds it to the host's libm exp and finds the same bits in the kernels. A
 * law's argument is -r/xi with r >= 0 and xi > 0, so x <= 0, or NaN. The includer defines SEMLB_BITS and
 * SEMLB_FROM_BITS (a double's bits as an unsigned 64-bit integer, and back) and provides fma.
 * Method (Cody and Waite 1980, "Software Manual for the Elementary Functions", ch. 6; Muller 2016, "Elementary
 * Functions", 3rd ed., sec. 11.3): x = k ln2 + r with k = rint(x / ln2) and |r| <= ln2/2, ln2 in two parts; exp(r) =
 * 1 + r + r^2 q(r), q of degree 9 (its Chebyshev interpolant, whose truncation error is at most 0.15 ulp); exp(x) =
 * 2^k exp(r), 2^k built from k's bits. 14 fma (3 for the reduction, 11 for the polynomial), a subtraction, an integer
 * add and shift, a multiply, a compare and a select: libdevice's exp adds the scaling branch for |k| >= 1021 and its
 * overflow, underflow and NaN tests.
 * Contract: within 1 ulp of the host's libm exp on [-708.39, 709] (test_exp.cpp); 0 below -708.39 (libm: below
 * 2.24e-308, the smallest normals and the subnormals, which the 2^-32 fixed point of a force truncates to 0 as well);
 * NaN -> NaN; above 709 not defined (a law's argument is never positive). */

/* 2^k exp(r) for x = k ln2 + r. */
static inline double semlb_exp_ranged(double x) {
  const double shifter = 6755399441055744.0; /* 1.5 * 2^52: x / ln2 + shifter rounds to the nearest integer k */
  const double t = fma(x, 1.4426950408889634, shifter);
  const double k = t - shifter;
  double r = fma(k, -6.93147180559945286e-01, x); /* ln2 as its double plus the rest: |r| <= ln2 / 2 + tiny */
  r = fma(k, -2.31904681384629956e-17, r);
  double q = 0x1.af389ecfc4b9cp-26;
  q = fma(q, r, 0x1.28917c89a43a7p-22);
  q = fma(q, r, 0x1.71de0db2f6b19p-19);
  q = fma(q, r, 0x1.a019b9149a41cp-16);
  q = fma(q, r, 0x1.a01a01a7c2efep-13);
  q = fma(q, r, 0x1.6c16c17889ef1p-10);
  q = fma(q, r, 0x1.11111111109b5p-7);
  q = fma(q, r, 0x1.5555555553d68p-5);
  q = fma(q, r, 0x1.5555555555556p-3);
  q = fma(q, r, 0x1.0000000000001p-1);
  const double p = fma(fma(q, r, 1.0), r, 1.0); /* 1 + r (1 + r q) */
  /* 2^k: t's low bits hold k (two's complement); k + 1023 in [1, 2046] is the exponent field of 2^k */
  const double scale = SEMLB_FROM_BITS((SEMLB_BITS(t) + 1023) << 52);
  return x < -708.39 ? 0.0 : p * scale; /* below, 2^k would leave the normal exponents */
}
