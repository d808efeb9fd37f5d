"""Plots run time against image error from canopy_bench_accuracy's accuracy.csv:
one panel per case, filter + render time against RMSE to the truth (every
pixel the exact average of the colours it covers), one curve per filter.

Usage: python3 plot_accuracy.py docs/data/accuracy/accuracy.csv docs/images/accuracy.png
(Debian's python3-matplotlib.)
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

CURVES = (
    ("canopy-colours", "o-", "Canopy, average colours (pixel threshold)"),
    ("canopy-values", "^:", "Canopy, coarse values (pixel threshold)"),
    ("vtk-adaptive", "s--", "vtkAdaptiveDataSetSurfaceFilter (Scale)"),
    ("vtk-axiscut", "D", "vtkHyperTreeGridAxisCut + Geometry"),
    ("every-leaf", "k*", "every leaf"),
)


def main():
    rows = list(csv.DictReader(open(sys.argv[1])))
    cases = list(dict.fromkeys(r["case"] for r in rows))
    columns = 2
    rows_of_panels = (len(cases) + columns - 1) // columns
    fig, axes = plt.subplots(rows_of_panels, columns, figsize=(11, 4.4 * rows_of_panels),
                             squeeze=False)
    panels = [ax for row in axes for ax in row]
    for ax in panels[len(cases):]:
        ax.axis("off")
    for ax, case in zip(panels, cases):
        mine = [r for r in rows if r["case"] == case]
        for name, style, label in CURVES:
            sel = [r for r in mine if r["filter"] == name]
            if not sel:
                continue
            t = [1e3 * (float(r["filter_s"]) + float(r["render_s"])) for r in sel]
            e = [float(r["rmse"]) for r in sel]
            ax.plot(t, e, style, label=label, markersize=5)
            if name in ("canopy-colours", "vtk-adaptive"):
                for r, x, y in zip(sel, t, e):
                    ax.annotate("%g" % float(r["parameter"]), (x, y), fontsize=7, xytext=(3, 3),
                                textcoords="offset points")
        ax.set_xscale("log")
        # Errors near 0 (the mini-app) stay visible: linear below 0.5, log above.
        ax.set_yscale("symlog", linthresh=0.5)
        ax.set_xlabel("filter + render time (ms, log)")
        ax.set_title("%s: %s leaves, %s px" % (case, mine[0]["leaves"], mine[0]["pixels"]),
                     fontsize=9)
        ax.grid(True, which="both", alpha=0.3)
        ax.set_ylabel("RMSE against the truth (0-255)")
        ax.legend(fontsize=6)

    fig.suptitle("Run time against image error (lower left is better)")
    fig.tight_layout()
    fig.savefig(sys.argv[2], dpi=100)


if __name__ == "__main__":
    main()
