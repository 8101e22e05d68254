#pragma once
// The subcommands of the `sdmesh` executable. Each returns the process exit code and throws
// sdmesh::Error or UsageError, which main() maps to exit codes.

#include <cstdio>
#include <initializer_list>
#include <string>
#include <string_view>

#include "cli/args.hpp"
#include "sdmesh/error.hpp"

namespace sdmesh::cli {

/// Exit codes, documented in README.md.
enum ExitCode : int {
    kSuccess = 0,
    /// The outputs are written but fall short of what was asked, with one line on stderr saying
    /// how: not self-Delaunay (check, convert, decimate), flip budget exhausted (intrinsic), not
    /// converged (eigs), or a solver's --convert or --intrinsic mesh not Delaunay.
    kFellShort = 1,
    kUsage = 2,
    kIoError = 3,
    kUnsupportedFormat = 4,
    kParseError = 5,
    kInvalidMesh = 6,
    kInvalidArgument = 7,
    kNumericalError = 8,
    kInternalError = 70,
};

/// Runs f(), naming `path` in the message of an InvalidMeshError or NumericalError it throws (the
/// library's messages name elements, the command knows the file).
template <class F>
decltype(auto) about_file(const std::string& path, F&& f) {
    try {
        return f();
    } catch (const InvalidMeshError& e) {
        throw InvalidMeshError(path + ": " + e.what());
    } catch (const NumericalError& e) {
        throw NumericalError(path + ": " + e.what());
    }
}

/// kSuccess, or kFellShort after a line "sdmesh COMMAND: PATH: MESSAGE" on stderr for each of
/// `shortfalls` that is not empty: how the outputs, written by then, fall short.
inline int exit_code_after(std::string_view command, const std::string& path,
                           std::initializer_list<std::string> shortfalls) {
    int code = kSuccess;
    for (const std::string& message : shortfalls)
        if (!message.empty()) {
            std::fprintf(stderr, "sdmesh %.*s: %s: %s\n", static_cast<int>(command.size()), command.data(),
                         path.c_str(), message.c_str());
            code = kFellShort;
        }
    return code;
}

int run_info(Args& args);
int run_check(Args& args);
int run_repair(Args& args);
int run_convert(Args& args);
int run_decimate(Args& args);
int run_operators(Args& args);
int run_intrinsic(Args& args);
int run_eigs(Args& args);
int run_geodesic(Args& args);
int run_poisson(Args& args);
int run_heat(Args& args);

}  // namespace sdmesh::cli
