#pragma once
// Options that several commands read alike.

#include <optional>
#include <string_view>
#include <utility>

#include "cli/args.hpp"
#include "sdmesh/convert.hpp"
#include "sdmesh/delaunay.hpp"

namespace sdmesh::cli {

/// --boundary strict|free (check, convert, decimate), if given.
inline std::optional<BoundaryPolicy> parse_boundary(Args& args) {
    return args.choice("--boundary",
                       {std::pair{"strict", BoundaryPolicy::strict}, std::pair{"free", BoundaryPolicy::free}});
}

/// A conversion method, split|hybrid|flip (convert's --method, the solvers' --convert), if given.
inline std::optional<ConvertMethod> parse_method(Args& args, std::string_view name) {
    return args.choice(name, {std::pair{"split", ConvertMethod::split}, std::pair{"hybrid", ConvertMethod::hybrid},
                              std::pair{"flip", ConvertMethod::flip}});
}

}  // namespace sdmesh::cli
