#!/usr/bin/env python3
"""Period of the attractor, and one orbit drawn in time and phase space.

The paper's model (paper preset, barrier at sigma = -0.150298) at a few reduced velocities:
the label counts the distinct maxima of y per period (P2 at Ur = 16, P3 at 19, P4 at 21.5
in the paper). Then the Ur = 21.5 orbit with its time series.

    PYTHONPATH=build/python /usr/bin/python3 examples/python/period.py
"""
import vimpact
import vimpact.plot
from _common import PROTOCOL, picture

model = vimpact.WakeImpact(sigma=-0.150298)
for ur in (16, 19, 21.5, 24.8):
    p = vimpact.period(model.with_(Ur=ur), **PROTOCOL)
    print(f"Ur = {ur:5}: {p.label:9} {p.impacts} impact(s) per period, "
          f"y at the section {p.cycle[:, 0].round(5).tolist()}")

s = vimpact.simulate(model.with_(Ur=21.5), sample_dt=0.05, **PROTOCOL)
print(s)
vimpact.plot.phase(s, picture("period.png"))
print("picture:", picture("period.png"))
