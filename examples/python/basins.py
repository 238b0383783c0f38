#!/usr/bin/env python3
"""Basins of attraction (the paper's Figure 3): at Ur = 14.9 a P1 and a P2 orbit coexist;
which one a run reaches depends on its initial (y, dy/dt), with x, dx/dt from the paper's
initial state. Starts below the barrier are left white.

    PYTHONPATH=build/python /usr/bin/python3 examples/python/basins.py
"""
import vimpact
import vimpact.plot
from _common import PROTOCOL, pick, picture

n = pick(30, 5)
b = vimpact.basins(vimpact.WakeImpact(Ur=14.9),
                   x=("y", vimpact.grid(-0.15, 0.25, n)), y=("ydot", vimpact.grid(-0.3, 0.3, n)), **PROTOCOL)
for a in b.attractors:
    print(f"attractor {a.id}: {a.label}, {a.cells} of {b.attractor.size} cells, "
          f"y at its section points {a.cycle[:, b.state_names.index('y')].round(5).tolist()}")
print(f"{b.stats['jobs']} runs on {b.stats['threads']} threads in {b.stats['wall_time']:.1f} s")
vimpact.plot.basins(b, picture("basins.png"))
print("picture:", picture("basins.png"))
