#pragma once
// Numbers in messages: the shortest text that reads back as the same double ("0.5", "-1",
// "1e+300", "nan"), where std::to_string prints six decimals (1e-20 as "0.000000", 1e300 with
// 301 digits).

#include <charconv>
#include <string>

namespace sdmesh::detail {

inline std::string number_text(double value) {
    char text[32];
    const auto result = std::to_chars(text, text + sizeof text, value);
    return std::string(text, result.ptr);
}

}  // namespace sdmesh::detail
