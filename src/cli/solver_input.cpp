#include "cli/solver_input.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <sstream>

#include "cli/commands.hpp"
#include "cli/reports.hpp"
#include "cli/shared_options.hpp"
#include "io/errors.hpp"
#include "io/memory_budget.hpp"
#include "io/whole_file.hpp"
#include "sdmesh/intrinsic.hpp"
#include "sdmesh/io.hpp"

namespace sdmesh::cli {

SolverChoices parse_solver_choices(Args& args) {
    SolverChoices choices{.mass = parse_mass(args)};
    choices.convert = parse_method(args, "--convert");
    choices.intrinsic = args.flag("--intrinsic");
    if (choices.convert && choices.intrinsic) throw UsageError("--convert and --intrinsic exclude each other");
    return choices;
}

namespace {

// The solvers' answers live on vertices of faces: a vertex in no face has no mass, no neighbour
// and no meaningful value (its Laplacian row is zero).
void reject_vertices_in_no_face(const TriangleMesh& mesh) {
    std::vector<char> in_face(static_cast<size_t>(mesh.num_vertices()), 0);
    for (Eigen::Index f = 0; f < mesh.F.rows(); ++f)
        for (int k = 0; k < 3; ++k)
            if (const int v = mesh.F(f, k); v >= 0 && v < mesh.num_vertices()) in_face[static_cast<size_t>(v)] = 1;
    const auto first = std::find(in_face.begin(), in_face.end(), 0);
    if (first == in_face.end()) return;
    throw InvalidMeshError("vertex " + std::to_string(first - in_face.begin()) + " is in no face (" +
                           std::to_string(std::count(in_face.begin(), in_face.end(), 0)) +
                           " such vertices); sdmesh repair drops them");
}

}  // namespace

SolverInput load_solver_input(const std::string& path, const SolverChoices& choices, JsonObject& report) {
    SolverInput input;
    about_file(path, [&] {
        input.mesh = read_mesh(path);
        reject_vertices_in_no_face(input.mesh);
        report.add("file", path);
        if (choices.convert) {
            ConversionResult converted = convert(input.mesh, {.method = *choices.convert});
            input.mesh = std::move(converted.mesh);
            report.add("mesh", "converted")
                .add("method", to_string(*choices.convert))
                .add("conversion_status", to_string(converted.report.status));
            if (converted.report.status != ConvertStatus::certified)
                input.shortfall = "the --convert " + std::string(to_string(*choices.convert)) + " mesh is " +
                                  not_certified_summary(converted.report) + "; sdmesh convert says more";
        }
        input.triangulation = Triangulation::from_mesh(input.mesh);
        if (choices.intrinsic) {
            IntrinsicResult idt = intrinsic_delaunay(input.triangulation);
            input.triangulation = std::move(idt.triangulation);
            report.add("mesh", "intrinsic").add("flips", idt.report.flips).add("flip_status", idt.report.status);
            input.shortfall = intrinsic_shortfall(idt.report);
        }
        if (!choices.convert && !choices.intrinsic) report.add("mesh", "extrinsic");
    });
    report.add("mass", choices.mass.name)
        .add("vertices", input.triangulation.num_vertices)
        .add("faces", input.triangulation.num_faces());
    return input;
}

std::vector<int> parse_vertex_list(const std::string& option, const std::string& text) {
    std::vector<int> vertices;
    std::istringstream in(text);
    for (std::string item; std::getline(in, item, ',');) {
        size_t end = 0;
        try {
            const long value = std::stol(item, &end);
            if (end == item.size() && value >= 0 && value <= 0x7fffffff) {
                vertices.push_back(static_cast<int>(value));
                continue;
            }
        } catch (const std::exception&) {
        }
        throw UsageError(option + " expects vertex indices separated by commas, got '" + text + "'");
    }
    if (vertices.empty()) throw UsageError(option + " expects at least one vertex index");
    return vertices;
}

void check_vertex_range(std::string_view command, std::string_view option, const std::vector<int>& vertices,
                        int num_vertices, const std::string& path) {
    for (const int v : vertices)
        if (v >= num_vertices)
            throw InvalidArgumentError(std::string(command) + ": " + std::string(option) + ": vertex " +
                                       std::to_string(v) + " is out of range [0, " + std::to_string(num_vertices) +
                                       ") of " + path);
}

Eigen::MatrixXd read_table(const std::string& path, int columns) {
    // Read whole within the cap of mesh files: a link to /dev/zero is refused, not read forever.
    std::istringstream in(io::read_file(path, io::max_text_bytes()));
    std::vector<double> values;
    int line_number = 0;
    for (std::string line; std::getline(in, line);) {
        ++line_number;
        if (line.find_first_not_of(" \t\r") == std::string::npos || line[line.find_first_not_of(" \t")] == '#')
            continue;
        std::istringstream fields(line);
        int count = 0;
        for (std::string field; fields >> field; ++count) {
            // from_chars, unlike stod, takes subnormal numbers; out-of-range ones are errors.
            const char* first = field.data() + (field.size() > 1 && field[0] == '+' && field[1] != '-');
            double value = 0;
            const auto [end, error] = std::from_chars(first, field.data() + field.size(), value);
            const bool parsed = error == std::errc() && end == field.data() + field.size();
            if (!parsed || !std::isfinite(value))
                throw ParseError(path + ":" + std::to_string(line_number) + ": " + io::quoted(field) + " is " +
                                 (error == std::errc::result_out_of_range ? "out of double range"
                                  : parsed                                ? "not finite"
                                                                          : "not a number"));
            values.push_back(value);
        }
        if (count != columns)
            throw ParseError(path + ":" + std::to_string(line_number) + ": " + std::to_string(count) +
                             " values, expected " + std::to_string(columns));
    }
    return Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
        values.data(), static_cast<Eigen::Index>(values.size()) / columns, columns);
}

}  // namespace sdmesh::cli
