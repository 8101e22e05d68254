#pragma once
// The bad-input corpus of test_bad_input.cpp, made in code: broken files of every format (what a
// reader must refuse) and defective meshes written in every format that can hold them (what the
// commands must refuse or report). Each case carries the exit code every command must give.

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <ostream>
#include <string>
#include <vector>

#include <zlib.h>

#include "meshes.hpp"
#include "sdmesh/mesh.hpp"

namespace sdmesh::test {

/// A file whose bytes are given, with the exit code of every mesh-reading command on it.
struct BadFile {
    std::string name;  ///< file name: case and extension, e.g. "truncated.ply"
    std::string bytes;
    int exit_code;     ///< 5 malformed, 4 unsupported (the reader's error, whatever the command)
};

// Test parameters print as their file name (not as raw bytes) in test listings.
inline void PrintTo(const BadFile& file, std::ostream* out) { *out << file.name; }

// ---- bytes of each format --------------------------------------------------------------------

inline std::string gzip_bytes(const std::string& bytes) {
    uLongf size = compressBound(static_cast<uLong>(bytes.size())) + 32;
    std::string out(size, '\0');
    z_stream stream{};
    deflateInit2(&stream, Z_DEFAULT_COMPRESSION, Z_DEFLATED, 15 + 16, 8, Z_DEFAULT_STRATEGY);  // gzip wrapper
    stream.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(bytes.data()));
    stream.avail_in = static_cast<uInt>(bytes.size());
    stream.next_out = reinterpret_cast<Bytef*>(out.data());
    stream.avail_out = static_cast<uInt>(out.size());
    deflate(&stream, Z_FINISH);
    out.resize(stream.total_out);
    deflateEnd(&stream);
    return out;
}

template <class T>
void append_binary(std::string& bytes, T value, bool big_endian) {
    char raw[sizeof(T)];
    std::memcpy(raw, &value, sizeof(T));
    if (big_endian) std::reverse(raw, raw + sizeof(T));  // the test host is little endian
    bytes.append(raw, sizeof(T));
}

/// Binary PLY: float x y z, faces as `list uchar int` (corner lists may have any length).
inline std::string binary_ply(const std::vector<std::array<float, 3>>& vertices,
                              const std::vector<std::vector<int>>& faces, bool big_endian) {
    std::string bytes = std::string("ply\nformat ") + (big_endian ? "binary_big_endian" : "binary_little_endian") +
                        " 1.0\nelement vertex " + std::to_string(vertices.size()) +
                        "\nproperty float x\nproperty float y\nproperty float z\nelement face " +
                        std::to_string(faces.size()) + "\nproperty list uchar int vertex_indices\nend_header\n";
    for (const auto& v : vertices)
        for (const float x : v) append_binary(bytes, x, big_endian);
    for (const auto& f : faces) {
        append_binary(bytes, static_cast<std::uint8_t>(f.size()), big_endian);
        for (const int i : f) append_binary(bytes, i, big_endian);
    }
    return bytes;
}

/// Binary STL of a mesh: zero normals, float corners; `facets` overrides the count in the header.
inline std::string binary_stl(const TriangleMesh& mesh, long long facets = -1) {
    std::string bytes(80, 'x');
    append_binary(bytes, static_cast<std::uint32_t>(facets < 0 ? mesh.num_faces() : facets), false);
    for (int f = 0; f < mesh.num_faces(); ++f) {
        for (int c = 0; c < 3; ++c) append_binary(bytes, 0.0f, false);
        for (int k = 0; k < 3; ++k)
            for (int c = 0; c < 3; ++c) append_binary(bytes, static_cast<float>(mesh.V(mesh.F(f, k), c)), false);
        append_binary(bytes, std::uint16_t{0}, false);
    }
    return bytes;
}

inline std::string ascii_stl(const TriangleMesh& mesh) {
    std::string text = "solid case\n";
    for (int f = 0; f < mesh.num_faces(); ++f) {
        text += "facet normal 0 0 0\nouter loop\n";
        for (int k = 0; k < 3; ++k) {
            text += "vertex";
            for (int c = 0; c < 3; ++c) {
                char number[32];
                std::snprintf(number, sizeof number, " %.17g", mesh.V(mesh.F(f, k), c));
                text += number;
            }
            text += "\n";
        }
        text += "endloop\nendfacet\n";
    }
    return text + "endsolid case\n";
}

// ---- broken files ----------------------------------------------------------------------------

/// Every way a file can be broken, in every format where the defect can be written. The valid
/// base is the unit square as two triangles (OBJ/OFF/PLY: 4 vertices; STL: 2 facets).
inline std::vector<BadFile> broken_files() {
    constexpr int kMalformed = 5, kUnsupported = 4;
    const std::string obj_vertices = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n";
    const std::string off_vertices = "OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n";
    const std::string ply_ascii_header =
        "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
        "element face 2\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n";
    const std::vector<std::array<float, 3>> square = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    const TriangleMesh square_mesh = make_mesh({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}, {{0, 1, 2}, {0, 2, 3}});
    const std::string valid_ply_le = binary_ply(square, {{0, 1, 2}, {0, 2, 3}}, false);
    const std::string valid_ply_be = binary_ply(square, {{0, 1, 2}, {0, 2, 3}}, true);
    const std::string valid_stl_ascii = ascii_stl(square_mesh);
    const std::string valid_stl_binary = binary_stl(square_mesh);

    std::vector<BadFile> files = {
        // empty, in every format
        {"empty.obj", "", kMalformed},
        {"empty.off", "", kMalformed},
        {"empty.ply", "", kMalformed},
        {"empty.stl", "", kMalformed},
        {"blank.obj", "\n  \n\t\n", kMalformed},
        // truncated
        {"truncated.obj", obj_vertices + "f 1 2 3\nv 0.5 ", kMalformed},
        {"truncated.off", off_vertices + "3 0 1 2\n3 0 2", kMalformed},
        {"truncated_ascii.ply", ply_ascii_header + "3 0 1 2\n3 0 2", kMalformed},
        {"truncated_le.ply", valid_ply_le.substr(0, valid_ply_le.size() - 3), kMalformed},
        {"truncated_be.ply", valid_ply_be.substr(0, valid_ply_be.size() - 3), kMalformed},
        {"truncated_header.ply", "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\n", kMalformed},
        {"truncated_ascii.stl", valid_stl_ascii.substr(0, valid_stl_ascii.size() / 2), kMalformed},
        {"truncated_binary.stl", valid_stl_binary.substr(0, valid_stl_binary.size() - 7), kMalformed},
        {"header_only_binary.stl", valid_stl_binary.substr(0, 60), kMalformed},
        // wrong headers
        {"wrong_keyword.off", "OFX\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n3 0 2 3\n", kMalformed},
        {"wrong_magic.ply", "plx" + ply_ascii_header.substr(3) + "3 0 1 2\n3 0 2 3\n", kMalformed},
        {"unknown_encoding.ply", "ply\nformat binary_middle_endian 1.0\nelement vertex 0\nend_header\n", kUnsupported},
        {"binary_garbage.obj", std::string("\x7f" "ELF\x02\x01\x01\0\0\0\0\0\0\0\0\0", 16), kMalformed},
        {"not_solid.stl", "hello\nfacet normal 0 0 0\n", kMalformed},
        // Text of other formats under a mesh's extension (games' levels): not empty meshes.
        {"level.stl", "(supertux-level\n  (version 3)\n  (name \"Empty Throne Room\")\n" + std::string(60, ' ') + ")\n",
         kMalformed},
        {"level.obj", "****..&..****--0\n***....&....***--1\n", kMalformed},
        // indices out of range, negative, zero where one-based is required
        {"index_out_of_range.obj", obj_vertices + "f 1 2 3\nf 1 3 9\n", kMalformed},
        {"index_zero.obj", obj_vertices + "f 0 1 2\n", kMalformed},
        {"index_too_negative.obj", obj_vertices + "f -1 -2 -5\n", kMalformed},
        {"index_out_of_range.off", off_vertices + "3 0 1 2\n3 0 2 4\n", kMalformed},
        {"index_negative.off", off_vertices + "3 0 1 2\n3 0 -1 3\n", kMalformed},
        {"index_out_of_range_ascii.ply", ply_ascii_header + "3 0 1 2\n3 0 2 4\n", kMalformed},
        {"index_negative_ascii.ply", ply_ascii_header + "3 0 1 2\n3 -1 2 3\n", kMalformed},
        {"index_out_of_range_le.ply", binary_ply(square, {{0, 1, 2}, {0, 2, 4}}, false), kMalformed},
        {"index_negative_be.ply", binary_ply(square, {{0, 1, 2}, {0, -2, 3}}, true), kMalformed},
        // numbers outside the double range, malformed numbers
        {"huge_number.obj", "v 0 0 0\nv 1e999 0 0\nv 0 1 0\nf 1 2 3\n", kMalformed},
        {"huge_number.off", "OFF\n3 1 0\n0 0 0\n1e999 0 0\n0 1 0\n3 0 1 2\n", kMalformed},
        {"huge_number_ascii.ply", ply_ascii_header.substr(0, ply_ascii_header.size() - 6) + "1e999 1 0\n3 0 1 2\n3 0 2 3\n",
         kMalformed},
        {"huge_number_ascii.stl", "solid a\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1e999 0 0\n"
                                  "vertex 0 1 0\nendloop\nendfacet\nendsolid a\n", kMalformed},
        {"bad_number.obj", obj_vertices + "v 1 x 0\nf 1 2 3\n", kMalformed},
        // faces with fewer than three corners
        {"no_corners.obj", obj_vertices + "f\n", kMalformed},
        {"two_corners.off", off_vertices + "3 0 1 2\n2 0 2\n", kMalformed},
        {"two_corners_le.ply", binary_ply(square, {{0, 1, 2}, {0, 2}}, false), kMalformed},
        // binary PLY with the wrong byte order or lengths
        {"big_endian_data_declared_little.ply", [&] {
             std::string bytes = valid_ply_be;
             bytes.replace(bytes.find("binary_big_endian"), 17, "binary_little_endian");
             return bytes;
         }(), kMalformed},
        {"more_faces_declared_le.ply", [&] {
             std::string bytes = valid_ply_le;
             bytes.replace(bytes.find("element face 2"), 14, "element face 3");
             return bytes;
         }(), kMalformed},
        {"double_declared_float_data_le.ply", [&] {
             std::string bytes = valid_ply_le;
             for (const char* axis : {"x", "y", "z"}) {
                 const std::string property = std::string("property float ") + axis;
                 bytes.replace(bytes.find(property), property.size(), std::string("property double ") + axis);
             }
             return bytes;
         }(), kMalformed},
        {"list_count_too_long_le.ply", [&] {
             std::string bytes = valid_ply_le;
             bytes[bytes.size() - 13] = '\xff';  // the last face's corner count: 255 corners, 3 given
             return bytes;
         }(), kMalformed},
        // binary STL whose facet count disagrees with its size
        {"facet_count_too_large.stl", binary_stl(square_mesh, 3), kMalformed},
        {"facet_count_too_large_solid_header.stl", "solid" + binary_stl(square_mesh, 3).substr(5), kMalformed},
    };
    // gzip: a corrupt stream (a flipped byte in the deflate data) and a truncated one, per format
    for (const auto& [extension, bytes] : {std::pair<std::string, std::string>{"obj", obj_vertices + "f 1 2 3\n"},
                                           {"off", off_vertices + "3 0 1 2\n3 0 2 3\n"},
                                           {"ply", valid_ply_le},
                                           {"stl", valid_stl_binary}}) {
        std::string corrupt = gzip_bytes(bytes);
        corrupt[corrupt.size() / 2] = static_cast<char>(corrupt[corrupt.size() / 2] ^ 0x55);
        files.push_back({"corrupt_gzip." + extension + ".gz", corrupt, kMalformed});
        files.push_back({"truncated_gzip." + extension + ".gz", gzip_bytes(bytes).substr(0, 20), kMalformed});
        files.push_back({"plain_bytes_named_gzip." + extension + ".gz", bytes, kMalformed});
    }
    return files;
}

// ---- defective meshes ------------------------------------------------------------------------

/// Exit codes of the mesh-reading commands, in the order of kCommands in test_bad_input.cpp.
struct CommandCodes {
    int info, check, repair, convert, operators, intrinsic, eigs, geodesic, poisson, heat, decimate;
};

/// A mesh with one defect (or none: the well-formed oddities), written in each format that can
/// hold it; what every command answers and what the library throws.
struct BadMesh {
    std::string name;
    TriangleMesh mesh;
    CommandCodes codes;
    bool stl;  ///< STL can hold it (float coordinates, no unreferenced vertices)
};

/// A regular tetrahedron-like closed surface, the base most defects are made from.
inline TriangleMesh tetrahedron() {
    return make_mesh({{1, 1, 1}, {1, -1, -1}, {-1, 1, -1}, {-1, -1, 1}}, {{0, 1, 2}, {0, 3, 1}, {0, 2, 3}, {1, 3, 2}});
}

/// A Möbius strip of `n` quads (2n triangles): the band is closed with a half twist.
inline TriangleMesh moebius_strip(int n) {
    TriangleMesh mesh;
    mesh.V.resize(2 * n, 3);
    for (int i = 0; i < n; ++i) {
        const double angle = 2 * M_PI * i / n, twist = angle / 2;
        const Eigen::RowVector3d center(3 * std::cos(angle), 3 * std::sin(angle), 0);
        const Eigen::RowVector3d across(std::cos(twist) * std::cos(angle), std::cos(twist) * std::sin(angle),
                                        std::sin(twist));
        mesh.V.row(2 * i) = center - across;
        mesh.V.row(2 * i + 1) = center + across;
    }
    mesh.F.resize(2 * n, 3);
    for (int i = 0; i < n; ++i) {
        const int a = 2 * i, b = 2 * i + 1;
        // the last quad joins the first pair swapped: the half twist
        const int c = i + 1 < n ? 2 * (i + 1) : 1, d = i + 1 < n ? 2 * (i + 1) + 1 : 0;
        mesh.F.row(2 * i) << a, c, b;
        mesh.F.row(2 * i + 1) << b, c, d;
    }
    return mesh;
}

inline std::vector<BadMesh> bad_meshes() {
    const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
    const TriangleMesh tet = tetrahedron();
    auto with_vertex = [&](double x) {
        TriangleMesh mesh = tet;
        mesh.V(1, 0) = x;
        return mesh;
    };
    auto scaled = [&](double s) {
        TriangleMesh mesh = tet;
        mesh.V *= s;
        return mesh;
    };
    TriangleMesh isolated = tet;
    isolated.V.conservativeResize(6, 3);
    isolated.V.bottomRows(2) << 5, 5, 5, 6, 6, 6;
    TriangleMesh flipped_face = tet;
    flipped_face.F.row(3) << 1, 2, 3;

    // clang-format off
    // Exit codes: 0 ok, 1 not self-Delaunay, 6 invalid mesh, 7 invalid argument, 8 numerical error.
    // A vertex in no face has no mass and no value: the solver commands refuse it, naming it (6).
    //                                       info check repair convert operators intrinsic eigs geodesic poisson heat decimate
    return {
        {"no_faces", make_mesh({{0, 0, 0}, {1, 0, 0}}, {}),          {0, 0, 0, 0, 0, 0, 6, 6, 6, 6, 0}, false},
        {"single_triangle", make_mesh({{0, 0, 0}, {1, 0, 0}, {0.5, 0.8, 0}}, {{0, 1, 2}}),
                                                                     {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0}, true},
        {"two_components", disjoint_union(tet, tet, 10),             {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0}, true},
        {"isolated_vertices", isolated,                              {0, 0, 0, 0, 0, 0, 6, 6, 6, 6, 0}, false},
        {"repeated_index", make_mesh({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 1, 2}, {0, 1, 1}}),
                                                                     {0, 1, 0, 6, 6, 6, 6, 6, 6, 6, 6}, true},
        {"zero_area", make_mesh({{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {0, 1, 0}}, {{0, 1, 2}, {0, 2, 3}}),
                                                                     {0, 1, 0, 6, 6, 6, 6, 6, 6, 6, 6}, true},
        // below the library's degeneracy tolerance: refused like a zero-area face
        {"needle", make_mesh({{0, 0, 0}, {1, 0, 0}, {0.5, 1e-13, 0}}, {{0, 1, 2}}),
                                                                     {0, 1, 0, 6, 6, 6, 6, 6, 6, 6, 6}, true},
        {"duplicate_faces", make_mesh({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 1, 2}, {0, 1, 2}}),
                                                                     {0, 0, 0, 6, 0, 6, 0, 0, 0, 0, 6}, true},
        {"nonmanifold_edge", make_mesh({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}},
                                       {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}}),
                                                                     {0, 1, 0, 6, 6, 6, 6, 6, 6, 6, 6}, true},
        {"bowtie_vertex", make_mesh({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {-1, 0, 0}, {-1, -1, 0}},
                                    {{0, 1, 2}, {0, 3, 4}}),         {0, 1, 0, 6, 0, 0, 0, 0, 0, 0, 6}, true},
        {"inconsistent_orientation", flipped_face,                   {0, 0, 0, 6, 0, 6, 0, 0, 0, 0, 6}, true},
        {"moebius_strip", moebius_strip(8),                          {0, 1, 0, 6, 0, 6, 0, 0, 0, 0, 6}, true},
        {"nan_coordinate", with_vertex(nan),                         {0, 6, 0, 6, 6, 6, 6, 6, 6, 6, 6}, true},
        {"infinite_coordinate", with_vertex(inf),                    {0, 6, 0, 6, 6, 6, 6, 6, 6, 6, 6}, true},
        // the supported extents end near 1e±150 (require_supported_extent); heat's t = 0.1 is
        // then 1e280 times the squared edge length, and refused
        {"large_coordinates", scaled(1e140),                         {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0}, false},
        {"small_coordinates", scaled(1e-140),                        {0, 0, 0, 0, 0, 0, 0, 0, 0, 7, 0}, false},
        {"too_large_coordinates", scaled(1e160),                     {0, 0, 0, 6, 6, 6, 6, 6, 6, 6, 6}, false},
        {"too_small_coordinates", scaled(1e-160),                    {0, 0, 0, 6, 6, 6, 6, 6, 6, 6, 6}, false},
        {"huge_coordinates", scaled(1e300),                          {0, 0, 0, 6, 6, 6, 6, 6, 6, 6, 6}, false},
        {"tiny_coordinates", scaled(1e-300),                         {0, 0, 0, 6, 6, 6, 6, 6, 6, 6, 6}, false},
    };
    // clang-format on
}

}  // namespace sdmesh::test
