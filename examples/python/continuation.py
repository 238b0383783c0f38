#!/usr/bin/env python3
"""Continuation of the paper's periodic orbits, stable and unstable (docs/continuation.md):

1. Figure 2a with its skeleton: the branches from the attractors at Ur = 12 (P1, with the
   period doublings switched onto), 19 (P3), 21.5 (P4) and 24.8 (P8), followed both ways, over
   the brute-force bifurcation diagram.
2. Figure 4 with its boundaries: the curves in (Ur, sigma) of the P1 period doubling, of the
   P2 branch's grazing and period doubling and of the barrier-free orbit's grazing (the
   grazing line), over the brute-force periodicity map.
3. Figure 5b with its skeleton: at Ur = 25, the branches in sigma from the barrier-free orbit
   at sigma = -0.16 and from the attractors at -0.149 (P6) and -0.03 (P2), both ways, over the
   brute-force diagram.

    PYTHONPATH=build/python /usr/bin/python3 examples/python/continuation.py
"""
import vimpact
import vimpact.plot
from _common import PROTOCOL, QUICK, pick, picture

model = vimpact.WakeImpact()

# 1. Figure 2a: branches from four attractors, over the brute-force diagram.
sweep = vimpact.sweep(model, "Ur", vimpact.grid(12, 25, pick(261, 14)), **PROTOCOL)
starts = [(12, 25, 3)] + ([] if QUICK else [(19, 12, 1), (19, 25, 1), (21.5, 12, 1), (21.5, 25, 1), (24.8, 24, 1),
                                            (24.8, 25, 1)])
results = []
for a, b, switch in starts:
    c = vimpact.continuation(model, "Ur", (a, b), switch=switch, **PROTOCOL)
    print(f"from Ur = {a} towards {b}:", c)
    results.append(c)
# The brute-force diagram underneath, as the command line's --diagram.
results[0].diagram = dict(value=sweep.point_value, label=sweep.label[sweep.point_run], points=sweep.points)
vimpact.plot.continuation(results, picture("continuation-fig2a.png"))

# 2. Figure 4: curves of bifurcation points in (Ur, sigma) over the periodicity map.
sigma = (-0.25, 0.0)
grid = vimpact.map(model, ("Ur", vimpact.grid(12, 25, pick(66, 6))), ("sigma", vimpact.grid(*sigma, pick(51, 5))),
                   tol=1e-5, **PROTOCOL)
curves = [
    # The P1 orbit's period doubling, and the P2 branch's grazing and period doubling.
    vimpact.continuation(model, "Ur", (12, 25), switch=1, param2="sigma", range2=sigma, **PROTOCOL),
    # The barrier-free orbit's grazing: the grazing line, from sigma at Ur = 25.
    vimpact.continuation(model.with_(Ur=25, sigma=-0.2), "sigma", (-0.2, -0.1), param2="Ur", range2=(12, 25),
                         **PROTOCOL),
]
# Both in the (Ur, sigma) plane: the second one's parameters swapped.
swapped = curves[1]
for c in swapped.curves:
    c.param, c.param2 = c.param2, c.param
swapped.param, swapped.param2, swapped.range, swapped.range2 = "Ur", "sigma", (12, 25), sigma
for c in curves:
    print(c)
vimpact.plot.curves(curves, picture("continuation-fig4.png"), map=grid)

# 3. Figure 5b: branches in sigma at Ur = 25.
at25 = model.with_(Ur=25)
sweep5 = vimpact.sweep(at25, "sigma", vimpact.grid(-0.16, 0, pick(321, 12)), **PROTOCOL)
starts5 = [(-0.16, 0, 1)] + ([] if QUICK else [(-0.149, -0.16, 1), (-0.149, 0, 1), (-0.03, -0.16, 1), (-0.03, 0, 1)])
results5 = []
for a, b, switch in starts5:
    c = vimpact.continuation(at25.with_(sigma=a), "sigma", (a, b), switch=switch, **PROTOCOL)
    print(f"from sigma = {a} towards {b}:", c)
    results5.append(c)
results5[0].diagram = dict(value=sweep5.point_value, label=sweep5.label[sweep5.point_run], points=sweep5.points)
vimpact.plot.continuation(results5, picture("continuation.png"))
print("picture:", picture("continuation.png"))
