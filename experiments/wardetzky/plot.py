#!/usr/bin/python3
"""Study 3 table and figure from wardetzky.csv (written by the wardetzky program).

    plot.py DIR

Writes DIR/wardetzky.md (one row per mesh and connectivity, and which of the properties hold)
and DIR/wardetzky.png (negative cotan weights and negative dual cells per mesh), and prints the
table.
"""

import math
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "study_support"))
import plotting  # noqa: E402

# Linear precision holds when the residual is at rounding level.
LINEAR_PRECISION_TOLERANCE = 1e-12


def holds(flag):
    return "yes" if flag else "**no**"


def main():
    out = Path(sys.argv[1])
    rows = plotting.read_rows(out / "wardetzky.csv")
    table = []
    for r in rows:
        linear = float(r["linear_precision_residual"])
        table.append([
            r["mesh"], r["connectivity"], r["vertices"],
            holds(float(r["symmetry_error"]) == 0),
            holds(int(r["nonlocal_entries"]) == 0),
            "n/a (curved)" if math.isnan(linear) else f"{holds(linear < LINEAR_PRECISION_TOLERANCE)} ({linear:.0e})",
            f"{100 * float(r['negative_weight_fraction']):.2f} %",
            f"{float(r['min_weight']):.3g}",
            f"{float(r['min_interior_margin']):.3g}",
            f"{r['negative_dual_cells']} ({100 * float(r['negative_dual_fraction']):.2f} %)",
            f"{float(r['min_dual_area_over_mean']):.3g}",
        ])
    markdown = plotting.markdown_table(
        ["mesh", "connectivity", "vertices", "symmetric", "local", "linear precision (residual)",
         "⋆1 < 0 (margin < −1e-10)", "min ⋆1", "min margin π−(α+β) (rad)", "negative dual cells ⋆0",
         "min ⋆0 / mean ⋆0"], table)
    plotting.write_text(out / "wardetzky.md", markdown + "\n")
    print(markdown)

    meshes = list(dict.fromkeys(r["mesh"] for r in rows))
    figure, axes = plotting.plt.subplots(2, 1, figsize=(max(6.0, 0.75 * len(meshes) + 2), 6.4), sharex=True)
    width = 0.2
    for panel, (column, label) in enumerate([("negative_weight_fraction", "edges with ⋆1 < 0 (%)"),
                                             ("negative_dual_fraction", "vertices with ⋆0 < 0 (%)")]):
        ax = axes[panel]
        for offset, c in enumerate(plotting.CONNECTIVITIES):
            fraction = [100 * float(r[column]) for m in meshes for r in rows if r["mesh"] == m and
                        r["connectivity"] == c]
            ax.bar(np.arange(len(meshes)) + (offset - 1.5) * width, fraction, width, color=plotting.COLOURS[c],
                   label=plotting.LABELS[c])
        ax.set_ylabel(label)
        ax.grid(True, axis="y", alpha=0.3)
    axes[0].legend(fontsize=8)
    axes[0].set_title("Positive weights and positive dual cells: only the self-Delaunay meshes have both", fontsize=10)
    axes[1].set_xticks(np.arange(len(meshes)), [m.rsplit(".", 1)[0] for m in meshes], rotation=35, ha="right",
                       fontsize=8)
    axes[1].set_xlabel("mesh")
    plotting.save(figure, out / "wardetzky.png")


if __name__ == "__main__":
    main()
