// Tests of mesh reading and writing (io.hpp): bit-exact round trips, every accepted variant of
// each format, and the exception type of every malformed input. Meshes are written in code; the
// real corpus (SDMESH_CORPUS_DIR) is read when present.

#include <gtest/gtest.h>
#include <zlib.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <bit>
#include <cfloat>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <functional>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

#include <Eigen/Geometry>

#include "io/gzip.hpp"
#include "io/memory_budget.hpp"
#include "io/mesh_builder.hpp"
#include "io/whole_file.hpp"
#include "sdmesh/error.hpp"
#include "sdmesh/io.hpp"

namespace fs = std::filesystem;
using namespace sdmesh;

namespace {

// ---- helpers ---------------------------------------------------------------------------------

// A fresh folder per test, removed afterwards.
class TempDir {
public:
    TempDir() {
        static int counter = 0;
        path_ = fs::temp_directory_path() /
                ("sdmesh_test_io_" + std::to_string(::getpid()) + "_" + std::to_string(counter++));
        fs::remove_all(path_);
        fs::create_directories(path_);
    }
    ~TempDir() {
        std::error_code ec;
        fs::remove_all(path_, ec);
    }
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;

    [[nodiscard]] fs::path operator/(const std::string& name) const { return path_ / name; }
    [[nodiscard]] const fs::path& path() const { return path_; }

    // Names of everything in the folder, sorted.
    [[nodiscard]] std::vector<std::string> entries() const {
        std::vector<std::string> names;
        for (const auto& entry : fs::directory_iterator(path_)) names.push_back(entry.path().filename().string());
        std::sort(names.begin(), names.end());
        return names;
    }

private:
    fs::path path_;
};

void write_bytes(const fs::path& path, const std::string& bytes) {
    std::ofstream out(path, std::ios::binary);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

std::string read_bytes(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void write_gzip(const fs::path& path, const std::string& bytes) {
    gzFile file = gzopen(path.string().c_str(), "wb");
    ASSERT_NE(file, nullptr);
    if (!bytes.empty()) {
        ASSERT_GT(gzwrite(file, bytes.data(), static_cast<unsigned>(bytes.size())), 0);
    }
    ASSERT_EQ(gzclose(file), Z_OK);
}

WriteOptions ply_options(bool ascii) {
    WriteOptions options;
    options.ply_ascii = ascii;
    return options;
}

TriangleMesh parse(const std::string& text, MeshFormat format, ReadReport* report = nullptr) {
    return parse_mesh(text, format, "test", report);
}

// The message of the ParseError thrown by parsing `text` (empty and a test failure if none).
std::string parse_error_message(const std::string& text, MeshFormat format) {
    try {
        parse(text, format);
    } catch (const ParseError& e) {
        return e.what();
    } catch (const std::exception& e) {
        ADD_FAILURE() << "expected ParseError, got: " << e.what();
        return {};
    }
    ADD_FAILURE() << "expected ParseError, nothing thrown for:\n" << text.substr(0, 300);
    return {};
}

// Expects a ParseError whose message contains `where` (e.g. "test:3:") and `what`.
void expect_parse_error(const std::string& text, MeshFormat format, const std::string& where,
                        const std::string& what = "") {
    const std::string message = parse_error_message(text, format);
    EXPECT_NE(message.find(where), std::string::npos) << "message: " << message;
    EXPECT_NE(message.find(what), std::string::npos) << "message: " << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << "message is not one line: " << message;
}

Eigen::MatrixX3i faces(std::initializer_list<std::array<int, 3>> rows) {
    Eigen::MatrixX3i F(static_cast<Eigen::Index>(rows.size()), 3);
    Eigen::Index r = 0;
    for (const auto& row : rows) {
        F.row(r++) << row[0], row[1], row[2];
    }
    return F;
}

// Sizes first: Eigen's == asserts on a size mismatch.
template <class A, class B>
::testing::AssertionResult same_matrix(const A& a, const B& b) {
    if (a.rows() != b.rows() || a.cols() != b.cols()) {
        return ::testing::AssertionFailure() << "sizes " << a.rows() << "x" << a.cols() << " and " << b.rows()
                                             << "x" << b.cols() << " differ:\n" << a << "\nvs\n" << b;
    }
    if (!(a == b)) return ::testing::AssertionFailure() << "\n" << a << "\nvs\n" << b;
    return ::testing::AssertionSuccess();
}

bool same_bits(double a, double b) { return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b); }

void expect_same_mesh_bits(const TriangleMesh& expected, const TriangleMesh& actual) {
    ASSERT_EQ(expected.V.rows(), actual.V.rows());
    ASSERT_EQ(expected.F.rows(), actual.F.rows());
    for (Eigen::Index i = 0; i < expected.V.rows(); ++i) {
        for (int k = 0; k < 3; ++k) {
            ASSERT_TRUE(same_bits(expected.V(i, k), actual.V(i, k)))
                << "V(" << i << "," << k << "): wrote " << expected.V(i, k) << ", read " << actual.V(i, k);
        }
    }
    EXPECT_TRUE(same_matrix(expected.F, actual.F));
}

// Doubles that are hard to round-trip through text: signed zeros, denormals, extremes, values
// with no short decimal form, and random bit patterns.
TriangleMesh tricky_mesh() {
    std::vector<double> values = {0.0,     -0.0,     0.1,      -0.1,    1.0 / 3.0, 2.0 / 3.0,
                                  1e300,   -1e300,   1e-300,   DBL_MAX, -DBL_MAX,  DBL_MIN,
                                  -DBL_MIN, 4.9406564584124654e-324, 2.2250738585072009e-308,
                                  -5e-324, 123456789.123456789, 0.30000000000000004, 1e22, 9007199254740993.0};
    std::mt19937_64 rng(12345);
    while (values.size() < 3 * 64) {
        const double value = std::bit_cast<double>(rng());
        if (std::isfinite(value)) values.push_back(value);
    }
    TriangleMesh mesh;
    const auto n = static_cast<Eigen::Index>(values.size() / 3);
    mesh.V.resize(n, 3);
    for (Eigen::Index i = 0; i < n; ++i) {
        for (int k = 0; k < 3; ++k) mesh.V(i, k) = values[static_cast<std::size_t>(3 * i + k)];
    }
    std::uniform_int_distribution<int> index(0, static_cast<int>(n) - 1);
    mesh.F.resize(50, 3);
    for (Eigen::Index f = 0; f < mesh.F.rows(); ++f) {
        for (int k = 0; k < 3; ++k) mesh.F(f, k) = index(rng);
    }
    return mesh;
}

TriangleMesh two_triangles() {
    TriangleMesh mesh;
    mesh.V.resize(4, 3);
    mesh.V << 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0;
    mesh.F = faces({{0, 1, 2}, {0, 2, 3}});
    return mesh;
}

// Bytes of binary files in a chosen byte order.
class Bytes {
public:
    explicit Bytes(bool big_endian = false) : big_(big_endian) {}
    Bytes& text(const std::string& s) {
        data_ += s;
        return *this;
    }
    template <class T>
    Bytes& put(T value) {
        char raw[sizeof(T)];
        std::memcpy(raw, &value, sizeof(T));
        if (big_ == (std::endian::native == std::endian::little)) std::reverse(raw, raw + sizeof(T));
        data_.append(raw, sizeof(T));
        return *this;
    }
    [[nodiscard]] const std::string& str() const { return data_; }

private:
    bool big_;
    std::string data_;
};

// ---- format from path ------------------------------------------------------------------------

TEST(FormatFromPath, ExtensionsAreCaseInsensitiveAndGzIsCompression) {
    bool compressed = true;
    EXPECT_EQ(format_from_path("a/b.obj", &compressed), MeshFormat::obj);
    EXPECT_FALSE(compressed);
    EXPECT_EQ(format_from_path("x.PLY.gz", &compressed), MeshFormat::ply);
    EXPECT_TRUE(compressed);
    EXPECT_EQ(format_from_path("x.Off.GZ", &compressed), MeshFormat::off);
    EXPECT_TRUE(compressed);
    EXPECT_EQ(format_from_path("dir.stl/x.StL"), MeshFormat::stl);
    EXPECT_THROW(format_from_path("x.gz"), UnsupportedFormatError);
    EXPECT_THROW(format_from_path("x.obj.zip"), UnsupportedFormatError);
    EXPECT_THROW(format_from_path("obj"), UnsupportedFormatError);
    EXPECT_THROW(format_from_path("x.vtk"), UnsupportedFormatError);
}

// ---- round trips -----------------------------------------------------------------------------

struct RoundTripCase {
    std::string file_name;
    bool ply_ascii;
};

class RoundTrip : public ::testing::TestWithParam<RoundTripCase> {};

TEST_P(RoundTrip, GivesBackTheSameBits) {
    TempDir dir;
    const fs::path path = dir / GetParam().file_name;
    const TriangleMesh mesh = tricky_mesh();
    write_mesh(path, mesh, ply_options(GetParam().ply_ascii));
    ReadReport report;
    const TriangleMesh back = read_mesh(path, &report);
    expect_same_mesh_bits(mesh, back);
    EXPECT_EQ(report.compressed, path.extension() == ".gz");
    EXPECT_EQ(report.file_faces, mesh.F.rows());
    EXPECT_EQ(report.file_vertices, mesh.V.rows());
    EXPECT_EQ(report.polygons, 0);
    EXPECT_EQ(dir.entries(), std::vector<std::string>{GetParam().file_name});  // no temporary left
}

TEST_P(RoundTrip, EmptyMeshRoundTrips) {
    TempDir dir;
    const fs::path path = dir / GetParam().file_name;
    write_mesh(path, TriangleMesh{}, ply_options(GetParam().ply_ascii));
    const TriangleMesh back = read_mesh(path);
    EXPECT_EQ(back.num_vertices(), 0);
    EXPECT_EQ(back.num_faces(), 0);
}

TEST_P(RoundTrip, OverwritesAnExistingFile) {
    TempDir dir;
    const fs::path path = dir / GetParam().file_name;
    write_mesh(path, tricky_mesh(), ply_options(GetParam().ply_ascii));
    write_mesh(path, two_triangles(), ply_options(GetParam().ply_ascii));
    expect_same_mesh_bits(two_triangles(), read_mesh(path));
}

INSTANTIATE_TEST_SUITE_P(Formats, RoundTrip,
                         ::testing::Values(RoundTripCase{"m.obj", false}, RoundTripCase{"m.obj.gz", false},
                                           RoundTripCase{"m.off", false}, RoundTripCase{"m.off.gz", false},
                                           RoundTripCase{"m.ply", false}, RoundTripCase{"m.ply.gz", false},
                                           RoundTripCase{"m.ply", true}, RoundTripCase{"m.ply.gz", true},
                                           RoundTripCase{"M.OBJ", false}),
                         [](const auto& param_info) {
                             const RoundTripCase& c = param_info.param;
                             std::string name = c.file_name + (c.ply_ascii ? "_ascii" : "");
                             std::replace(name.begin(), name.end(), '.', '_');
                             return name;
                         });

TEST(RoundTrip, NonFiniteCoordinatesAreWrittenAndReadAsTheyAre) {
    TempDir dir;
    TriangleMesh mesh = two_triangles();
    mesh.V(0, 0) = std::numeric_limits<double>::quiet_NaN();
    mesh.V(1, 1) = std::numeric_limits<double>::infinity();
    mesh.V(2, 2) = -std::numeric_limits<double>::infinity();
    for (const std::string name : {"n.obj", "n.off", "n.ply"}) {
        for (bool ascii : {false, true}) {
            write_mesh(dir / name, mesh, ply_options(ascii));
            const TriangleMesh back = read_mesh(dir / name);
            EXPECT_TRUE(std::isnan(back.V(0, 0))) << name;
            EXPECT_EQ(back.V(1, 1), std::numeric_limits<double>::infinity()) << name;
            EXPECT_EQ(back.V(2, 2), -std::numeric_limits<double>::infinity()) << name;
        }
    }
}

// ---- PLY vertex fields -----------------------------------------------------------------------

// The header lines of a PLY file and the offset of its body.
std::vector<std::string> ply_header_lines(const std::string& bytes, std::size_t* body = nullptr) {
    const std::size_t end = bytes.find("end_header\n");
    EXPECT_NE(end, std::string::npos);
    if (body != nullptr) *body = end + std::strlen("end_header\n");
    std::vector<std::string> lines;
    std::istringstream in(bytes.substr(0, end));
    for (std::string line; std::getline(in, line);) lines.push_back(line);
    return lines;
}

TEST(PlyFields, BinaryFieldsAreDoublePropertiesAfterXyz) {
    TempDir dir;
    const TriangleMesh mesh = two_triangles();
    Eigen::VectorXd curvature(4), u(4);
    curvature << 0.1, -0.0, 1e-310, 7;
    u << 1, 2, 3, 4;
    write_mesh(dir / "f.ply", mesh, {.vertex_fields = {{"curvature", curvature}, {"_u1", u}}});

    std::size_t body = 0;
    const std::string bytes = read_bytes(dir / "f.ply");
    const std::vector<std::string> header = ply_header_lines(bytes, &body);
    const std::vector<std::string> expected_start = {
        "ply", "format binary_little_endian 1.0"};
    ASSERT_GE(header.size(), 2u);
    EXPECT_EQ(header[0], expected_start[0]);
    EXPECT_EQ(header[1], expected_start[1]);
    const auto property_x = std::find(header.begin(), header.end(), "property double x");
    ASSERT_NE(property_x, header.end());
    ASSERT_GE(header.end() - property_x, 5);
    EXPECT_EQ(property_x[1], "property double y");
    EXPECT_EQ(property_x[2], "property double z");
    EXPECT_EQ(property_x[3], "property double curvature");
    EXPECT_EQ(property_x[4], "property double _u1");
    EXPECT_NE(std::find(header.begin(), header.end(), "property list uchar int vertex_indices"), header.end());

    // Vertex records are 5 little-endian doubles: x y z curvature u.
    ASSERT_GE(bytes.size(), body + 4 * 5 * sizeof(double));
    for (int v = 0; v < 4; ++v) {
        double record[5];
        std::memcpy(record, bytes.data() + body + static_cast<std::size_t>(v) * sizeof record, sizeof record);
        if constexpr (std::endian::native == std::endian::little) {
            EXPECT_TRUE(same_bits(record[0], mesh.V(v, 0)));
            EXPECT_TRUE(same_bits(record[3], curvature[v])) << v;
            EXPECT_TRUE(same_bits(record[4], u[v])) << v;
        }
    }
    // Our own reader skips the extra properties.
    expect_same_mesh_bits(mesh, read_mesh(dir / "f.ply"));
}

TEST(PlyFields, AsciiFieldsAreWrittenPerVertexLine) {
    TempDir dir;
    const TriangleMesh mesh = two_triangles();
    Eigen::VectorXd field(4);
    field << 0.5, 1.5, 2.5, 3.5;
    write_mesh(dir / "f.ply", mesh, {.vertex_fields = {{"value", field}}, .ply_ascii = true});
    std::size_t body = 0;
    const std::string bytes = read_bytes(dir / "f.ply");
    const std::vector<std::string> header = ply_header_lines(bytes, &body);
    EXPECT_EQ(header[1], "format ascii 1.0");
    EXPECT_NE(std::find(header.begin(), header.end(), "property double value"), header.end());
    std::istringstream in(bytes.substr(body));
    for (int v = 0; v < 4; ++v) {
        double x, y, z, value;
        ASSERT_TRUE(in >> x >> y >> z >> value);
        EXPECT_EQ(value, field[v]);
    }
    expect_same_mesh_bits(mesh, read_mesh(dir / "f.ply"));
}

TEST(PlyFields, BadFieldsAreRejectedBeforeWriting) {
    TempDir dir;
    const TriangleMesh mesh = two_triangles();
    const Eigen::VectorXd good = Eigen::VectorXd::Zero(4);
    const Eigen::VectorXd too_short = Eigen::VectorXd::Zero(3);
    const std::vector<std::vector<VertexField>> bad = {
        {{"f", too_short}}, {{"x", good}},  {{"z", good}},     {{"", good}},
        {{"1abc", good}},   {{"a b", good}}, {{"a-b", good}},  {{"a", good}, {"a", good}},
    };
    for (const auto& fields : bad) {
        EXPECT_THROW(write_mesh(dir / "bad.ply", mesh, {.vertex_fields = fields}), InvalidArgumentError)
            << fields.back().name;
    }
    EXPECT_THROW(write_mesh(dir / "bad.obj", mesh, {.vertex_fields = {{"f", good}}}), InvalidArgumentError);
    EXPECT_THROW(write_mesh(dir / "bad.off", mesh, {.vertex_fields = {{"f", good}}}), InvalidArgumentError);
    EXPECT_TRUE(dir.entries().empty());
}

// ---- writing failures ------------------------------------------------------------------------

TEST(Write, FailedWriteLeavesTheExistingTargetUntouched) {
    TempDir dir;
    const fs::path path = dir / "keep.ply";
    write_mesh(path, two_triangles());
    const std::string before = read_bytes(path);
    EXPECT_THROW(write_mesh(path, tricky_mesh(), {.vertex_fields = {{"f", Eigen::VectorXd::Zero(3)}}}),
                 InvalidArgumentError);
    TriangleMesh bad_index = two_triangles();
    bad_index.F(1, 2) = 4;
    EXPECT_THROW(write_mesh(path, bad_index), InvalidArgumentError);
    bad_index.F(1, 2) = -1;
    EXPECT_THROW(write_mesh(path, bad_index), InvalidArgumentError);
    EXPECT_EQ(read_bytes(path), before);
    EXPECT_EQ(dir.entries(), std::vector<std::string>{"keep.ply"});
}

TEST(Write, MissingFolderIsIoErrorAndLeavesNothing) {
    TempDir dir;
    EXPECT_THROW(write_mesh(dir / "no" / "such" / "m.obj", two_triangles()), IoError);
    EXPECT_TRUE(dir.entries().empty());
}

TEST(Write, FailedRenameRemovesTheTemporary) {
    TempDir dir;
    // A non-empty folder cannot be replaced by a file.
    fs::create_directories(dir / "m.obj" / "inside");
    EXPECT_THROW(write_mesh(dir / "m.obj", two_triangles()), IoError);
    EXPECT_EQ(dir.entries(), std::vector<std::string>{"m.obj"});
    EXPECT_TRUE(fs::is_directory(dir / "m.obj"));
}

TEST(Write, StlAndUnknownExtensionsAreUnsupported) {
    TempDir dir;
    EXPECT_THROW(write_mesh(dir / "m.stl", two_triangles()), UnsupportedFormatError);
    EXPECT_THROW(write_mesh(dir / "m.stl.gz", two_triangles()), UnsupportedFormatError);
    EXPECT_THROW(write_mesh(dir / "m.vtk", two_triangles()), UnsupportedFormatError);
    EXPECT_TRUE(dir.entries().empty());
}

// ---- reading failures common to all formats --------------------------------------------------

TEST(Read, MissingFileIsIoError) {
    TempDir dir;
    for (const std::string name : {"none.obj", "none.off", "none.ply", "none.stl", "none.obj.gz"}) {
        EXPECT_THROW(read_mesh(dir / name), IoError) << name;
    }
    EXPECT_THROW(read_mesh(dir.path()), UnsupportedFormatError);  // no extension: checked first
    fs::create_directories(dir / "folder.obj");
    EXPECT_THROW(read_mesh(dir / "folder.obj"), IoError);
}

TEST(Read, UnknownExtensionIsUnsupported) {
    TempDir dir;
    write_bytes(dir / "m.vtk", "v 0 0 0\n");
    EXPECT_THROW(read_mesh(dir / "m.vtk"), UnsupportedFormatError);
}

TEST(Read, EmptyFileIsParseErrorInEveryFormat) {
    TempDir dir;
    for (const std::string name : {"e.obj", "e.off", "e.ply", "e.stl"}) {
        write_bytes(dir / name, "");
        EXPECT_THROW(read_mesh(dir / name), ParseError) << name;
        write_gzip(dir / (name + ".gz"), "");
        EXPECT_THROW(read_mesh(dir / (name + ".gz")), ParseError) << name << ".gz";
        write_bytes(dir / name, " \n\r\n\t");
        EXPECT_THROW(read_mesh(dir / name), ParseError) << name << " (blank)";
    }
}

TEST(Read, CorruptOrPlainGzipIsParseError) {
    TempDir dir;
    write_bytes(dir / "plain.obj.gz", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    EXPECT_THROW(read_mesh(dir / "plain.obj.gz"), ParseError);
    write_gzip(dir / "cut.obj.gz", std::string(100000, '#'));
    std::string bytes = read_bytes(dir / "cut.obj.gz");
    write_bytes(dir / "cut.obj.gz", bytes.substr(0, bytes.size() / 2));
    EXPECT_THROW(read_mesh(dir / "cut.obj.gz"), ParseError);
}

TEST(Read, ConcatenatedGzipMembersAreOneFile) {
    TempDir dir;
    write_gzip(dir / "a.gz", "v 0 0 0\nv 1 0 0\n");
    write_gzip(dir / "b.gz", "v 0 1 0\nf 1 2 3\n");
    write_bytes(dir / "ab.obj.gz", read_bytes(dir / "a.gz") + read_bytes(dir / "b.gz"));
    EXPECT_EQ(read_mesh(dir / "ab.obj.gz").num_faces(), 1);
    // Zero padding after the last member is ignored; anything else after it is not gzip data.
    write_bytes(dir / "padded.obj.gz", read_bytes(dir / "ab.obj.gz") + std::string(512, '\0'));
    EXPECT_EQ(read_mesh(dir / "padded.obj.gz").num_faces(), 1);
    write_bytes(dir / "junk.obj.gz", read_bytes(dir / "ab.obj.gz") + std::string(2, '\0') + "junk");
    EXPECT_THROW(read_mesh(dir / "junk.obj.gz"), ParseError);
}

// Classic Mac OS ended lines with a lone CR. Such an OBJ used to be read as its first line alone
// (one vertex, no face, no error); every text format now reads it as its LF twin, and errors name
// the same lines.
TEST(Read, LinesEndedByALoneCrAreLines) {
    std::string stl = "solid tetrahedron\n";
    for (const auto& corners : std::vector<std::string>{"0 0 0\n0 1 0\n1 0 0", "0 0 0\n1 0 0\n0 0 1",
                                                        "1 0 0\n0 1 0\n0 0 1", "0 0 0\n0 0 1\n0 1 0"}) {
        std::string vertices;
        std::istringstream lines(corners);
        for (std::string line; std::getline(lines, line);) vertices += "vertex " + line + "\n";
        stl += "facet normal 0 0 0\nouter loop\n" + vertices + "endloop\nendfacet\n";
    }
    stl += "endsolid tetrahedron\n";
    struct Text {
        MeshFormat format;
        std::string lf;
        int line;  // of the first "1 0 0"
    };
    const std::vector<Text> texts = {
        {MeshFormat::obj, "# a tetrahedron\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 1 4 3\n", 3},
        {MeshFormat::off, "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 1 2 3\n3 0 3 2\n", 4},
        {MeshFormat::ply, "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
                          "property float z\nelement face 4\nproperty list uchar int vertex_indices\nend_header\n"
                          "0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 1 2 3\n3 0 3 2\n", 11},
        {MeshFormat::stl, stl, 6},
    };
    for (const auto& [format, lf, line] : texts) {
        std::string cr = lf;
        std::replace(cr.begin(), cr.end(), '\n', '\r');
        const TriangleMesh expected = parse(lf, format), read = parse(cr, format);
        EXPECT_EQ(read.num_faces(), 4) << cr;
        EXPECT_TRUE(same_matrix(read.V, expected.V));
        EXPECT_TRUE(same_matrix(read.F, expected.F));
        // A bad number: the error names its line.
        std::string broken = cr;
        broken.replace(broken.find("1 0 0"), 5, "1 0 x");
        expect_parse_error(broken, format, "test:" + std::to_string(line) + ":", "'x'");
    }
    // Line breaks of all three kinds in one file, and a continuation across a lone CR.
    const TriangleMesh mixed = parse("v 0 0 0\rv 1 0 0\r\nv 0 1 0\nf 1 2 \\\r3\r", MeshFormat::obj);
    EXPECT_EQ(mixed.num_vertices(), 3);
    EXPECT_TRUE(same_matrix(mixed.F, faces({{0, 1, 2}})));
    expect_parse_error("v 0 0 0\rv 1 0 0\r\nv 0 1 0\nf 1 2 \\\r3\rf 1 2 x\n", MeshFormat::obj, "test:6:");
}

TEST(Read, TextBeyondTheMemoryCapIsRefusedNotRead) {
    // A gzip bomb in miniature: 1 MiB of one byte, about a thousand times smaller compressed.
    TempDir dir;
    const std::string text(1 << 20, '#');
    write_gzip(dir / "bomb.obj.gz", text);
    const std::string compressed = read_bytes(dir / "bomb.obj.gz");
    ASSERT_LT(compressed.size(), text.size() / 500);
    EXPECT_EQ(io::gunzip(compressed, "bomb.obj.gz", text.size()), text);  // exactly the cap
    try {
        io::gunzip(compressed, "bomb.obj.gz", text.size() - 1);
        ADD_FAILURE() << "no IoError";
    } catch (const IoError& e) {
        EXPECT_NE(std::string(e.what()).find("bomb.obj.gz: decompresses to more than"), std::string::npos) << e.what();
    }
    // The same for a plain file, read in full up to the cap and refused one byte beyond it.
    write_bytes(dir / "big.obj", text);
    EXPECT_EQ(io::read_file(dir / "big.obj", text.size()), text);
    try {
        io::read_file(dir / "big.obj", 4096);
        ADD_FAILURE() << "no IoError";
    } catch (const IoError& e) {
        EXPECT_NE(std::string(e.what()).find("big.obj: holds more than 4096 bytes"), std::string::npos) << e.what();
    }
    // A quarter of the memory this process may use, which is at most the machine's.
    const std::size_t memory = static_cast<std::size_t>(::sysconf(_SC_PHYS_PAGES)) *
                               static_cast<std::size_t>(::sysconf(_SC_PAGE_SIZE));
    EXPECT_LE(io::usable_memory(), memory);
    EXPECT_GT(io::usable_memory(), 0u);
    EXPECT_EQ(io::max_text_bytes(), io::usable_memory() / 4);
    EXPECT_EQ(io::max_mesh_bytes(), io::usable_memory() / 16);
}

// Control groups limit a container's memory below the machine's: the least limit of the group and
// of its ancestors counts, under cgroup v2 and under v1's memory controller.
TEST(Read, MemoryLimitsOfControlGroupsAreFound) {
    TempDir dir;
    const fs::path& root = dir.path();
    auto write_limit = [&](const fs::path& group, const std::string& file, const std::string& text) {
        fs::create_directories(root / group);
        write_bytes(root / group / file, text);
    };
    // v2: "max" at the top, 1 GiB in the group, 512 MiB in its parent.
    write_limit("a/b", "memory.max", "1073741824\n");
    EXPECT_EQ(io::cgroup_memory_limit("0::/a/b\n", root), std::size_t{1} << 30);
    write_limit("a", "memory.max", "536870912\n");
    EXPECT_EQ(io::cgroup_memory_limit("0::/a/b\n", root), std::size_t{1} << 29);
    write_limit("", "memory.max", "max\n");
    EXPECT_EQ(io::cgroup_memory_limit("0::/\n", root), SIZE_MAX);
    // v1: the memory controller's hierarchy, alone or with others; other controllers do not count.
    write_limit("memory/x", "memory.limit_in_bytes", "9223372036854771712\n");
    write_limit("memory/y", "memory.limit_in_bytes", "2147483648\n");
    EXPECT_EQ(io::cgroup_memory_limit("4:memory:/x\n", root), std::size_t{9223372036854771712ULL});
    EXPECT_EQ(io::cgroup_memory_limit("1:cpu:/y\n3:cpu,memory:/y\n", root), std::size_t{1} << 31);
    EXPECT_EQ(io::cgroup_memory_limit("1:cpu:/y\n", root), SIZE_MAX);
    // Both (a hybrid system), a group whose folder is not there, and text that is not a list.
    EXPECT_EQ(io::cgroup_memory_limit("4:memory:/y\n0::/a/b\n", root), std::size_t{1} << 29);
    EXPECT_EQ(io::cgroup_memory_limit("0::/gone/deeper\n", root), SIZE_MAX);
    EXPECT_EQ(io::cgroup_memory_limit("garbage", root), SIZE_MAX);
}

// What a text grows into is budgeted too: 24 bytes a vertex, 12 a triangle, more for a polygon.
// The budget can be met exactly; what would go beyond it is refused and adds nothing.
TEST(Read, MeshBeyondItsMemoryBudgetIsRefused) {
    auto expect_refused = [](const std::function<void()>& add) {
        try {
            add();
            ADD_FAILURE() << "no IoError";
        } catch (const IoError& e) {
            EXPECT_STREQ(e.what(), "bomb.obj: its vertices and faces take more than 1000 bytes, the most a mesh "
                                   "read may take (a sixteenth of the memory this process may use)");
        }
    };
    io::MeshBuilder mesh("bomb.obj", 1000);
    for (int i = 0; i < 40; ++i) mesh.add_vertex(i, i * i, 0);  // 960 bytes
    const std::vector<int> triangle{0, 1, 2}, quad{0, 1, 2, 3};
    for (int i = 0; i < 3; ++i) ASSERT_TRUE(mesh.add_face(triangle));  // 996
    expect_refused([&] { (void)mesh.add_face(quad); });  // two triangles (24 bytes) and its record
    mesh.take(4);  // what a reader holds beside the mesh: 1000, the budget exactly
    expect_refused([&] { mesh.add_vertex(0, 0, 0); });
    expect_refused([&] { mesh.take(1); });
    ReadReport report;
    const TriangleMesh read = mesh.finish(report);
    EXPECT_EQ(read.V.rows(), 40);
    EXPECT_EQ(read.F.rows(), 3);
    EXPECT_EQ(report.polygons, 0);
}

// ---- OBJ -------------------------------------------------------------------------------------

TEST(Obj, PolygonsAreFanTriangulatedAndCounted) {
    ReadReport report;
    const TriangleMesh mesh = parse(
        "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv -1 0.5 0\n"
        "f 1 2 3\nf 1 2 3 4\nf 1 2 3 4 5\n",
        MeshFormat::obj, &report);
    EXPECT_TRUE(same_matrix(mesh.F, faces({{0, 1, 2}, {0, 1, 2}, {0, 2, 3}, {0, 1, 2}, {0, 2, 3}, {0, 3, 4}})));
    EXPECT_EQ(report.format, MeshFormat::obj);
    EXPECT_EQ(report.file_vertices, 5);
    EXPECT_EQ(report.file_faces, 3);
    EXPECT_EQ(report.polygons, 2);
    EXPECT_EQ(report.polygon_triangles, 5);
    EXPECT_FALSE(report.compressed);
}

// An OBJ file with one polygon, its corners (x, y) laid in a tilted plane far from the origin.
std::string tilted_polygon_obj(const std::vector<std::array<double, 2>>& corners) {
    const std::array<double, 3> origin{5, -3, 7}, e1{1.0 / 3, 2.0 / 3, 2.0 / 3}, e2{2.0 / 3, 1.0 / 3, -2.0 / 3};
    std::ostringstream obj;
    obj.precision(17);
    for (const auto& [x, y] : corners)
        obj << "v " << origin[0] + x * e1[0] + y * e2[0] << ' ' << origin[1] + x * e1[1] + y * e2[1] << ' '
            << origin[2] + x * e1[2] + y * e2[2] << '\n';
    obj << 'f';
    for (size_t i = 1; i <= corners.size(); ++i) obj << ' ' << i;
    obj << '\n';
    return obj.str();
}

// The triangles tile the polygon 0, 1, ..., n-1 of `area`: each is turned as the polygon (no
// fold), their areas add up to the polygon's, each side of the polygon is in one triangle and
// each diagonal in two, once each way.
void expect_tiles_polygon(const TriangleMesh& mesh, double area) {
    const int n = mesh.num_vertices();
    ASSERT_EQ(mesh.num_faces(), n - 2);
    Eigen::Vector3d normal = Eigen::Vector3d::Zero();
    for (int i = 0; i < n; ++i) normal += mesh.V.row(i).cross(mesh.V.row((i + 1) % n)).transpose();
    normal.normalize();
    double sum = 0;
    std::map<std::pair<int, int>, int> directed;
    for (int f = 0; f < mesh.num_faces(); ++f) {
        const Eigen::Vector3d a = mesh.V.row(mesh.F(f, 0)), b = mesh.V.row(mesh.F(f, 1)), c = mesh.V.row(mesh.F(f, 2));
        const double signed_area = (b - a).cross(c - a).dot(normal) / 2;
        EXPECT_GT(signed_area, 0) << "triangle " << f << " is folded over";
        sum += signed_area;
        for (int k = 0; k < 3; ++k) ++directed[{mesh.F(f, k), mesh.F(f, (k + 1) % 3)}];
    }
    EXPECT_NEAR(sum, area, 1e-12 * area);
    for (const auto& [edge, count] : directed) {
        const auto [i, j] = edge;
        EXPECT_EQ(count, 1) << "edge " << i << "-" << j;
        if (j != (i + 1) % n) {
            EXPECT_EQ(directed.count({j, i}), 1u) << "diagonal " << i << "-" << j;
        }
    }
    for (int i = 0; i < n; ++i) EXPECT_EQ(directed.count({i, (i + 1) % n}), 1u) << "side " << i;
}

TEST(Obj, AnLShapeWhoseFanFoldsIsEarClipped) {
    // From (2, 0) the fan's second triangle (2,0) (1,1) (1,2) is turned the wrong way.
    ReadReport report;
    const TriangleMesh mesh =
        parse(tilted_polygon_obj({{2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}, {0, 0}}), MeshFormat::obj, &report);
    EXPECT_EQ(report.polygons, 1);
    EXPECT_EQ(report.polygon_triangles, 4);
    EXPECT_EQ(report.ear_clipped_polygons, 1);
    expect_tiles_polygon(mesh, 3.0);
}

TEST(Obj, ACombWithManyReflexCornersIsEarClipped) {
    // A base 2k x 1 with k teeth 1 x 1 on top: 2k reflex corners.
    constexpr int kTeeth = 25;
    std::vector<std::array<double, 2>> comb{{0, 0}, {2 * kTeeth, 0}};
    for (int t = kTeeth; t >= 1; --t) {
        comb.push_back({2.0 * t, 2});
        comb.push_back({2.0 * t - 1, 2});
        comb.push_back({2.0 * t - 1, 1});
        comb.push_back({2.0 * t - 2, 1});
    }
    ReadReport report;
    const TriangleMesh mesh = parse(tilted_polygon_obj(comb), MeshFormat::obj, &report);
    EXPECT_EQ(report.ear_clipped_polygons, 1);
    expect_tiles_polygon(mesh, 3.0 * kTeeth);
}

TEST(Obj, ConvexAndStarShapedPolygonsKeepTheirFan) {
    // The L shape again, from the corner that sees all of it: its fan is a triangulation.
    ReadReport report;
    const TriangleMesh mesh =
        parse(tilted_polygon_obj({{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}}), MeshFormat::obj, &report);
    EXPECT_EQ(report.ear_clipped_polygons, 0);
    EXPECT_TRUE(same_matrix(mesh.F, faces({{0, 1, 2}, {0, 2, 3}, {0, 3, 4}, {0, 4, 5}})));
    expect_tiles_polygon(mesh, 3.0);
}

TEST(Obj, PolygonsThatAreNotSimpleStillGiveTheirTriangles) {
    // A bow tie (no normal: its two loops cancel), a self-crossing pentagram and all corners at
    // one point: n - 2 triangles of the polygon's corners each, whatever they look like.
    for (const std::string face : {"f 1 2 3 4\n", "f 1 3 5 2 4\n", "f 6 6 6 6\n"}) {
        ReadReport report;
        const TriangleMesh mesh = parse("v 0 0 0\nv 1 1 0\nv 1 0 0\nv 0 1 0\nv 0.5 1.5 0\nv 2 2 2\n" + face,
                                        MeshFormat::obj, &report);
        const int corners = static_cast<int>(std::count(face.begin(), face.end(), ' '));
        EXPECT_EQ(mesh.num_faces(), corners - 2) << face;
        for (int f = 0; f < mesh.num_faces(); ++f)
            for (int k = 0; k < 3; ++k) EXPECT_GE(mesh.F(f, k), 0);
    }
    // A large comb: the work bound stops ear clipping part way, the rest is fanned.
    std::vector<std::array<double, 2>> comb{{0, 0}, {4000, 0}};
    for (int t = 2000; t >= 1; --t)
        for (const auto& [x, y] : std::vector<std::array<double, 2>>{{2.0 * t, 2}, {2.0 * t - 1, 2}, {2.0 * t - 1, 1}, {2.0 * t - 2, 1}})
            comb.push_back({x, y});
    ReadReport report;
    const TriangleMesh mesh = parse(tilted_polygon_obj(comb), MeshFormat::obj, &report);
    EXPECT_EQ(mesh.num_faces(), static_cast<int>(comb.size()) - 2);
    EXPECT_EQ(report.ear_clipped_polygons, 1);
}

TEST(Obj, CornerFormsAndNegativeIndices) {
    const TriangleMesh mesh = parse(
        "# comment\r\n"
        "mtllib a.mtl\r\n"
        "o thing\r\ng group\r\ns 1\r\nusemtl red\r\n"
        "v 0 0 0 1\r\nv 1 0 0 1.0\r\nv 0 1 0 0.5 0.5 0.5\r\n"
        "vt 0 0\r\nvt 1 0\r\nvt 0 1\r\nvn 0 0 1\r\nvp 0.5\r\n"
        "\r\n   \t\r\n"
        "f 1/1 2/2 3/3\r\n"
        "f 1//1 2//1 3//1\r\n"
        "f 1/1/1 2/2/1 3/3/1 # trailing comment\r\n"
        "f -3 -2 -1\r\n"
        "f -3/-3/-1 -2/-2/-1 -1/-1/-1\r\n"
        "v 1 1 0\r\n"
        "f -1 -2 -3\r\n"
        "l 1 2\r\np 1\r\ncurv 0 1\r\n",
        MeshFormat::obj);
    EXPECT_EQ(mesh.num_vertices(), 4);
    EXPECT_TRUE(same_matrix(mesh.F, faces({{0, 1, 2}, {0, 1, 2}, {0, 1, 2}, {0, 1, 2}, {0, 1, 2}, {3, 2, 1}})));
    EXPECT_EQ(mesh.V(1, 0), 1.0);
}

TEST(Obj, LineContinuationAndForwardReferences) {
    const TriangleMesh mesh = parse("f 1 2 \\\n 3\nv 0 0 0\nv 1 0 0\nv 0 1 0\n", MeshFormat::obj);
    EXPECT_TRUE(same_matrix(mesh.F, faces({{0, 1, 2}})));
    // The error after a continuation names the physical line.
    expect_parse_error("v 0 0 0\nf 1 \\\n 1 \\\n x\n", MeshFormat::obj, "test:4:");
}

TEST(Obj, FacesOfOneOrTwoCornersAreSkippedAndCounted) {
    // Points and lines that exporters write as `f` (SweetHome3D's furniture has them).
    ReadReport report;
    const TriangleMesh mesh =
        parse("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\nf 1 2 3\nf 3\nf 2/1 3/1\nf -1 -2\n", MeshFormat::obj, &report);
    EXPECT_TRUE(same_matrix(mesh.F, faces({{0, 1, 2}})));
    EXPECT_EQ(report.skipped_line_faces, 4);
    EXPECT_EQ(report.file_faces, 1);
}

TEST(Obj, RepeatedAndDuplicateFacesAreKept) {
    const TriangleMesh mesh = parse("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 1 2\nf 1 2 3\nf 1 2 3\nf 3 2 1\n",
                                    MeshFormat::obj);
    EXPECT_TRUE(same_matrix(mesh.F, faces({{0, 0, 1}, {0, 1, 2}, {0, 1, 2}, {2, 1, 0}})));
}

TEST(Obj, ExtremeNumbersAreReadAndNonFiniteKept) {
    const TriangleMesh mesh = parse("v 1e300 -1e-300 4.9e-324\nv nan inf -inf\nv +1.5 -0 .5\n", MeshFormat::obj);
    EXPECT_EQ(mesh.V(0, 0), 1e300);
    EXPECT_EQ(mesh.V(0, 1), -1e-300);
    EXPECT_GT(mesh.V(0, 2), 0.0);
    EXPECT_TRUE(std::isnan(mesh.V(1, 0)));
    EXPECT_EQ(mesh.V(1, 1), std::numeric_limits<double>::infinity());
    EXPECT_EQ(mesh.V(1, 2), -std::numeric_limits<double>::infinity());
    EXPECT_EQ(mesh.V(2, 0), 1.5);
    EXPECT_TRUE(std::signbit(mesh.V(2, 1)));
    EXPECT_EQ(mesh.V(2, 2), 0.5);
}

// Old MSVC runtimes wrote infinity and NaN as "1.#INF00" and "-1.#IND00". In OBJ and OFF the '#'
// used to start a comment, so that such a NaN was read as -1 without a word: now they are what
// they say, in every text format, and a '#' elsewhere still starts a comment.
TEST(Read, OldMsvcSpellingsOfNonFiniteValuesAreRead) {
    const std::string values = "1.#INF -1.#INF00 +1.#INF0\n-1.#IND00 1.#QNAN0 -1.#SNAN\n";
    for (const auto& [format, text] : std::vector<std::pair<MeshFormat, std::string>>{
             {MeshFormat::obj, "v 1.#INF -1.#INF00 +1.#INF0 # comment\nv -1.#IND00 1.#QNAN0 -1.#SNAN\nv 1 2 3#4\n"},
             {MeshFormat::off, "OFF\n3 0 0\n1.#INF -1.#INF00 +1.#INF0 # comment\n-1.#IND00 1.#QNAN0 -1.#SNAN\n1 2 3#4\n"},
             {MeshFormat::ply, "ply\nformat ascii 1.0\nelement vertex 3\nproperty double x\nproperty double y\n"
                               "property double z\nend_header\n" + values + "1 2 3\n"},
         }) {
        const TriangleMesh mesh = parse(text, format);
        ASSERT_EQ(mesh.num_vertices(), 3) << text;
        for (int k = 0; k < 3; ++k) {
            EXPECT_EQ(std::abs(mesh.V(0, k)), std::numeric_limits<double>::infinity()) << text;
            EXPECT_TRUE(std::isnan(mesh.V(1, k))) << text;
            EXPECT_EQ(mesh.V(2, k), k + 1.0) << text;
        }
        EXPECT_LT(mesh.V(0, 1), 0);
        EXPECT_GT(mesh.V(0, 2), 0);
    }
    // Anything else after "1.#INF" is not a number.
    expect_parse_error("v 0 0 1.#INFINITE\n", MeshFormat::obj, "test:1:", "'1.#INFINITE'");
    expect_parse_error("OFF\n1 0 0\n0 0 1.#IND01\n", MeshFormat::off, "test:3:", "'1.#IND01'");
}

TEST(Obj, MalformedInputIsParseErrorWithFileAndLine) {
    const std::string triangle = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
    expect_parse_error(triangle + "f 1 2 0\n", MeshFormat::obj, "test:4:", "0");
    expect_parse_error(triangle + "f 1 2 4\n", MeshFormat::obj, "test:4:", "4");
    expect_parse_error(triangle + "f 1 2 3\nf 1 2 7\nf 1 2 5\n", MeshFormat::obj, "test:5:", "7");
    expect_parse_error(triangle + "f -1 -2 -4\n", MeshFormat::obj, "test:4:", "-4");
    expect_parse_error(triangle + "f 1 9\n", MeshFormat::obj, "test:4:", "9");  // a line's indices too
    expect_parse_error(triangle + "f\n", MeshFormat::obj, "test:4:", "0 corners");
    expect_parse_error(triangle + "f 1 2 x\n", MeshFormat::obj, "test:4:", "'x'");
    expect_parse_error(triangle + "f 1 2 3x\n", MeshFormat::obj, "test:4:");
    expect_parse_error(triangle + "f 1 2 99999999999999999999999\n", MeshFormat::obj, "test:4:");
    expect_parse_error("v 1 2\n", MeshFormat::obj, "test:1:", "z coordinate");
    expect_parse_error("v 1 2 # 3\n", MeshFormat::obj, "test:1:");
    expect_parse_error("\n\nv 1.2.3 0 0\n", MeshFormat::obj, "test:3:", "'1.2.3'");
    expect_parse_error("v 1 2 3e\n", MeshFormat::obj, "test:1:");
    expect_parse_error("v 1 2 0x10\n", MeshFormat::obj, "test:1:");
    expect_parse_error("v +-1 0 0\n", MeshFormat::obj, "test:1:", "'+-1'");
    expect_parse_error(triangle + "f 1 2 +-3\n", MeshFormat::obj, "test:4:");
    expect_parse_error("v 1e999 0 0\n", MeshFormat::obj, "test:1:", "range");
    expect_parse_error("v -1e999 0 0\n", MeshFormat::obj, "test:1:", "range");
    // Text of another format (a game's level with the .obj extension) is not an empty mesh...
    expect_parse_error("# level 1\n****..&..****--0\n", MeshFormat::obj, "test:2:",
                       "no vertex in the file, and '****..&..****--0' is not an OBJ statement");
    // ... but an empty export is.
    EXPECT_EQ(parse("# nothing\nmtllib a.mtl\no empty\ng\ns off\n", MeshFormat::obj).num_faces(), 0);
}

// ---- OFF -------------------------------------------------------------------------------------

TEST(Off, CommentsBlankLinesColorsAndPolygons) {
    ReadReport report;
    const TriangleMesh mesh = parse(
        "# leading comment\n\nCOFF # keyword comment\n"
        "# counts next\n"
        "5 3 0\n"
        "\n"
        "0 0 0 255 0 0 255\n"
        "1 0 0   0 255 0 255 # comment\n"
        "   \n# a comment between vertices\n"
        "1 1 0 0 0 255 255\n0 1 0 1 1 1 1\n-1 0.5 0 0 0 0 0\n"
        "3 0 1 2 255 0 0\n"
        "\n4 0 1 2 3\n"
        "5 0 1 2 3 4 0.5 0.5 0.5 1\n",
        MeshFormat::off, &report);
    EXPECT_EQ(mesh.num_vertices(), 5);
    EXPECT_EQ(mesh.V(4, 0), -1.0);
    EXPECT_TRUE(same_matrix(mesh.F, faces({{0, 1, 2}, {0, 1, 2}, {0, 2, 3}, {0, 1, 2}, {0, 2, 3}, {0, 3, 4}})));
    EXPECT_EQ(report.format, MeshFormat::off);
    EXPECT_EQ(report.file_vertices, 5);
    EXPECT_EQ(report.file_faces, 3);
    EXPECT_EQ(report.polygons, 2);
    EXPECT_EQ(report.polygon_triangles, 5);
}

TEST(Off, HeaderVariants) {
    const std::string body = "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
    for (const std::string header : {"OFF\n3 1 0\n", "OFF 3 1 0\n", "OFF\r\n3 1\r\n", "NOFF\n3 1 0\n",
                                     "CNOFF\n3 1 0\n", "STOFF\n3 1 0\n", "STCNOFF 3 1 3\n"}) {
        EXPECT_EQ(parse(header + body, MeshFormat::off).num_faces(), 1) << header;
    }
    EXPECT_EQ(parse("OFF\n0 0 0\n", MeshFormat::off).num_vertices(), 0);
}

TEST(Off, MalformedInputIsParseError) {
    const std::string vertices = "0 0 0\n1 0 0\n0 1 0\n";
    expect_parse_error("OFX\n3 1 0\n" + vertices + "3 0 1 2\n", MeshFormat::off, "test:1:", "OFF");
    expect_parse_error("3 1 0\n" + vertices + "3 0 1 2\n", MeshFormat::off, "test:1:");
    expect_parse_error("OFF\n", MeshFormat::off, "test:2:", "counts");
    expect_parse_error("OFF\n-3 1 0\n", MeshFormat::off, "test:2:");
    expect_parse_error("OFF\n3 1 0\n0 0 0\n1 0 0\n", MeshFormat::off, "test:5:", "2 of 3 vertices");
    expect_parse_error("OFF\n3 2 0\n" + vertices + "3 0 1 2\n", MeshFormat::off, "test:7:", "1 of 2 faces");
    expect_parse_error("OFF\n3 1 0\n" + vertices + "3 0 1 3\n", MeshFormat::off, "test:6:", "3");
    expect_parse_error("OFF\n3 1 0\n" + vertices + "3 0 1 -1\n", MeshFormat::off, "test:6:", "-1");
    expect_parse_error("OFF\n3 1 0\n" + vertices + "2 0 1\n", MeshFormat::off, "test:6:", "2 corners");
    expect_parse_error("OFF\n3 1 0\n" + vertices + "4 0 1 2\n", MeshFormat::off, "test:6:");
    expect_parse_error("OFF\n3 1 0\n" + vertices + "1000000000 0 1 2\n", MeshFormat::off, "test:6:",
                       "face of 1000000000 corners: the 7 bytes left in the file cannot hold them");
    expect_parse_error("OFF\n3 1 0\n" + vertices + "-3 0 1 2\n", MeshFormat::off, "test:6:",
                       "negative number of face corners -3");
    expect_parse_error("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 zero\n3 0 1 2\n", MeshFormat::off, "test:5:");
    // Counts the file cannot hold are a truncation error, not a huge allocation.
    expect_parse_error("OFF\n2000000000 2000000000 0\n0 0 0\n", MeshFormat::off, "test:4:");
}

TEST(Off, UnsupportedVariants) {
    EXPECT_THROW(parse("OFF BINARY\n", MeshFormat::off), UnsupportedFormatError);
    EXPECT_THROW(parse("4OFF\n1 0 0\n0 0 0 0\n", MeshFormat::off), UnsupportedFormatError);
    EXPECT_THROW(parse("nOFF\n3\n1 0 0\n0 0 0\n", MeshFormat::off), UnsupportedFormatError);
}

// ---- PLY -------------------------------------------------------------------------------------

const std::string kAsciiPly =
    "ply\r\n"
    "format ascii 1.0\n"
    "comment made by hand\n"
    "obj_info nothing\n"
    "element camera 1\n"
    "property float position\n"
    "property list uchar float tags\n"
    "element vertex 4\n"
    "property uchar red\n"
    "property float x\n"
    "property double y\n"
    "property list int int neighbours\n"
    "property int z\n"
    "element face 2\n"
    "property uchar flags\n"
    "property list uchar uint vertex_indices\n"
    "property list uchar float texcoord\n"
    "element edge 1\n"
    "property int vertex1\n"
    "property int vertex2\n"
    "end_header\n"
    "1.5 3 0.1 0.2 0.3\n"
    "255 0 0 2 1 2 0\n"
    "0 1 0 0 0\n"
    "\n"
    "7 1 1 1 3 5\n"
    "0 0 1 1 0 -7\n"
    "1 3 0 1 2 0\n"
    "2 4 0 1 2 3 6 0 0 1 0 1 1\n"
    "0 1\n";

TEST(Ply, AsciiWithExtraElementsAndProperties) {
    ReadReport report;
    const TriangleMesh mesh = parse(kAsciiPly, MeshFormat::ply, &report);
    Eigen::MatrixX3d V(4, 3);
    V << 0, 0, 0, 1, 0, 0, 1, 1, 5, 0, 1, -7;
    EXPECT_TRUE(same_matrix(mesh.V, V));
    // The quad is warped so that its fan would fold over in its mean plane: it is ear clipped.
    EXPECT_TRUE(same_matrix(mesh.F, faces({{0, 1, 2}, {1, 2, 3}, {1, 3, 0}})));
    EXPECT_EQ(report.ear_clipped_polygons, 1);
    EXPECT_EQ(report.format, MeshFormat::ply);
    EXPECT_EQ(report.file_vertices, 4);
    EXPECT_EQ(report.file_faces, 2);
    EXPECT_EQ(report.polygons, 1);
    EXPECT_EQ(report.polygon_triangles, 2);
}

// The same content as kAsciiPly in binary, with the face element first and various index types.
std::string binary_ply(bool big_endian, const std::string& index_type, const std::string& count_type = "uchar") {
    Bytes b(big_endian);
    b.text("ply\nformat ").text(big_endian ? "binary_big_endian" : "binary_little_endian").text(" 1.0\n");
    b.text("element camera 1\nproperty float position\nproperty list uchar float tags\n");
    b.text("element face 2\nproperty uchar flags\nproperty list " + count_type + " " + index_type +
           " vertex_index\nproperty list uchar float texcoord\n");
    b.text("element vertex 4\nproperty uchar red\nproperty float x\nproperty double y\n"
           "property list int int neighbours\nproperty int z\n");
    b.text("element edge 1\nproperty int vertex1\nproperty int vertex2\nend_header\n");
    // camera
    b.put(1.5f).put(std::uint8_t{3}).put(0.1f).put(0.2f).put(0.3f);
    // faces
    auto put_count = [&](int n) {
        if (count_type == "uchar") b.put(static_cast<std::uint8_t>(n));
        if (count_type == "int") b.put(static_cast<std::int32_t>(n));
        if (count_type == "ushort") b.put(static_cast<std::uint16_t>(n));
    };
    auto put_index = [&](int i) {
        if (index_type == "int") b.put(static_cast<std::int32_t>(i));
        if (index_type == "uint") b.put(static_cast<std::uint32_t>(i));
        if (index_type == "ushort") b.put(static_cast<std::uint16_t>(i));
        if (index_type == "uchar") b.put(static_cast<std::uint8_t>(i));
        if (index_type == "double") b.put(static_cast<double>(i));
    };
    b.put(std::uint8_t{1});
    put_count(3);
    for (int i : {0, 1, 2}) put_index(i);
    b.put(std::uint8_t{0});
    b.put(std::uint8_t{2});
    put_count(4);
    for (int i : {0, 1, 2, 3}) put_index(i);
    b.put(std::uint8_t{2}).put(0.f).put(1.f);
    // vertices: red x y neighbours z
    const double xyz[4][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 5}, {0, 1, -7}};
    for (const auto& p : xyz) {
        b.put(std::uint8_t{9}).put(static_cast<float>(p[0])).put(p[1]);
        b.put(std::int32_t{2}).put(std::int32_t{1}).put(std::int32_t{2});
        b.put(static_cast<std::int32_t>(p[2]));
    }
    // edge
    b.put(std::int32_t{0}).put(std::int32_t{1});
    return b.str();
}

TEST(Ply, BinaryBothByteOrdersAndIndexTypes) {
    const TriangleMesh expected = parse(kAsciiPly, MeshFormat::ply);
    for (bool big : {false, true}) {
        for (const std::string index_type : {"int", "uint", "ushort", "uchar", "double"}) {
            for (const std::string count_type : {"uchar", "ushort", "int"}) {
                SCOPED_TRACE((big ? "big " : "little ") + index_type + " " + count_type);
                ReadReport report;
                const TriangleMesh mesh = parse(binary_ply(big, index_type, count_type), MeshFormat::ply, &report);
                EXPECT_TRUE(same_matrix(mesh.V, expected.V));
                EXPECT_TRUE(same_matrix(mesh.F, expected.F));
                EXPECT_EQ(report.polygons, 1);
            }
        }
    }
}

TEST(Ply, BinaryTruncatedAnywhereIsParseError) {
    const std::string full = binary_ply(false, "int");
    const std::size_t body = full.find("end_header\n") + std::strlen("end_header\n");
    // Cutting the data anywhere must fail, also inside the skipped elements.
    for (std::size_t size = body; size < full.size(); ++size) {
        EXPECT_THROW(parse(full.substr(0, size), MeshFormat::ply), ParseError) << "size " << size;
    }
    const std::string message = parse_error_message(full.substr(0, full.size() - 3), MeshFormat::ply);
    EXPECT_NE(message.find("test: edge 0: "), std::string::npos) << message;
}

TEST(Ply, BinaryListCountsAreChecked) {
    const std::string header =
        "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
        "property float z\nelement face 1\nproperty list char int vertex_indices\nend_header\n";
    Bytes vertices;
    for (int i = 0; i < 9; ++i) vertices.put(static_cast<float>(i % 2));
    auto face = [&](std::int8_t count, int indices) {
        Bytes b;
        b.text(header + vertices.str()).put(count);
        for (int i = 0; i < indices; ++i) b.put(static_cast<std::int32_t>(i));
        return b.str();
    };
    EXPECT_EQ(parse(face(3, 3), MeshFormat::ply).num_faces(), 1);
    expect_parse_error(face(-1, 3), MeshFormat::ply, "test: face 0: ", "negative");
    expect_parse_error(face(100, 3), MeshFormat::ply, "test: face 0: ", "100");
    expect_parse_error(face(2, 2), MeshFormat::ply, "test: face 0: ", "2 corners");
    expect_parse_error(face(0, 0), MeshFormat::ply, "test: face 0: ", "0 corners");
    std::string out_of_range = face(3, 2);
    out_of_range += Bytes().put(std::int32_t{3}).str();
    expect_parse_error(out_of_range, MeshFormat::ply, "test: face 0: ", "3");
    std::string negative = face(3, 2);
    negative += Bytes().put(std::int32_t{-1}).str();
    expect_parse_error(negative, MeshFormat::ply, "test: face 0: ", "-1");
}

TEST(Ply, HugeHeaderCountsFailWithoutAllocating) {
    for (const std::string count : {"4000000000", "9223372036854775807", "2147483647"}) {
        const std::string ply = "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\n"
                                "property float y\nproperty float z\nelement face " + count +
                                "\nproperty list uchar int vertex_indices\nend_header\n" +
                                std::string(36, '\0') + std::string(13, '\0');
        EXPECT_THROW(parse(ply, MeshFormat::ply), ParseError) << count;
        const std::string vertices = "ply\nformat ascii 1.0\nelement vertex " + count +
                                     "\nproperty float x\nproperty float y\nproperty float z\nend_header\n0 0 0\n";
        EXPECT_THROW(parse(vertices, MeshFormat::ply), ParseError) << count;
    }
    // An element without properties needs no bytes, whatever its count.
    const std::string empty_element =
        "ply\nformat binary_little_endian 1.0\nelement nothing 9223372036854775807\n"
        "element vertex 0\nproperty float x\nproperty float y\nproperty float z\nend_header\n";
    EXPECT_EQ(parse(empty_element, MeshFormat::ply).num_vertices(), 0);
}

TEST(Ply, MalformedHeaderOrBody) {
    const std::string vertex_decl = "element vertex 3\nproperty float x\nproperty float y\nproperty float z\n";
    const std::string faces_decl = "element face 1\nproperty list uchar int vertex_indices\n";
    const std::string data = "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
    const std::string good = "ply\nformat ascii 1.0\n" + vertex_decl + faces_decl + "end_header\n" + data;
    EXPECT_EQ(parse(good, MeshFormat::ply).num_faces(), 1);

    expect_parse_error("plx\n" + good.substr(4), MeshFormat::ply, "test:1:");
    expect_parse_error("ply\n" + vertex_decl + faces_decl + "end_header\n" + data, MeshFormat::ply, "test:", "format");
    expect_parse_error("ply\nformat ascii 1.0\n" + vertex_decl + faces_decl, MeshFormat::ply, "test:", "end_header");
    expect_parse_error("ply\nformat ascii 1.0\nproperty float x\n" + vertex_decl + faces_decl + "end_header\n" + data,
                       MeshFormat::ply, "test:3:");
    expect_parse_error("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                       "property half z\n" + faces_decl + "end_header\n" + data,
                       MeshFormat::ply, "test:6:", "half");
    expect_parse_error("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n" +
                           faces_decl + "end_header\n" + data,
                       MeshFormat::ply, "test:3:", "x, y and z");
    expect_parse_error("ply\nformat ascii 1.0\n" + vertex_decl + "element face 1\nproperty list uchar int corners\n"
                       "end_header\n" + data,
                       MeshFormat::ply, "test:7:", "vertex_indices");
    expect_parse_error("ply\nformat ascii 1.0\n" + vertex_decl + "element face -1\n" + "end_header\n",
                       MeshFormat::ply, "test:7:");
    expect_parse_error("ply\nformat ascii 1.0\n" + vertex_decl + "elephant\n" + "end_header\n",
                       MeshFormat::ply, "test:7:", "elephant");
    expect_parse_error("ply\nformat ascii 1.0\n" + faces_decl + "end_header\n3 0 1 2\n", MeshFormat::ply,
                       "test:", "vertex");
    // Body errors name the line and the record.
    const std::string header = "ply\nformat ascii 1.0\n" + vertex_decl + faces_decl + "end_header\n";
    expect_parse_error(header + "0 0 0\n1 0 0\n0 1\n3 0 1 2\n", MeshFormat::ply, "test:12:", "vertex 2");
    expect_parse_error(header + "0 0 0\n1 0 0\n0 1 0 9\n3 0 1 2\n", MeshFormat::ply, "test:12:", "vertex 2");
    expect_parse_error(header + "0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n", MeshFormat::ply, "test:13:", "face 0");
    expect_parse_error(header + "0 0 0\n1 0 0\n0 1 0\n2 0 1\n", MeshFormat::ply, "test:13:", "2 corners");
    expect_parse_error(header + "0 0 0\n1 0 0\n0 1 0\n256 0 1 2\n", MeshFormat::ply, "test:13:");
    expect_parse_error(header + "0 0 0\n1 0 0\n0 1 0\n-3 0 1 2\n", MeshFormat::ply, "test:13:");
    expect_parse_error(header + "0 0 0\n1 0 0\n0 1 0\n", MeshFormat::ply, "test:", "face 0");
    expect_parse_error(header + "0 0 0\n1 0 0\n0 1e999 0\n3 0 1 2\n", MeshFormat::ply, "test:12:");
}

TEST(Ply, UnsupportedVariants) {
    EXPECT_THROW(parse("ply\nformat binary_middle_endian 1.0\nend_header\n", MeshFormat::ply),
                 UnsupportedFormatError);
    EXPECT_THROW(parse("ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\n"
                       "property float z\nelement tristrips 1\nproperty list int int vertex_indices\n"
                       "end_header\n4 0 1 2 3\n",
                       MeshFormat::ply),
                 UnsupportedFormatError);
}

// ---- STL -------------------------------------------------------------------------------------

// The 12 triangles of the unit cube, the corners of each as 9 floats.
std::vector<std::array<float, 9>> cube_facets() {
    const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    auto corner = [](int i) { return std::array<float, 3>{float(i & 1), float((i >> 1) & 1), float((i >> 2) & 1)}; };
    std::vector<std::array<float, 9>> facets;
    for (const auto& q : quads) {
        for (const auto& tri : {std::array<int, 3>{q[0], q[1], q[2]}, std::array<int, 3>{q[0], q[2], q[3]}}) {
            std::array<float, 9> facet{};
            for (int k = 0; k < 3; ++k) {
                const auto p = corner(tri[static_cast<std::size_t>(k)]);
                for (int d = 0; d < 3; ++d) facet[static_cast<std::size_t>(3 * k + d)] = p[static_cast<std::size_t>(d)];
            }
            facets.push_back(facet);
        }
    }
    return facets;
}

std::string ascii_stl(const std::vector<std::array<float, 9>>& facets) {
    std::ostringstream out;
    out << "solid cube\n";
    for (const auto& f : facets) {
        out << "  facet normal 0 0 0\n    outer loop\n";
        for (std::size_t k = 0; k < 3; ++k) out << "      vertex " << f[3 * k] << ' ' << f[3 * k + 1] << ' ' << f[3 * k + 2] << '\n';
        out << "    endloop\n  endfacet\n";
    }
    out << "endsolid cube\n";
    return out.str();
}

std::string binary_stl(const std::vector<std::array<float, 9>>& facets, const std::string& header_text = "binary") {
    Bytes b;
    std::string header = header_text;
    header.resize(80, ' ');
    b.text(header).put(static_cast<std::uint32_t>(facets.size()));
    for (const auto& f : facets) {
        b.put(0.f).put(0.f).put(1.f);
        for (float value : f) b.put(value);
        b.put(std::uint16_t{0});
    }
    return b.str();
}

void expect_welded_cube(const TriangleMesh& mesh, const ReadReport& report) {
    EXPECT_EQ(mesh.num_vertices(), 8);
    EXPECT_EQ(mesh.num_faces(), 12);
    EXPECT_EQ(report.format, MeshFormat::stl);
    EXPECT_EQ(report.file_vertices, 36);
    EXPECT_EQ(report.welded_vertices, 28);
    EXPECT_EQ(report.file_faces, 12);
    // Numbered in order of first appearance: the first facet gives vertices 0, 1, 2.
    EXPECT_EQ(mesh.F.row(0), Eigen::RowVector3i(0, 1, 2));
    const auto facets = cube_facets();
    for (Eigen::Index f = 0; f < 12; ++f) {
        for (int k = 0; k < 3; ++k) {
            for (int d = 0; d < 3; ++d) {
                EXPECT_EQ(mesh.V(mesh.F(f, k), d), facets[static_cast<std::size_t>(f)][static_cast<std::size_t>(3 * k + d)]);
            }
        }
    }
}

TEST(Stl, AsciiCubeIsWelded) {
    ReadReport report;
    expect_welded_cube(parse(ascii_stl(cube_facets()), MeshFormat::stl, &report), report);
}

TEST(Stl, BinaryCubeIsWeldedEvenWithASolidHeader) {
    for (const std::string header : {"binary", "solid cube (but binary)"}) {
        ReadReport report;
        expect_welded_cube(parse(binary_stl(cube_facets(), header), MeshFormat::stl, &report), report);
    }
}

TEST(Stl, ReadFromGzipFiles) {
    TempDir dir;
    write_gzip(dir / "cube.STL.gz", binary_stl(cube_facets()));
    ReadReport report;
    expect_welded_cube(read_mesh(dir / "cube.STL.gz", &report), report);
    EXPECT_TRUE(report.compressed);
}

TEST(Stl, NegativeZeroWeldsWithZeroAndKeywordsAnyCase) {
    const TriangleMesh mesh = parse(
        "SOLID x\nFACET NORMAL 0 0 1\nOUTER LOOP\nVERTEX 0 0 0\nVERTEX 1 0 0\nVERTEX 0 1 0\nENDLOOP\nENDFACET\n"
        "facet normal 0 0 1\nouter loop\nvertex -0 -0.0 0\nvertex 0 1 0\nvertex -1 0 0\nvertex -1 -1 0\n"
        "endloop\nendfacet\nendsolid x\n",
        MeshFormat::stl);
    EXPECT_EQ(mesh.num_vertices(), 5);
    EXPECT_TRUE(same_matrix(mesh.F, faces({{0, 1, 2}, {0, 2, 3}, {0, 3, 4}})));
    EXPECT_FALSE(std::signbit(mesh.V(0, 0)));
}

TEST(Stl, MalformedInputIsParseError) {
    auto facets = cube_facets();
    const std::string binary = binary_stl(facets);
    for (std::size_t size : {std::size_t{1}, std::size_t{50}, std::size_t{83}, std::size_t{84}, std::size_t{100},
                             binary.size() - 1, binary.size() + 1}) {
        std::string bytes = binary;
        bytes.resize(size, '\0');
        EXPECT_THROW(parse(bytes, MeshFormat::stl), ParseError) << size;
    }
    std::string truncated = binary.substr(0, binary.size() - 60);
    expect_parse_error(truncated, MeshFormat::stl, "test: facet 10: ", "truncated");
    expect_parse_error(binary + "x", MeshFormat::stl, "test: ");
    // ascii
    expect_parse_error("solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nendloop\nendfacet\n",
                       MeshFormat::stl, "test:7:", "2 corners");
    expect_parse_error("solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n", MeshFormat::stl,
                       "test:", "ends inside a facet");
    expect_parse_error("solid s\nvertex 0 0 0\n", MeshFormat::stl, "test:2:", "outside");
    expect_parse_error("solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 x\n", MeshFormat::stl, "test:4:", "'x'");
    expect_parse_error("solid s\nfacets\n", MeshFormat::stl, "test:2:", "facets");
    // Text of another format (a game's level with the .stl extension) is not read as a binary STL
    // truncated at some facet.
    expect_parse_error("(supertux-level\n  (version 3)\n  (name (_ \"Empty Throne Room\"))\n" + std::string(90, ' ') + ")\n",
                       MeshFormat::stl, "test: ", "text that does not start with 'solid': neither an ascii nor a binary STL");
}

TEST(Stl, BinaryWithASolidHeaderAndAWrongCountIsParseErrorNotAscii) {
    // Such a file used to be read as an ascii STL whose "solid" line never ends: no facets.
    const std::string binary = binary_stl(cube_facets(), "solid cube (but binary)");
    std::string count_too_large = binary;
    count_too_large[80] = static_cast<char>(count_too_large[80] + 1);
    expect_parse_error(count_too_large, MeshFormat::stl, "test: facet 12: ", "truncated");
    expect_parse_error(binary + std::string(2, '\0'), MeshFormat::stl, "test: ", "declares 12 facets");
}

TEST(TextFormats, AByteOrderMarkAtTheStartIsSkipped) {
    const std::string bom = "\xEF\xBB\xBF";
    const std::vector<std::pair<MeshFormat, std::string>> files = {
        {MeshFormat::obj, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"},
        {MeshFormat::off, "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"},
        {MeshFormat::ply, "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                          "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                          "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"},
        {MeshFormat::stl, ascii_stl({{0, 0, 0, 1, 0, 0, 0, 1, 0}})},
    };
    for (const auto& [format, text] : files) {
        const TriangleMesh mesh = parse(bom + text, format);
        EXPECT_TRUE(same_matrix(mesh.F, faces({{0, 1, 2}}))) << text;
        EXPECT_EQ(mesh.V(1, 0), 1.0) << text;
    }
}

// ---- the corpus ------------------------------------------------------------------------------

// Faces in the file, counted the simplest way (the corpus is all-triangle): lines starting with
// "f " in OBJ (gzipped or not), the count in the header of OFF.
long long count_obj_faces(std::istream& in) {
    long long faces = 0;
    for (std::string line; std::getline(in, line);) faces += line.rfind("f ", 0) == 0 ? 1 : 0;
    return faces;
}

long long count_faces(const fs::path& path) {
    const std::string name = path.filename().string();
    if (name.ends_with(".obj.gz")) {
        gzFile file = gzopen(path.string().c_str(), "rb");
        EXPECT_NE(file, nullptr);
        std::string text;
        char buffer[1 << 16];
        for (int n; (n = gzread(file, buffer, sizeof buffer)) > 0;) text.append(buffer, static_cast<std::size_t>(n));
        gzclose(file);
        std::istringstream in(text);
        return count_obj_faces(in);
    }
    std::ifstream in(path);
    if (name.ends_with(".obj")) return count_obj_faces(in);
    std::string word;
    long long vertices = 0, faces = -1;
    while (in >> word) {  // skip comments, then the keyword
        if (word[0] == '#') {
            std::getline(in, word);
        } else if (word == "OFF") {
            in >> vertices >> faces;
            break;
        }
    }
    return faces;
}

std::vector<std::string> corpus_files() {
    const fs::path dir = SDMESH_CORPUS_DIR;
    std::vector<std::string> files;
    if (!fs::is_directory(dir)) return {""};  // the test skips
    for (const auto& entry : fs::directory_iterator(dir)) {
        const std::string name = entry.path().filename().string();
        if ((name.starts_with("cgal_") && name.ends_with(".off")) || name.ends_with(".obj") || name.ends_with(".obj.gz")) {
            files.push_back(name);
        }
    }
    std::sort(files.begin(), files.end());
    return files;
}

class Corpus : public ::testing::TestWithParam<std::string> {};

TEST_P(Corpus, EveryFaceIsRead) {
    if (GetParam().empty()) GTEST_SKIP() << "corpus folder " << SDMESH_CORPUS_DIR << " is absent";
    const fs::path path = fs::path(SDMESH_CORPUS_DIR) / GetParam();
    ReadReport report;
    const TriangleMesh mesh = read_mesh(path, &report);
    const long long faces_in_file = count_faces(path);
    EXPECT_GT(faces_in_file, 0);
    EXPECT_EQ(mesh.num_faces(), faces_in_file);
    EXPECT_EQ(report.file_faces, faces_in_file);
    EXPECT_EQ(report.polygons, 0);
    EXPECT_EQ(report.compressed, GetParam().ends_with(".gz"));
    EXPECT_GE(mesh.F.minCoeff(), 0);
    EXPECT_LT(mesh.F.maxCoeff(), mesh.num_vertices());
}

INSTANTIATE_TEST_SUITE_P(Files, Corpus, ::testing::ValuesIn(corpus_files()), [](const auto& param_info) {
    std::string name = param_info.param.empty() ? std::string("absent") : param_info.param;
    for (char& c : name) {
        if (std::isalnum(static_cast<unsigned char>(c)) == 0) c = '_';
    }
    return name;
});

}  // namespace
