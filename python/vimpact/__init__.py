"""vimpact: nonlinear dynamics of a wake-induced vibro-impacting oscillator.

This package holds the plotting helpers used by the command line (``vimpact.plot``).
"""
