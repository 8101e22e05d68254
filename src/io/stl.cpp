// STL, ascii and binary: a soup of facets, three corners each, which are welded into shared
// vertices by exact position.
//
// Binary: an 80-byte header, a uint32 facet count n, then n records of 50 bytes (normal, three
// float corners, a 2-byte attribute), little endian. A file is binary exactly when its size is
// 84 + 50 n; otherwise it is ascii if it starts with "solid" and has no NUL byte (binary headers
// often start with "solid" too, hence the size test first; a binary file whose count is wrong
// still has NULs, and is reported as binary rather than read as an ascii file of no facets).
// Normals are ignored: they are often wrong, and the corner order defines the orientation.

#include <algorithm>
#include <array>
#include <bit>
#include <cctype>
#include <cstdint>
#include <string>
#include <unordered_map>
#include <vector>

#include "io/binary_reader.hpp"
#include "io/formats.hpp"
#include "io/mesh_builder.hpp"
#include "io/text_scanner.hpp"
#include "sdmesh/error.hpp"

namespace sdmesh::io {
namespace {

constexpr std::size_t kHeaderBytes = 84;
constexpr std::size_t kFacetBytes = 50;

// Merges corners at exactly the same position into one vertex, numbered in order of first
// appearance so that reading is deterministic.
class VertexWelder {
public:
    explicit VertexWelder(MeshBuilder& mesh) : mesh_(mesh) {}

    void reserve(std::size_t corners) { ids_.reserve(corners / 4); }

    int vertex(double x, double y, double z) {
        ++corners_;
        // +0.0 turns -0.0 into 0.0 so the two weld; other values are compared bit for bit (so a
        // NaN corner welds only with the very same NaN).
        const Key key{std::bit_cast<std::uint64_t>(x + 0.0), std::bit_cast<std::uint64_t>(y + 0.0),
                      std::bit_cast<std::uint64_t>(z + 0.0)};
        const auto [it, inserted] = ids_.try_emplace(key, static_cast<int>(ids_.size()));
        if (inserted) {
            mesh_.take(kTableBytesPerVertex);
            mesh_.add_vertex(x + 0.0, y + 0.0, z + 0.0);
        }
        return it->second;
    }

    [[nodiscard]] long long corners() const { return corners_; }
    [[nodiscard]] long long welded() const { return corners_ - static_cast<long long>(ids_.size()); }

private:
    using Key = std::array<std::uint64_t, 3>;
    // A node of ids_ (link, key, id, cached hash: 64 bytes with malloc's header) and its bucket.
    static constexpr std::size_t kTableBytesPerVertex = 72;
    struct KeyHash {
        std::size_t operator()(const Key& key) const {
            std::uint64_t h = key[0];
            h = (h ^ (h >> 29)) * 0xbf58476d1ce4e5b9ULL + key[1];
            h = (h ^ (h >> 31)) * 0x94d049bb133111ebULL + key[2];
            return static_cast<std::size_t>(h ^ (h >> 32));
        }
    };

    MeshBuilder& mesh_;
    std::unordered_map<Key, int, KeyHash> ids_;
    long long corners_ = 0;
};

bool starts_with_solid(std::string_view bytes) {
    bytes = without_utf8_bom(bytes);
    const auto first = bytes.find_first_not_of(" \t\r\n");
    if (first == std::string_view::npos || bytes.size() - first < 5) return false;
    std::string word(bytes.substr(first, 5));
    std::transform(word.begin(), word.end(), word.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return word == "solid";
}

std::uint32_t binary_facet_count(std::string_view bytes) {
    BinaryReader in(bytes.substr(80, 4), ByteOrder::little, "");
    return in.read<std::uint32_t>();
}

void parse_binary(std::string_view bytes, std::string_view file, MeshBuilder& mesh, VertexWelder& welder) {
    auto fail = [&](const std::string& what) { throw ParseError(std::string(file) + ": " + what); };
    if (bytes.size() < kHeaderBytes) {
        fail("file too short for a binary STL (" + std::to_string(bytes.size()) +
             " bytes) and not ascii ('solid' at the start, no NUL byte)");
    }
    const std::uint32_t n = binary_facet_count(bytes);
    const std::size_t expected = kHeaderBytes + kFacetBytes * std::size_t{n};
    // A binary STL's floats hold control bytes; a text file of another format has none.
    if (bytes.size() != expected && std::none_of(bytes.begin(), bytes.end(), [](char c) {
            const auto byte = static_cast<unsigned char>(c);
            return (byte < 0x20 && !std::isspace(byte)) || byte == 0x7f;
        })) {
        fail("text that does not start with 'solid': neither an ascii nor a binary STL");
    }
    if (bytes.size() > expected) {
        fail("the binary STL header declares " + std::to_string(n) + " facets (" +
             std::to_string(expected) + " bytes) but the file has " + std::to_string(bytes.size()) +
             " bytes");
    }
    BinaryReader in(bytes.substr(kHeaderBytes), ByteOrder::little, file);
    // Sizes match unless the file is truncated, which the reader reports at the facet concerned.
    welder.reserve(3 * std::min<std::size_t>(n, bytes.size() / kFacetBytes));
    mesh.reserve_triangles(std::min<std::size_t>(n, bytes.size() / kFacetBytes));
    int corners[3];
    for (std::uint32_t f = 0; f < n; ++f) {
        in.set_location("facet", f);
        in.skip(12);  // normal
        for (int& corner : corners) {
            const float x = in.read<float>();
            const float y = in.read<float>();
            const float z = in.read<float>();
            corner = welder.vertex(x, y, z);
        }
        in.skip(2);  // attribute byte count
        (void)mesh.add_face(corners);  // always 3 corners
    }
}

bool is_keyword(std::string_view token, std::string_view keyword) {
    return token.size() == keyword.size() &&
           std::equal(token.begin(), token.end(), keyword.begin(), [](char a, char b) {
               return std::tolower(static_cast<unsigned char>(a)) == b;
           });
}

// solid name / facet normal n n n / outer loop / vertex x y z (3 or more) / endloop / endfacet /
// ... / endsolid name. Keywords in any case; facets of more than 3 corners are triangulated as polygons.
void parse_ascii(std::string_view text, std::string_view file, MeshBuilder& mesh, VertexWelder& welder) {
    TextScanner in(text, file, false);
    std::vector<int> corners;
    bool in_facet = false;
    while (in.skip_empty_lines()) {
        const std::string_view keyword = in.token();
        if (is_keyword(keyword, "facet")) {
            if (in_facet) in.fail("'facet' inside a facet");
            in_facet = true;
            corners.clear();
        } else if (is_keyword(keyword, "vertex")) {
            if (!in_facet) in.fail("'vertex' outside a facet");
            const double x = in.read_double("vertex x coordinate");
            const double y = in.read_double("vertex y coordinate");
            const double z = in.read_double("vertex z coordinate");
            corners.push_back(welder.vertex(x, y, z));
        } else if (is_keyword(keyword, "endfacet")) {
            if (!in_facet) in.fail("'endfacet' outside a facet");
            if (!mesh.add_face(corners)) {
                in.fail("facet with " + std::to_string(corners.size()) + " corners (needs 3 or more)");
            }
            in_facet = false;
        } else if (!is_keyword(keyword, "solid") && !is_keyword(keyword, "endsolid") &&
                   !is_keyword(keyword, "outer") && !is_keyword(keyword, "endloop")) {
            in.fail("unexpected " + quoted(keyword) + " in an ascii STL file");
        }
        in.next_line();  // solid names, normals, "loop"
    }
    if (in_facet) in.fail("file ends inside a facet");
}

bool is_binary(std::string_view bytes) {
    return bytes.size() >= kHeaderBytes &&
           bytes.size() == kHeaderBytes + kFacetBytes * std::size_t{binary_facet_count(bytes)};
}

}  // namespace

TriangleMesh parse_stl(std::string_view bytes, std::string_view file, ReadReport& report) {
    MeshBuilder mesh(file);
    VertexWelder welder(mesh);
    const bool ascii = !is_binary(bytes) && starts_with_solid(bytes) &&
                       bytes.find('\0') == std::string_view::npos;
    if (ascii) {
        parse_ascii(bytes, file, mesh, welder);
    } else {
        parse_binary(bytes, file, mesh, welder);
    }
    TriangleMesh result = mesh.finish(report);
    report.file_vertices = welder.corners();
    report.welded_vertices = welder.welded();
    return result;
}

}  // namespace sdmesh::io
