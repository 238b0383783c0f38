"""A row of cylinders colliding with their neighbours (examples/models/cylinder_row.py) against
the paper's single cylinder: two identical cylinders in mirror-symmetric motion are one cylinder
with a rigid barrier at half their gap (the gap L + 2 y closes at y = -L/2, and the momentum
exchange with restitution r gives ydot -> -r ydot there). The symmetric motion is invariant,
so the pair's monodromy holds the single cylinder's as its symmetric block: the pair's Floquet
multipliers include the single cylinder's."""
import os
import sys

import numpy as np
import pytest

import vimpact

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "examples", "models"))
from cylinder_row import row_model  # noqa: E402

L = 0.300596  # twice the paper's barrier distance |sigma|


def pair():
    return vimpact.Model.from_toml(row_model(2, [L]), source="cylinder_row_2")


def single():
    return vimpact.Model("wake_impact", sigma=-L / 2)


@pytest.mark.parametrize("Ur", [16.0, 19.0, 22.0])  # P2, P3, P4 orbits of the paper's diagram
def test_a_mirror_pair_is_the_single_cylinder_at_half_the_gap(Ur):
    p, s = vimpact.period(pair().with_(Ur=Ur)), vimpact.period(single().with_(Ur=Ur))
    assert p.label == s.label
    a, b = p.simulation.section, s.simulation.section
    assert a.shape == (b.shape[0], 8)
    assert np.abs(a[:, :4] - b).max() < 1e-7
    assert np.abs(a[:, 4:] + a[:, :4]).max() < 1e-7  # the motion stays mirror-symmetric
    # Every impact of the pair is one of the single cylinder's, at the same time.
    assert np.abs(p.simulation.impact_t - s.simulation.impact_t).max() < 1e-7


def test_a_pairs_sweep_is_the_single_cylinders():
    values = vimpact.grid(15.0, 23.0, 9)
    p, s = vimpact.sweep(pair(), "Ur", values), vimpact.sweep(single(), "Ur", values)
    assert p.label.tolist() == s.label.tolist()
    assert "aperiodic" in s.label and len(set(s.label)) >= 4  # the window crosses P2, P3, P4 and chaos
    # Round-off differences (1e-15) grow on a chaotic attractor: the points agree on the orbits.
    periodic = s.label[s.point_run] != "aperiodic"
    assert np.abs(p.points[periodic, :4] - s.points[periodic]).max() < 1e-7


@pytest.mark.parametrize("Ur", [16.0, 19.0])
def test_the_pairs_multipliers_include_the_single_cylinders(Ur):
    p, s = vimpact.floquet(pair().with_(Ur=Ur)), vimpact.floquet(single().with_(Ur=Ur))
    assert p.status == s.status == "ok"
    for mu in s.multipliers:
        if abs(mu) > 1e-9:  # below, both are round-off of the monodromy
            assert np.min(np.abs(p.multipliers - mu)) < 1e-6 * max(1.0, abs(mu)), (mu, p.multipliers)


def row_of_pairs(pairs):
    """`pairs` mirror pairs at gap L, each 5 D from the next (they never touch), each started
    with its own wake amplitude, so that their impacts never coincide."""
    n = 2 * pairs
    gaps = [L if k % 2 == 0 else 5.0 for k in range(n - 1)]
    start = []
    for k in range(n):
        wake = 0.1 * (1 + 0.25 * (k // 2))
        start += [0.0, 0.0, 0.0, wake if k % 2 == 0 else -wake]
    return vimpact.Model.from_toml(row_model(n, gaps, start), source=f"cylinder_row_{n}")


@pytest.mark.parametrize("pairs", [5])  # 10 cylinders, 40 state variables
def test_a_row_of_mirror_pairs_is_single_cylinders(pairs):
    row = row_of_pairs(pairs)
    assert row.dim == 8 * pairs
    for Ur in (16.0, 19.0):
        p, s = vimpact.period(row.with_(Ur=Ur)), vimpact.period(single().with_(Ur=Ur))
        assert p.label == s.label
        a = p.simulation.section
        # The section is the first cylinder's maxima: its pair runs the single cylinder's orbit
        # (the integration's step sizes follow all 8 * pairs states: agreement to the tolerance).
        assert np.abs(a[:, :4] - s.simulation.section).max() < 1e-7
        for j in range(pairs):
            first, second = a[:, 8 * j:8 * j + 4], a[:, 8 * j + 4:8 * j + 8]
            assert np.abs(first + second).max() < 1e-7  # every pair stays mirror-symmetric
    f, g = vimpact.floquet(row.with_(Ur=16.0)), vimpact.floquet(single().with_(Ur=16.0))
    # Each pair's phase is free (a multiplier 1 per pair): Newton's shooting may stop short
    # of its tolerance on the whole row, the multipliers are still those of its monodromy.
    assert f.status in ("ok", "not_converged") and len(f.multipliers) == 8 * pairs
    for mu in g.multipliers:
        if abs(mu) > 1e-9:
            assert np.min(np.abs(f.multipliers - mu)) < 1e-6 * max(1.0, abs(mu)), (mu, f.multipliers)
