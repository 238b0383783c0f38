#!/usr/bin/env python3
"""Lock-in without the barrier (the paper's Figure 10a, b): amplitude max|y| and frequency of
the structure against Ur, for three couplings with A/eps = 40. The amplitude peaks where the
structure's natural frequency 1/(St Ur) meets the wake's; the frequency locks on to it.

    PYTHONPATH=build/python /usr/bin/python3 examples/python/response.py
"""
import numpy as np

import vimpact
import vimpact.plot
from _common import pick, picture

r = vimpact.response(vimpact.WakeImpact(), "Ur", vimpact.grid(2, 25, pick(93, 6)),
                     curves=[(14, 0.35), (12, 0.3), (10, 0.25)])
for (A, eps), amp in zip(r.curves, r.amplitude):
    k = int(np.nanargmax(amp))
    print(f"A = {A:g}, eps = {eps:g}: peak amplitude {amp[k]:.4f} at Ur = {r.values[k]:g}")
print("points whose minima did not settle:", r.not_converged.tolist())
vimpact.plot.response(r, picture("response.png"))
print("picture:", picture("response.png"))
