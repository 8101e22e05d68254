#!/usr/bin/python3
"""Study 2 figure from accuracy_eigenvalues.csv (written by the accuracy program).

    plot.py DIR

Exact spectra: unit sphere l(l+1) with multiplicity 2l+1; upper hemisphere, Dirichlet: l(l+1)
with multiplicity l (spherical harmonics odd in z), Neumann: multiplicity l+1 (even in z); unit
disk, Dirichlet: j_{n,k}^2 (zeros of the Bessel function J_n, from scipy.special.jn_zeros),
multiplicity 1 for n = 0 and 2 for n >= 1. The error of a mesh is the mean relative error
|λ_i − λ_i^exact| / λ_i^exact over its computed non-zero eigenvalues; the order is the slope of
log(error) against log(h), h the mean edge length of the regular mesh of the same level.
Writes DIR/accuracy.png and DIR/accuracy_summary.md and prints the summary.
"""

import sys
from collections import defaultdict
from pathlib import Path

import numpy as np
from scipy.special import jn_zeros

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "study_support"))
import plotting  # noqa: E402

TITLES = {
    "sphere": "unit sphere",
    "hemisphere_dirichlet": "hemisphere, Dirichlet",
    "hemisphere_neumann": "hemisphere, Neumann",
    "disk_dirichlet": "unit disk, Dirichlet",
}
STYLES = {"regular": "-", "flipped": "--", "jittered": ":"}
MARKERS = {"regular": "o", "flipped": "s", "jittered": "^"}


def exact_spectrum(shape, count):
    """The `count` smallest exact eigenvalues of a shape, ascending, with multiplicity."""
    values = []
    if shape == "disk_dirichlet":
        for n in range(count):
            for zero in jn_zeros(n, count):
                values += [zero * zero] * (1 if n == 0 else 2)
        return np.sort(values)[:count]
    multiplicity = {"sphere": lambda l: 2 * l + 1, "hemisphere_neumann": lambda l: l + 1,
                    "hemisphere_dirichlet": lambda l: l}[shape]
    l = 0
    while len(values) < count:
        values += [l * (l + 1)] * multiplicity(l)
        l += 1
    return np.array(values[:count], dtype=float)


def main():
    out = Path(sys.argv[1])
    spectra = defaultdict(dict)  # (shape, triangulation, connectivity) -> level -> (h, eigenvalues)
    for r in plotting.read_rows(out / "accuracy_eigenvalues.csv"):
        key = (r["shape"], r["triangulation"], r["connectivity"])
        h, values = spectra[key].setdefault(int(r["level"]), (float(r["regular_mean_edge_length"]), []))
        values.append(float(r["eigenvalue"]))

    shapes = [s for s in TITLES if any(key[0] == s for key in spectra)]
    figure, axes = plotting.plt.subplots(1, len(shapes), figsize=(4.3 * len(shapes), 4.4), squeeze=False)
    summary = []
    for ax, shape in zip(axes[0], shapes):
        for (s, triangulation, connectivity), levels in sorted(spectra.items()):
            if s != shape or connectivity == "hybrid":
                continue
            h, error = [], []
            for level in sorted(levels):
                mesh_h, values = levels[level]
                exact = exact_spectrum(shape, len(values))
                nonzero = exact > 0
                h.append(mesh_h)
                error.append(np.mean(np.abs(np.array(values)[nonzero] - exact[nonzero]) / exact[nonzero]))
            order = plotting.fitted_order(h, error) if len(h) > 1 else float("nan")
            ax.loglog(h, error, STYLES[triangulation], marker=MARKERS[triangulation], ms=4,
                      color=plotting.COLOURS[connectivity],
                      label=f"{triangulation}, {connectivity}: order {order:.2f}")
            summary.append([TITLES[shape], triangulation, plotting.LABELS[connectivity], f"{order:.2f}",
                            f"{error[-1]:.2e}", f"{h[-1]:.4f}"])
        ax.set_title(TITLES[shape], fontsize=10)
        ax.set_xlabel("h: mean edge length of the regular mesh (unit radius)")
        ax.set_ylabel("mean relative eigenvalue error")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=6.5, loc="upper left")
        ax.xaxis.set_minor_formatter(plotting.NullFormatter())  # decades only: minor labels collide
    figure.suptitle("Eigenvalue error under refinement: regular (solid), flipped (dashed), jittered (dotted); "
                    "red original, blue split self-Delaunay, green iDT", fontsize=10)
    plotting.save(figure, out / "accuracy.png", title_space=0.08)
    table = plotting.markdown_table(
        ["shape", "triangulation", "connectivity", "fitted order", "error, finest mesh", "h, finest mesh"], summary)
    plotting.write_text(out / "accuracy_summary.md", table + "\n")
    print(table)


if __name__ == "__main__":
    main()
