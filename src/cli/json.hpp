#pragma once
// A minimal writer for the flat and nested JSON objects the CLI prints (keys keep their order).

#include <string>
#include <string_view>

namespace sdmesh::cli {

class JsonObject {
public:
    JsonObject& add(std::string_view key, long long value);
    JsonObject& add(std::string_view key, int value) { return add(key, static_cast<long long>(value)); }
    JsonObject& add(std::string_view key, double value);  ///< NaN and ±inf become null
    JsonObject& add(std::string_view key, bool value);
    JsonObject& add(std::string_view key, std::string_view value);
    JsonObject& add(std::string_view key, const char* value) { return add(key, std::string_view(value)); }
    JsonObject& add(std::string_view key, const JsonObject& nested);
    /// Appends the members of `other` (a flat union; keys are not checked for repeats).
    JsonObject& merge(const JsonObject& other);

    /// The object as text; `indent` > 0 puts one member per line.
    [[nodiscard]] std::string str(int indent = 2) const;

private:
    void add_raw(std::string_view key, std::string value);
    std::string members_;  // "\"key\": value" entries separated by '\n'
};

/// s as a JSON string literal, quotes included.
std::string json_quote(std::string_view s);

}  // namespace sdmesh::cli
