#!/usr/bin/python3
"""Study 4 figure and table from the negative_dual program's output.

    plot.py DIR

Writes DIR/negative_dual.png — the mesh around the centre before and after conversion, vertices
coloured by the sign of ⋆0, and one heat step from a unit of heat at the centre with the
circumcentric mass — and DIR/negative_dual.md (one row per connectivity and mass), and prints the
table.
"""

import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "study_support"))
import plotting  # noqa: E402

ZOOM = 0.3  # half-width of the drawn window around the centre (unit disk)


def main():
    out = Path(sys.argv[1])
    vertices = plotting.read_rows(out / "negative_dual_vertices.csv")
    faces = plotting.read_rows(out / "negative_dual_faces.csv")
    summary = plotting.read_rows(out / "negative_dual.csv")

    def field(connectivity, mass, column):
        rows = [r for r in vertices if r["connectivity"] == connectivity and r["mass"] == mass]
        return np.array([[float(r["x"]), float(r["y"]), float(r[column])] for r in rows])

    figure, axes = plotting.plt.subplots(1, 3, figsize=(13, 4.3))
    for ax, connectivity in zip(axes[:2], ("original", "split")):
        points = field(connectivity, "circumcentric", "star0")
        triangles = np.array([[int(r["a"]), int(r["b"]), int(r["c"])] for r in faces if r["connectivity"] == connectivity])
        ax.triplot(points[:, 0], points[:, 1], triangles, color="0.6", lw=0.7)
        negative = points[:, 2] < 0
        ax.scatter(points[~negative, 0], points[~negative, 1], s=14, color="tab:blue", label="⋆0 > 0", zorder=3)
        ax.scatter(points[negative, 0], points[negative, 1], s=60, color="tab:red", marker="X", label="⋆0 < 0",
                   zorder=4)
        ax.set_xlim(-ZOOM, ZOOM)
        ax.set_ylim(-ZOOM, ZOOM)
        ax.set_aspect("equal")
        ax.set_xlabel("x (unit disk)")
        ax.set_ylabel("y")
        ax.set_title(f"{plotting.LABELS[connectivity]}: ⋆0(centre) = {points[0, 2]:.2e}", fontsize=9)
        ax.legend(fontsize=8, loc="upper right")
    ax = axes[2]
    for connectivity, marker in (("original", "x"), ("split", "o")):
        heat = field(connectivity, "circumcentric", "heat_from_centre")
        radius = np.hypot(heat[:, 0], heat[:, 1])
        ax.scatter(radius, heat[:, 2], s=10, marker=marker, color=plotting.COLOURS[connectivity],
                   label=plotting.LABELS[connectivity])
    ax.set_yscale("symlog", linthresh=1e-5)
    ax.axhline(0, color="k", lw=0.6)
    ax.set_xlabel("distance r from the centre (unit disk)")
    ax.set_ylabel("temperature after one step")
    ax.set_title("one heat step (M + h²L)u₁ = M·e_centre, M = ⋆0", fontsize=9)
    ax.legend(fontsize=8)
    plotting.save(figure, out / "negative_dual.png")

    rows = [[r["connectivity"], r["mass"], r["vertices"], f"{float(r['centre_star0_over_mean']):.3f}",
             r["negative_dual_cells"], r["negative_weights"], f"{float(r['pointwise_laplacian_centre']):.3f}",
             f"{float(r['max_error']):.2e}", f"{float(r['heat_from_centre_min']):.2e}",
             f"{float(r['heat_from_centre_max']):.2e}", r["heat_step_h2_over_10000"], r["eigenpairs"]] for r in summary]
    table = plotting.markdown_table(
        ["connectivity", "mass M", "vertices", "⋆0(centre) / mean ⋆0", "⋆0 < 0", "⋆1 < 0 (margin < −1e-10)",
         "(L u)/M at centre (exact 3)", "Poisson max error", "heat step min", "heat step max",
         "heat step, t = h²/10⁴", "10 eigenpairs"], rows)
    plotting.write_text(out / "negative_dual.md", table + "\n")
    print(table)


if __name__ == "__main__":
    main()
