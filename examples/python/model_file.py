#!/usr/bin/env python3
"""Any impacting system: a forced oscillator between two stops, loaded from a model file
(examples/models/two_sided_impact_oscillator.toml, compiled to native code on first use and
cached), and the same system written as a Python dict. A bifurcation diagram over the forcing
frequency w shows the displacement x once per forcing period (the section "strobe"), with the
grazing value of the stops' half-clearance d; then the Floquet multipliers at one point.

    PYTHONPATH=build/python /usr/bin/python3 examples/python/model_file.py
"""
import os

import vimpact
import vimpact.plot
from _common import PROTOCOL, pick, picture

HERE = os.path.dirname(os.path.abspath(__file__))
# Relative to where the script is started, so that the model prints the same on any machine.
model = vimpact.Model.from_file(os.path.relpath(os.path.join(HERE, "..", "models", "two_sided_impact_oscillator.toml")))
print(model)
print("state:", model.state_names, "surfaces:", model.surfaces, "sections:", model.sections)

# The same file's keys as a dict (docs/model-files.md): parameters in the dict's order.
same = vimpact.Model({
    "name": "two_sided_impact_oscillator",
    "description": "a harmonically forced linear oscillator x'' + 2 zeta x' + x = a cos(phi), phi' = w, "
                   "between rigid stops at x = -d and x = d",
    "state": [{"name": "x", "meaning": "displacement"}, {"name": "v", "meaning": "velocity"},
              {"name": "phi", "meaning": "forcing phase", "unit": "rad"}],
    "initial_state": [0.0, 0.0, 0.0],
    "parameters": {"zeta": {"default": 0.05, "meaning": "damping ratio", "min": 0},
                   "a": {"default": 1.0, "meaning": "forcing amplitude"},
                   "w": {"default": 1.2, "meaning": "forcing frequency / natural frequency", "above": 0},
                   "d": {"default": 1.0, "meaning": "half the clearance between the stops", "above": 0},
                   "r": {"default": 0.8, "meaning": "coefficient of restitution", "min": 0, "max": 1}},
    "derivatives": {"x": "v", "v": "-2*zeta*v - x + a*cos(phi)", "phi": "w"},
    "angles": {"phi": "2*pi"},
    "surfaces": [{"name": "right", "meaning": "stop at x = d", "gap": "d - x", "reset": {"v": "-r*v"}},
                 {"name": "left", "meaning": "stop at x = -d", "gap": "x + d", "reset": {"v": "-r*v"}}],
    "sections": [{"name": "strobe", "meaning": "once per forcing period: sin(phi) = 0, increasing (phi = 0 mod 2 pi)",
                  "when": "sin(phi)", "direction": "up"}],
})
print("the dict describes the same model as the file:", same == model)

s = vimpact.sweep(model.with_(d=0.8), "w", vimpact.grid(0.6, 1.6, pick(101, 11)), grazing=True, **PROTOCOL)
print(s)
f = vimpact.floquet(model.with_(d=0.8, w=1.2), **PROTOCOL)
print(f)
print("impacts per period by stop:", f.impacts_by_surface)
vimpact.plot.bifurcation(s, picture("model_file.png"))
print("picture:", picture("model_file.png"))
