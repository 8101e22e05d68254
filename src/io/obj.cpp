// Wavefront OBJ: `v x y z [w]` and `f` (also the old `fo`) lines; every other keyword is ignored
// (a keyword with control characters means binary data: a ParseError).
//
// Face corners are `v`, `v/vt`, `v//vn` or `v/vt/vn`; only v is kept. A face of one or two corners
// is a point or a line that an exporter wrote as `f` (3ds converters do): its indices are checked,
// and it is skipped and counted. A face of no corners is a ParseError. Indices start at 1;
// negative ones count back from the last vertex defined so far. A positive index may refer to a
// vertex defined further down the file, so it is checked against the final vertex count.

#include <algorithm>
#include <climits>
#include <iterator>
#include <string>
#include <string_view>
#include <vector>

#include "io/formats.hpp"
#include "io/mesh_builder.hpp"
#include "io/text_scanner.hpp"

namespace sdmesh::io {
namespace {

class ObjReader {
public:
    ObjReader(std::string_view text, std::string_view file) : in_(text, file, true), file_(file), mesh_(file) {}

    TriangleMesh read(ReadReport& report) {
        while (in_.skip_empty_lines()) {
            const std::string_view keyword = in_.token();
            if (keyword == "v") {
                read_vertex();
            } else if (keyword == "f" || keyword == "fo") {
                read_face();
            } else if (std::any_of(keyword.begin(), keyword.end(), is_control)) {
                // Unknown keywords are skipped, but a binary file is not an OBJ file without faces.
                in_.fail("binary data, not an OBJ statement: " + quoted(keyword));
            } else if (foreign_line_ == 0 && !is_obj_keyword(keyword)) {
                foreign_line_ = in_.line();
                foreign_keyword_ = quoted(keyword);
            }
            in_.next_line();  // also skips `w`, vertex colors and every other keyword
        }
        // Text without a vertex is an empty mesh when its lines are OBJ's (an empty export:
        // comments, groups, materials); with other lines, it is another format.
        if (foreign_line_ > 0 && mesh_.num_vertices() == 0)
            throw_at_line(file_, foreign_line_, "no vertex in the file, and " + foreign_keyword_ + " is not an OBJ statement");
        check_forward_indices();
        TriangleMesh mesh = mesh_.finish(report);
        report.skipped_line_faces = skipped_line_faces_;
        return mesh;
    }

private:
    // The statements of the OBJ specification, and comments.
    static bool is_obj_keyword(std::string_view keyword) {
        static constexpr std::string_view kKeywords[] = {
            "v", "vt", "vn", "vp", "f", "fo", "l", "p", "g", "o", "s", "mg", "mtllib", "usemtl", "maplib",
            "usemap", "cstype", "deg", "bmat", "step", "curv", "curv2", "surf", "parm", "trim", "hole", "scrv",
            "sp", "end", "con", "bevel", "c_interp", "d_interp", "lod", "shadow_obj", "trace_obj", "ctech",
            "stech", "call", "csh"};
        return keyword.starts_with('#') ||
               std::find(std::begin(kKeywords), std::end(kKeywords), keyword) != std::end(kKeywords);
    }

    static bool is_control(char c) {
        const auto byte = static_cast<unsigned char>(c);
        return byte < 0x20 || byte == 0x7f;
    }

    void read_vertex() {
        const double x = in_.read_double("vertex x coordinate");
        const double y = in_.read_double("vertex y coordinate");
        const double z = in_.read_double("vertex z coordinate");
        mesh_.add_vertex(x, y, z);
    }

    void read_face() {
        corners_.clear();
        for (;;) {
            in_.skip_blanks();
            if (in_.at_line_end()) break;
            corners_.push_back(vertex_index(in_.token()));
        }
        if (corners_.empty()) in_.fail("face with 0 corners (needs 3 or more)");
        if (!mesh_.add_face(corners_)) ++skipped_line_faces_;
    }

    // The 0-based vertex of one corner token "v[/vt][/vn]".
    int vertex_index(std::string_view token) {
        long long index = 0;
        const std::size_t used = in_.parse_integer_prefix(token, index);
        if (used == 0 || (used < token.size() && token[used] != '/')) {
            in_.fail("bad face corner " + quoted(token));
        }
        const long long defined = mesh_.num_vertices();
        if (index == 0) in_.fail("vertex index 0 (OBJ indices start at 1)");
        if (index < 0) {
            if (-index > defined) {
                in_.fail("relative vertex index " + std::to_string(index) + " reaches before the first vertex (" +
                         std::to_string(defined) + " defined so far)");
            }
            return static_cast<int>(defined + index);
        }
        if (index > INT_MAX) in_.fail("vertex index " + std::to_string(index) + " out of range");
        if (index > max_index_) {
            max_index_ = index;
            max_index_line_ = in_.line();
        }
        return static_cast<int>(index - 1);
    }

    void check_forward_indices() const {
        const long long defined = mesh_.num_vertices();
        if (max_index_ > defined) {
            throw_at_line(file_, max_index_line_,
                          "vertex index " + std::to_string(max_index_) + " out of range (the file has " +
                              std::to_string(defined) + " vertices)");
        }
    }

    TextScanner in_;
    std::string_view file_;
    MeshBuilder mesh_;
    std::vector<int> corners_;    // reused for every face
    long long max_index_ = 0;     // largest positive index seen, and where
    long long max_index_line_ = 0;
    long long skipped_line_faces_ = 0;
    long long foreign_line_ = 0;  // the first line whose keyword OBJ does not have, and that keyword
    std::string foreign_keyword_;
};

}  // namespace

TriangleMesh parse_obj(std::string_view text, std::string_view file, ReadReport& report) {
    return ObjReader(text, file).read(report);
}

void write_obj(const TriangleMesh& mesh, OutputFile& out) {
    // Also keeps the file of an empty mesh non-empty (an empty file is a read error).
    out.write("# written by sdmesh: ");
    out.write_text(static_cast<long long>(mesh.V.rows()));
    out.write(" vertices, ");
    out.write_text(static_cast<long long>(mesh.F.rows()));
    out.write(" triangles\n");
    for (Eigen::Index v = 0; v < mesh.V.rows(); ++v) {
        out.write("v");
        for (int k = 0; k < 3; ++k) {
            out.put(' ');
            out.write_text(mesh.V(v, k));
        }
        out.put('\n');
    }
    for (Eigen::Index f = 0; f < mesh.F.rows(); ++f) {
        out.write("f");
        for (int k = 0; k < 3; ++k) {
            out.put(' ');
            out.write_text(static_cast<long long>(mesh.F(f, k)) + 1);
        }
        out.put('\n');
    }
}

}  // namespace sdmesh::io
