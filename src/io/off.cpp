// Object File Format (OFF): a header keyword, the counts "nv nf ne", nv vertex lines, nf face
// lines "n i0 ... i{n-1}" with 0-based indices. Comments (#) and blank lines may appear anywhere.
//
// The keyword may carry the prefixes ST (texture coordinates), C (colors) and N (normals): they
// only add values at the end of vertex lines, which are ignored, as are face colors. 4OFF, nOFF
// (other dimensions) and binary OFF are not supported.

#include <algorithm>
#include <cctype>
#include <climits>
#include <string>
#include <vector>

#include "io/formats.hpp"
#include "io/mesh_builder.hpp"
#include "io/text_scanner.hpp"
#include "sdmesh/error.hpp"

namespace sdmesh::io {
namespace {

// Accepts [ST][C][N]OFF.
void check_keyword(std::string_view keyword, const TextScanner& in, std::string_view file) {
    if (keyword.size() < 3 || keyword.substr(keyword.size() - 3) != "OFF") {
        in.fail("expected an OFF header, found " + quoted(keyword));
    }
    std::string_view prefix = keyword.substr(0, keyword.size() - 3);
    if (prefix.find_first_of("4n") != std::string_view::npos) {
        throw UnsupportedFormatError(std::string(file) + ":" + std::to_string(in.line()) + ": " +
                                     quoted(keyword) + " (not 3-dimensional OFF) is not supported");
    }
    for (std::string_view part : {"ST", "C", "N"}) {
        if (prefix.starts_with(part)) prefix.remove_prefix(part.size());
    }
    if (!prefix.empty()) in.fail("unknown OFF header " + quoted(keyword));
}

class OffReader {
public:
    OffReader(std::string_view text, std::string_view file) : in_(text, file, true), file_(file), mesh_(file) {}

    TriangleMesh read(ReadReport& report) {
        read_header();
        // Every vertex line takes at least 6 bytes ("0 0 0\n"), every face line 8: never reserve
        // more than the file can hold, whatever the header says.
        const auto bytes = static_cast<long long>(in_.remaining());
        mesh_.reserve_vertices(static_cast<std::size_t>(std::min(vertices_, bytes / 6)));
        mesh_.reserve_triangles(static_cast<std::size_t>(std::min(faces_, bytes / 8)));
        for (long long v = 0; v < vertices_; ++v) read_vertex(v);
        for (long long f = 0; f < faces_; ++f) read_face(f);
        return mesh_.finish(report);
    }

private:
    void read_header() {
        if (!in_.skip_empty_lines()) in_.fail("empty file");
        check_keyword(in_.token(), in_, file_);
        in_.skip_blanks();
        if (in_.at_line_end()) {
            in_.next_line();  // the counts are on a line of their own (or on the keyword's line)
            if (!in_.skip_empty_lines()) in_.fail("file ends before the vertex and face counts");
        } else if (!std::isdigit(static_cast<unsigned char>(*in_.position()))) {
            throw UnsupportedFormatError(std::string(file_) + ":" + std::to_string(in_.line()) +
                                         ": OFF variant " + quoted(in_.token()) + " is not supported");
        }
        vertices_ = read_count("vertex count");
        faces_ = read_count("face count");
        in_.next_line();  // the edge count, if any, is not needed
    }

    long long read_count(std::string_view what) {
        const long long count = in_.read_integer(what);
        if (count < 0 || count > INT_MAX) in_.fail(std::string(what) + " " + std::to_string(count) + " out of range");
        return count;
    }

    void read_vertex(long long v) {
        if (!in_.skip_empty_lines()) {
            in_.fail("file ends after " + std::to_string(v) + " of " + std::to_string(vertices_) + " vertices");
        }
        const double x = in_.read_double("vertex x coordinate");
        const double y = in_.read_double("vertex y coordinate");
        const double z = in_.read_double("vertex z coordinate");
        mesh_.add_vertex(x, y, z);
        in_.next_line();  // colors, normals, texture coordinates
    }

    void read_face(long long f) {
        if (!in_.skip_empty_lines()) {
            in_.fail("file ends after " + std::to_string(f) + " of " + std::to_string(faces_) + " faces");
        }
        const long long n = in_.read_integer("number of face corners");
        // Each corner takes at least 2 bytes: bounds the allocation below.
        if (n < 0) in_.fail("negative number of face corners " + std::to_string(n));
        if (n > static_cast<long long>(in_.remaining() / 2)) {
            in_.fail("face of " + std::to_string(n) + " corners: the " + std::to_string(in_.remaining()) +
                     " bytes left in the file cannot hold them");
        }
        corners_.clear();
        for (long long k = 0; k < n; ++k) {
            const long long index = in_.read_integer("vertex index");
            if (index < 0 || index >= vertices_) {
                in_.fail("vertex index " + std::to_string(index) + " out of range [0, " +
                         std::to_string(vertices_) + ")");
            }
            corners_.push_back(static_cast<int>(index));
        }
        if (!mesh_.add_face(corners_)) {
            in_.fail("face with " + std::to_string(n) + " corners (needs 3 or more)");
        }
        in_.next_line();  // face colors
    }

    TextScanner in_;
    std::string_view file_;
    MeshBuilder mesh_;
    std::vector<int> corners_;  // reused for every face
    long long vertices_ = 0;
    long long faces_ = 0;
};

}  // namespace

TriangleMesh parse_off(std::string_view text, std::string_view file, ReadReport& report) {
    return OffReader(text, file).read(report);
}

void write_off(const TriangleMesh& mesh, OutputFile& out) {
    out.write("OFF\n");
    out.write_text(static_cast<long long>(mesh.V.rows()));
    out.put(' ');
    out.write_text(static_cast<long long>(mesh.F.rows()));
    out.write(" 0\n");
    for (Eigen::Index v = 0; v < mesh.V.rows(); ++v) {
        for (int k = 0; k < 3; ++k) {
            if (k > 0) out.put(' ');
            out.write_text(mesh.V(v, k));
        }
        out.put('\n');
    }
    for (Eigen::Index f = 0; f < mesh.F.rows(); ++f) {
        out.write("3");
        for (int k = 0; k < 3; ++k) {
            out.put(' ');
            out.write_text(static_cast<long long>(mesh.F(f, k)));
        }
        out.put('\n');
    }
}

}  // namespace sdmesh::io
