#!/usr/bin/python3
"""Like for like at one point of the paper's protocol (Ur = 16, sigma = -0.150298, paper
preset, 500 impacts discarded, 200 maxima kept, rtol = atol = 1e-10): every C++ program of
the work-precision diagram, run in rounds (each program once per round, REPEAT rounds) so that
a change of the machine's load touches them all alike; medians. Error: the largest state
difference (max-norm of y, v, x, w) of the 200 section points from vimpact's DOP853 at 1e-14.
"hold B": vimpact with the step-size controller's hold band B (integrator_options::hold_band);
without it, each method's default (0.1 for DOPRI5, off for DOP853).
The peers are compiled with GCC's default for C++, -ffp-contract=fast: the compiler may fuse
their multiplies and adds, as vimpact's stage sums do explicitly.

Usage: /usr/bin/python3 bench/like_for_like.py BUILD_DIR [REPEAT]
Prints a Markdown table (docs/performance.md quotes it): wall, steps, rejected, rhs calls,
ns per step, ns per rhs call, error, and the time relative to the plain DOPRI5 loop and to
Odeint's DOPRI5.
"""
import json
import os
import statistics
import subprocess
import sys
import tempfile

import numpy as np


def main():
    build = sys.argv[1]
    repeat = int(sys.argv[2]) if len(sys.argv) > 2 else 7
    progs = [("vimpact DOP853", [f"{build}/wp_vimpact", "--method", "dop853"]),
             ("vimpact DOPRI5", [f"{build}/wp_vimpact", "--method", "dopri5"]),
             ("vimpact DOP853, hold 0.1", [f"{build}/wp_vimpact", "--method", "dop853", "--hold", "0.1"]),
             ("vimpact DOPRI5, hold 0 (off)", [f"{build}/wp_vimpact", "--method", "dopri5", "--hold", "0"]),
             ("plain DOPRI5 loop", [f"{build}/baseline_plain"]),
             ("Odeint DOPRI5", [f"{build}/baseline_odeint", "--method", "dopri5"]),
             ("Odeint RKF78", [f"{build}/baseline_odeint", "--method", "rkf78"])]
    if os.path.exists(f"{build}/baseline_sundials"):
        progs += [("CVODE Adams", [f"{build}/baseline_sundials", "--method", "cvode-adams"]),
                  ("ARKODE ERK (DP5)", [f"{build}/baseline_sundials", "--method", "arkode-erk"])]
    with tempfile.TemporaryDirectory() as d:
        ref = os.path.join(d, "ref.csv")
        subprocess.run([f"{build}/wp_vimpact", "--tol", "1e-14", "--points", ref], check=True, capture_output=True)
        xr = np.genfromtxt(ref, delimiter=",", skip_header=1)[:, 1:5]
        walls = {name: [] for name, _ in progs}
        info, err = {}, {}
        for _ in range(repeat):
            for name, cmd in progs:
                pts = os.path.join(d, "p.csv")
                r = json.loads(subprocess.run(cmd + ["--tol", "1e-10", "--points", pts], check=True,
                                              capture_output=True, text=True).stdout)
                walls[name].append(r["cpu_s"])
                info[name] = r
                x = np.genfromtxt(pts, delimiter=",", skip_header=1)[:, 1:5]
                err[name] = float(np.max(np.abs(x - xr)))
    med = {k: statistics.median(v) for k, v in walls.items()}
    plain, odeint = med["plain DOPRI5 loop"], med["Odeint DOPRI5"]
    print(f"medians of {repeat} rounds of process CPU time (a loaded machine inflates wall time, not this); "
          f"error: max state difference of the 200 section points from DOP853 at 1e-14")
    print()
    print("| program | CPU time [ms] | steps | rejected | rhs calls | ns/step | ns/rhs call | error | / plain DOPRI5 | / Odeint DOPRI5 |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for name, _ in progs:
        r, w = info[name], med[name]
        print(f"| {name} | {w * 1e3:.2f} | {r['steps']} | {r['rejected']} | {r['rhs_calls']} | "
              f"{w / r['steps'] * 1e9:.0f} | {w / r['rhs_calls'] * 1e9:.1f} | {err[name]:.1e} | "
              f"{w / plain:.2f} | {w / odeint:.2f} |")


if __name__ == "__main__":
    main()
