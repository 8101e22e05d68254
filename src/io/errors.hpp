#pragma once
// How the readers word their ParseErrors, so that every format says "where" the same way:
//   text formats:   "<file>:<line>: <what>"
//   binary formats: "<file>: <element> <index>: <what>"
// Messages are always one line; tokens from the file are quoted and cleaned by quoted().
// IoErrors read "<file>: <what>: <the system's reason>".

#include <string>
#include <string_view>

namespace sdmesh::io {

[[noreturn]] void throw_at_line(std::string_view file, long long line, std::string_view what);
[[noreturn]] void throw_at_element(std::string_view file, std::string_view element, long long index,
                                   std::string_view what);

/// \throws IoError for `file`, the reason being strerror(error_number).
[[noreturn]] void throw_io(const std::string& file, std::string_view what, int error_number);

/// A token from the file, in quotes, cut to a readable length, control bytes replaced by '?'
/// (binary garbage must not break the one-line message).
std::string quoted(std::string_view token);

}  // namespace sdmesh::io
