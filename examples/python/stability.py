#!/usr/bin/env python3
"""Stability along a sweep (the paper's Figures 14 and 16, coarser): the Floquet multipliers
and the largest Lyapunov exponent against Ur, each over the bifurcation diagram. Periodic
orbits have multipliers inside the unit circle and a negative largest exponent; the chaotic
windows have no period (no multipliers) and a positive exponent.

    PYTHONPATH=build/python /usr/bin/python3 examples/python/stability.py
"""
import vimpact
import vimpact.plot
from _common import PROTOCOL, pick, picture

model = vimpact.WakeImpact()
values = vimpact.grid(16, 25, pick(37, 4))
f = vimpact.floquet_sweep(model, "Ur", values, **PROTOCOL)
print(f)
ly = vimpact.lyapunov_sweep(model, "Ur", values, impacts=pick(800, 60), record=pick(100, 10),
                            transient=PROTOCOL.get("transient", 500))
print(ly)
for v, label, lle, se in zip(f.value, f.label, ly.lle, ly.lle_standard_error):
    print(f"  Ur = {v:6.3f}: {label:9} largest exponent {lle:+.4f} +- {se:.1g}")
vimpact.plot.floquet_sweep(f, picture("stability-floquet.png"))
vimpact.plot.lyapunov_sweep(ly, picture("stability.png"))
print("picture:", picture("stability.png"))
