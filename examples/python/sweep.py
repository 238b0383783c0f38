#!/usr/bin/env python3
"""Bifurcation diagram (the paper's Figure 2a): y at the maxima of y against Ur.

Every point starts from the paper's initial state (0, 0, 0, 0.1), runs 500 impacts and keeps
the next 200 maxima; the blue line is the grazing value of the barrier-free system, which
the barrier (green) must lie above for impacts to happen. The points run in parallel, and the
result does not depend on the number of threads.

    PYTHONPATH=build/python /usr/bin/python3 examples/python/sweep.py
"""
import vimpact
import vimpact.plot
from _common import PROTOCOL, pick, picture

model = vimpact.WakeImpact(sigma=-0.150298)
s = vimpact.sweep(model, "Ur", vimpact.grid(12, 25, pick(131, 14)), grazing=True, **PROTOCOL)
print(s)
for ur, label in zip(s.value, s.label):
    if round(ur, 9) in (16, 19, 21.5, 24.8):  # the paper's P2, P3, P4, P8
        print(f"  Ur = {ur}: {label}")
print(f"{s.stats['jobs']} runs on {s.stats['threads']} threads in {s.stats['wall_time']:.1f} s")
vimpact.plot.bifurcation(s, picture("sweep.png"))
print("picture:", picture("sweep.png"))
