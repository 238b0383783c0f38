"""Reads the outputs of bench/run_benchmarks.sh and prints the Markdown comparison table.

The vimpact rows time build/protocol_bench (the library's simulate); their accuracy comes
from `vimpact period --out` runs of the same protocol (sections.csv), whose step counts
(run.json) must equal the benchmark's: the same arithmetic, so the same points.
"""
import json
import os
import sys

import numpy as np


def ys(path):
    """The y column of section points, found by name: vimpact names the columns after the
    model's state (t,y,ydot,x,xdot), the baselines write t,y,v,x,w."""
    data = np.genfromtxt(path, delimiter=",", names=True)
    return np.atleast_1d(data["y"])


def main(d):
    ref = ys(os.path.join(d, "ref", "sections.csv"))
    bench = json.load(open(os.path.join(d, "bench.json")))
    rows = []
    for b in bench["benchmarks"]:
        if b.get("aggregate_name") != "median":
            continue
        method = b["run_name"].split("/")[1]
        wall = b["real_time"] / 1000.0  # ms -> s
        run = json.load(open(os.path.join(d, method, "run.json")))
        cli_steps = run["result"]["stats"]["steps"]
        if cli_steps != int(b["steps"]):
            sys.exit(f"{method}: the benchmark took {int(b['steps'])} steps, `vimpact period` {cli_steps}: "
                     "not the same run")
        rows.append((f"vimpact {method}", wall, int(b["steps"]), int(b["rhs_calls"]),
                     np.max(np.abs(ys(os.path.join(d, method, "sections.csv")) - ref))))
    o = json.load(open(os.path.join(d, "odeint.json")))
    rows.append(("Boost.Odeint dopri5 + bisection", o["wall_s"], o["steps"], o["rhs_calls"],
                 np.max(np.abs(ys(os.path.join(d, "odeint.csv")) - ref))))
    for m in ("RK45", "DOP853"):
        if os.path.exists(os.path.join(d, f"scipy-{m}.json")):
            s = json.load(open(os.path.join(d, f"scipy-{m}.json")))
            rows.append((f"scipy solve_ivp {m}", s["wall_s"], s["steps"], s["rhs_calls"],
                         np.max(np.abs(ys(os.path.join(d, f"scipy-{m}.csv")) - ref))))
    ours = rows[0][1]
    print("| implementation | median wall [ms] | accepted steps | rhs calls | steps/s | max abs error of y at section | time / vimpact dop853 |")
    print("|---|---|---|---|---|---|---|")
    for name, wall, steps, rhs, err in rows:
        print(f"| {name} | {wall * 1e3:.2f} | {steps} | {rhs} | {steps / wall:.3g} | {err:.1e} | {wall / ours:.2f} |")


if __name__ == "__main__":
    main(sys.argv[1])
