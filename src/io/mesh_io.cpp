// The public entry points of io.hpp: format from extension, reading whole files (gunzipped when
// needed), dispatch to the format readers and writers, and atomic writing through a temporary
// file. Also the small pieces the readers and writers share (error wording, MeshBuilder, output).

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cerrno>
#include <climits>
#include <cmath>
#include <cstring>
#include <string>
#include <system_error>
#include <utility>

#include <unistd.h>

#include <Eigen/Geometry>

#include "io/errors.hpp"
#include "io/formats.hpp"
#include "io/gzip.hpp"
#include "io/mesh_builder.hpp"
#include "io/output_file.hpp"
#include "io/memory_budget.hpp"
#include "io/whole_file.hpp"
#include "sdmesh/error.hpp"
#include "sdmesh/io.hpp"

namespace sdmesh {
namespace io {

// ---- error wording ---------------------------------------------------------------------------

void throw_at_line(std::string_view file, long long line, std::string_view what) {
    throw ParseError(std::string(file) + ":" + std::to_string(line) + ": " + std::string(what));
}

void throw_at_element(std::string_view file, std::string_view element, long long index,
                      std::string_view what) {
    throw ParseError(std::string(file) + ": " + std::string(element) + " " +
                     std::to_string(index) + ": " + std::string(what));
}

std::string quoted(std::string_view token) {
    constexpr std::size_t kMaxShown = 40;
    std::string text = "'";
    for (char c : token.substr(0, kMaxShown)) {
        text += std::isprint(static_cast<unsigned char>(c)) != 0 ? c : '?';
    }
    text += token.size() > kMaxShown ? "...'" : "'";
    return text;
}

// ---- MeshBuilder -----------------------------------------------------------------------------

namespace {

// Point tests ear clipping may spend per corner: quadratic work for the polygons modellers write,
// and a file of huge combs stays linear in its size.
constexpr std::size_t kEarClippingWorkPerCorner = 256;

// Re-triangulates in place the polygon whose fan is `fan` (n - 2 rows of F), if that fan folds
// over: ear clipping in the plane of the polygon's Newell normal, trying corners from 1 on, so
// that it would clip the fan's own triangles where they are ears. Returns whether it did.
bool unfold_polygon(const Eigen::MatrixX3d& V, Eigen::Ref<Eigen::MatrixX3i> fan) {
    const auto n = static_cast<std::size_t>(fan.rows()) + 2;
    auto read_corner = [&](std::size_t i) {
        return i < 2 ? fan(0, static_cast<Eigen::Index>(i)) : fan(static_cast<Eigen::Index>(i) - 2, 2);
    };
    auto point = [&](std::size_t i) -> Eigen::Vector3d { return V.row(read_corner(i)).transpose(); };

    Eigen::Vector3d normal = Eigen::Vector3d::Zero();
    for (std::size_t i = 0; i < n; ++i) normal += point(i).cross(point((i + 1) % n));
    if (const double norm2 = normal.squaredNorm(); !(norm2 > 0) || !std::isfinite(norm2)) return false;
    bool folds = false;
    for (std::size_t i = 1; i + 1 < n; ++i)
        folds = folds || (point(i) - point(0)).cross(point(i + 1) - point(0)).dot(normal) < 0;
    if (!folds) return false;

    std::vector<int> corners(n);  // read before the rows are overwritten
    for (std::size_t i = 0; i < n; ++i) corners[i] = read_corner(i);
    // (u, v, normal) is right-handed, so the polygon runs counterclockwise in (u, v).
    const Eigen::Vector3d w = normal.normalized();
    const Eigen::Vector3d u = w.unitOrthogonal();
    const Eigen::Vector3d v = w.cross(u);
    std::vector<Eigen::Vector2d> q(n);
    for (std::size_t i = 0; i < n; ++i) q[i] = {(point(i) - point(0)).dot(u), (point(i) - point(0)).dot(v)};
    // The sine of the turn from a to b to c: +1 left, -1 right, 0 straight or degenerate.
    auto turn = [&](std::size_t a, std::size_t b, std::size_t c) {
        const Eigen::Vector2d ab = q[b] - q[a], ac = q[c] - q[a];
        const double lengths = std::sqrt(ab.squaredNorm() * ac.squaredNorm());
        return lengths > 0 ? (ab.x() * ac.y() - ab.y() * ac.x()) / lengths : 0.0;
    };
    // Turns within rounding of straight count as straight (the corners are rounded into the plane).
    constexpr double kStraight = 1e-12;
    std::vector<std::size_t> next(n), prev(n);
    for (std::size_t i = 0; i < n; ++i) {
        next[i] = (i + 1) % n;
        prev[i] = (i + n - 1) % n;
    }
    std::size_t work = 0;
    const std::size_t work_bound = kEarClippingWorkPerCorner * n;
    // An ear: a convex corner whose triangle holds no other corner (only reflex ones can be in it).
    auto is_ear = [&](std::size_t i) {
        const std::size_t a = prev[i], c = next[i];
        if (!(turn(a, i, c) > kStraight)) return false;
        for (std::size_t j = next[c]; j != a; j = next[j]) {
            ++work;
            if (turn(prev[j], j, next[j]) > kStraight) continue;
            if (turn(a, i, j) >= -kStraight && turn(i, c, j) >= -kStraight && turn(c, a, j) >= -kStraight)
                return false;
        }
        return true;
    };
    Eigen::Index row = 0;
    auto emit = [&](std::size_t a, std::size_t b, std::size_t c) {
        fan.row(row++) << corners[a], corners[b], corners[c];
    };
    std::size_t remaining = n, i = 1, tried = 0;
    while (remaining > 3 && tried < remaining && work <= work_bound) {
        if (is_ear(i)) {
            emit(prev[i], i, next[i]);
            next[prev[i]] = next[i];
            prev[next[i]] = prev[i];
            i = next[i];
            --remaining;
            tried = 0;
        } else {
            i = next[i];
            ++tried;
        }
    }
    // The last triangle, or the rest of a polygon without ears (not simple) as a fan.
    for (std::size_t j = i; next[j] != prev[i]; j = next[j]) emit(prev[i], j, next[j]);
    return true;
}

}  // namespace

TriangleMesh MeshBuilder::finish(ReadReport& report) const {
    using RowMajorX3d = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;
    using RowMajorX3i = Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor>;
    TriangleMesh mesh;
    const auto n_vertices = static_cast<Eigen::Index>(xyz_.size() / 3);
    const auto n_triangles = static_cast<Eigen::Index>(triangles_.size() / 3);
    mesh.V = Eigen::Map<const RowMajorX3d>(xyz_.data(), n_vertices, 3);
    mesh.F = Eigen::Map<const RowMajorX3i>(triangles_.data(), n_triangles, 3);
    for (const PolygonFan& polygon : polygon_fans_) {
        const auto rows = static_cast<Eigen::Index>(polygon.corners) - 2;
        report.ear_clipped_polygons +=
            unfold_polygon(mesh.V, mesh.F.middleRows(static_cast<Eigen::Index>(polygon.first_triangle), rows));
    }
    report.file_vertices = num_vertices();
    report.file_faces = faces_;
    report.polygons = polygons_;
    report.polygon_triangles = polygon_triangles_;
    return mesh;
}

// ---- OutputFile ------------------------------------------------------------------------------

void throw_io(const std::string& file, std::string_view what, int error_number) {
    throw IoError(file + ": " + std::string(what) + ": " + std::strerror(error_number));
}

OutputFile::OutputFile(const std::filesystem::path& path, bool gzip, std::string name_for_errors)
    : name_(name_for_errors.empty() ? path.string() : std::move(name_for_errors)) {
    if (gzip) gzip_ = std::make_unique<GzipEncoder>();
    buffer_.reserve(kFlushSize + 64);
    // Opened last, so that a throwing constructor leaves no file behind. "x": fail rather than
    // clobber anything that is already there under this name.
    file_ = std::fopen(path.c_str(), "wbx");
    if (file_ == nullptr) throw_io(name_, "cannot create file", errno);
}

OutputFile::~OutputFile() {
    if (file_ != nullptr) std::fclose(file_);
}

void OutputFile::write_raw(std::string_view bytes) {
    if (std::fwrite(bytes.data(), 1, bytes.size(), file_) != bytes.size()) {
        throw_io(name_, "write failed", errno);
    }
}

void OutputFile::flush(bool finish) {
    if (gzip_) {
        compressed_.clear();
        gzip_->compress(buffer_, finish, compressed_);
        write_raw(compressed_);
    } else {
        write_raw(buffer_);
    }
    buffer_.clear();
}

void OutputFile::close() {
    flush(true);
    std::FILE* file = std::exchange(file_, nullptr);
    if (std::fclose(file) != 0) throw_io(name_, "write failed", errno);
}

namespace {
// A name that no other writer (thread or process) uses at the same time.
std::filesystem::path temporary_path_for(const std::filesystem::path& path) {
    static std::atomic<unsigned long> counter{0};
    std::filesystem::path temporary = path;
    temporary += ".tmp-" + std::to_string(::getpid()) + "-" + std::to_string(counter++);
    return temporary;
}
}  // namespace

void write_atomically(const std::filesystem::path& path, bool gzip,
                      const std::function<void(OutputFile&)>& write) {
    const std::filesystem::path temporary = temporary_path_for(path);
    // Recorded before it exists, so that a signal at any moment finds it (see TemporaryFiles).
    struct Recorded {
        int slot;
        ~Recorded() { TemporaryFiles::release(slot); }
    } recorded{TemporaryFiles::add(temporary)};
    OutputFile out(temporary, gzip, path.string());  // on failure nothing has been created
    try {
        write(out);
        out.close();
        std::error_code ec;
        std::filesystem::rename(temporary, path, ec);
        if (ec) {
            throw IoError(path.string() + ": cannot rename the temporary file over it: " + ec.message());
        }
    } catch (...) {
        std::error_code ignored;
        std::filesystem::remove(temporary, ignored);
        throw;
    }
}

}  // namespace io

// ---- reading ---------------------------------------------------------------------------------

namespace {

std::string lowercase(std::string text) {
    std::transform(text.begin(), text.end(), text.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return text;
}

bool ends_with(std::string_view text, std::string_view suffix) {
    return text.size() >= suffix.size() && text.substr(text.size() - suffix.size()) == suffix;
}

bool is_blank_text(std::string_view bytes) {
    return std::all_of(bytes.begin(), bytes.end(),
                       [](unsigned char c) { return std::isspace(c) != 0; });
}

}  // namespace

MeshFormat format_from_path(const std::filesystem::path& path, bool* compressed) {
    std::string name = lowercase(path.filename().string());
    const bool gz = ends_with(name, ".gz");
    if (gz) name.resize(name.size() - 3);
    const std::string extension = lowercase(std::filesystem::path(name).extension().string());
    MeshFormat format{};
    if (extension == ".obj") {
        format = MeshFormat::obj;
    } else if (extension == ".off") {
        format = MeshFormat::off;
    } else if (extension == ".ply") {
        format = MeshFormat::ply;
    } else if (extension == ".stl") {
        format = MeshFormat::stl;
    } else {
        throw UnsupportedFormatError(path.string() +
                                     ": unknown mesh file extension (expected .obj, .off, .ply "
                                     "or .stl, optionally followed by .gz)");
    }
    if (compressed != nullptr) *compressed = gz;
    return format;
}

TriangleMesh parse_mesh(std::string_view bytes, MeshFormat format, std::string_view name,
                        ReadReport* report) {
    // An empty file is never a mesh: most likely a failed download or export.
    if (is_blank_text(bytes)) throw ParseError(std::string(name) + ": empty file");
    ReadReport local;
    ReadReport& r = report != nullptr ? *report : local;
    r = ReadReport{};
    r.format = format;
    switch (format) {
        case MeshFormat::obj: return io::parse_obj(bytes, name, r);
        case MeshFormat::off: return io::parse_off(bytes, name, r);
        case MeshFormat::ply: return io::parse_ply(bytes, name, r);
        case MeshFormat::stl: return io::parse_stl(bytes, name, r);
    }
    throw UnsupportedFormatError(std::string(name) + ": unknown MeshFormat value");
}

TriangleMesh read_mesh(const std::filesystem::path& path, ReadReport* report) {
    bool compressed = false;
    const MeshFormat format = format_from_path(path, &compressed);
    const std::string name = path.string();
    const std::size_t max_bytes = io::max_text_bytes();
    std::string bytes = io::read_file(path, max_bytes);
    if (compressed) bytes = io::gunzip(bytes, name, max_bytes);
    TriangleMesh mesh = parse_mesh(bytes, format, name, report);
    if (report != nullptr) report->compressed = compressed;
    return mesh;
}

// ---- writing ---------------------------------------------------------------------------------

namespace {

bool is_ply_identifier(std::string_view name) {
    auto is_start = [](unsigned char c) { return std::isalpha(c) != 0 || c == '_'; };
    auto is_rest = [](unsigned char c) { return std::isalnum(c) != 0 || c == '_'; };
    return !name.empty() && is_start(static_cast<unsigned char>(name[0])) &&
           std::all_of(name.begin() + 1, name.end(),
                       [&](char c) { return is_rest(static_cast<unsigned char>(c)); });
}

// The format write_mesh writes for `path`, or what it rejects about the name alone.
MeshFormat writable_format(const std::filesystem::path& path, bool with_vertex_fields, bool* compressed) {
    const MeshFormat format = format_from_path(path, compressed);
    if (format == MeshFormat::stl) {
        throw UnsupportedFormatError(path.string() + ": writing STL is not supported (use OBJ, OFF or PLY)");
    }
    if (with_vertex_fields && format != MeshFormat::ply) {
        throw InvalidArgumentError(path.string() + ": vertex fields can only be written to PLY files");
    }
    return format;
}

// Everything else write_mesh promises to reject before it creates any file.
void check_writable(const std::string& name, const TriangleMesh& mesh, const WriteOptions& options) {
    auto reject = [&](const std::string& what) { throw InvalidArgumentError(name + ": " + what); };
    if (mesh.V.rows() > INT_MAX) reject("too many vertices for int indices");
    for (std::size_t i = 0; i < options.vertex_fields.size(); ++i) {
        const VertexField& field = options.vertex_fields[i];
        if (!is_ply_identifier(field.name) || field.name == "x" || field.name == "y" ||
            field.name == "z") {
            reject("vertex field name " + io::quoted(field.name) +
                   " is not a PLY identifier other than x, y, z");
        }
        for (std::size_t j = 0; j < i; ++j) {
            if (options.vertex_fields[j].name == field.name) {
                reject("vertex field name " + io::quoted(field.name) + " used twice");
            }
        }
        if (field.values.size() != mesh.V.rows()) {
            reject("vertex field " + io::quoted(field.name) + " has " +
                   std::to_string(field.values.size()) + " values for " +
                   std::to_string(mesh.V.rows()) + " vertices");
        }
    }
    for (Eigen::Index f = 0; f < mesh.F.rows(); ++f) {
        for (int k = 0; k < 3; ++k) {
            const int index = mesh.F(f, k);
            if (index < 0 || index >= mesh.V.rows()) {
                reject("face " + std::to_string(f) + " has vertex index " + std::to_string(index) +
                       " out of range [0, " + std::to_string(mesh.V.rows()) + ")");
            }
        }
    }
}

}  // namespace

void write_mesh(const std::filesystem::path& path, const TriangleMesh& mesh,
                const WriteOptions& options) {
    bool compressed = false;
    const MeshFormat format = writable_format(path, !options.vertex_fields.empty(), &compressed);
    check_writable(path.string(), mesh, options);

    io::write_atomically(path, compressed, [&](io::OutputFile& out) {
        switch (format) {
            case MeshFormat::obj: io::write_obj(mesh, out); break;
            case MeshFormat::off: io::write_off(mesh, out); break;
            case MeshFormat::ply: io::write_ply(mesh, options.vertex_fields, options.ply_ascii, out); break;
            case MeshFormat::stl: break;  // rejected above
        }
    });
}

void write_text_file(const std::filesystem::path& path, std::string_view text) {
    io::write_atomically(path, path.extension() == ".gz", [&](io::OutputFile& out) { out.write(text); });
}

void check_text_output(const std::filesystem::path& path) {
    // The temporary file goes beside `path`: its folder must exist and take new files, and the
    // rename must not meet a folder of that name.
    const std::filesystem::path folder = path.has_parent_path() ? path.parent_path() : ".";
    if (::access(folder.c_str(), W_OK | X_OK) != 0) io::throw_io(path.string(), "cannot create file", errno);
    std::error_code ignored;
    if (std::filesystem::is_directory(path, ignored)) io::throw_io(path.string(), "cannot create file", EISDIR);
}

void check_mesh_output(const std::filesystem::path& path, bool with_vertex_fields) {
    writable_format(path, with_vertex_fields, nullptr);
    check_text_output(path);
}

}  // namespace sdmesh
