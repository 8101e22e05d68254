"""The module gives the CLI's results on the same meshes: operators to 1e-14, eigenvalues to 1e-10,
reports with the same keys and values (timings aside)."""

import json
import re

import numpy as np
import pytest
import scipy.io
import scipy.sparse

import sdmesh
from conftest import DATA_DIR, cli_json, grid, without_timings
from test_arrays_and_errors import read_binary_ply_fields

MASSES = ["barycentric", "circumcentric", "mixed", "galerkin"]
OPERATOR_NAMES = ["L", "M", "d0", "d1", "star0", "star1", "star2"]


def assert_same_matrix(ours, mtx_path):
    theirs = scipy.sparse.csc_matrix(scipy.io.mmread(mtx_path))
    assert ours.shape == theirs.shape
    assert ours.nnz == theirs.nnz  # the same stored entries, explicit zeros included
    scale = max(1.0, abs(theirs).max())
    assert abs(ours - theirs).max() <= 1e-14 * scale, mtx_path.name


@pytest.fixture(scope="module")
def converted_bunny(tmp_path_factory, cli, bunny_path):
    path = tmp_path_factory.mktemp("converted") / "bunny_sd.obj"
    cli("convert", bunny_path, path)
    return path


@pytest.mark.parametrize("mass", MASSES)
def test_operators_equal_the_cli_files(cli, tmp_path, bunny_path, bunny, mass):
    cli("operators", bunny_path, "--out", tmp_path, "--mass", mass)
    ops = sdmesh.operators(*bunny, mass=mass)
    assert list(ops) == OPERATOR_NAMES
    for name in OPERATOR_NAMES:
        assert isinstance(ops[name], scipy.sparse.csc_matrix)
        assert_same_matrix(ops[name], tmp_path / f"{name}.mtx")


def test_operators_satisfy_the_dec_identities(bunny):
    ops = sdmesh.operators(*bunny)
    L, d0, d1, star1 = ops["L"], ops["d0"], ops["d1"], ops["star1"]
    assert (d1 @ d0).count_nonzero() == 0
    assert abs(L - L.T).max() == 0
    assert abs(L @ np.ones(L.shape[0])).max() <= 1e-12 * abs(L).max()
    assert abs(L - d0.T @ star1 @ d0).max() <= 1e-12 * abs(L).max()


def test_intrinsic_operators_and_report_equal_the_cli(cli, tmp_path, bunny_path, bunny):
    cli("intrinsic", bunny_path, "--out", tmp_path, "--mass", "circumcentric")
    ops, report = sdmesh.intrinsic_operators(*bunny, mass="circumcentric")
    for name in OPERATOR_NAMES:
        assert_same_matrix(ops[name], tmp_path / f"{name}.mtx")
    expected = json.loads((tmp_path / "report.json").read_text())
    del expected["file"]
    assert list(report) == list(expected)
    assert without_timings(report) == without_timings(expected)
    assert report["proper"] and report["status"] == "delaunay" and report["flips"] > 0


@pytest.mark.parametrize("boundary", ["strict", "free"])
def test_check_equals_the_cli_json(cli, tmp_path, bunny_path, bunny, boundary):
    V, F = grid(7, 4)
    V[:, 0] += 0.8 * V[:, 1] ** 2  # sheared: obtuse boundary angles, non-Delaunay interior edges
    sdmesh.write_mesh(tmp_path / "grid.obj", V, F)
    for path, mesh in ((bunny_path, bunny), (tmp_path / "grid.obj", (V, F))):
        done = cli("check", path, "--json", "--boundary", boundary, expect=(0, 1))
        expected = cli_json(done)
        for key in ("file", "file_faces", "polygons", "ear_clipped_polygons", "skipped_line_faces"):
            del expected[key]
        report = sdmesh.check(*mesh, boundary=boundary)
        assert list(report) == list(expected)
        assert without_timings(report) == without_timings(expected)


def test_repair_equals_the_cli_and_makes_a_messy_mesh_convertible(cli, tmp_path, bunny):
    V, F = bunny
    F = F.copy()
    V = np.vstack([V, V[F[0, 0]], [[9.0, 9.0, 9.0]]])  # a copy of a vertex, and a vertex in no face
    F[0, 0] = len(V) - 2
    F[1] = F[1, ::-1]                                  # one face turned the wrong way
    F = np.vstack([F, F[5]])                           # a face twice
    messy = tmp_path / "messy.obj"
    sdmesh.write_mesh(messy, V, F)
    with pytest.raises(sdmesh.InvalidMeshError):
        sdmesh.convert(V, F)
    done = cli("repair", messy, tmp_path / "repaired.obj")
    expected = cli_json(done)
    del expected["input"], expected["output"]
    V2, F2, report = sdmesh.repair(V, F)
    assert report == expected
    assert (report["merged_vertices"], report["flipped_faces"], report["dropped_duplicate_faces"],
            report["dropped_vertices"]) == (1, 1, 1, 2)
    V_cli, F_cli = sdmesh.read_mesh(tmp_path / "repaired.obj")
    np.testing.assert_array_equal(V2, V_cli)
    np.testing.assert_array_equal(F2, F_cli)
    assert sdmesh.convert(V2, F2)[2]["status"] == "certified"
    # Each repair can be turned off, as the CLI's --keep-... flags do.
    assert sdmesh.repair(V, F, orient=False)[2]["flipped_faces"] == 0


def test_repair_collapses_a_needle_unless_kept_as_the_cli_does(cli, tmp_path):
    # The octahedron with its top vertex pushed into the plane, 1e-11 beyond +y: face 0-2-4 is a
    # needle, which no flip mends.
    e = 1e-11 / np.sqrt(2.0)
    V = np.array([[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [-e, 1 + e, 0], [0, 0, -1]], dtype=float)
    F = np.array([[0, 2, 4], [2, 1, 4], [1, 3, 4], [3, 0, 4], [2, 0, 5], [1, 2, 5], [3, 1, 5], [0, 3, 5]])
    path = tmp_path / "needle.ply"
    sdmesh.write_mesh(path, V, F)
    for flags, keywords, collapsed, faces in (((), {}, 1, 6), (("--keep-needles",), {"collapse_needles": False}, 0, 8)):
        expected = cli_json(cli("repair", path, tmp_path / "repaired.ply", *flags))
        del expected["input"], expected["output"]
        _, F2, report = sdmesh.repair(V, F, **keywords)
        assert report == expected
        assert (report["collapsed_needles"], len(F2)) == (collapsed, faces)


def test_convert_equals_the_cli(cli, tmp_path, bunny_path, bunny, converted_bunny):
    done = cli("convert", bunny_path, tmp_path / "out.obj", "--method", "hybrid", "--max-dihedral", "5")
    expected = cli_json(done)
    del expected["input"], expected["output"]
    V, F, report = sdmesh.convert(*bunny, method="hybrid", max_dihedral_deg=5)
    assert list(report) == list(expected)
    assert without_timings(report) == without_timings(expected)
    V_cli, F_cli = sdmesh.read_mesh(tmp_path / "out.obj")
    np.testing.assert_array_equal(V, V_cli)
    np.testing.assert_array_equal(F, F_cli)
    assert sdmesh.check(V, F)["self_delaunay"]


def test_convert_without_hausdorff_equals_the_cli(cli, tmp_path, bunny_path, bunny):
    done = cli("convert", bunny_path, tmp_path / "out.obj", "--method", "hybrid", "--no-hausdorff")
    expected = cli_json(done)
    del expected["input"], expected["output"]
    V, F, report = sdmesh.convert(*bunny, method="hybrid", measure_hausdorff=False)
    assert without_timings(report) == without_timings(expected)
    assert report["hausdorff_rel"] is None  # not measured; measured, the flips moved the bunny
    assert sdmesh.convert(*bunny, method="hybrid")[2]["hausdorff_rel"] > 0


@pytest.mark.parametrize("option, value", [("local_search", 1), ("cascade_trials", 0)])
def test_convert_options_equal_the_cli(cli, tmp_path, bunny_path, bunny, option, value):
    flag = "--" + option.replace("_", "-")
    done = cli("convert", bunny_path, tmp_path / "out.obj", flag, str(value))
    expected = cli_json(done)
    del expected["input"], expected["output"]
    V, F, report = sdmesh.convert(*bunny, **{option: value})
    assert without_timings(report) == without_timings(expected)
    assert report[option] == value
    V_cli, F_cli = sdmesh.read_mesh(tmp_path / "out.obj")
    np.testing.assert_array_equal(V, V_cli)
    np.testing.assert_array_equal(F, F_cli)


def test_decimate_equals_the_cli(cli, tmp_path, converted_bunny):
    V, F = sdmesh.read_mesh(converted_bunny)
    level = len(V) * 3 // 4
    done = cli("decimate", converted_bunny, tmp_path / "out.obj", "--target-ratio", "0.5", "--levels",
               repr(level / len(V)))
    expected = cli_json(done)
    del expected["input"], expected["output"]
    V2, F2, report, levels = sdmesh.decimate(V, F, target_ratio=0.5, levels=[level])
    assert list(report) == list(expected)
    assert report["levels"] == list(expected["levels"].values()) == [level]
    assert without_timings(report) | {"levels": None} == without_timings(expected) | {"levels": None}
    for (ours_V, ours_F), path in (((V2, F2), tmp_path / "out.obj"), (levels[0], tmp_path / "out_level1.obj")):
        theirs_V, theirs_F = sdmesh.read_mesh(path)
        np.testing.assert_array_equal(ours_V, theirs_V)
        np.testing.assert_array_equal(ours_F, theirs_F)
    assert report["certificate"]["self_delaunay"] and sdmesh.check(V2, F2)["self_delaunay"]
    V3, F3, report3, _ = sdmesh.decimate(V, F, target_ratio=0.5, halves_from_vertices=1)  # in two halves
    assert len(V3) == len(V2) and sdmesh.check(V3, F3)["self_delaunay"]
    assert report3["certificate"]["self_delaunay"]
    with pytest.raises(sdmesh.InvalidArgumentError):
        sdmesh.decimate(V, F, halves_from_vertices=-1)
    with pytest.raises(sdmesh.InvalidArgumentError):
        sdmesh.decimate(*sdmesh.read_mesh(DATA_DIR / "bunny.obj"))  # not self-Delaunay


def read_eigs(directory):
    values = np.loadtxt(directory / "eigenvalues.csv")
    raw = (directory / "eigenvectors.bin").read_bytes()
    n, k = np.frombuffer(raw, dtype="<i4", count=2)
    vectors = np.frombuffer(raw, dtype="<f8", offset=8).reshape(k, n).T
    return values, vectors, json.loads((directory / "report.json").read_text())


@pytest.mark.parametrize("options", [("--mass", "circumcentric"), ("--intrinsic",), ("--solver", "spectra")])
def test_eigs_equal_the_cli(cli, tmp_path, converted_bunny, options):
    cli("eigs", converted_bunny, "-k", 12, "--out", tmp_path, *options)
    values, vectors, expected = read_eigs(tmp_path)
    V, F = sdmesh.read_mesh(converted_bunny)
    keywords = {"--mass": {"mass": options[-1]}, "--intrinsic": {"intrinsic": True},
                "--solver": {"solver": options[-1]}}[options[0]]
    evals, evecs, report = sdmesh.eigs(V, F, 12, return_report=True, **keywords)
    assert np.abs(evals - values).max() <= 1e-10 * max(1.0, np.abs(values).max())
    assert np.abs(evecs - vectors).max() <= 1e-8
    assert set(report) <= set(expected)
    assert without_timings(report) == without_timings({key: expected[key] for key in report})
    if "mass" in keywords:  # the same problem given as matrices
        ops = sdmesh.operators(V, F, mass=keywords["mass"])
        np.testing.assert_array_equal(sdmesh.eigs(ops["L"], ops["M"], k=12)[0], evals)
    if "solver" in keywords:
        assert report["solver"] == "spectra"
        with pytest.raises(sdmesh.InvalidArgumentError, match=re.escape("solver must be block|spectra, got 'arpack'")):
            sdmesh.eigs(V, F, 12, solver="arpack")


def test_eigs_progress_goes_to_stderr_as_in_the_cli(capfd, converted_bunny):
    V, F = sdmesh.read_mesh(converted_bunny)
    quiet = sdmesh.eigs(V, F, 12)
    capfd.readouterr()
    loud = sdmesh.eigs(V, F, 12, progress=True)
    err = capfd.readouterr().err
    assert "eigs: factorizing L - sigma M (n = " in err and "eigs: converged, " in err
    np.testing.assert_array_equal(loud[0], quiet[0])
    np.testing.assert_array_equal(loud[1], quiet[1])


def test_eigs_warns_when_it_did_not_converge(converted_bunny):
    V, F = sdmesh.read_mesh(converted_bunny)
    with pytest.warns(RuntimeWarning, match=re.escape("eigs: not converged (largest relative residual ")):
        values, _, report = sdmesh.eigs(V, F, 6, tolerance=1e-30, return_report=True)
    assert report["status"] == "not_converged" and abs(values[0]) <= 1e-6


def test_what_the_cli_exits_1_for_warns(cli, tmp_path, bunny_path, bunny):
    """A conversion that is not certified and intrinsic flips out of their budget: the CLI writes
    its outputs, exits 1 and says why on stderr; Python returns them with a RuntimeWarning."""
    done = cli("convert", bunny_path, tmp_path / "budget.obj", "--max-vertices", "1850", expect=1)
    with pytest.warns(RuntimeWarning, match=re.escape("convert: not certified (budget_exhausted, ")):
        _, _, report = sdmesh.convert(*bunny, max_vertices=1850)
    assert report["status"] == cli_json(done)["status"] == "budget_exhausted"

    done = cli("intrinsic", bunny_path, "--out", tmp_path / "idt", "--max-flips", "2", expect=1)
    assert "ran out of their budget after 2 flips" in done.stderr
    with pytest.warns(RuntimeWarning, match=re.escape("intrinsic_operators: the intrinsic flips ran out of their "
                                                      "budget after 2 flips")):
        _, report = sdmesh.intrinsic_operators(*bunny, max_flips=2)
    assert report["status"] == "flip_budget_exhausted"


def test_geodesic_equals_the_cli(cli, tmp_path, converted_bunny):
    done = cli("geodesic", converted_bunny, "--source", "0,17", "--out", tmp_path / "d.ply", "--mass", "mixed")
    expected = read_binary_ply_fields(tmp_path / "d.ply", ["distance"])["distance"]
    distance = sdmesh.geodesic(*sdmesh.read_mesh(converted_bunny), [0, 17], mass="mixed")
    assert np.abs(distance - expected).max() <= 1e-12 * expected.max()
    assert distance.max() == pytest.approx(cli_json(done)["max_distance"], rel=1e-15)


def test_poisson_equals_the_cli(cli, tmp_path, converted_bunny):
    V, F = sdmesh.read_mesh(converted_bunny)
    f = np.sin(3 * V[:, 0]) + V[:, 1]
    np.savetxt(tmp_path / "f.txt", f, fmt="%.17g")
    (tmp_path / "dirichlet.txt").write_text("0 1.5\n10 -2\n")
    cli("poisson", converted_bunny, "--f", tmp_path / "f.txt", "--dirichlet", tmp_path / "dirichlet.txt",
        "--out", tmp_path / "u.ply")
    expected = read_binary_ply_fields(tmp_path / "u.ply", ["u"])["u"]
    u = sdmesh.poisson(V, F, f, dirichlet_vertices=[0, 10], dirichlet_values=[1.5, -2])
    assert np.abs(u - expected).max() <= 1e-12 * np.abs(expected).max()
    assert u[0] == 1.5 and u[10] == -2


def test_heat_equals_the_cli(cli, tmp_path, converted_bunny):
    V, F = sdmesh.read_mesh(converted_bunny)
    u0 = np.exp(-((V - V[5]) ** 2).sum(axis=1))  # no subnormal values: the CLI's reader refuses them
    np.savetxt(tmp_path / "u0.txt", u0, fmt="%.17g")
    cli("heat", converted_bunny, "--u0", tmp_path / "u0.txt", "--time", "1e-3", "--steps", 3,
        "--mass", "galerkin", "--out", tmp_path / "u.ply")
    expected = read_binary_ply_fields(tmp_path / "u.ply", ["u"])["u"]
    u = sdmesh.heat(V, F, u0, 1e-3, steps=3, mass="galerkin")
    assert np.abs(u - expected).max() <= 1e-12 * np.abs(expected).max()
