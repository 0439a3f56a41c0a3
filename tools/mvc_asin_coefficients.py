#!/usr/bin/python3
"""Coefficients of the arc sine of the 3D mean value coordinates' batch kernel (kAsinP in
core/coordinates/mean_value_coordinates.cpp), and their accuracy.

asin(z) = z + z s P(s), s = z^2, for 0 <= z <= sqrt(1/2) (the kernel's half chords). P is the
polynomial of degree 18 that interpolates (asin(sqrt(s)) / sqrt(s) - 1) / s at the 19 Chebyshev
nodes of [0, 1/2], solved in 60-digit arithmetic and rounded to double. The script prints the
coefficients and the largest error, in units in the last place of asin(z), of the kernel's
evaluation order (even and odd parts in s^2, in double precision) at 33,000 points: uniform in
[0, sqrt(1/2)] and log-uniform down to 1e-18. Needs mpmath and numpy (Debian python3-mpmath,
python3-numpy).
"""
import mpmath as mp
import numpy as np

mp.mp.dps = 60
DEGREE = 18


def p_exact(s):
    s = mp.mpf(s)
    if s == 0:
        return mp.mpf(1) / 6
    r = mp.sqrt(s)
    return (mp.asin(r) / r - 1) / s


def coefficients():
    a, b = mp.mpf(0), mp.mpf("0.5")
    nodes = [(a + b) / 2 + (b - a) / 2 * mp.cos(mp.pi * (k + mp.mpf(1) / 2) / (DEGREE + 1))
             for k in range(DEGREE + 1)]
    A = mp.matrix([[x ** j for j in range(DEGREE + 1)] for x in nodes])
    c = mp.lu_solve(A, mp.matrix([p_exact(x) for x in nodes]))
    return [float(c[j]) for j in range(DEGREE + 1)]


def kernel_asin(c, z):
    """The kernel's evaluation order, in double precision (without fused multiply-adds)."""
    s = z * z
    s2 = s * s
    even = c[18]
    for j in (16, 14, 12, 10, 8, 6, 4, 2, 0):
        even = even * s2 + c[j]
    odd = c[17]
    for j in (15, 13, 11, 9, 7, 5, 3, 1):
        odd = odd * s2 + c[j]
    return z + (z * s) * (even + s * odd)


def main():
    c = coefficients()
    print("kAsinP = {", ", ".join(repr(x) for x in c), "}")
    rng = np.random.default_rng(1)
    zs = np.concatenate([rng.uniform(0, np.sqrt(0.5), 30000),
                         np.sqrt(0.5) * np.exp(rng.uniform(-40, 0, 3000))])
    worst = 0.0
    for z in zs:
        exact = mp.asin(mp.mpf(float(z)))
        err = abs(mp.mpf(kernel_asin(c, float(z))) - exact) / np.spacing(float(exact))
        worst = max(worst, float(err))
    print(f"max error: {worst:.3f} ulp over {len(zs)} points")


if __name__ == "__main__":
    main()
