#!/usr/bin/python3
"""Study 5 figures from conversion_table.csv (written by the conversion_table program).

    plot.py DIR

Writes DIR/conversion_efficiency.png (vertex efficiency of the two split rules, and of the interval
rule with a pass of local search, per mesh, against the lower bound 1 and the per-mesh lower bound) and DIR/conversion_hybrid.png (what hybrid conversion trades: vertices added
against the Hausdorff distance it allows, per dihedral bound).
"""

import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "study_support"))
import plotting  # noqa: E402

# (split rule, local search passes): label and colour.
SPLIT_SERIES = {
    ("interval", "0"): ("interval rule", "tab:blue"),
    ("interval", "1"): ("interval rule, local search", "tab:green"),
    ("shell", "0"): ("shell rule", "tab:orange"),
}
HYBRID_BOUNDS = {"5": "tab:green", "10": "tab:cyan", "20": "tab:purple"}


def converted(rows):
    """Rows of conversions that ran and were certified."""
    return [r for r in rows if r["status"] == "certified" and r["seconds"]]


def efficiency_figure(rows, path):
    split = [r for r in rows if r["method"] == "split" and r["vertex_efficiency"]]
    meshes = sorted({r["mesh"] for r in split}, key=lambda m: m.split(".")[0])
    figure, axes = plotting.plt.subplots(figsize=(8, 4.2))
    for offset, ((rule, passes), (label, colour)) in zip((-0.2, 0.0, 0.2), SPLIT_SERIES.items()):
        by_mesh = {r["mesh"]: float(r["vertex_efficiency"]) for r in split
                   if r["split_rule"] == rule and r.get("local_search", "0") == passes
                   and r.get("cascade_trials") != "0"}
        x = [i + offset for i, m in enumerate(meshes) if m in by_mesh]
        y = [by_mesh[m] for m in meshes if m in by_mesh]
        if y:
            axes.scatter(x, y, color=colour, label=f"split, {label} (median {np.median(y):.2f})", zorder=3)
    bounds = {r["mesh"]: float(r["efficiency_lower_bound"]) for r in split if r.get("efficiency_lower_bound")}
    if bounds:
        axes.scatter([i for i, m in enumerate(meshes) if m in bounds], [bounds[m] for m in meshes if m in bounds],
                     marker="_", s=400, color="black", zorder=2,
                     label=f"lower bound of any split conversion (median {np.median(list(bounds.values())):.2f})")
    axes.axhline(1.0, color="black", linestyle="--", linewidth=1, label="one vertex per edge")
    axes.set_yscale("log")
    axes.set_xticks(range(len(meshes)))
    axes.set_xticklabels([m.split(".")[0] for m in meshes], rotation=40, ha="right")
    axes.set_ylabel("vertex efficiency\n(added vertices / non-flat non-Delaunay edges)")
    axes.set_title("Geometry-preserving split: vertices added per non-Delaunay edge")
    axes.grid(True, which="both", axis="y", alpha=0.3)
    axes.legend(fontsize=8)
    plotting.save(figure, path)


def hybrid_figure(rows, path):
    hybrid = [r for r in rows if r["method"] == "hybrid"]
    split = {r["mesh"]: int(r["added_vertices"]) for r in rows
             if r["method"] == "split" and r["split_rule"] == "interval" and r.get("local_search", "0") == "0"
             and r.get("cascade_trials") != "0"}
    figure, axes = plotting.plt.subplots(figsize=(6.5, 4.5))
    for bound, colour in HYBRID_BOUNDS.items():
        chosen = [r for r in hybrid if r["max_dihedral_deg"] == bound and split.get(r["mesh"])]
        # Meshes whose hybrid conversion moved nothing measurable sit on the axis floor.
        x = [int(r["added_vertices"]) / split[r["mesh"]] for r in chosen]
        y = [max(float(r["hausdorff_rel"]), 1e-9) for r in chosen]
        axes.scatter(x, y, color=colour, label=f"hybrid, flips within {bound}° of flat")
    axes.set_yscale("log")
    axes.set_xlabel("vertices added, relative to split (interval rule)")
    axes.set_ylabel("Hausdorff distance to the input\n(fraction of the bounding-box diagonal)")
    axes.set_title("Hybrid conversion: fewer vertices for a bounded change")
    axes.grid(True, which="both", alpha=0.3)
    axes.legend(fontsize=8)
    plotting.save(figure, path)


def main():
    out = Path(sys.argv[1])
    rows = converted(plotting.read_rows(out / "conversion_table.csv"))
    efficiency_figure(rows, out / "conversion_efficiency.png")
    hybrid_figure(rows, out / "conversion_hybrid.png")


if __name__ == "__main__":
    main()
