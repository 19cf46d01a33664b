#!/usr/bin/env python3
"""Re-derives the numerical coefficients of lux-math's `elliptic` module (not needed to build).

1. Carlson's R_F and R_D Taylor series to 7th order (used after the duplication steps): the
   expansion R_{-a}(b; 1 - Z) = sum_N (a)_N/(c)_N T_N(b; Z), T_N = sum_{|m|=N} prod (b_i)_{m_i}/m_i! Z_i^{m_i},
   with R_F = R_{-1/2}(1/2, 1/2, 1/2) and R_D = R_{-3/2}(1/2, 1/2, 3/2), rewritten in the
   variables the Rust code uses (E2, E3 for R_F; Z and Q = XY for R_D).
2. The Gauss-Kummer function GK(h) = 2F1(-1/2, -1/2; 1; h) on four intervals of h: Chebyshev
   interpolants at 40 digits, converted to powers of t in [-1, 1].
3. The ellipse perimeter in its trace form P = sqrt(a^2 + b^2) * F(m), m = ((a^2 - b^2)/(a^2 + b^2))^2,
   exact (F_E, by mpmath's ellipe) and Ramanujan's second approximation (F_R), on the 52
   intervals [(i - 1/2)/64, (i + 1/2)/64] of m (clipped to m >= 0), i.e. m < 0.8047: Chebyshev
   interpolants of degree 7, converted to powers of s = 64 m - i in [-1/2, 1/2], printed as
   Rust arrays.

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


def chebyshev_monomial(f, lo, hi, n):
    """Degree n - 1 Chebyshev interpolant of f on [lo, hi] in powers of t in [-1, 1]."""
    nodes = [mp.cos(mp.pi * (k + mp.mpf(1) / 2) / n) for k in range(n)]
    vals = [f((hi + lo) / 2 + (hi - lo) / 2 * t) for t in nodes]
    cheb = [2 * sum(v * mp.cos(mp.pi * j * (k + mp.mpf(1) / 2) / n) for k, v in enumerate(vals)) / n
            for j in range(n)]
    cheb[0] /= 2
    tpoly = [[mp.mpf(0)] * n for _ in range(n)]
    tpoly[0][0] = 1
    tpoly[1][1] = 1
    for j in range(2, n):
        for i in range(n):
            tpoly[j][i] = (2 * tpoly[j - 1][i - 1] if i else 0) - tpoly[j - 2][i]
    return [sum(cheb[j] * tpoly[j][i] for j in range(n)) for i in range(n)]


def compose_shift(mono, alpha, beta):
    """Powers of s for p(alpha*s + beta), p given by its powers of t (exact at working precision)."""
    out = [mp.mpf(0)] * len(mono)
    for c in reversed(mono):  # Horner over polynomials: out = out*(alpha s + beta) + c
        nxt = [mp.mpf(0)] * len(mono)
        for k, o in enumerate(out):
            nxt[k] += o * beta
            if k + 1 < len(mono):
                nxt[k + 1] += o * alpha
        nxt[0] += c
        out = nxt
    return out


def trace_form():
    mp.mp.dps = 40

    def axes(m):
        s = mp.sqrt(m)
        return mp.sqrt((1 + s) / 2), mp.sqrt((1 - s) / 2)

    def exact(m):
        a, b = axes(m)
        return 2 * mp.pi * a if m == 0 else 4 * a * mp.ellipe(1 - (b / a) ** 2)

    def ramanujan(m):
        a, b = axes(m)
        h = ((a - b) / (a + b)) ** 2
        return mp.pi * (a + b) * (1 + 3 * h / (10 + mp.sqrt(4 - 3 * h)))

    # piece i of x = 64 m covers [i - 1/2, i + 1/2] (piece 0: [0, 1/2], piece 51: up to 51.5)
    for name, f in [("TRACE_EXACT", exact), ("TRACE_RAMANUJAN", ramanujan)]:
        print(f"const {name}: [[f64; 8]; 52] = [")
        for i in range(52):
            lo = max(mp.mpf(i) - mp.mpf(1) / 2, mp.mpf(0))
            hi = mp.mpf(i) + mp.mpf(1) / 2
            mono = chebyshev_monomial(lambda x: f(x / 64), lo, hi, 8)
            # t = (2x - lo - hi)/(hi - lo) with x = i + s
            alpha = 2 / (hi - lo)
            beta = (2 * i - lo - hi) / (hi - lo)
            c = compose_shift(mono, alpha, beta)
            print("    [" + ", ".join(repr(float(x)) for x in c) + "],")
        print("];")


def gauss_kummer():
    mp.mp.dps = 40

    def gk(h):
        return mp.hyp2f1(-0.5, -0.5, 1, h)

    for lo, hi, deg in [(0, 0.25, 11), (0.25, 0.5, 12), (0.5, 0.7, 13), (0.7, 0.85, 14)]:
        mono = chebyshev_monomial(gk, mp.mpf(lo), mp.mpf(hi), deg + 1)
        print(f"GK h in [{lo}, {hi}], degree {deg}:", [repr(float(c)) for c in mono])


if __name__ == "__main__":
    carlson()
    gauss_kummer()
    trace_form()
