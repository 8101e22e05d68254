"""What the plot scripts of the studies share: reading their CSV, one colour and label per
connectivity, saving figures, markdown tables, and drawing a vertex field on a mesh.
Debian's python3-matplotlib and python3-numpy (run with /usr/bin/python3)."""

import csv
from pathlib import Path

import matplotlib

matplotlib.use("Agg")  # headless
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.ticker import NullFormatter  # noqa: E402,F401  (re-exported for the plot scripts)
import numpy as np  # noqa: E402

CONNECTIVITIES = ["original", "split", "hybrid", "idt"]
LABELS = {
    "original": "original connectivity",
    "split": "self-Delaunay (split)",
    "hybrid": "self-Delaunay (hybrid 10°)",
    "idt": "intrinsic Delaunay (iDT)",
}
COLOURS = {"original": "tab:red", "split": "tab:blue", "hybrid": "tab:cyan", "idt": "tab:green"}


def read_rows(path):
    """The rows of a CSV file as dicts of strings."""
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def save(figure, path, title_space=0.0):
    """Saves a PNG; title_space: fraction of the height kept free at the top for a suptitle."""
    figure.tight_layout(rect=(0, 0, 1, 1 - title_space))
    figure.savefig(path, dpi=110)
    plt.close(figure)
    print(f"wrote {path}")


def markdown_table(header, rows):
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(str(cell) for cell in row) + " |" for row in rows]
    return "\n".join(lines)


def write_text(path, text):
    """Writes a small text output atomically (temporary file, then rename)."""
    path = Path(path)
    temporary = path.with_name(path.name + ".tmp")
    temporary.write_text(text)
    temporary.replace(path)
    print(f"wrote {path}")


def fitted_order(h, error):
    """Slope of log(error) against log(h): the order of convergence."""
    return float(np.polyfit(np.log(h), np.log(error), 1)[0])


def read_ascii_ply(path):
    """Vertices (n x 3), faces (m x 3) and the named vertex fields of an ascii PLY written by
    sdmesh::write_mesh (double vertex properties, faces as a uchar-int list)."""
    with open(path) as f:
        lines = f.read().splitlines()
    end = lines.index("end_header")
    vertex_count = face_count = 0
    properties = []
    for line in lines[:end]:
        words = line.split()
        if words[:2] == ["element", "vertex"]:
            vertex_count = int(words[2])
        elif words[:2] == ["element", "face"]:
            face_count = int(words[2])
        elif words[0] == "property" and words[1] != "list":
            properties.append(words[2])
    data = np.array([line.split() for line in lines[end + 1:end + 1 + vertex_count]], dtype=float)
    faces = np.array([line.split()[1:4] for line in lines[end + 1 + vertex_count:end + 1 + vertex_count + face_count]],
                     dtype=int)
    fields = {name: data[:, i] for i, name in enumerate(properties)}
    vertices = np.column_stack([fields.pop("x"), fields.pop("y"), fields.pop("z")])
    return vertices, faces, fields


def principal_frame(vertices):
    """(centre, rotation) that turn a mesh to its principal axes: x the longest extent, z the
    middle one (up), y the shortest (depth, towards the viewer)."""
    centre = vertices.mean(axis=0)
    axes_of_extent = np.linalg.svd(vertices - centre, full_matrices=False)[2]  # rows: longest to shortest
    return centre, axes_of_extent[[0, 2, 1]]


def draw_field(axes, vertices, faces, values, view, frame, colour_map="viridis", bands=0, limits=None):
    """Draws a mesh on 3D axes with each face coloured by the mean of `values` at its corners,
    lit by a fixed light; bands > 0 quantizes the colours into that many stripes (isolines).
    The mesh is turned by `frame` (principal_frame of the mesh, or of another one to draw several
    meshes alike), then seen from view = (elevation, azimuth) in degrees."""
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    low, high = limits if limits else (values.min(), values.max())
    face_value = (values[faces].mean(axis=1) - low) / (high - low)
    if bands:
        face_value = np.floor(np.clip(face_value, 0, 0.999) * bands) / (bands - 1)
    colours = plt.get_cmap(colour_map)(np.clip(face_value, 0, 1))
    centre, rotation = frame
    vertices = (vertices - centre) @ rotation.T
    corners = vertices[faces]
    normals = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    light = np.array([0.3, -0.5, 0.8]) / np.linalg.norm([0.3, -0.5, 0.8])
    shade = 0.55 + 0.45 * np.abs(normals @ light)
    colours[:, :3] *= shade[:, None]
    axes.add_collection3d(Poly3DCollection(corners, facecolors=colours, edgecolors="none"))
    centre = (vertices.max(axis=0) + vertices.min(axis=0)) / 2
    radius = (vertices.max(axis=0) - vertices.min(axis=0)).max() / 2
    for set_limits, c in zip((axes.set_xlim, axes.set_ylim, axes.set_zlim), centre):
        set_limits(c - radius, c + radius)
    axes.view_init(*view)
    axes.set_box_aspect((1, 1, 1), zoom=1.5)
    axes.set_axis_off()
