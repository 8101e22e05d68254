// Stanford PLY: ascii, binary_little_endian and binary_big_endian.
//
// The header declares elements, each a count of records made of scalar and list properties.
// Only `vertex` (its x, y, z) and `face` (its vertex_indices or vertex_index list) are read;
// every other element and property is skipped, lists included, which in binary means walking
// each record. One record reader, templated on the value source (text or binary), serves all
// three encodings. Header counts are checked against the bytes left before anything is
// allocated for them.

#include <climits>
#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "io/binary_reader.hpp"
#include "io/formats.hpp"
#include "io/mesh_builder.hpp"
#include "io/text_scanner.hpp"
#include "number_text.hpp"
#include "sdmesh/error.hpp"

namespace sdmesh::io {
namespace {

// ---- types -----------------------------------------------------------------------------------

enum class PlyType { int8, uint8, int16, uint16, int32, uint32, float32, float64 };

std::optional<PlyType> type_from_name(std::string_view name) {
    struct Entry {
        std::string_view name;
        PlyType type;
    };
    static constexpr Entry kNames[] = {
        {"char", PlyType::int8},      {"int8", PlyType::int8},       {"uchar", PlyType::uint8},
        {"uint8", PlyType::uint8},    {"short", PlyType::int16},     {"int16", PlyType::int16},
        {"ushort", PlyType::uint16},  {"uint16", PlyType::uint16},   {"int", PlyType::int32},
        {"int32", PlyType::int32},    {"uint", PlyType::uint32},     {"uint32", PlyType::uint32},
        {"float", PlyType::float32},  {"float32", PlyType::float32}, {"double", PlyType::float64},
        {"float64", PlyType::float64}};
    for (const Entry& entry : kNames) {
        if (entry.name == name) return entry.type;
    }
    return std::nullopt;
}

std::size_t size_of(PlyType type) {
    switch (type) {
        case PlyType::int8:
        case PlyType::uint8: return 1;
        case PlyType::int16:
        case PlyType::uint16: return 2;
        case PlyType::int32:
        case PlyType::uint32:
        case PlyType::float32: return 4;
        case PlyType::float64: return 8;
    }
    return 8;
}

bool is_integral(PlyType type) { return type != PlyType::float32 && type != PlyType::float64; }

// The range of an integral type, to check ascii values against their declared type.
bool fits(long long value, PlyType type) {
    switch (type) {
        case PlyType::int8: return value >= INT8_MIN && value <= INT8_MAX;
        case PlyType::uint8: return value >= 0 && value <= UINT8_MAX;
        case PlyType::int16: return value >= INT16_MIN && value <= INT16_MAX;
        case PlyType::uint16: return value >= 0 && value <= UINT16_MAX;
        case PlyType::int32: return value >= INT32_MIN && value <= INT32_MAX;
        case PlyType::uint32: return value >= 0 && value <= UINT32_MAX;
        case PlyType::float32:
        case PlyType::float64: return true;
    }
    return true;
}

// ---- header ----------------------------------------------------------------------------------

struct PlyProperty {
    std::string name;
    PlyType type = PlyType::float32;  // of the value, or of the items of a list
    bool is_list = false;
    PlyType count_type = PlyType::uint8;  // lists only
    int slot = -1;  // kept as: 0, 1, 2 = x, y, z of a vertex; 0 = the corners of a face
};

enum class ElementRole { skipped, vertex, face };

struct PlyElement {
    std::string name;
    long long count = 0;
    std::vector<PlyProperty> properties;
    long long line = 0;  // of its declaration, for errors found after the header
    ElementRole role = ElementRole::skipped;
};

enum class PlyEncoding { ascii, binary_little_endian, binary_big_endian };

struct PlyHeader {
    PlyEncoding encoding = PlyEncoding::ascii;
    std::vector<PlyElement> elements;
    long long vertex_count = 0;
};

PlyType type_named(std::string_view name, const TextScanner& in) {
    const std::optional<PlyType> type = type_from_name(name);
    if (!type) in.fail("unknown PLY property type " + quoted(name));
    return *type;
}

void read_format(TextScanner& in, std::string_view file, PlyHeader& header) {
    const std::string_view encoding = in.token();
    if (encoding == "ascii") {
        header.encoding = PlyEncoding::ascii;
    } else if (encoding == "binary_little_endian") {
        header.encoding = PlyEncoding::binary_little_endian;
    } else if (encoding == "binary_big_endian") {
        header.encoding = PlyEncoding::binary_big_endian;
    } else {
        throw UnsupportedFormatError(std::string(file) + ":" + std::to_string(in.line()) +
                                     ": PLY format " + quoted(encoding) + " is not supported");
    }
    in.token();  // the version, "1.0"
}

void read_element(TextScanner& in, PlyHeader& header) {
    PlyElement element;
    element.name = in.token();
    if (element.name.empty()) in.fail("element without a name");
    element.count = in.read_integer("element count");
    if (element.count < 0) in.fail("negative element count " + std::to_string(element.count));
    element.line = in.line();
    header.elements.push_back(std::move(element));
}

void read_property(TextScanner& in, PlyHeader& header) {
    if (header.elements.empty()) in.fail("property declared before any element");
    PlyProperty property;
    const std::string_view first = in.token();
    if (first == "list") {
        property.is_list = true;
        property.count_type = type_named(in.token(), in);
        if (!is_integral(property.count_type)) in.fail("a list count must have an integer type");
        property.type = type_named(in.token(), in);
    } else {
        property.type = type_named(first, in);
    }
    property.name = in.token();
    if (property.name.empty()) in.fail("property without a name");
    header.elements.back().properties.push_back(std::move(property));
}

// Reads the header lines and leaves `in` at the first byte of the body.
PlyHeader read_header_lines(TextScanner& in, std::string_view file) {
    if (in.token() != "ply") in.fail("not a PLY file (the first line must be 'ply')");
    in.finish_line();
    PlyHeader header;
    bool has_format = false;
    for (;;) {
        if (in.at_end()) in.fail("file ends before 'end_header'");
        const std::string_view keyword = in.token();
        if (keyword == "comment" || keyword == "obj_info") {
            in.next_line();
            continue;
        }
        if (keyword == "format") {
            read_format(in, file, header);
            has_format = true;
        } else if (keyword == "element") {
            read_element(in, header);
        } else if (keyword == "property") {
            read_property(in, header);
        } else if (keyword != "end_header" && !keyword.empty()) {
            in.fail("unknown PLY header keyword " + quoted(keyword));
        }
        in.finish_line();
        if (keyword == "end_header") break;
    }
    if (!has_format) in.fail("PLY header without a 'format' line");
    return header;
}

void assign_vertex_role(PlyElement& element, std::string_view file, PlyHeader& header) {
    if (element.count > INT_MAX) throw_at_line(file, element.line, "too many vertices for int indices");
    element.role = ElementRole::vertex;
    header.vertex_count = element.count;
    int found = 0;
    for (PlyProperty& property : element.properties) {
        if (property.is_list || property.name.size() != 1) continue;
        const int slot = property.name[0] - 'x';
        if (slot >= 0 && slot < 3) {
            property.slot = slot;
            ++found;
        }
    }
    if (found != 3) throw_at_line(file, element.line, "the vertex element needs scalar properties x, y and z");
}

void assign_face_role(PlyElement& element, std::string_view file) {
    element.role = ElementRole::face;
    for (PlyProperty& property : element.properties) {
        if (property.is_list && (property.name == "vertex_indices" || property.name == "vertex_index")) {
            property.slot = 0;
            return;
        }
    }
    throw_at_line(file, element.line, "the face element has no list 'vertex_indices' or 'vertex_index'");
}

// Marks the vertex and face elements and, in them, the properties the reader keeps.
void assign_roles(PlyHeader& header, std::string_view file) {
    bool has_vertices = false;
    bool has_faces = false;
    for (PlyElement& element : header.elements) {
        if (element.name == "tristrips") {
            // Skipping it would silently drop every face of the file.
            throw UnsupportedFormatError(std::string(file) + ":" + std::to_string(element.line) +
                                         ": PLY triangle strips ('tristrips') are not supported");
        }
        const bool is_vertex = element.name == "vertex";
        const bool is_face = element.name == "face";
        if ((is_vertex && has_vertices) || (is_face && has_faces)) {
            throw_at_line(file, element.line, "a second '" + element.name + "' element");
        }
        if (is_vertex) assign_vertex_role(element, file, header);
        if (is_face) assign_face_role(element, file);
        has_vertices |= is_vertex;
        has_faces |= is_face;
    }
    if (!has_vertices) throw_at_line(file, 1, "PLY file without a 'vertex' element");
}

// ---- value sources ---------------------------------------------------------------------------
// Both give: begin_record / end_record, number(type), integer(type) for integral types,
// skip(type, n), remaining(), min_value_bytes(type), fail(what).

class BinarySource {
public:
    BinarySource(std::string_view body, ByteOrder order, std::string_view file)
        : in_(body, order, file) {}

    void begin_record(std::string_view element, long long index) { in_.set_location(element, index); }
    void end_record() {}

    double number(PlyType type) { return read_as<double>(type); }
    long long integer(PlyType type) { return read_as<long long>(type); }
    void skip(PlyType type, long long n) { in_.skip(size_of(type) * static_cast<std::size_t>(n)); }

    [[nodiscard]] std::size_t remaining() const { return in_.remaining(); }
    static std::size_t min_value_bytes(PlyType type) { return size_of(type); }
    [[noreturn]] void fail(std::string_view what) const { in_.fail(what); }

private:
    template <class T>
    T read_as(PlyType type) {
        switch (type) {
            case PlyType::int8: return static_cast<T>(in_.read<std::int8_t>());
            case PlyType::uint8: return static_cast<T>(in_.read<std::uint8_t>());
            case PlyType::int16: return static_cast<T>(in_.read<std::int16_t>());
            case PlyType::uint16: return static_cast<T>(in_.read<std::uint16_t>());
            case PlyType::int32: return static_cast<T>(in_.read<std::int32_t>());
            case PlyType::uint32: return static_cast<T>(in_.read<std::uint32_t>());
            case PlyType::float32: return static_cast<T>(in_.read<float>());
            case PlyType::float64: return static_cast<T>(in_.read<double>());
        }
        return T{};
    }

    BinaryReader in_;
};

class AsciiSource {
public:
    explicit AsciiSource(TextScanner& in) : in_(in) {}

    // One record per line (blank lines between records are tolerated).
    void begin_record(std::string_view element, long long index) {
        in_.set_location(element, index);
        if (!in_.skip_empty_lines()) fail("file ends before this record");
    }
    void end_record() {
        in_.skip_blanks();
        if (!in_.at_line_end()) fail("more values than the header declares: " + quoted(in_.token()));
        in_.next_line();
    }

    double number(PlyType type) {
        if (is_integral(type)) return static_cast<double>(integer(type));
        return in_.read_double("a number");
    }
    long long integer(PlyType type) {
        const long long value = in_.read_integer("an integer");
        if (!fits(value, type)) fail("value " + std::to_string(value) + " out of range of its type");
        return value;
    }
    void skip(PlyType, long long n) {
        for (long long i = 0; i < n; ++i) {
            if (in_.token().empty()) fail("fewer values than the header declares");
        }
    }

    [[nodiscard]] std::size_t remaining() const { return in_.remaining(); }
    // A value takes at least one character and one separator.
    static std::size_t min_value_bytes(PlyType) { return 2; }
    [[noreturn]] void fail(std::string_view what) const { in_.fail(what); }

private:
    TextScanner& in_;
};

// ---- body ------------------------------------------------------------------------------------

template <class Source>
class BodyReader {
public:
    BodyReader(Source& source, long long vertex_count, MeshBuilder& mesh)
        : in_(source), vertex_count_(vertex_count), mesh_(mesh) {}

    void read_element(const PlyElement& element) {
        if (element.properties.empty()) return;  // nothing to read, however large the count
        check_capacity(element);
        if (element.role == ElementRole::vertex) mesh_.reserve_vertices(static_cast<std::size_t>(element.count));
        if (element.role == ElementRole::face) mesh_.reserve_triangles(static_cast<std::size_t>(element.count));
        for (long long i = 0; i < element.count; ++i) {
            in_.begin_record(element.name, i);
            switch (element.role) {
                case ElementRole::vertex: read_vertex(element); break;
                case ElementRole::face: read_face(element); break;
                case ElementRole::skipped:
                    for (const PlyProperty& property : element.properties) skip_property(property);
                    break;
            }
            in_.end_record();
        }
    }

private:
    // A header count the remaining bytes cannot hold is an error now, not an allocation.
    void check_capacity(const PlyElement& element) {
        std::size_t min_record = 0;
        for (const PlyProperty& property : element.properties) {
            min_record += in_.min_value_bytes(property.is_list ? property.count_type : property.type);
        }
        const std::size_t max_records = (in_.remaining() + 1) / min_record;
        if (static_cast<unsigned long long>(element.count) > max_records) {
            in_.begin_record(element.name, 0);
            in_.fail("truncated: the header declares " + std::to_string(element.count) + " '" + element.name +
                     "' records, the " + std::to_string(in_.remaining()) + " bytes left hold at most " +
                     std::to_string(max_records));
        }
    }

    void read_vertex(const PlyElement& element) {
        double xyz[3] = {0, 0, 0};
        for (const PlyProperty& property : element.properties) {
            if (property.slot >= 0) {
                xyz[property.slot] = in_.number(property.type);
            } else {
                skip_property(property);
            }
        }
        mesh_.add_vertex(xyz[0], xyz[1], xyz[2]);
    }

    void read_face(const PlyElement& element) {
        for (const PlyProperty& property : element.properties) {
            if (property.slot < 0) {
                skip_property(property);
                continue;
            }
            const long long n = read_list_count(property);
            corners_.clear();
            for (long long k = 0; k < n; ++k) corners_.push_back(read_vertex_index(property.type));
            if (!mesh_.add_face(corners_)) {
                in_.fail("face with " + std::to_string(n) + " corners (needs 3 or more)");
            }
        }
    }

    int read_vertex_index(PlyType type) {
        const long long index = read_integer(type);
        if (index < 0 || index >= vertex_count_) {
            in_.fail("vertex index " + std::to_string(index) + " out of range [0, " +
                     std::to_string(vertex_count_) + ")");
        }
        return static_cast<int>(index);
    }

    // An integer stored with any type; a float type must hold an integral value.
    long long read_integer(PlyType type) {
        if (is_integral(type)) return in_.integer(type);
        const double value = in_.number(type);
        if (!(std::abs(value) < 0x1p62) || value != std::trunc(value)) {
            in_.fail("expected an integer, found " + detail::number_text(value));
        }
        return static_cast<long long>(value);
    }

    // The length of a list, checked against the bytes left before anything is read for it.
    long long read_list_count(const PlyProperty& property) {
        const long long n = in_.integer(property.count_type);
        if (n < 0) in_.fail("negative list length " + std::to_string(n));
        if (static_cast<unsigned long long>(n) > in_.remaining() / in_.min_value_bytes(property.type)) {
            in_.fail("list length " + std::to_string(n) + " exceeds the " + std::to_string(in_.remaining()) +
                     " bytes left in the file");
        }
        return n;
    }

    void skip_property(const PlyProperty& property) {
        in_.skip(property.type, property.is_list ? read_list_count(property) : 1);
    }

    Source& in_;
    long long vertex_count_;
    MeshBuilder& mesh_;
    std::vector<int> corners_;  // reused for every face
};

template <class Source>
TriangleMesh read_body(Source& source, const PlyHeader& header, std::string_view file, ReadReport& report) {
    MeshBuilder mesh(file);
    BodyReader<Source> body(source, header.vertex_count, mesh);
    for (const PlyElement& element : header.elements) body.read_element(element);
    return mesh.finish(report);
}

}  // namespace

TriangleMesh parse_ply(std::string_view bytes, std::string_view file, ReadReport& report) {
    TextScanner text(bytes, file, false);
    PlyHeader header = read_header_lines(text, file);
    assign_roles(header, file);
    if (header.encoding == PlyEncoding::ascii) {
        AsciiSource source(text);
        return read_body(source, header, file, report);
    }
    const std::string_view body = bytes.substr(static_cast<std::size_t>(text.position() - bytes.data()));
    const ByteOrder order =
        header.encoding == PlyEncoding::binary_little_endian ? ByteOrder::little : ByteOrder::big;
    BinarySource source(body, order, file);
    return read_body(source, header, file, report);
}

// ---- writing ---------------------------------------------------------------------------------

namespace {

void write_header(const TriangleMesh& mesh, std::span<const VertexField> fields, bool ascii,
                  OutputFile& out) {
    out.write(ascii ? "ply\nformat ascii 1.0\n" : "ply\nformat binary_little_endian 1.0\n");
    out.write("comment written by sdmesh\nelement vertex ");
    out.write_text(static_cast<long long>(mesh.V.rows()));
    out.write("\nproperty double x\nproperty double y\nproperty double z\n");
    for (const VertexField& field : fields) {
        out.write("property double ");
        out.write(field.name);
        out.put('\n');
    }
    out.write("element face ");
    out.write_text(static_cast<long long>(mesh.F.rows()));
    out.write("\nproperty list uchar int vertex_indices\nend_header\n");
}

// One value in the file's encoding; `first` = first value of its record (no separator).
void write_value(double value, bool ascii, bool first, OutputFile& out) {
    if (ascii) {
        if (!first) out.put(' ');
        out.write_text(value);
    } else {
        out.write_little_endian(value);
    }
}

void write_value(int value, bool ascii, bool first, OutputFile& out) {
    if (ascii) {
        if (!first) out.put(' ');
        out.write_text(static_cast<long long>(value));
    } else {
        out.write_little_endian(static_cast<std::int32_t>(value));
    }
}

}  // namespace

void write_ply(const TriangleMesh& mesh, std::span<const VertexField> fields, bool ascii,
               OutputFile& out) {
    write_header(mesh, fields, ascii, out);
    for (Eigen::Index v = 0; v < mesh.V.rows(); ++v) {
        for (int k = 0; k < 3; ++k) write_value(mesh.V(v, k), ascii, k == 0, out);
        for (const VertexField& field : fields) write_value(field.values[v], ascii, false, out);
        if (ascii) out.put('\n');
    }
    for (Eigen::Index f = 0; f < mesh.F.rows(); ++f) {
        if (ascii) {
            out.put('3');
        } else {
            out.write_little_endian(std::uint8_t{3});
        }
        for (int k = 0; k < 3; ++k) write_value(mesh.F(f, k), ascii, false, out);
        if (ascii) out.put('\n');
    }
}

}  // namespace sdmesh::io
