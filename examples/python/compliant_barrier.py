"""The paper's wake model with a compliant barrier tends to the rigid barrier's as the contact
stiffens: the bifurcation diagram over Ur of examples/models/wake_compliant.toml (a spring and
dashpot beyond y = sigma, a switch) at contact stiffnesses kc = 1e3 ... 1e6, each with the
contact damping ratio whose free contact has the rigid model's restitution r, against the
built-in wake_impact's (a rigid barrier and Newton's law). Prints, per kc, how many values of
Ur get the rigid model's label and how far apart the section points are where they do; draws
both diagrams to OUT/python/compliant_barrier.png.

Usage: PYTHONPATH=build/python /usr/bin/python3 examples/python/compliant_barrier.py [--quick]"""
import math
import os

import numpy as np

import vimpact
from _common import PROTOCOL, pick, picture

FILE = os.path.join(os.path.dirname(__file__), "..", "models", "wake_compliant.toml")
Ur = vimpact.grid(14, 26, pick(49, 7))
stiffnesses = pick([1e3, 1e4, 1e5, 1e6], [1e3, 1e5])


def cycles(s):
    """Per value of Ur: its label and, for a label PN, the y of its last N section points, sorted
    (P0: the last point's)."""
    out = []
    for k, label in enumerate(s.label):
        y = s.points[s.point_run == k, 0]
        n = int(label[1:]) if label.startswith("P") else 0
        out.append((label, np.sort(y[-max(n, 1):]) if label.startswith("P") and len(y) else None))
    return out


rigid = vimpact.sweep(vimpact.WakeImpact(), "Ur", Ur, **PROTOCOL)
reference = cycles(rigid)
r = rigid.parameters["r"]
print(f"rigid barrier (wake_impact, r = {r}): {rigid}")
print(f"{'kc':>9} {'zc':>8} {'labels as rigid':>16} {'median |dy|':>12} {'largest |dy|':>13}")
sweeps = {}
for kc in stiffnesses:
    s = vimpact.sweep(vimpact.Model(FILE, kc=kc, r=r), "Ur", Ur, **PROTOCOL)
    sweeps[kc] = s
    same, distances = 0, []
    for (a, ya), (b, yb) in zip(reference, cycles(s)):
        if a == b:
            same += 1
            if ya is not None:
                distances.append(np.max(np.abs(ya - yb)))
    zc = -math.log(r) / math.sqrt(math.pi ** 2 + math.log(r) ** 2)
    print(f"{kc:9.0e} {zc:8.5f} {same:>9} of {len(Ur):<4} {np.median(distances):12.2e} {max(distances):13.2e}")
differ = [f"Ur = {u:g} ({a} rigid, {b})" for u, a, b in zip(Ur, rigid.label, s.label) if a != b]
print(f"labels that differ at kc = {kc:.0e}: {', '.join(differ) or 'none'}")

import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

fig, ax = plt.subplots(figsize=(7, 4))
stiff = stiffnesses[len(stiffnesses) // 2]
ax.plot(rigid.values[rigid.point_run], rigid.points[:, 0], "k.", ms=3, label="rigid barrier")
ax.plot(sweeps[stiff].values[sweeps[stiff].point_run], sweeps[stiff].points[:, 0], "r.", ms=1,
        label=f"compliant, kc = {stiff:.0e}")
ax.set_xlabel("Ur")
ax.set_ylabel("y at the maxima")
ax.legend()
fig.savefig(picture("compliant_barrier.png"), dpi=120)
print("picture:", picture("compliant_barrier.png"))
