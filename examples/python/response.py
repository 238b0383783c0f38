#!/usr/bin/env python3
"""Lock-in without the barrier (the paper's Figure 10a, b): amplitude max|y| and angular
frequency of the structure against Ur, for three couplings with A/eps = 40. The amplitude peaks
where the structure's natural frequency 1/(St Ur) meets the wake's (1 in the model's time
unit); the frequency locks on to it. Each curve is a dict of the parameters it sets.

    PYTHONPATH=build/python /usr/bin/python3 examples/python/response.py
"""
import numpy as np

import vimpact
import vimpact.plot
from _common import pick, picture

r = vimpact.response(vimpact.WakeImpact(), "Ur", vimpact.grid(2, 25, pick(93, 6)),
                     curves=[{"A": 14, "eps": 0.35}, {"A": 12, "eps": 0.3}, {"A": 10, "eps": 0.25}])
for k, amp in enumerate(r.amplitude):
    i = int(np.nanargmax(amp))
    print(f"{r.curve_label(k)}: peak amplitude {amp[i]:.4f} at Ur = {r.values[i]:g}")
print("points whose minima did not settle:", r.not_converged.tolist())
vimpact.plot.response(r, picture("response.png"))
print("picture:", picture("response.png"))
