#!/usr/bin/python3
"""Prints the coefficients of the step-size controller's two polynomials
(include/vimpact/integrate/step_control.hpp) and their maximum errors.

  log2(1 + t) = t q(t),  q of degree 7, t in [sqrt(1/2) - 1, sqrt(2) - 1]
  2^g = 1 + g p(g),      p of degree 5, g in [-1/2, 1/2]

Each is interpolated at the Chebyshev points of its interval (within a small factor of the
best polynomial of its degree); written as t q(t) and 1 + g p(g), log2(1) = 0 and 2^0 = 1
exactly. Run by hand: /usr/bin/python3 scripts/gen_controller_polynomials.py
"""
import numpy as np


def chebyshev_fit(f, lo, hi, degree):
    k = np.arange(degree + 1)
    nodes = (lo + hi) / 2 + (hi - lo) / 2 * np.cos((2 * k + 1) * np.pi / (2 * (degree + 1)))
    return np.polyfit(nodes, f(nodes), degree)[::-1]  # c[0] + c[1] x + ...


def show(name, c):
    print(f"{name} = {{{', '.join(repr(float(v)) for v in c)}}}")


lo, hi = np.sqrt(0.5) - 1, np.sqrt(2.0) - 1
q = chebyshev_fit(lambda t: np.log2(1 + t) / t, lo, hi, 7)
t = np.linspace(lo, hi, 400001)
t = t[t != 0]
show("log2 q", q)
print("  max |t q(t) - log2(1 + t)| =", np.max(np.abs(t * np.polynomial.polynomial.polyval(t, q) - np.log2(1 + t))))

p = chebyshev_fit(lambda g: np.expm1(g * np.log(2)) / g, -0.5, 0.5, 5)
g = np.linspace(-0.5, 0.5, 400001)
g = g[g != 0]
show("exp2 p", p)
print("  max |(1 + g p(g)) / 2^g - 1| =", np.max(np.abs((1 + g * np.polynomial.polynomial.polyval(g, p)) / 2**g - 1)))
