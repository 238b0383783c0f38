"""Your own model in Python: the impacting pendulum of docs/own-model.md from its model file,
its bifurcation diagram over the forcing amplitude, Floquet multipliers of a P2 orbit, the
Lyapunov spectrum in the chaotic band, and the same model given as a dict; the diagram is
drawn to OUT/python/own_model.png.

Usage: PYTHONPATH=build/python /usr/bin/python3 examples/python/own_model.py [--quick]"""
import os
import tomllib

import vimpact
from _common import PROTOCOL, pick, picture

FILE = os.path.join(os.path.dirname(__file__), "..", "models", "impacting_pendulum.toml")

m = vimpact.Model.from_file(FILE).with_(w=1.3)
print(f"{m.name}: {', '.join(m.state_names)}; parameters {', '.join(m.parameter_names)}; "
      f"surfaces {', '.join(m.surfaces)}")
s = vimpact.sweep(m, "a", vimpact.grid(0.8, 0.94, pick(141, 15)), section="strobe", **PROTOCOL)
print("sweep:", s)
vimpact.plot.bifurcation(s, picture("own_model.png"))
print("picture:", picture("own_model.png"))
f = vimpact.floquet(m.with_(a=0.85), section="strobe", **PROTOCOL)
print("floquet at a = 0.85:", f)
l = vimpact.lyapunov(m.with_(a=0.891), impacts=pick(800, 100), transient=PROTOCOL.get("transient", 500))
print("lyapunov at a = 0.891:", l)
# The same model from a dict with the file's keys (here read from the file itself).
with open(FILE, "rb") as fh:
    d = vimpact.Model(tomllib.load(fh)).with_(w=1.3, a=0.85)
print("the same model from a dict:", vimpact.floquet(d, section="strobe", **PROTOCOL))
