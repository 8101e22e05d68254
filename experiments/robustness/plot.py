#!/usr/bin/python3
"""Study 1 figure and summary from robustness_eigenvalues.csv (written by the robustness program).

    plot.py DIR

For every base mesh, perturbation kind and connectivity, the relative spread of eigenvalue i
across the perturbations, (max - min) / mean, per index i >= 1 (index 0 is the zero eigenvalue).
The area spread, (max - min) / mean of the total area of the perturbed meshes, measures how much
the flips changed the surface itself. Writes DIR/robustness_spread.png and
DIR/robustness_summary.md, and prints the summary.
"""

import sys
from collections import defaultdict
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "study_support"))
import plotting  # noqa: E402

SPREAD_FLOOR = 1e-6  # lower end of the y axis; smaller spreads are named in the panel


def spectra(rows):
    """{(mesh, kind, connectivity): array perturbations x k}, and the vertex counts."""
    values = defaultdict(lambda: defaultdict(dict))
    vertices = defaultdict(list)
    for r in rows:
        key = (r["mesh"], r["kind"], r["connectivity"])
        values[key][int(r["perturbation"])][int(r["index"])] = float(r["eigenvalue"])
        if r["index"] == "0":
            vertices[key].append(int(r["vertices"]))
    arrays = {}
    for key, by_perturbation in values.items():
        k = min(len(v) for v in by_perturbation.values())
        arrays[key] = np.array([[v[i] for i in range(k)] for _, v in sorted(by_perturbation.items())])
    return arrays, vertices


def area_spread(rows):
    """{(mesh, kind): (max - min) / mean of the total area over the perturbed meshes}: how much the
    surface itself changed, which no choice of connectivity on it can undo."""
    areas = defaultdict(list)
    for r in rows:
        if r["connectivity"] == "original":
            areas[(r["mesh"], r["kind"])].append(float(r["area"]))
    return {key: (max(a) - min(a)) / np.mean(a) for key, a in areas.items()}


def relative_spread(array):
    """Per eigenvalue index >= 1: (max - min) / mean over the perturbations."""
    nonzero = array[:, 1:]
    return (nonzero.max(axis=0) - nonzero.min(axis=0)) / nonzero.mean(axis=0)


def main():
    out = Path(sys.argv[1])
    arrays, vertices = spectra(plotting.read_rows(out / "robustness_eigenvalues.csv"))
    area = area_spread(plotting.read_rows(out / "robustness_meshes.csv"))
    meshes = sorted({m for m, _, _ in arrays}, key=lambda m: (not m.startswith("icosphere"), m))
    kinds = [k for k in ("flips", "retriangulation") if any(key[1] == k for key in arrays)]

    figure, axes = plotting.plt.subplots(len(kinds), len(meshes), figsize=(4.2 * len(meshes), 3.4 * len(kinds)),
                                         squeeze=False, sharey=True)
    summary = []
    for row, kind in enumerate(kinds):
        for column, mesh in enumerate(meshes):
            ax = axes[row][column]
            spread = {}
            for c in plotting.CONNECTIVITIES:
                if (mesh, kind, c) not in arrays:
                    continue
                spread[c] = relative_spread(arrays[(mesh, kind, c)])
                index = np.arange(1, len(spread[c]) + 1)
                ax.semilogy(index, np.maximum(spread[c], 1e-16), color=plotting.COLOURS[c], label=plotting.LABELS[c],
                            lw=1.3)
            below = [c for c in spread if np.median(spread[c]) < SPREAD_FLOOR]
            if below:  # e.g. hybrid flipping every perturbed edge back: the spectrum to rounding
                ax.text(0.02, 0.04, ", ".join(f"{c}: {np.median(spread[c]):.0e} (below the axis)" for c in below),
                        transform=ax.transAxes, fontsize=7)
            ax.set_ylim(bottom=SPREAD_FLOOR)
            perturbations = arrays[(mesh, kind, "original")].shape[0]
            ax.set_title(f"{mesh}: {kind} ({perturbations} meshes)", fontsize=9)
            ax.set_xlabel("eigenvalue index i")
            if column == 0:
                ax.set_ylabel("relative spread (max−min)/mean of λ_i")
            ax.grid(True, which="major", alpha=0.3)
            original = spread["original"]
            for c in plotting.CONNECTIVITIES[1:]:
                if c in spread:
                    ratio = np.median(original / np.maximum(spread[c], 1e-300))
                    summary.append([mesh, kind, perturbations, plotting.LABELS[c], f"{np.median(original):.2e}",
                                    f"{np.median(spread[c]):.2e}", f"{ratio:.3g}×",
                                    f"{np.mean(vertices[(mesh, kind, c)]):.0f}", f"{area[(mesh, kind)]:.1e}"])
    axes[0][0].legend(fontsize=7, loc="lower right")
    figure.suptitle("Eigenvalue spread across connectivity perturbations of the same vertices (lower is better)",
                    fontsize=10)
    plotting.save(figure, out / "robustness_spread.png", title_space=0.06)

    table = plotting.markdown_table(
        ["mesh", "perturbation", "meshes", "connectivity", "median spread, original", "median spread, this",
         "median ratio original / this", "mean vertices", "area spread"], summary)
    plotting.write_text(out / "robustness_summary.md", table + "\n")
    print(table)


if __name__ == "__main__":
    main()
