// Conversion table: every corpus mesh through convert() with the split and hybrid configurations,
// one CSV row per (mesh, configuration), to measure vertex efficiency = added vertices / non-flat
// non-Delaunay input edges (lower bound 1.0 for split, ALGORITHMS.md §3; the split-interval rows
// also give the sharper per-mesh bound of ConversionReport::added_vertices_lower_bound, which
// holds for every conversion that moves nothing).
//   conversion_table --out DIR [--corpus DIR] [--max-faces N] [--quick]
// Writes DIR/conversion_table.csv; experiments/conversion_table/make_table.py turns it into markdown.
// Exit status: 0 all conversions ran (certified or not), 1 a conversion threw, 2 bad usage or input.

#include <algorithm>
#include <exception>
#include <filesystem>
#include <iostream>
#include <optional>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "sdmesh/convert.hpp"
#include "sdmesh/error.hpp"
#include "sdmesh/io.hpp"
#include "sdmesh/validate.hpp"
#include "study.hpp"

namespace fs = std::filesystem;

namespace {

constexpr int kQuickMaxFaces = 10000;  // --quick: meshes with fewer faces only

struct Config {
    const char* label;
    sdmesh::ConvertOptions options;
    bool quick;  ///< part of the --quick run
};

const std::vector<Config>& configs() {
    using sdmesh::ConvertMethod;
    using sdmesh::SplitRule;
    static const std::vector<Config> all = {
        {"split-interval",
         {.method = ConvertMethod::split, .split_rule = SplitRule::interval, .lower_bound = true},
         true},
        {"split-interval-no-trials",
         {.method = ConvertMethod::split, .split_rule = SplitRule::interval, .cascade_trials = 0}, false},
        {"split-interval-local-search",
         {.method = ConvertMethod::split, .split_rule = SplitRule::interval, .local_search = 1}, false},
        {"split-shell", {.method = ConvertMethod::split, .split_rule = SplitRule::shell}, false},
        {"hybrid-5", {.method = ConvertMethod::hybrid, .max_dihedral_deg = 5}, false},
        {"hybrid-10", {.method = ConvertMethod::hybrid, .max_dihedral_deg = 10}, true},
        {"hybrid-20", {.method = ConvertMethod::hybrid, .max_dihedral_deg = 20}, false},
    };
    return all;
}

// The mesh files of the corpus (any extension read_mesh knows), by name.
std::vector<fs::path> corpus_files(const fs::path& corpus) {
    std::vector<fs::path> files;
    for (const auto& entry : fs::directory_iterator(corpus)) {
        if (!entry.is_regular_file()) continue;
        try {
            sdmesh::format_from_path(entry.path());
            files.push_back(entry.path());
        } catch (const sdmesh::UnsupportedFormatError&) {
            // MANIFEST.md and the like
        }
    }
    std::sort(files.begin(), files.end());
    return files;
}

// Why convert() would refuse the mesh (its documented preconditions); empty when it would not.
std::string conversion_obstacle(const sdmesh::TriangleMesh& mesh) {
    const sdmesh::MeshInfo info = sdmesh::validate(mesh);
    if (std::string defect = sdmesh::first_defect(info); !defect.empty()) return defect;
    if (info.orientation_conflicts > 0)
        return std::to_string(info.orientation_conflicts) + " edges with inconsistent orientation";
    if (info.zero_area_faces > 0) return std::to_string(info.zero_area_faces) + " faces of zero area";
    return {};
}

std::string csv_field(std::string_view text) {
    if (text.find_first_of(",\"\n") == std::string_view::npos) return std::string(text);
    std::string quoted = "\"";
    for (const char c : text) {
        if (c == '"') quoted += '"';  // a quote inside a field is doubled
        quoted += c;
    }
    return quoted + "\"";
}

constexpr const char* kHeader =
    "mesh,faces,repaired,method,split_rule,max_dihedral_deg,local_search,cascade_trials,input_vertices,output_vertices,added_vertices,"
    "input_non_delaunay_edges,input_nonflat_non_delaunay_edges,vertex_efficiency,flips,splits,status,"
    "seconds,hausdorff_rel,output_non_delaunay_edges,output_negative_dual_cells,efficiency_lower_bound\n";

// The columns that name the row: mesh, faces, repaired (1: not manifold as read, converted after
// repair()), method, split_rule, max_dihedral_deg, local_search, cascade_trials.
std::string row_key(const std::string& mesh, int faces, bool repaired, const Config& config) {
    const bool hybrid = config.options.method == sdmesh::ConvertMethod::hybrid;
    std::ostringstream row;
    row << csv_field(mesh) << ',' << faces << ',' << (repaired ? 1 : 0) << ',' << sdmesh::to_string(config.options.method) << ','
        << sdmesh::to_string(config.options.split_rule) << ',';
    if (hybrid) row << config.options.max_dihedral_deg;  // split ignores the dihedral bound
    row << ',' << config.options.local_search << ',' << config.options.cascade_trials;
    return row.str();
}

// A row for a configuration that did not run: only the key and the status.
std::string status_row(const std::string& key, std::string_view status) {
    return key + ",,,,,,,,," + csv_field(status) + ",,,,,\n";
}

std::optional<double> vertex_efficiency(const sdmesh::ConversionReport& r) {
    if (r.input_nonflat_non_delaunay_edges == 0) return std::nullopt;
    return static_cast<double>(r.output_vertices - r.input_vertices) /
           static_cast<double>(r.input_nonflat_non_delaunay_edges);
}

std::string result_row(const std::string& key, const sdmesh::ConversionReport& r) {
    const auto efficiency = vertex_efficiency(r);
    const bool bounded = efficiency && r.added_vertices_lower_bound >= 0;
    // Counted like input_non_delaunay_edges: interior non-LD plus boundary-obtuse, since every
    // configuration here uses the (default) strict boundary policy.
    const long long output_non_delaunay = r.certificate.non_delaunay_edges + r.certificate.boundary_obtuse_edges;
    std::ostringstream row;
    row << key << ',' << r.input_vertices << ',' << r.output_vertices << ',' << r.output_vertices - r.input_vertices
        << ',' << r.input_non_delaunay_edges << ',' << r.input_nonflat_non_delaunay_edges << ',';
    if (efficiency) row << *efficiency;
    row << ',' << r.flips << ',' << r.splits << ',' << sdmesh::to_string(r.status) << ',' << r.seconds << ','
        << r.hausdorff_rel << ',' << output_non_delaunay << ',' << r.certificate.negative_dual_cells << ',';
    if (bounded)
        row << static_cast<double>(r.added_vertices_lower_bound) / static_cast<double>(r.input_nonflat_non_delaunay_edges);
    row << '\n';
    return row.str();
}

}  // namespace

int main(int argc, char** argv) {
    const study::Args options = study::parse_args(argc, argv, "conversion_table");
    if (!fs::is_directory(options.corpus)) {
        std::cerr << "conversion_table: no corpus folder " << options.corpus << (options.quick ? ", nothing to do" : "")
                  << "\n";
        return options.quick ? 0 : 2;  // ctest runs --quick; a machine without the corpus skips
    }
    const std::optional<long long> max_faces =
        options.quick ? std::optional<long long>(kQuickMaxFaces - 1) : options.max_faces;
    const fs::path csv_path = options.out / "conversion_table.csv";

    try {
        fs::create_directories(options.out);
        const std::vector<fs::path> files = corpus_files(options.corpus);
        std::string csv = kHeader;
        sdmesh::write_text_file(csv_path, csv);
        bool any_threw = false;
        for (size_t i = 0; i < files.size(); ++i) {
            const std::string name = files[i].filename().string();
            std::ostringstream where_stream;  // (not "[" + std::to_string: GCC 12 warns falsely, PR105651)
            where_stream << '[' << i + 1 << '/' << files.size() << "] " << name;
            const std::string where = where_stream.str();
            sdmesh::TriangleMesh mesh = sdmesh::read_mesh(files[i]);
            if (max_faces && mesh.num_faces() > *max_faces) {
                std::cerr << where << ": skipped, " << mesh.num_faces() << " faces > " << *max_faces << "\n";
                continue;
            }
            std::string obstacle = conversion_obstacle(mesh);
            const bool repaired = !obstacle.empty();
            if (repaired) {
                sdmesh::RepairReport report;
                mesh = sdmesh::repair(mesh, {}, &report);
                std::cerr << where << ": repaired (" << obstacle << "): merged " << report.merged_vertices
                          << " vertices, copied " << report.split_vertices << " non-manifold ones, re-wound "
                          << report.flipped_faces << " faces\n";
                obstacle = conversion_obstacle(mesh);
                if (!obstacle.empty()) std::cerr << where << ": skipped, still not convertible: " << obstacle << "\n";
            }
            for (const Config& config : configs()) {
                if (options.quick && !config.quick) continue;
                const std::string key = row_key(name, mesh.num_faces(), repaired, config);
                if (!obstacle.empty()) {
                    csv += status_row(key, "skipped: " + obstacle);
                    continue;
                }
                std::cerr << where << " (" << mesh.num_faces() << " faces) " << config.label << ":" << std::flush;
                try {
                    const sdmesh::ConversionReport r = sdmesh::convert(mesh, config.options).report;
                    const auto efficiency = vertex_efficiency(r);
                    std::cerr << ' ' << r.input_vertices << " -> " << r.output_vertices << " vertices, efficiency "
                              << (efficiency ? std::to_string(*efficiency) : std::string("n/a")) << ", "
                              << sdmesh::to_string(r.status) << ", " << r.seconds << " s\n";
                    csv += result_row(key, r);
                } catch (const sdmesh::Error& e) {
                    std::cerr << " FAILED: " << e.what() << "\n";
                    csv += status_row(key, std::string("error: ") + e.what());
                    any_threw = true;
                }
            }
            // Rewritten after every mesh so an interrupted full run keeps the rows it has.
            sdmesh::write_text_file(csv_path, csv);
        }
        std::cerr << "wrote " << csv_path.string() << "\n";
        return any_threw ? 1 : 0;
    } catch (const std::exception& e) {
        std::cerr << "conversion_table: " << e.what() << "\n";
        return 2;
    }
}
