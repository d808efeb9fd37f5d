"""Plots run time against image error from canopy_bench_surface's tradeoff.csv.

Usage: python3 plot_surface_tradeoff.py docs/data/surface/tradeoff.csv docs/data/surface/tradeoff.png
(Debian's python3-matplotlib.)
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main():
    rows = list(csv.DictReader(open(sys.argv[1])))
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    for name, style, label in (("canopy", "o-", "Canopy (pixel threshold)"),
                               ("vtk-adaptive", "s--", "vtkAdaptiveDataSetSurfaceFilter (Scale)"),
                               ("canopy-full", "k*", "full resolution")):
        sel = [r for r in rows if r["filter"] == name]
        if not sel:
            continue
        t = [1e3 * float(r["filter_s"]) for r in sel]
        e = [float(r["rmse_super"]) for r in sel]
        cells = [float(r["cells"]) for r in sel]
        axes[0].plot(t, e, style, label=label)
        axes[1].plot(cells, e, style, label=label)
        for r, x, y in zip(sel, t, e):
            if name != "canopy-full":
                axes[0].annotate(r["parameter"], (x, y), fontsize=7, xytext=(3, 3),
                                 textcoords="offset points")
    axes[0].set_xscale("log")
    axes[0].set_xlabel("filter time (ms, log)")
    axes[0].set_ylabel("RMSE vs 4x supersampled reference (0-255)")
    axes[1].set_xscale("log")
    axes[1].set_xlabel("cells emitted (log)")
    for ax in axes:
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
    fig.suptitle("Run time against image error, 2D front, 512 x 512")
    fig.tight_layout()
    fig.savefig(sys.argv[2], dpi=110)


if __name__ == "__main__":
    main()
