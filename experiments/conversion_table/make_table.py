#!/usr/bin/env python3
"""Turns conversion_table.csv (written by the conversion_table program) into markdown.

    make_table.py CSV [--out MD]     MD defaults to conversion_table.md next to CSV

Writes a summary (median and max vertex efficiency per configuration, over the meshes where it is
defined: first those that are manifold as read, then with the repaired ones too) and one table of
per-mesh rows per configuration, and prints the first summary. Python 3 standard library only.
"""

import argparse
import csv
import statistics
import sys
from pathlib import Path


def configuration(row):
    """A configuration's name, e.g. 'split-interval', 'split-interval-no-trials' or 'hybrid-10'."""
    if row["method"] == "hybrid":
        return f"hybrid-{row['max_dihedral_deg']}"
    search = "-local-search" if row.get("local_search", "0") not in ("", "0") else ""
    trials = "-no-trials" if row.get("cascade_trials") == "0" else ""
    return f"{row['method']}-{row['split_rule']}{search}{trials}"


def efficiency(row):
    value = row["vertex_efficiency"]
    return float(value) if value else None


def lower_bound(row):
    value = row.get("efficiency_lower_bound", "")
    return float(value) if value else None


def summary_table(groups):
    lines = [
        "| configuration | meshes converted | certified | median efficiency | max efficiency (mesh) "
        "| added vertices | seconds | median (max) lower bound |",
        "|---|---:|---:|---:|---|---:|---:|---:|",
    ]
    for name, rows in groups.items():
        ran = [r for r in rows if r["seconds"]]
        measured = [r for r in ran if efficiency(r) is not None]
        certified = sum(r["status"] == "certified" for r in ran)
        if measured:
            worst = max(measured, key=efficiency)
            median = f"{statistics.median(efficiency(r) for r in measured):.2f}"
            maximum = f"{efficiency(worst):.2f} ({worst['mesh']})"
        else:
            median = maximum = "n/a"
        added = sum(int(r["added_vertices"]) for r in ran)
        seconds = sum(float(r["seconds"]) for r in ran)
        bounds = [lower_bound(r) for r in measured if lower_bound(r) is not None]
        bound = f"{statistics.median(bounds):.2f} ({max(bounds):.2f})" if bounds else ""
        lines.append(
            f"| {name} | {len(ran)} | {certified} | {median} | {maximum} | {added:,} | {seconds:.1f} | {bound} |"
        )
    return "\n".join(lines)


def mesh_table(rows):
    lines = [
        "| mesh | faces | input V | output V | added V | non-flat non-LD edges | efficiency | lower bound "
        "| flips | splits | status | seconds | Hausdorff (% diag) | output non-LD | negative dual cells |",
        "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|---:|---:|---:|---:|",
    ]
    for r in rows:
        name = r["mesh"] + (" (repaired)" if r.get("repaired") == "1" else "")
        if not r["seconds"]:  # skipped or failed: only the status is known
            lines.append(f"| {name} | {int(r['faces']):,} | | | | | | | | | {r['status']} | | | | |")
            continue
        value, bound = efficiency(r), lower_bound(r)
        lines.append(
            f"| {name} | {int(r['faces']):,} | {int(r['input_vertices']):,} | {int(r['output_vertices']):,} "
            f"| {int(r['added_vertices']):,} | {int(r['input_nonflat_non_delaunay_edges']):,} "
            f"| {'n/a' if value is None else f'{value:.2f}'} | {'' if bound is None else f'{bound:.2f}'} "
            f"| {int(r['flips']):,} | {int(r['splits']):,} "
            f"| {r['status']} | {float(r['seconds']):.2f} | {100 * float(r['hausdorff_rel']):.3g} "
            f"| {r['output_non_delaunay_edges']} | {r['output_negative_dual_cells']} |"
        )
    return "\n".join(lines)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("csv", type=Path)
    parser.add_argument("--out", type=Path, help="markdown file (default: conversion_table.md next to CSV)")
    args = parser.parse_args()
    out = args.out or args.csv.with_name("conversion_table.md")

    with args.csv.open(newline="") as f:
        rows = list(csv.DictReader(f))
    groups = {}  # configuration -> rows, in the order the program ran them
    for row in rows:
        groups.setdefault(configuration(row), []).append(row)

    # The targets are over the meshes that are manifold as read; the others (converted after
    # repair(), column `repaired`) get a summary of their own.
    as_read = {name: [r for r in group if r.get("repaired", "0") == "0"] for name, group in groups.items()}
    summary = summary_table(as_read)
    parts = [
        "# Conversion table",
        f"From `{args.csv.name}`. Vertex efficiency = added vertices / non-flat non-Delaunay input edges; "
        "1.0 is the lower bound for split (ALGORITHMS.md §3). The lower bound column (split-interval rows) "
        "is the sharper per-mesh bound of `--lower-bound`, as an efficiency: no conversion that moves nothing "
        "adds fewer vertices. Hybrid flips edges within the dihedral bound, "
        "so its efficiency can be below 1. Median and max are over the meshes where it is defined.",
        "## Summary",
        "Over the meshes that are manifold as read (the set of the conversion issue's targets).",
        summary,
    ]
    if any(r.get("repaired") == "1" for r in rows):
        parts += ["## Summary with the repaired meshes",
                  "The same with the meshes that were not manifold as read and are converted after `repair()` "
                  "(column `repaired`).",
                  summary_table(groups)]
    for name, group in groups.items():
        parts += [f"## {name}", mesh_table(group)]
    out.write_text("\n\n".join(parts) + "\n")
    print(summary)
    print(f"wrote {out}", file=sys.stderr)


if __name__ == "__main__":
    main()
