#!/usr/bin/env python3
"""Three risers in a row, each with its wake oscillator, colliding with their neighbours (the
model file of examples/models/cylinder_row.py, 12 state variables): a bifurcation diagram of
the first riser over the reduced velocity Ur, and the Lyapunov spectrum at two values.

    PYTHONPATH=build/python /usr/bin/python3 examples/python/cylinder_row.py
"""
import os
import sys

import numpy as np

import vimpact
import vimpact.plot
from _common import PROTOCOL, pick, picture

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "models"))
from cylinder_row import row_model  # noqa: E402

model = vimpact.Model.from_toml(row_model(3), source="cylinder_row_3")
print(model.name, "with", model.dim, "state variables and surfaces", model.surfaces)

s = vimpact.sweep(model, "Ur", vimpact.grid(12, 25, pick(53, 14)), **PROTOCOL)
print(s)
print("impacts in the recorded window, per value:", s.statistics["impacts_recorded"].astype(int).tolist())
for Ur in (14.0, 20.0):
    ly = vimpact.lyapunov(model.with_(Ur=Ur), **PROTOCOL)
    lead = ", ".join(f"{x:.4f}" for x in ly.exponents[:4])
    print(f"Ur = {Ur:g}: largest exponents {lead} (standard error of the largest {ly.lle_standard_error:.1e}); "
          f"sum {np.sum(ly.exponents):.4f}")
vimpact.plot.bifurcation(s, picture("cylinder_row.png"))
print("picture:", picture("cylinder_row.png"))
