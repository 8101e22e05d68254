#!/usr/bin/env python3
"""Converts every mesh that thirty-six Debian packages ship, none of them used in development.

    sweep.py SDMESH OUT [--work DIR] [--jobs N] [--timeout SECONDS] [--no-download]

SDMESH is the sdmesh program (a Release build), OUT the results folder, DIR a scratch folder for
the extracted meshes and the reports (default: a temporary one). The meshes come from
libcgal-demo (data.tar.gz: CGAL's test and demo meshes, extracted into DIR/meshes), occt-misc
(Open CASCADE's STL samples), geomview (its OFF examples), assimp-testmodels (Assimp's importer
tests, broken files included) and openscad-testing-data (OpenSCAD's STL tests):

    apt-get install libcgal-demo occt-misc geomview assimp-testmodels openscad-testing-data

and from thirty-one packages that are downloaded (`apt-get download`) and unpacked into
DIR/debs rather than installed, since some pull in a desktop: cura (3D printers' beds),
prusa-slicer (printers' beds and its shape gallery), minetest-data (a game's models),
openfoam-examples (the surfaces of OpenFOAM's tutorials, mostly gzipped), sweethome3d-furniture
(820 OBJ models of furniture, plants and people, in zip archives that are unpacked too),
stellarium-data (shape models of asteroids and moons, and two observatories' scenery), gmsh-doc
and netgen-doc (the STL surfaces of two mesh generators' demos and tutorials), and the
twenty-three of DOWNLOADED's last lines (robots' links from dart-doc, libsimbody-dev and
linuxcnc; games' models, and SuperTux's and gravitywars' levels, text of other formats with a
mesh's extension; LIGGGHTS's and yade's walls; InVesalius's, OpenCV's, matgeom's, mayavi's and
Qt's samples; Uranium's reader tests). Without a network, or with --no-download, those are left
out.

Each mesh is converted with the default split method and with hybrid at 10°, under a time limit
(an invalid one again with --repair).
Every output of a successful conversion must pass `sdmesh check` and convert again with no flip
and no split. A conversion that runs out of its vertex or flip budget is reported (exit 1, status
budget_exhausted: the budget did its job), not counted as a failure. Writes OUT/unseen_meshes.csv (one row per mesh and method) and OUT/unseen_meshes.md
(what each exit code stands for, how many, the slowest and least efficient conversions), prints
the summary and exits 1 if a conversion crashed, timed out, was not certified on a manifold mesh
or failed the output checks. Python 3 standard library only.
"""

import argparse
import concurrent.futures
import csv
import hashlib
import json
import statistics
import subprocess
import sys
import tarfile
import tempfile
import time
import zipfile
from pathlib import Path

CGAL_DATA = Path("/usr/share/doc/libcgal-dev/data.tar.gz")
OCCT_STL = Path("/usr/share/opencascade/data/stl")
GEOMVIEW = Path("/usr/share/geomview")
ASSIMP = Path("/usr/share/assimp/models")
OPENSCAD = Path("/usr/share/openscad")
# The packages whose mesh files are read where they are installed.
INSTALLED = (("occt-misc", OCCT_STL), ("geomview", GEOMVIEW), ("assimp-testmodels", ASSIMP),
             ("openscad-testing-data", OPENSCAD))
# The packages whose .deb is downloaded and unpacked, and the folder inside it that names a mesh.
DOWNLOADED = (("cura", "usr/share/cura"), ("prusa-slicer", "usr/share/PrusaSlicer"),
              ("minetest-data", "usr/share/games/minetest"),
              ("openfoam-examples", "usr/share/doc/openfoam-examples/examples"),
              ("sweethome3d-furniture", "usr/share/sweethome3d/furniture"),
              ("stellarium-data", "usr/share/stellarium"), ("gmsh-doc", "usr/share/doc/gmsh-doc"),
              ("netgen-doc", "usr/share/doc/netgen/examples"),
              # Robots' links, games' models (and levels of other formats with a mesh's extension),
              # simulation examples, medical and vision samples, file readers' tests.
              ("dart-doc", "usr/share/doc/dart/data"), ("libsimbody-dev", "usr/share/doc/simbody/examples/src"),
              ("linuxcnc-uspace", "usr"), ("minetest-mod-homedecor", "usr/share/games/minetest/mods/homedecor"),
              ("minetest-mod-pipeworks", "usr/share/games/minetest/mods/pipeworks/models"),
              ("minetest-mod-moreblocks", "usr/share/games/minetest/mods/moreblocks/models"),
              ("neverball-common", "usr/share/games/neverball"), ("etw-data", "usr/share/games/etw"),
              ("bouncy", "usr/share/games/bouncy/data"), ("brutalchess", "usr/share/games/brutalchess/models"),
              ("gltron", "usr/share/games/gltron/data"), ("gravitywars", "usr/share/games/gravitywars/levels"),
              ("supertux-data", "usr/share/games/supertux2/levels"),
              ("liggghts-doc", "usr/share/doc/liggghts/examples/LIGGGHTS/Tutorials_public"),
              ("yade", "usr/share/doc/yade/examples"), ("sumo-tools", "usr/share/sumo/data/3D"),
              ("invesalius", "usr/share/invesalius/navigation/objects"),
              ("opencv-doc", "usr/share/doc/opencv-doc/examples"),
              ("octave-matgeom", "usr/share/octave/packages/matgeom-1.2.3/meshes3d"), ("mayavi2", "usr"),
              ("qtdatavisualization5-examples", "usr/lib/x86_64-linux-gnu/qt5/examples/datavisualization"),
              ("uranium-plugins", "usr/lib/uranium/plugins/FileHandlers"),
              ("structure-synth", "usr/share/structure-synth/Misc"))
MESH_SUFFIXES = (".off", ".obj", ".ply", ".stl")
METHODS = {"split": [], "hybrid-10": ["--method", "hybrid", "--max-dihedral", "10"]}
# sdmesh's exit codes (README, "Exit codes"): 0 certified, 1 not certified, 4 unsupported format,
# 5 malformed file, 6 invalid mesh (non-manifold, inconsistent orientation, zero-area faces).
EXPECTED_REFUSALS = {4: "unsupported format", 5: "malformed file", 6: "invalid mesh"}


def is_mesh(path):
    """Whether the file name ends in a mesh format that sdmesh reads, gzipped or not."""
    name = path.name.lower().removesuffix(".gz")
    return any(name.endswith(suffix) for suffix in MESH_SUFFIXES)


def extract_meshes(archive, names, target):
    """Writes the mesh files among `names` of an open tar or zip archive below target, once."""
    for name in names:
        path = Path(name)
        if is_mesh(path) and not path.is_absolute() and ".." not in path.parts and not (target / path).exists():
            (target / path).parent.mkdir(parents=True, exist_ok=True)
            data = archive.extractfile(name).read() if isinstance(archive, tarfile.TarFile) else archive.read(name)
            (target / path).write_bytes(data)


def unpack_downloaded(work):
    """Unpacks DOWNLOADED's packages into work/debs/PACKAGE once; returns those that are there."""
    debs = work / "debs"
    missing = [package for package, _ in DOWNLOADED if not (debs / package).exists()]
    if missing:
        debs.mkdir(parents=True, exist_ok=True)
        fetched = subprocess.run(["apt-get", "download", *missing], cwd=debs, capture_output=True, text=True)
        if fetched.returncode != 0:
            print(f"sweep.py: apt-get download {' '.join(missing)} failed, leaving them out: "
                  f"{(fetched.stderr.strip().splitlines() or [''])[-1]}", file=sys.stderr)
        for package in missing:
            for deb in debs.glob(f"{package}_*.deb"):
                subprocess.run(["dpkg-deb", "-x", str(deb), str(debs / package)], check=True)
                deb.unlink()
            for furniture in (debs / package).rglob("*.sh3f"):  # SweetHome3D's zip archives
                with zipfile.ZipFile(furniture) as archive:
                    extract_meshes(archive, archive.namelist(), furniture.with_suffix(""))
    return [(package, debs / package / inside) for package, inside in DOWNLOADED if (debs / package).exists()]


def gather_meshes(work, sources):
    """The packages' mesh files, sorted; CGAL's tarball is extracted into work/meshes once."""
    found = []
    if CGAL_DATA.exists():
        target = work / "meshes"
        if not target.exists():
            with tarfile.open(CGAL_DATA) as archive:  # mesh files only, and only below target
                extract_meshes(archive, [m.name for m in archive.getmembers() if m.isfile()], target)
        found += [p for p in target.rglob("*") if is_mesh(p)]
    for _, folder in sources:
        if folder.exists():
            found += [p for p in folder.rglob("*") if is_mesh(p)]
    return sorted(p for p in found if p.is_file())


def shared_arguments(doc):
    """The command line that sweep.py and every_command.py share; each adds its own --timeout."""
    parser = argparse.ArgumentParser(description=doc.splitlines()[0])
    parser.add_argument("sdmesh")
    parser.add_argument("out", type=Path)
    parser.add_argument("--work", type=Path)
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--no-download", action="store_true", help="leave out the downloaded packages")
    return parser


def find_meshes(work, no_download):
    """The packages (name and folder) and their mesh files, unpacked below work as needed."""
    sources = [*INSTALLED, *([] if no_download else unpack_downloaded(work))]
    return sources, gather_meshes(work, sources)


def source_name(mesh, work, sources):
    """The mesh's package and its path there, e.g. libcgal-demo:data/meshes/elk.off."""
    for package, root in (("libcgal-demo", work / "meshes"), *sources):
        if mesh.is_relative_to(root):
            return f"{package}:{mesh.relative_to(root)}"
    return str(mesh)


def run(command, timeout):
    began = time.monotonic()
    try:
        done = subprocess.run(command, capture_output=True, text=True, timeout=timeout)
        return done.returncode, done.stderr.strip().splitlines()[-1:] or [""], time.monotonic() - began
    except subprocess.TimeoutExpired:
        return "timeout", ["timed out"], time.monotonic() - began


def convert_one(sdmesh, mesh, method, work, sources, timeout):
    """Converts mesh with one method, then checks the output; returns a CSV row."""
    stem = f"{hashlib.md5(str(mesh).encode()).hexdigest()[:8]}_{mesh.name}.{method}"
    converted, report = work / "outputs" / f"{stem}.ply", work / "outputs" / f"{stem}.json"
    code, message, seconds = run([sdmesh, "convert", str(mesh), str(converted), "--report", str(report),
                                  *METHODS[method]], timeout)
    name = source_name(mesh, work, sources)
    row = {"mesh": name, "method": method, "exit": code, "wall_seconds": f"{seconds:.2f}",
           # The mesh's name, not the scratch folder's: the table stays the same from run to run.
           "message": message[0].replace(str(mesh), name) if code != 0 else ""}
    if code == 6:  # an invalid mesh: what the safe repairs make of it
        row["exit_with_repair"], _, _ = run([sdmesh, "convert", str(mesh), str(converted), "--repair",
                                             *METHODS[method]], timeout)
        converted.unlink(missing_ok=True)
    if code not in (0, 1) or not report.exists():
        return row
    r = json.loads(report.read_text())
    if code == 1:
        row.update(input_faces=r["input_faces"], status=r["status"])
        converted.unlink(missing_ok=True)
        return row
    added = r["output_vertices"] - r["input_vertices"]
    folds = r["input_nonflat_non_delaunay_edges"]
    row.update(input_faces=r["input_faces"], added_vertices=added, nonflat_non_delaunay_edges=folds,
               efficiency=f"{added / folds:.3f}" if folds else "", status=r["status"],
               hausdorff_rel=r["hausdorff_rel"])
    check, _, _ = run([sdmesh, "check", str(converted)], timeout)
    again = work / "outputs" / f"{stem}.again.json"
    code_again, _, _ = run([sdmesh, "convert", str(converted), str(work / "outputs" / f"{stem}.again.ply"),
                            "--report", str(again), *METHODS[method]], timeout)
    redone = -1
    if code_again == 0 and again.exists():
        a = json.loads(again.read_text())
        redone = a["flips"] + a["splits"]
    row.update(check_exit=check, reconvert_work=redone)
    for leftover in (converted, work / "outputs" / f"{stem}.again.ply"):
        leftover.unlink(missing_ok=True)  # the reports suffice; outputs of the big meshes are large
    return row


def failed(row):
    if row["exit"] in EXPECTED_REFUSALS or (row["exit"] == 1 and row.get("status") == "budget_exhausted"):
        return False
    return row["exit"] != 0 or row.get("check_exit") != 0 or row.get("reconvert_work") != 0


def summarize(rows, seconds):
    lines = ["# Conversion of meshes never used in development", "",
             f"{len({r['mesh'] for r in rows})} mesh files from Debian's "
             f"{', '.join(sorted({r['mesh'].split(':')[0] for r in rows}))}, "
             f"each converted with split (the default) and hybrid at 10° by "
             f"`experiments/unseen_meshes/sweep.py` ({seconds:.0f} s on 2 jobs). A successful output must pass "
             f"`sdmesh check` and convert again with no flip and no split.", ""]
    for method in METHODS:
        mine = [r for r in rows if r["method"] == method]
        by_exit = {}
        for r in mine:
            by_exit[r["exit"]] = by_exit.get(r["exit"], 0) + 1
        done = [r for r in mine if r["exit"] == 0]
        effs = [float(r["efficiency"]) for r in done if r.get("efficiency")]
        lines += [f"## {method}", "",
                  "| exit | meaning | meshes |", "|---:|---|---:|"]
        for code, count in sorted(by_exit.items(), key=lambda kv: str(kv[0])):
            meaning = "certified" if code == 0 else EXPECTED_REFUSALS.get(code, "FAILURE")
            if code == 1 and all(r.get("status") == "budget_exhausted" for r in mine if r["exit"] == 1):
                meaning = "budget exhausted (reported status)"
            lines.append(f"| {code} | {meaning} | {count} |")
        invalid = [r for r in mine if r["exit"] == 6]
        repaired = sum(1 for r in invalid if r.get("exit_with_repair") == 0)
        over_budget = sum(1 for r in invalid if r.get("exit_with_repair") == 1)
        lines += ["", f"Of the {len(invalid)} invalid meshes, {repaired} convert (certified) with `--repair` "
                      f"and {over_budget} are repaired but not certified (exit 1: their budget)."]
        bad = [r for r in mine if failed(r)]
        lines += ["", f"Output checks failed or unexpected exits: {len(bad)}."]
        for r in (r for r in mine if r["exit"] == 1):
            lines += [f"Not certified: {r['mesh']} ({r['input_faces']:,} faces), status {r.get('status')}."]
        if effs:
            lines.append(f"Vertex efficiency over the {len(effs)} certified meshes with non-Delaunay folds: "
                         f"median {statistics.median(effs):.2f}, max {max(effs):.2f}.")
        lines += ["", "| slowest | faces | seconds | efficiency |", "|---|---:|---:|---:|"]
        for r in sorted(done, key=lambda r: -float(r["wall_seconds"]))[:5]:
            lines.append(f"| {r['mesh']} | {r['input_faces']:,} | {r['wall_seconds']} | "
                         f"{r.get('efficiency', '')} |")
        lines += ["", "| least efficient | faces | non-Delaunay folds | added vertices | efficiency |",
                  "|---|---:|---:|---:|---:|"]
        for r in sorted((r for r in done if r.get("efficiency")), key=lambda r: -float(r["efficiency"]))[:8]:
            lines.append(f"| {r['mesh']} | {r['input_faces']:,} | {r['nonflat_non_delaunay_edges']:,} | "
                         f"{r['added_vertices']:,} | {r['efficiency']} |")
        lines.append("")
    return "\n".join(lines)


def main():
    parser = shared_arguments(__doc__)
    parser.add_argument("--timeout", type=float, default=300)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory(prefix="sdmesh_sweep_") as scratch:
        work = args.work or Path(scratch)
        (work / "outputs").mkdir(parents=True, exist_ok=True)
        sources, meshes = find_meshes(work, args.no_download)
        if not meshes:
            sys.exit("sweep.py: no meshes found; apt-get install libcgal-demo occt-misc geomview "
                     "assimp-testmodels openscad-testing-data")
        began = time.monotonic()
        with concurrent.futures.ThreadPoolExecutor(args.jobs) as pool:
            rows = list(pool.map(lambda job: convert_one(args.sdmesh, job[0], job[1], work, sources, args.timeout),
                                 [(m, method) for m in meshes for method in METHODS]))
        seconds = time.monotonic() - began
    args.out.mkdir(parents=True, exist_ok=True)
    fields = ["mesh", "method", "exit", "exit_with_repair", "status", "wall_seconds", "input_faces", "nonflat_non_delaunay_edges",
              "added_vertices", "efficiency", "hausdorff_rel", "check_exit", "reconvert_work", "message"]
    with open(args.out / "unseen_meshes.csv", "w", newline="") as f:
        writer = csv.DictWriter(f, fields)
        writer.writeheader()
        writer.writerows(rows)
    summary = summarize(rows, seconds)
    (args.out / "unseen_meshes.md").write_text(summary)
    print(summary)
    bad = [r for r in rows if failed(r)]
    for r in bad:
        print(f"FAILED: {r['mesh']} ({r['method']}): exit {r['exit']}, check {r.get('check_exit')}, "
              f"work on reconversion {r.get('reconvert_work')} {r['message']}", file=sys.stderr)
    sys.exit(1 if bad else 0)


if __name__ == "__main__":
    main()
