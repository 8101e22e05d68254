#!/usr/bin/env python3
"""Runs every sdmesh command on meshes that Debian packages ship, none of them used in development.

    every_command.py SDMESH OUT [--work DIR] [--jobs N] [--timeout SECONDS] [--sample N] [--seed S]
                     [--no-download]

The meshes are sweep.py's (the same packages, found and unpacked the same way, into the same
--work folder if given). A sample of N of them (default 300, drawn with seed S; 0 takes all) is
first put through `sdmesh repair`; each mesh that repair accepts then goes through info, check,
operators, intrinsic, eigs (-k 6, on the mesh and on its intrinsic Delaunay triangulation),
geodesic and heat from vertex 0, poisson (f = 1, u = 0 at vertex 0) and decimate to half its
vertices with --convert-first. sweep.py converts every mesh; this covers the other commands on
the same kind of input: tiny pieces, thousands of components, boundaries, needles, far
coordinates.

A run fails if it crashes (a signal, or exit 70), times out, exits 2 (the command lines are
valid) or with a code the README does not list, or exits nonzero without one line on stderr
(check's exit 1 excepted: "not self-Delaunay" is its answer, on stdout). Writes
OUT/unseen_commands.csv (one row per mesh and command) and OUT/unseen_commands.md (exit codes by
command, the slowest runs, the failures), prints the summary and exits 1 if a run failed.
Python 3 standard library only.
"""

import collections
import concurrent.futures
import csv
import json
import random
import subprocess
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import sweep  # noqa: E402  (the mesh sources, shared)

# sdmesh's exit codes (README, "Exit codes").
EXIT_CODES = {0: "ok", 1: "short of the goal", 3: "I/O error", 4: "unsupported format", 5: "malformed file",
              6: "invalid mesh", 7: "invalid argument", 8: "numerical error"}


def commands(sdmesh, repaired, folder):
    """The command lines to run on a repaired mesh, by name (poisson's comes after operators')."""
    r, out = str(repaired), lambda name: str(folder / name)
    return {name: [sdmesh, *line] for name, line in {
        "info": ["info", r],
        "check": ["check", r],
        "operators": ["operators", r, "--out", out("operators")],
        "intrinsic": ["intrinsic", r, "--out", out("intrinsic")],
        "eigs": ["eigs", r, "-k", "6", "--out", out("eigs")],
        "eigs --intrinsic": ["eigs", r, "-k", "6", "--intrinsic", "--out", out("eigs_idt")],
        "geodesic": ["geodesic", r, "--source", "0", "--out", out("distance.ply")],
        "heat": ["heat", r, "--source", "0", "--time", "0.01", "--out", out("heat.ply")],
        "decimate --convert-first": ["decimate", r, out("decimated.ply"), "--target-ratio", "0.5",
                                     "--convert-first", "--no-hausdorff"],
    }.items()}


def poisson(sdmesh, repaired, folder, vertices):
    """-Δu = 1 with u = 0 at vertex 0."""
    (folder / "f.txt").write_text("1\n" * vertices)
    (folder / "dirichlet.txt").write_text("0 0\n")
    return [sdmesh, "poisson", str(repaired), "--f", str(folder / "f.txt"), "--dirichlet",
            str(folder / "dirichlet.txt"), "--out", str(folder / "u.ply")]


def run(command, timeout):
    """Exit code (or "timeout"), stderr's lines and seconds."""
    began = time.monotonic()
    try:
        done = subprocess.run(command, capture_output=True, text=True, errors="replace", timeout=timeout)
        return done.returncode, done.stderr.strip().splitlines(), time.monotonic() - began
    except subprocess.TimeoutExpired:
        return "timeout", [], time.monotonic() - began


def failure(command, code, stderr):
    """Why a run counts as failed, or None."""
    if code == "timeout":
        return "timed out"
    if code not in EXIT_CODES:
        return f"exit {code}"
    if code != 0 and len(stderr) != 1 and not (command == "check" and code == 1):
        return f"{len(stderr)} lines on stderr"
    return None


def run_all(sdmesh, mesh, name, scratch, timeout):
    """Repairs mesh, then runs every command on it; returns CSV rows."""
    with tempfile.TemporaryDirectory(dir=scratch) as folder:
        folder = Path(folder)
        repaired = folder / "repaired.ply"
        runs = [("repair", *run([sdmesh, "repair", str(mesh), str(repaired)], timeout))]
        if runs[0][1] == 0:
            for command, line in commands(sdmesh, repaired, folder).items():
                runs.append((command, *run(line, timeout)))
                if command == "operators" and runs[-1][1] == 0:
                    vertices = json.loads((folder / "operators" / "report.json").read_text())["vertices"]
                    runs.append(("poisson", *run(poisson(sdmesh, repaired, folder, vertices), timeout)))
        rows = []
        for command, code, stderr, seconds in runs:
            message = stderr[-1].replace(str(mesh), name).replace(str(folder), "TMP") if stderr else ""
            rows.append({"mesh": name, "command": command, "exit": code, "seconds": f"{seconds:.2f}",
                         "failure": failure(command, code, stderr) or "", "message": message})
        return rows


def summarize(rows, meshes, seconds):
    by_command = collections.defaultdict(collections.Counter)
    for r in rows:
        by_command[r["command"]][r["exit"]] += 1
    codes = sorted({c for counts in by_command.values() for c in counts}, key=str)
    lines = ["# Every command on unseen meshes\n",
             f"{meshes} meshes, {len(rows)} runs in {seconds:.0f} s. Exit codes by command "
             f"({', '.join(f'{c}: {EXIT_CODES.get(c, c)}' for c in codes)}):\n",
             "| command | " + " | ".join(str(c) for c in codes) + " |",
             "|---|" + "---:|" * len(codes)]
    for command, counts in by_command.items():
        lines.append(f"| {command} | " + " | ".join(str(counts.get(c, 0)) for c in codes) + " |")
    lines += ["", "Slowest runs:", ""]
    for r in sorted(rows, key=lambda r: -float(r["seconds"]))[:8]:
        lines.append(f"- {r['command']} on {r['mesh']}: {r['seconds']} s, exit {r['exit']}")
    failed = [r for r in rows if r["failure"]]
    lines += ["", f"Failures: {len(failed)}", ""]
    lines += [f"- {r['command']} on {r['mesh']}: {r['failure']} {r['message']}" for r in failed]
    return "\n".join(lines) + "\n"


def main():
    parser = sweep.shared_arguments(__doc__)
    parser.add_argument("--timeout", type=float, default=600)
    parser.add_argument("--sample", type=int, default=300, help="how many meshes (0: all)")
    parser.add_argument("--seed", type=int, default=1)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory(prefix="sdmesh_every_command_") as scratch:
        work = args.work or Path(scratch)
        sources, meshes = sweep.find_meshes(work, args.no_download)
        if not meshes:
            sys.exit("every_command.py: no meshes found; see sweep.py")
        if 0 < args.sample < len(meshes):
            meshes = sorted(random.Random(args.seed).sample(meshes, args.sample))
        began = time.monotonic()
        with concurrent.futures.ThreadPoolExecutor(args.jobs) as pool:
            rows = [row for rows in pool.map(lambda m: run_all(args.sdmesh, m, sweep.source_name(m, work, sources),
                                                               scratch, args.timeout), meshes)
                    for row in rows]
        seconds = time.monotonic() - began
    args.out.mkdir(parents=True, exist_ok=True)
    with open(args.out / "unseen_commands.csv", "w", newline="") as f:
        writer = csv.DictWriter(f, ["mesh", "command", "exit", "seconds", "failure", "message"])
        writer.writeheader()
        writer.writerows(rows)
    summary = summarize(rows, len(meshes), seconds)
    (args.out / "unseen_commands.md").write_text(summary)
    print(summary)
    sys.exit(1 if any(r["failure"] for r in rows) else 0)


if __name__ == "__main__":
    main()
