#!/usr/bin/python3
"""Peer baseline: the paper's impact-oscillator protocol, written plainly with
scipy.integrate.solve_ivp (RK45 or DOP853, rtol = atol = 1e-10, event location).

Standalone; run with /usr/bin/python3 (needs numpy + scipy):

    /usr/bin/python3 bench/baseline_scipy.py [--method RK45|DOP853] [--ur U] [--tol T] [--horizon H]
                                             [--points FILE] [--repeat N]

Model (state X = (y, v, x, w)):
    dy/dt = v
    dv/dt = a(X) = -delta^2 y - alpha v + M x
    dx/dt = w
    dw/dt = -x - eps (x^2 - 1) w + A a(X)
    delta = 1/(St Ur), alpha = 2 xi delta + gamma/mu, M = 0.05/mu
Impact: y decreasing through sigma -> (y, v, x, w) := (sigma, -r v, x, w).
Section: maxima of y (v crosses 0 downward).
Protocol: discard the first 500 impacts, then record the next 200 section
points and stop; with --horizon H, record every section point with t <= H instead.

Prints one JSON line: wall_s, steps (accepted steps), nfev (= rhs_calls),
rhs_calls, impacts, points; with --repeat N also wall_all.
"""

import argparse
import json
import statistics
import sys
import time

from scipy.integrate import solve_ivp

# ---- paper preset ----------------------------------------------------------
St = 0.2
xi = 0.0052
gamma = 0.8
mu = 1.19381
eps = 0.3
A = 12.0
r = 0.8
sigma = -0.150298


def set_ur(ur):
    global delta, alpha, M, delta2
    delta = 1.0 / (St * ur)
    alpha = 2.0 * xi * delta + gamma / mu
    M = 0.05 / mu
    delta2 = delta * delta


set_ur(16.0)

# ---- protocol --------------------------------------------------------------
N_DISCARD_IMPACTS = 500
N_POINTS = 200
TOL = 1e-10
SEGMENT_SPAN = 1e6  # t_span of one segment; every segment ends at an event


def rhs(t, X):
    y, v, x, w = X
    a = -delta2 * y - alpha * v + M * x
    return [v, a, w, -x - eps * (x * x - 1.0) * w + A * a]


def impact(t, X):
    return X[0] - sigma


impact.terminal = True
impact.direction = -1


def section(t, X):
    return X[1]


section.terminal = False
section.direction = -1


def section_last(t, X):
    # Same section, but terminal: used only when exactly one more point is
    # needed, so the final segment stops at the last recorded point.
    return X[1]


section_last.terminal = True
section_last.direction = -1


def run_protocol(method, tol=TOL, horizon=0.0):
    t = 0.0
    X = [0.0, 0.0, 0.0, 0.1]
    impacts = 0
    steps = 0
    nfev = 0
    points = []

    wall0 = time.perf_counter()
    cpu0 = time.process_time()
    while horizon > 0.0 or len(points) < N_POINTS:
        recording = horizon > 0.0 or impacts >= N_DISCARD_IMPACTS
        last = horizon <= 0.0 and recording and (N_POINTS - len(points) == 1)
        t_end = horizon if horizon > 0.0 else t + SEGMENT_SPAN
        sol = solve_ivp(rhs, (t, t_end), X, method=method,
                        rtol=tol, atol=tol,
                        events=[impact, section_last if last else section])
        if sol.status < 0:
            raise RuntimeError(sol.message)
        steps += len(sol.t) - 1
        nfev += sol.nfev

        if recording:
            for ts, Xs in zip(sol.t_events[1], sol.y_events[1]):
                points.append((float(ts), *map(float, Xs)))
                if horizon <= 0.0 and len(points) >= N_POINTS:
                    break
            if horizon <= 0.0 and len(points) >= N_POINTS:
                break

        if horizon > 0.0 and sol.status == 0:
            break
        if sol.status != 1 or len(sol.t_events[0]) == 0:
            raise RuntimeError("segment ended without an impact")
        t = float(sol.t_events[0][-1])
        y, v, x, w = sol.y_events[0][-1]
        X = [sigma, -r * v, x, w]
        impacts += 1
    wall1 = time.perf_counter()

    return {"wall_s": wall1 - wall0, "cpu_s": time.process_time() - cpu0, "steps": steps, "nfev": nfev,
            "impacts": impacts, "points": points}


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--points", metavar="FILE",
                    help="write the recorded section points as CSV")
    ap.add_argument("--method", choices=("RK45", "DOP853"), default="RK45",
                    help="solve_ivp's method: RK45 (DOPRI5) or DOP853, the orders of vimpact's two")
    ap.add_argument("--ur", type=float, default=16.0, help="reduced velocity")
    ap.add_argument("--tol", type=float, default=TOL, help="rtol = atol")
    ap.add_argument("--horizon", type=float, default=0.0,
                    help="record every section point up to this time instead of the protocol")
    ap.add_argument("--repeat", type=int, default=1, metavar="N",
                    help="run the protocol N times, report the median wall time")
    args = ap.parse_args()
    if args.repeat < 1:
        ap.error("--repeat must be >= 1")
    set_ur(args.ur)

    walls, cpus = [], []
    res = None
    for _ in range(args.repeat):
        res = run_protocol(args.method, args.tol, args.horizon)
        walls.append(res["wall_s"])
        cpus.append(res["cpu_s"])

    if args.points:
        with open(args.points, "w") as f:
            f.write("t,y,v,x,w\n")
            for p in res["points"]:
                f.write(",".join("%.17g" % c for c in p) + "\n")

    out = {"name": "scipy-" + args.method, "method": args.method, "wall_s": statistics.median(walls), "cpu_s": statistics.median(cpus), "steps": res["steps"],
           "rejected": None, "rhs_calls": res["nfev"], "nfev": res["nfev"],
           "impacts": res["impacts"], "points": len(res["points"])}
    out["wall_all"] = walls
    json.dump(out, sys.stdout)
    sys.stdout.write("\n")


if __name__ == "__main__":
    main()
