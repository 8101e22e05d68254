// `sdmesh decimate IN OUT`: a coarser self-Delaunay mesh (or a hierarchy of them) by edge collapses.

#include <cmath>
#include <filesystem>
#include <iostream>
#include <limits>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "cli/commands.hpp"
#include "cli/json.hpp"
#include "cli/reports.hpp"
#include "cli/shared_options.hpp"
#include "sdmesh/convert.hpp"
#include "sdmesh/decimate.hpp"
#include "sdmesh/io.hpp"

namespace sdmesh::cli {
namespace {

constexpr const char* kDecimateUsage =
    "sdmesh decimate IN OUT (--target-vertices N | --target-ratio R) [--max-error REL] [--boundary strict|free] "
    "[--convert-first] [--levels R1,R2,...] [--tolerance RAD] [--no-hausdorff] [--report FILE.json] [--progress]";

// "0.5,0.2" -> {0.5, 0.2}.
std::vector<double> parse_ratios(const std::string& text) {
    std::vector<double> ratios;
    std::stringstream in(text);
    for (std::string item; std::getline(in, item, ',');) {
        size_t end = 0;
        double value = 0;
        try {
            value = std::stod(item, &end);
        } catch (const std::exception&) {
            end = 0;
        }
        if (end == 0 || end != item.size() || !(value > 0 && value < 1))
            throw UsageError("--levels expects ratios in (0, 1) separated by commas, got '" + text + "'");
        ratios.push_back(value);
    }
    return ratios;
}

// out/name.obj.gz, level 2 -> out/name_level2.obj.gz (the extension starts at the name's first dot).
std::filesystem::path level_path(const std::filesystem::path& out, size_t level) {
    const std::string name = out.filename().string();
    const size_t dot = name.find('.');
    const std::string stem = name.substr(0, dot), extension = dot == std::string::npos ? "" : name.substr(dot);
    return out.parent_path() / (stem + "_level" + std::to_string(level) + extension);
}

}  // namespace

int run_decimate(Args& args) {
    DecimateOptions options;
    const std::optional<long long> target_vertices =
        args.whole_number("--target-vertices", 1, std::numeric_limits<int>::max());
    const std::optional<double> target_ratio = args.number("--target-ratio");
    if (target_vertices.has_value() == target_ratio.has_value())
        args.missing("exactly one of --target-vertices N and --target-ratio R is", kDecimateUsage);
    options.target_vertices = target_vertices.value_or(0);
    options.target_ratio = target_ratio.value_or(options.target_ratio);
    options.max_error = args.number("--max-error").value_or(options.max_error);
    options.tolerance = args.number("--tolerance").value_or(options.tolerance);
    options.boundary = parse_boundary(args).value_or(options.boundary);
    const bool convert_first = args.flag("--convert-first");
    const std::optional<std::string> levels_text = args.option("--levels");
    options.progress = args.flag("--progress");
    options.measure_hausdorff = !args.flag("--no-hausdorff");
    const std::optional<std::string> report_path = args.option("--report");
    const auto paths = args.positionals(2, kDecimateUsage);

    if (options.progress) std::cerr << "decimate: reading " << paths[0] << std::endl;
    TriangleMesh mesh = read_mesh(paths[0]);
    check_mesh_output(paths[1]);  // before the decimation, not after it; levels go beside it
    if (report_path) check_text_output(*report_path);
    std::optional<ConversionReport> conversion;
    if (convert_first) {
        ConversionResult converted = about_file(paths[0], [&] {
            return convert(mesh, {.boundary = options.boundary, .tolerance = options.tolerance, .progress = options.progress});
        });
        if (converted.report.status != ConvertStatus::certified)
            throw InvalidArgumentError(paths[0] + ": --convert-first did not make it self-Delaunay (status " +
                                       std::string(to_string(converted.report.status)) + ", " +
                                       std::to_string(converted.report.certificate.non_delaunay_edges) +
                                       " non-Delaunay edges left), so it cannot be decimated; see sdmesh convert");
        mesh = std::move(converted.mesh);
        conversion = converted.report;
    }
    // Level ratios are of the mesh being decimated, as the target ratio is.
    if (levels_text)
        for (double ratio : parse_ratios(*levels_text))
            options.levels.push_back(std::llround(ratio * mesh.num_vertices()));
    const DecimateResult result = about_file(paths[0], [&] { return decimate(mesh, options); });
    if (options.progress) std::cerr << "decimate: writing " << paths[1] << std::endl;
    write_mesh(paths[1], result.mesh);
    std::vector<std::string> level_files;
    for (size_t i = 0; i < result.levels.size(); ++i) {
        level_files.push_back(level_path(paths[1], i + 1).string());
        write_mesh(level_files.back(), result.levels[i]);
    }

    const DecimateReport& r = result.report;
    JsonObject levels_json;
    for (size_t i = 0; i < result.levels.size(); ++i) levels_json.add(level_files[i], result.levels[i].num_vertices());
    JsonObject json;
    json.add("input", paths[0]).add("output", paths[1]);
    if (conversion)
        json.add("conversion_splits", conversion->splits).add("converted_vertices", conversion->output_vertices);
    json.merge(decimation_counts_json(options, r))
        .add("levels", levels_json)
        .merge(decimation_outcome_json(options, r));
    const std::string text = json.str() + "\n";
    if (report_path) write_text_file(*report_path, text);
    std::cout << text;
    if (r.status == DecimateStatus::stalled)
        std::cerr << "sdmesh decimate: " << paths[1] << ": stalled at " << r.output_vertices << " vertices (target "
                  << r.target_vertices << ")\n";
    if (!r.certificate.self_delaunay) {
        std::cerr << "sdmesh decimate: " << paths[1] << ": the output is not self-Delaunay\n";
        return kFellShort;
    }
    return kSuccess;
}

}  // namespace sdmesh::cli
