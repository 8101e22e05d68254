#pragma once
// Reading and writing meshes: OBJ, OFF, PLY (ascii, binary little/big endian), STL (ascii,
// binary), each optionally gzip-compressed ("bunny.obj.gz"). The format is chosen by the file
// extension (case-insensitive, a trailing ".gz" means gzip).
//
// Reading keeps every face in the file: nothing is dropped or repaired here (validate.hpp reports
// and repairs). Polygons with n > 3 corners become n - 2 triangles, counted: the fan (0, i, i+1)
// when none of its triangles is inverted against the polygon's normal (convex polygons, for
// one), else ear clipping in the polygon's plane, so that a non-convex polygon is not folded
// over itself. A polygon ear clipping cannot finish (not simple, or past its work bound of
// about 256 tests per corner) has the rest of it fanned.
// STL vertices are welded by exact position (-0.0 == 0.0), numbered in order of first appearance.
// Everything is double precision: OBJ/OFF are written with 17 significant digits and PLY with
// `double` properties, so write -> read gives back the same bits.

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "sdmesh/mesh.hpp"

namespace sdmesh {

enum class MeshFormat { obj, off, ply, stl };

/// What a reader saw in the file.
struct ReadReport {
    MeshFormat format = MeshFormat::obj;
    bool compressed = false;        ///< the file was gzip-compressed
    long long file_vertices = 0;    ///< vertices declared or listed in the file (STL: 3 per facet)
    long long file_faces = 0;       ///< faces in the file, whatever their number of corners
    long long polygons = 0;         ///< faces with more than 3 corners
    long long polygon_triangles = 0;///< triangles made from those polygons
    long long ear_clipped_polygons = 0; ///< polygons whose fan would fold over: ear clipped
    long long welded_vertices = 0;  ///< STL only: file vertices merged with an earlier equal one
    long long skipped_line_faces = 0; ///< OBJ only: `f` of 1 or 2 corners (points, lines), skipped
};

/// Reads a mesh file.
///
/// What is accepted, beyond the plain formats:
/// - OBJ: `v x y z [w]` (w and vertex colors ignored), `f`/`fo` with corners `v`, `v/vt`, `v//vn`,
///   `v/vt/vn`; negative indices are relative to the vertices defined so far; a positive index may
///   refer to a vertex defined further down. Other keywords, comments, CRLF and backslash line
///   continuations are fine. An `f` of one or two corners (a point or a line written as a face)
///   is skipped and counted in ReadReport::skipped_line_faces.
/// - OFF: [ST][C][N]OFF, counts on the keyword line or the next one, `#` comments and blank lines
///   anywhere, extra values (colors, normals) after vertices and faces ignored.
/// - PLY: any element order, all property types, other elements and properties (lists too)
///   skipped; faces from the `face` element's `vertex_indices` or `vertex_index` list.
///   Triangle strips (`tristrips`) are an UnsupportedFormatError rather than silently dropped.
/// - STL: binary when the size is exactly 84 + 50 n, else ascii if it starts with "solid" and has
///   no NUL byte, else binary (whose size then does not match: a ParseError).
/// A UTF-8 byte order mark at the start of a text file (or of a PLY header) is skipped. Lines of
/// text end with LF, CR LF or a lone CR (classic Mac OS), mixed or not.
/// Non-finite coordinates (nan, inf, and old MSVC's 1.#INF, -1.#IND) are read as they are;
/// values outside the double range (1e999) are a ParseError. An empty or all-blank file is a
/// ParseError.
///
/// \throws IoError the file cannot be opened or read, or its text or the mesh it holds would take
///         more memory than reading may use: a quarter of what the process may use for the text
///         (decompressed), a sixteenth for the vertices and faces.
/// \throws UnsupportedFormatError unknown extension, or a header variant that is not supported.
/// \throws ParseError malformed content; the message names the file and the line (text formats)
///         or byte offset / element (binary formats): truncation, bad numbers, a face with fewer
///         than 3 corners, a vertex index out of range (also 0 or too negative in OBJ).
TriangleMesh read_mesh(const std::filesystem::path& path, ReadReport* report = nullptr);

/// Parses mesh data already in memory (decompressed); `name` is used in error messages only.
/// Same rules and exceptions as read_mesh (IoError only for a mesh beyond its memory budget).
TriangleMesh parse_mesh(std::string_view bytes, MeshFormat format, std::string_view name,
                        ReadReport* report = nullptr);

/// A named per-vertex scalar field, written as a `double` vertex property (PLY only).
struct VertexField {
    std::string name;
    Eigen::VectorXd values;  ///< one value per vertex
};

struct WriteOptions {
    /// Extra per-vertex properties, PLY only (empty by default).
    std::vector<VertexField> vertex_fields;
    /// PLY only: write ascii instead of binary little endian.
    bool ply_ascii = false;
};

/// Writes a mesh: OBJ, OFF or PLY (STL is read-only), chosen by extension, ".gz" compresses
/// (zlib level 1: several times faster than the default level for files a few percent larger).
/// PLY is binary little endian unless `ply_ascii`: `double x y z`, then one `double` property per
/// vertex field, and faces as `property list uchar int vertex_indices`.
/// The data go to a temporary file in the same folder which is renamed over `path` at the end,
/// so a failed or interrupted write never leaves a partial file under `path`.
/// \throws UnsupportedFormatError unknown or read-only extension.
/// \throws InvalidArgumentError vertex fields for a non-PLY file, a field of the wrong size or
///         with a name that is not a PLY identifier, a face index out of range.
/// \throws IoError the file cannot be written or renamed.
void write_mesh(const std::filesystem::path& path, const TriangleMesh& mesh,
                const WriteOptions& options = {});

/// Writes `text` to `path` atomically (temporary file in the same folder, then rename), for
/// reports and other small outputs; ".gz" compresses. \throws IoError
void write_text_file(const std::filesystem::path& path, std::string_view text);

/// What write_mesh (with vertex fields or not) would refuse about `path` itself, checked before the
/// mesh exists, so that a command fails before it computes rather than after: an extension it
/// does not write, vertex fields outside PLY, a folder that is missing or takes no new files, a
/// folder where the file would be.
/// \throws UnsupportedFormatError, InvalidArgumentError, IoError as write_mesh.
void check_mesh_output(const std::filesystem::path& path, bool with_vertex_fields = false);

/// The same for write_text_file: a folder that is missing or takes no new files, a folder where
/// the file would be. \throws IoError
void check_text_output(const std::filesystem::path& path);

/// The format an extension names ("x.PLY.gz" -> ply, compressed = true).
/// \throws UnsupportedFormatError for any other extension.
MeshFormat format_from_path(const std::filesystem::path& path, bool* compressed = nullptr);

}  // namespace sdmesh
