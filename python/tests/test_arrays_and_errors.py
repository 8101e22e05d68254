"""Reading and writing, the dtype and shape rules, zero-copy results and the exception classes."""

import re

import numpy as np
import pytest
import scipy.sparse as sp

import sdmesh
from conftest import grid, octahedron


def parse_obj(path):
    """The v and f lines of a plain OBJ, parsed independently of sdmesh."""
    vertices, faces = [], []
    for line in open(path):
        words = line.split()
        if words and words[0] == "v":
            vertices.append([float(w) for w in words[1:4]])
        elif words and words[0] == "f":
            faces.append([int(w.split("/")[0]) - 1 for w in words[1:]])
    return np.array(vertices), np.array(faces)


def read_binary_ply_fields(path, names):
    """The double vertex properties of a binary little-endian PLY written by sdmesh (x y z + fields)."""
    data = open(path, "rb").read()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    header = data[:end].decode().splitlines()
    vertex_count = next(int(line.split()[2]) for line in header if line.startswith("element vertex"))
    properties = [line.split()[2] for line in header if line.startswith("property double")]
    table = np.frombuffer(data, dtype="<f8", count=vertex_count * len(properties), offset=end)
    table = table.reshape(vertex_count, len(properties))
    return {name: table[:, properties.index(name)] for name in names}


def test_read_mesh_matches_the_file(bunny_path, bunny):
    V, F = bunny
    expected_V, expected_F = parse_obj(bunny_path)
    assert V.dtype == np.float64 and V.shape == expected_V.shape
    assert F.dtype == np.int32 and F.shape == expected_F.shape
    np.testing.assert_array_equal(V, expected_V)
    np.testing.assert_array_equal(F, expected_F)


def test_results_view_the_cpp_buffers(bunny):
    V, F = bunny
    L = sdmesh.operators(V, F)["L"]
    for array in (V, F, L.data, L.indices, L.indptr):
        base = array
        while isinstance(getattr(base, "base", None), np.ndarray):
            base = base.base
        assert type(base.base).__name__ == "PyCapsule"  # owned by C++, never copied into NumPy
    assert V.flags.f_contiguous and F.flags.f_contiguous
    assert L.indices.dtype == np.int32 and L.indptr.dtype == np.int32 and L.data.dtype == np.float64


def test_write_then_read_gives_the_same_bits(tmp_path, bunny):
    V, F = bunny
    for name in ("m.obj", "m.off", "m.ply", "m.obj.gz"):
        sdmesh.write_mesh(tmp_path / name, V, F)
        V2, F2 = sdmesh.read_mesh(str(tmp_path / name))
        np.testing.assert_array_equal(V2, V)
        np.testing.assert_array_equal(F2, F)


def test_vertex_fields_are_written_to_ply(tmp_path, bunny):
    V, F = bunny
    height = V[:, 1].copy()
    sdmesh.write_mesh(tmp_path / "f.ply", V, F, fields={"height": height, "index": np.arange(len(V))})
    fields = read_binary_ply_fields(tmp_path / "f.ply", ["height", "index"])
    np.testing.assert_array_equal(fields["height"], height)
    np.testing.assert_array_equal(fields["index"], np.arange(len(V)))
    with pytest.raises(sdmesh.InvalidArgumentError, match=r"\(3,\)"):
        sdmesh.write_mesh(tmp_path / "g.ply", V, F, fields={"short": np.zeros(3)})
    with pytest.raises(sdmesh.InvalidArgumentError):
        sdmesh.write_mesh(tmp_path / "g.obj", V, F, fields={"height": height})


def operators_equal(a, b):
    assert a.keys() == b.keys()
    for key in a:
        assert (a[key] != b[key]).nnz == 0, key


def test_dtype_rule_and_layouts_give_the_same_operators():
    V, F = grid(6, 5)
    reference = sdmesh.operators(V, F)
    operators_equal(reference, sdmesh.operators(np.asfortranarray(V), F.astype(np.int64)))
    operators_equal(reference, sdmesh.operators(V.tolist(), F.tolist()))
    padded = np.zeros((len(V), 5))
    padded[:, 1:4] = V
    operators_equal(reference, sdmesh.operators(padded[:, 1:4], F.astype(np.uint16)))  # strided view
    # float32 positions are read as float64: the same result as converting them first.
    operators_equal(sdmesh.operators(V.astype(np.float32).astype(np.float64), F),
                    sdmesh.operators(V.astype(np.float32), F))


def test_wrong_shapes_raise_value_error_with_the_shape():
    V, F = grid(2, 2)
    cases = [((V[:, :2], F), r"V must have shape \(n, 3\), got \(9, 2\)"),
             ((V.ravel(), F), r"V must have shape \(n, 3\), got \(27,\)"),
             ((V, np.zeros((4, 4), dtype=np.int32)), r"F must have shape \(m, 3\), got \(4, 4\)")]
    for args, message in cases:
        with pytest.raises(ValueError, match=message):
            sdmesh.operators(*args)
    with pytest.raises(ValueError, match=r"f must have shape \(9,\), got \(8,\)"):
        sdmesh.poisson(V, F, np.zeros(8))
    with pytest.raises(ValueError, match=r"sources must have shape \(n,\), got \(1, 2\)"):
        sdmesh.geodesic(V, F, [[0, 1]])


def test_wrong_dtypes_raise_type_error():
    V, F = grid(2, 2)
    with pytest.raises(TypeError, match="F must be an array of integers, got dtype float64"):
        sdmesh.operators(V, F.astype(np.float64))
    with pytest.raises(TypeError, match="V must be an array of real numbers, got dtype <U1"):
        sdmesh.operators(np.full((3, 3), "a"), F)
    with pytest.raises(sdmesh.InvalidArgumentError, match="F has values outside the int32 range"):
        sdmesh.operators(V, F.astype(np.int64) + 2**31)


def test_solvers_name_dense_matrices_instead_of_misreading_them_as_a_mesh():
    V, F = grid(3, 3)
    L, M = (sdmesh.operators(V, F)[key] for key in ("L", "M"))
    with pytest.raises(TypeError, match="F_or_M holds floats: a mesh's faces F are integers, and matrices L and M"):
        sdmesh.eigs(L.toarray(), M.toarray(), k=2)
    with pytest.raises(TypeError, match="V_or_L is not sparse but F_or_M is"):
        sdmesh.heat(L.toarray(), M, np.ones(L.shape[0]), 0.1)
    with pytest.raises(sdmesh.InvalidArgumentError, match=r"eigenpairs: L is not symmetric: L\("):
        sdmesh.eigs(L + sp.triu(L, 1) * 0.5, M, k=2)
    broken = sp.csc_matrix(M, copy=True)
    broken.data[0] = np.nan  # M(0, 0): the barycentric mass is diagonal
    with pytest.raises(sdmesh.InvalidArgumentError, match=r"Poisson: M\(0, 0\) = nan is not finite"):
        sdmesh.poisson(L, broken, np.ones(L.shape[0]), dirichlet_vertices=[0], dirichlet_values=[0.0])


def test_exception_classes_mirror_the_cpp_hierarchy():
    for cls in (sdmesh.IoError, sdmesh.UnsupportedFormatError, sdmesh.ParseError, sdmesh.InvalidMeshError,
                sdmesh.InvalidArgumentError, sdmesh.NumericalError):
        assert issubclass(cls, sdmesh.Error) and cls.__module__ == "sdmesh"
    assert issubclass(sdmesh.IoError, OSError) and issubclass(sdmesh.InvalidArgumentError, ValueError)


def cli_message(done):
    return done.stderr.strip().removeprefix("sdmesh: ")


def test_file_errors_have_the_cli_class_and_message(cli, tmp_path):
    bad = tmp_path / "bad.obj"
    bad.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 x\n")
    (tmp_path / "mesh.xyz").write_text("0 0 0\n")
    cases = [(tmp_path / "missing.obj", sdmesh.IoError, 3), (tmp_path / "mesh.xyz", sdmesh.UnsupportedFormatError, 4),
             (bad, sdmesh.ParseError, 5)]
    for path, cls, exit_code in cases:
        with pytest.raises(cls) as raised:
            sdmesh.read_mesh(path)
        assert str(raised.value) == cli_message(cli("check", path, expect=exit_code))


def test_mesh_and_argument_errors(bunny):
    V, F = octahedron()
    fin = np.array([[0, 1, 2], [0, 1, 3], [0, 1, 4]], dtype=np.int32)  # three faces on edge (0, 1)
    with pytest.raises(sdmesh.InvalidMeshError, match=re.escape("edge (0, 1) has 3 faces")):
        sdmesh.operators(V, fin)
    with pytest.raises(sdmesh.InvalidMeshError, match="face 4 references vertex 6, but the mesh has 6 vertices"):
        sdmesh.check(V, F + 1)
    with pytest.raises(sdmesh.InvalidArgumentError, match="k"):
        sdmesh.eigs(V, F, k=6)
    with pytest.raises(sdmesh.InvalidArgumentError, match=re.escape("method must be split|hybrid|flip, got 'best'")):
        sdmesh.convert(V, F, method="best")
    with pytest.raises(sdmesh.InvalidArgumentError, match=re.escape("mass must be barycentric|circumcentric|mixed|galerkin, got 'lumped'")):
        sdmesh.operators(V, F, mass="lumped")
    with pytest.raises(sdmesh.InvalidArgumentError, match="not to given matrices"):
        ops = sdmesh.operators(V, F)
        sdmesh.eigs(ops["L"], ops["M"], k=2, mass="barycentric")
    with pytest.raises(sdmesh.NumericalError):
        ops = sdmesh.operators(*bunny)
        sdmesh.eigs(ops["L"], -ops["M"], k=3, sigma=-0.01)  # L + 0.01·M is indefinite
