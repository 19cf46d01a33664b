#!/usr/bin/env python3
"""Re-derives the numerical coefficients of lux-math's `elliptic` module (not needed to build).

1. Carlson's R_F and R_D Taylor series to 7th order (used after the duplication steps): the
   expansion R_{-a}(b; 1 - Z) = sum_N (a)_N/(c)_N T_N(b; Z), T_N = sum_{|m|=N} prod (b_i)_{m_i}/m_i! Z_i^{m_i},
   with R_F = R_{-1/2}(1/2, 1/2, 1/2) and R_D = R_{-3/2}(1/2, 1/2, 3/2), rewritten in the
   variables the Rust code uses (E2, E3 for R_F; Z and Q = XY for R_D).
2. The Gauss-Kummer function GK(h) = 2F1(-1/2, -1/2; 1; h) on four intervals of h: Chebyshev
   interpolants at 40 digits, converted to powers of t in [-1, 1].

Needs sympy and mpmath:  python3 crates/lux-math/scripts/derive_coefficients.py
"""
from itertools import product

import mpmath as mp
import sympy as sp

X, Y, Z = sp.symbols("X Y Z")
HALF = sp.Rational(1, 2)


def poch(a, n):
    r = sp.Integer(1)
    for k in range(n):
        r *= a + k
    return r


def carlson_series(a, b, zs, order):
    c = sum(b)
    total = 0
    for n in range(order + 1):
        tn = 0
        for m in product(range(n + 1), repeat=len(b)):
            if sum(m) != n:
                continue
            t = sp.Integer(1)
            for bi, mi, zi in zip(b, m, zs):
                t *= poch(bi, mi) / sp.factorial(mi) * zi**mi
            tn += t
        total += poch(a, n) / poch(c, n) * tn
    return sp.expand(total)


def fit(target, basis, symbols):
    cs = sp.symbols(f"c0:{len(basis)}")
    expr = sum(c * b for c, b in zip(cs, basis))
    sol = sp.solve(sp.Poly(sp.expand(expr - target), *symbols).coeffs(), cs)
    return [sol[c] for c in cs]


def carlson():
    rf = sp.expand(carlson_series(HALF, [HALF] * 3, [X, Y, Z], 7).subs(Z, -X - Y))
    e2, e3 = sp.expand(X * Y - (X + Y) ** 2), sp.expand(-X * Y * (X + Y))
    terms = [(i, j) for i in range(4) for j in range(3) if 2 * i + 3 * j <= 7]
    coefs = fit(rf, [e2**i * e3**j for i, j in terms], (X, Y))
    print("R_F series, E2^i E3^j:", {t: c for t, c in zip(terms, coefs)})
    rd = carlson_series(3 * HALF, [HALF, HALF, 3 * HALF], [X, Y, Z], 7)
    rd = sp.expand(rd.subs(Z, -(X + Y) / 3))
    terms = [(i, j) for j in range(4) for i in range(8) if i + 2 * j <= 7]
    basis = [(-(X + Y) / 3) ** i * (X * Y) ** j for i, j in terms]
    coefs = fit(rd, basis, (X, Y))
    print("R_D series, Z^i Q^j:", {t: c for t, c in zip(terms, coefs) if c != 0})


def gauss_kummer():
    mp.mp.dps = 40

    def gk(h):
        return mp.hyp2f1(-0.5, -0.5, 1, h)

    for lo, hi, deg in [(0, 0.25, 11), (0.25, 0.5, 12), (0.5, 0.7, 13), (0.7, 0.85, 14)]:
        lo, hi, n = mp.mpf(lo), mp.mpf(hi), deg + 1
        nodes = [mp.cos(mp.pi * (k + mp.mpf(1) / 2) / n) for k in range(n)]
        vals = [gk((hi + lo) / 2 + (hi - lo) / 2 * t) for t in nodes]
        cheb = [2 * sum(v * mp.cos(mp.pi * j * (k + mp.mpf(1) / 2) / n) for k, v in enumerate(vals)) / n
                for j in range(n)]
        cheb[0] /= 2
        tpoly = [[mp.mpf(0)] * n for _ in range(n)]
        tpoly[0][0] = 1
        tpoly[1][1] = 1
        for j in range(2, n):
            for i in range(n):
                tpoly[j][i] = (2 * tpoly[j - 1][i - 1] if i else 0) - tpoly[j - 2][i]
        mono = [sum(cheb[j] * tpoly[j][i] for j in range(n)) for i in range(n)]
        print(f"GK h in [{lo}, {hi}], degree {deg}:", [repr(float(c)) for c in mono])


if __name__ == "__main__":
    carlson()
    gauss_kummer()
