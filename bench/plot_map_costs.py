#!/usr/bin/python3
"""The cost per job of a real map (bench/job_costs.cpp's CSV): where in (Ur, sigma) the
time goes, and how it follows the work (accepted steps).

Usage: /usr/bin/python3 bench/plot_map_costs.py MAP_COSTS.csv OUT.png
Prints the totals, the quantiles of the cost per job, the cost per step of a least-squares
fit seconds = a * steps, and the share of the time spent in the slowest 1 % of the jobs.
"""
import sys

import numpy as np


def main(path, png):
    d = np.genfromtxt(path, delimiter=",", names=True, dtype=None, encoding="utf-8")
    # seconds: the CPU time of the thread that ran the job (build/job_costs), what the job
    # costs whatever else the machine was doing.
    ur, sigma, sec, steps = d["Ur"], d["sigma"], d["seconds"], d["steps"].astype(float)
    nx, ny = int(d["ix"].max()) + 1, int(d["iy"].max()) + 1
    a = float(np.dot(steps, sec) / np.dot(steps, steps))
    q = np.quantile(sec, [0.5, 0.9, 0.99, 1.0])
    top = np.sort(sec)[::-1]
    share = top[: max(1, len(top) // 100)].sum() / sec.sum()
    print(f"jobs {len(sec)} ({nx} x {ny}), sum of job times {sec.sum():.1f} s, mean {sec.mean() * 1e3:.2f} ms")
    print(f"per job: median {q[0] * 1e3:.2f} ms, 90 % {q[1] * 1e3:.2f} ms, 99 % {q[2] * 1e3:.2f} ms, "
          f"max {q[3] * 1e3:.1f} ms; slowest 1 % of the jobs: {share * 100:.1f} % of the time")
    print(f"fit seconds = a * steps: a = {a * 1e9:.1f} ns per accepted step "
          f"(r = {np.corrcoef(steps, sec)[0, 1]:.3f})")
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.colors import LogNorm
    fig, ax = plt.subplots(1, 3, figsize=(17, 5), constrained_layout=True)
    grid = np.full((ny, nx), np.nan)
    grid[d["iy"], d["ix"]] = sec * 1e3
    im = ax[0].imshow(grid, origin="lower", aspect="auto", norm=LogNorm(),
                      extent=[ur.min(), ur.max(), sigma.min(), sigma.max()], cmap="viridis")
    fig.colorbar(im, ax=ax[0], label="CPU time per job [ms]")
    ax[0].set_xlabel("Ur")
    ax[0].set_ylabel("sigma [D]")
    ax[0].set_title("cost per job over the map")
    for s in np.unique(sigma)[:: max(1, ny // 5)]:
        sel = sigma == s
        ax[1].semilogy(ur[sel], sec[sel] * 1e3, lw=0.8, label=f"sigma = {s:.3f}")
    ax[1].set_xlabel("Ur")
    ax[1].set_ylabel("CPU time per job [ms]")
    ax[1].set_title("cost per job against Ur")
    ax[1].legend(loc="upper left", bbox_to_anchor=(1.0, 1.0), fontsize=8)
    ax[2].loglog(steps, sec * 1e3, ".", ms=1.5, alpha=0.4)
    xs = np.array([steps.min(), steps.max()])
    ax[2].loglog(xs, a * xs * 1e3, "r-", label=f"{a * 1e9:.0f} ns per step")
    ax[2].set_xlabel("accepted steps of the job")
    ax[2].set_ylabel("CPU time per job [ms]")
    ax[2].set_title("cost against work")
    ax[2].legend()
    fig.savefig(png, dpi=100)


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
