#!/usr/bin/env python3
"""Periodicity map (the paper's Figure 4, coarser): the period label over Ur and sigma.

Below the red grazing line the barrier is out of reach (P0); above it the impacting orbits
are P1, P2, ... or aperiodic. Period tolerance 1e-5 as in the paper's Figure 4.

    PYTHONPATH=build/python /usr/bin/python3 examples/python/map.py
"""
import vimpact
import vimpact.plot
from _common import PROTOCOL, pick, picture

m = vimpact.map(vimpact.WakeImpact(),
                x=("Ur", vimpact.grid(12, 25, pick(40, 6))),
                y=("sigma", vimpact.grid(-0.25, 0, pick(26, 5))),
                tol=1e-5, grazing=True, **PROTOCOL)
print(m)
print("label counts:", m.label_counts)
print(f"{m.stats['jobs']} runs on {m.stats['threads']} threads in {m.stats['wall_time']:.1f} s")
vimpact.plot.map(m, picture("map.png"))
print("picture:", picture("map.png"))
