#!/usr/bin/env python3
"""A row of N identical cylinders in a flow, each with its wake oscillator (the paper's model per
cylinder), that collide with their neighbours: the model file, for any N.

    python3 examples/models/cylinder_row.py 3 > cylinder_row_3.toml
    python3 examples/models/cylinder_row.py 4 --gaps 0.3,5,0.3 > pairs.toml

Cylinder k (k = 1..N) rests at -(k - 1) L across the flow and moves by y_k from there, so the
gap between cylinders k and k + 1 is L_k + y_k - y_{k+1}. At contact the two exchange momentum
(equal masses) with Newton's restitution r: the centre-of-mass velocity is kept, the relative
velocity reversed and multiplied by r,

    v_k+ = (v_k + v_{k+1})/2 - r (v_k - v_{k+1})/2,   v_{k+1}+ = (v_k + v_{k+1})/2 + r (v_k - v_{k+1})/2.

Two cylinders in mirror-symmetric motion (y_2 = -y_1, x_2 = -x_1) are the paper's single
cylinder with its barrier at sigma = -L/2: the gap L + 2 y_1 vanishes at y_1 = -L/2, where the
reset gives ydot_1+ = -r ydot_1 (docs/own-model.md, tests/python/test_cylinder_row.py).
Each cylinder carries the paper's equations:

    ydot_k' = a_k = -delta^2 y_k - alpha ydot_k + M x_k
    xdot_k' = -x_k - eps (x_k^2 - 1) xdot_k + A a_k
"""
import argparse
import sys


def row_model(n, gaps=None, initial=None):
    """The model file (TOML text) of a row of `n` cylinders; `gaps` the n - 1 distances at rest
    (default 0.300596 each, twice the paper's barrier distance); `initial` the state to start
    from (default: the paper's start for every cylinder, the wake of every second one mirrored)."""
    if n < 1:
        raise ValueError(f"n must be >= 1 (got {n})")
    gaps = list(gaps) if gaps is not None else [0.300596] * (n - 1)
    if len(gaps) != n - 1:
        raise ValueError(f"--gaps needs {n - 1} values for {n} cylinders (got {len(gaps)})")
    ks = range(1, n + 1)
    lines = [f'name = "cylinder_row_{n}"',
             f'description = "a row of {n} identical cylinders in a flow, each with its wake oscillator, colliding '
             f'with their neighbours (momentum exchange with restitution r)"', "", "state = ["]
    for k in ks:
        lines += [f'    {{ name = "y{k}", meaning = "cross-flow displacement of cylinder {k}", unit = "D" }},',
                  f'    {{ name = "ydot{k}", meaning = "its velocity", unit = "D" }},',
                  f'    {{ name = "x{k}", meaning = "wake variable of cylinder {k}" }},',
                  f'    {{ name = "xdot{k}", meaning = "its rate" }},']
    lines.append("]")
    if initial is None:
        initial = [v for k in ks for v in (0.0, 0.0, 0.0, 0.1 if k % 2 else -0.1)]
    lines += [f"initial_state = [{', '.join(repr(float(v)) for v in initial)}]", "", "[parameters]",
              'Ur = { default = 16.0, meaning = "reduced velocity U/(f_n D)", above = 0 }',
              'r = { default = 0.8, meaning = "coefficient of restitution between cylinders", min = 0, max = 1 }',
              'A = { default = 12.0, meaning = "wake coupling coefficient" }',
              'eps = { default = 0.3, meaning = "Van der Pol coefficient", min = 0 }',
              'St = { default = 0.2, meaning = "Strouhal number", above = 0 }',
              'xi = { default = 0.0052, meaning = "structural damping ratio", min = 0 }',
              'gamma = { default = 0.8, meaning = "stall parameter (fluid damping)", min = 0 }',
              'mu = { default = 1.19381, meaning = "mass ratio (m* + C_m) pi/4", above = 0 }',
              'CL0 = { default = 0.31582734083485947, meaning = "lift coefficient of the fixed cylinder", min = 0 }']
    lines += [f'L{k} = {{ default = {gaps[k - 1]!r}, meaning = "gap between cylinders {k} and {k + 1} at rest", '
              f'unit = "D", above = 0 }}' for k in ks if k < n]
    lines += ["", "[derived]", 'delta = "1/(St*Ur)"', 'alpha = "2*xi*delta + gamma/mu"',
              'M = "CL0/(16*pi^2*St^2*mu)"', "", "[expressions]"]
    lines += [f'a{k} = "-delta^2*y{k} - alpha*ydot{k} + M*x{k}"' for k in ks]
    lines += ["", "[derivatives]"]
    for k in ks:
        lines += [f'y{k} = "ydot{k}"', f'ydot{k} = "a{k}"', f'x{k} = "xdot{k}"',
                  f'xdot{k} = "-x{k} - eps*(x{k}^2 - 1)*xdot{k} + A*a{k}"']
    for k in ks:
        if k == n:
            break
        j = k + 1
        lines += ["", "[[surfaces]]", f'name = "contact{k}{j}"',
                  f'meaning = "cylinders {k} and {j} touch"', f'gap = "L{k} + y{k} - y{j}"',
                  f'reset = {{ ydot{k} = "(ydot{k} + ydot{j})/2 - r*(ydot{k} - ydot{j})/2", '
                  f'ydot{j} = "(ydot{k} + ydot{j})/2 + r*(ydot{k} - ydot{j})/2" }}']
    lines += ["", "[[sections]]", 'name = "maxima"', 'meaning = "maxima of y1: ydot1 = 0, decreasing"',
              'when = "ydot1"', 'direction = "down"', ""]
    return "\n".join(lines)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("n", type=int, help="number of cylinders")
    ap.add_argument("--gaps", help="the n - 1 gaps at rest, comma-separated (default 0.300596 each)")
    a = ap.parse_args(argv)
    try:
        gaps = None if a.gaps is None else [float(g) for g in a.gaps.split(",")]
        sys.stdout.write(row_model(a.n, gaps))
    except ValueError as e:
        print(f"cylinder_row.py: {e}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
