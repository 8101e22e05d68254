#!/usr/bin/python3
"""Study 6 figures from the geodesics program's output.

    plot.py DIR

Writes DIR/geodesics_sphere.png (error against the great-circle distance under refinement, with
fitted orders), DIR/geodesics_field_<mesh>.png for every mesh with PLY files (its distance field,
original / split / iDT, banded so that the bands are isolines), DIR/geodesics_summary.md, and
prints the summary.
"""

import sys
from collections import defaultdict
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "study_support"))
import plotting  # noqa: E402

STYLES = {"regular": "-", "flipped": "--"}


def sphere_figure(out):
    curves = defaultdict(list)
    for r in plotting.read_rows(out / "geodesics_sphere.csv"):
        curves[(r["triangulation"], r["connectivity"])].append(
            (float(r["regular_mean_edge_length"]), float(r["mean_abs_error"])))
    figure, ax = plotting.plt.subplots(figsize=(6.6, 4.6))
    rows = []
    for (triangulation, connectivity), points in sorted(curves.items()):
        h, error = np.array(sorted(points)).T
        order = plotting.fitted_order(h, error)
        ax.loglog(h, error, STYLES[triangulation], marker="o", ms=4, color=plotting.COLOURS[connectivity],
                  label=f"{triangulation}, {plotting.LABELS[connectivity]}: order {order:.2f}")
        rows.append([triangulation, plotting.LABELS[connectivity], f"{order:.2f}", f"{error[0]:.3e}"])
    ax.set_xlabel("h: mean edge length of the regular icosphere (unit sphere)")
    ax.set_ylabel("mean |d − great-circle distance| (radians)")
    ax.set_title("Heat-method distance on icospheres: regular (solid) vs re-triangulated (dashed)", fontsize=10)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7)
    ax.xaxis.set_minor_formatter(plotting.NullFormatter())  # decades only: minor labels collide
    plotting.save(figure, out / "geodesics_sphere.png")
    return plotting.markdown_table(["sphere mesh", "connectivity", "fitted order", "error, finest mesh"], rows)


def field_figures(out):
    """One figure per mesh with PLY files: its distance field under each connectivity."""
    for original in sorted(out.glob("geodesics_*_original.ply")):
        stem = original.name[len("geodesics_"):-len("_original.ply")]
        panels = [c for c in ("original", "split", "idt") if (out / f"geodesics_{stem}_{c}.ply").exists()]
        fields = {c: plotting.read_ascii_ply(out / f"geodesics_{stem}_{c}.ply") for c in panels}
        limits = (0.0, max(f[2]["distance"].max() for f in fields.values()))
        frame = plotting.principal_frame(fields["original"][0])  # every panel seen alike
        figure = plotting.plt.figure(figsize=(4.2 * len(panels), 4.4))
        for i, c in enumerate(panels):
            vertices, faces, values = fields[c]
            ax = figure.add_subplot(1, len(panels), i + 1, projection="3d")
            plotting.draw_field(ax, vertices, faces, values["distance"], view=(15, -75), frame=frame, colour_map="turbo",
                                bands=16, limits=limits)
            label = plotting.LABELS[c] + (" (drawn on the input's faces)" if c == "idt" else "")
            ax.set_title(f"{label}\nmax distance {values['distance'].max():.3g}", fontsize=9)
        figure.suptitle(f"{stem}: heat-method distance from vertex 0, 16 colour bands of equal width "
                        f"(0 to {limits[1]:.3g} model units): the bands should be smooth, evenly spaced rings",
                        fontsize=10)
        plotting.save(figure, out / f"geodesics_field_{stem}.png", title_space=0.08)


def main():
    out = Path(sys.argv[1])
    sphere_table = sphere_figure(out)
    field_figures(out)
    corpus_rows = [[r["mesh"], plotting.LABELS[r["connectivity"]], r["vertices"], f"{float(r['eikonal_residual']):.4f}",
                    f"{float(r['max_distance']):.4g}"] for r in plotting.read_rows(out / "geodesics_corpus.csv")]
    corpus_table = plotting.markdown_table(
        ["mesh", "connectivity", "vertices", "mean abs(‖∇d‖ − 1)", "max distance"], corpus_rows)
    text = sphere_table + "\n\n" + corpus_table + "\n"
    plotting.write_text(out / "geodesics_summary.md", text)
    print(text)


if __name__ == "__main__":
    main()
