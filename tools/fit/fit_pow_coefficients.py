#!/usr/bin/env python3
"""Derives the coefficients of facet's `fast` pow tier (engine/src/fastmath/pow_simd.hpp).

  log2(m) ~= (m - 1) * q(m)   for m in [sqrt(1/2), sqrt(2)),  q of degree LOG_DEGREE
  2^f     ~= 1 + f * r(f)     for f in [0, 1),                r of degree EXP_DEGREE - 1

Both are weighted least-squares fits of the *relative* error at 4000 Chebyshev nodes, solved in
double precision by Gaussian elimination (pure Python: no numpy on the build machines). Writing
log2 as (m - 1) q(m) and 2^f as 1 + f r(f) makes log2(1) = 0 and 2^0 = 1 exact, so 1^s = 1 exactly.
Prints the coefficients and the largest relative error of each approximation.
"""
import math

LOG_DEGREE = 4
EXP_DEGREE = 4
NODES = 4000


def chebyshev(a, b, n):
    return [0.5 * (a + b) + 0.5 * (b - a) * math.cos(math.pi * (k + 0.5) / n) for k in range(n)]


def least_squares(rows, rhs):
    n = len(rows[0])
    ata = [[sum(r[i] * r[j] for r in rows) for j in range(n)] for i in range(n)]
    atb = [sum(r[i] * y for r, y in zip(rows, rhs)) for i in range(n)]
    for c in range(n):
        p = max(range(c, n), key=lambda r: abs(ata[r][c]))
        ata[c], ata[p] = ata[p], ata[c]
        atb[c], atb[p] = atb[p], atb[c]
        for r in range(c + 1, n):
            f = ata[r][c] / ata[c][c]
            for k in range(c, n):
                ata[r][k] -= f * ata[c][k]
            atb[r] -= f * atb[c]
    x = [0.0] * n
    for r in reversed(range(n)):
        x[r] = (atb[r] - sum(ata[r][k] * x[k] for k in range(r + 1, n))) / ata[r][r]
    return x


def poly(c, x):
    y = 0.0
    for a in reversed(c):
        y = y * x + a
    return y


# log2(m) = (m - 1) q(m): fit q(m) = log2(m) / (m - 1) (relative error of log2 = relative error of q).
ms = [m for m in chebyshev(math.sqrt(0.5), math.sqrt(2.0), NODES) if abs(m - 1) > 1e-9]
q = least_squares([[m ** k for k in range(LOG_DEGREE + 1)] for m in ms], [math.log2(m) / (m - 1) for m in ms])
log_err = max(abs(poly(q, m) * (m - 1) / math.log2(m) - 1) for m in ms)

# 2^f = 1 + f r(f), relative error weighted by 1 / 2^f.
fs = [f for f in chebyshev(0.0, 1.0, NODES) if f > 1e-9]
r = least_squares([[f ** (k + 1) / 2 ** f for k in range(EXP_DEGREE)] for f in fs], [(2 ** f - 1) / 2 ** f for f in fs])
exp_err = max(abs((1 + f * poly(r, f)) / 2 ** f - 1) for f in fs)

print("log2 q coefficients (m^0 ..):", ", ".join("%.9ef" % c for c in q))
print("largest relative error of log2: %.3g" % log_err)
print("exp2 r coefficients (f^0 ..):", ", ".join("%.9ef" % c for c in r))
print("largest relative error of exp2: %.3g" % exp_err)
