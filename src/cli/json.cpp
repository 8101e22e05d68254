#include "cli/json.hpp"

#include <charconv>
#include <cmath>
#include <cstdio>

namespace sdmesh::cli {

std::string json_quote(std::string_view s) {
    std::string out = "\"";
    for (const char c : s) {
        switch (c) {
            case '"': out += "\\\""; break;
            case '\\': out += "\\\\"; break;
            case '\n': out += "\\n"; break;
            case '\t': out += "\\t"; break;
            default:
                if (static_cast<unsigned char>(c) < 0x20) {
                    char buffer[8];
                    std::snprintf(buffer, sizeof buffer, "\\u%04x", c);
                    out += buffer;
                } else {
                    out += c;
                }
        }
    }
    return out + "\"";
}

void JsonObject::add_raw(std::string_view key, std::string value) {
    if (!members_.empty()) members_ += '\n';
    members_ += json_quote(key) + ": " + value;
}

JsonObject& JsonObject::add(std::string_view key, long long value) {
    add_raw(key, std::to_string(value));
    return *this;
}

JsonObject& JsonObject::add(std::string_view key, double value) {
    if (!std::isfinite(value)) {
        add_raw(key, "null");
        return *this;
    }
    char buffer[32];
    const auto end = std::to_chars(buffer, buffer + sizeof buffer, value).ptr;  // shortest round trip
    add_raw(key, std::string(buffer, end));
    return *this;
}

JsonObject& JsonObject::add(std::string_view key, bool value) {
    add_raw(key, value ? "true" : "false");
    return *this;
}

JsonObject& JsonObject::add(std::string_view key, std::string_view value) {
    add_raw(key, json_quote(value));
    return *this;
}

JsonObject& JsonObject::add(std::string_view key, const JsonObject& nested) {
    add_raw(key, nested.str(0));
    return *this;
}

JsonObject& JsonObject::merge(const JsonObject& other) {
    if (!members_.empty() && !other.members_.empty()) members_ += '\n';
    members_ += other.members_;
    return *this;
}

std::string JsonObject::str(int indent) const {
    const std::string separator = indent > 0 ? ",\n" + std::string(static_cast<size_t>(indent), ' ') : ", ";
    std::string out = indent > 0 ? "{\n" + std::string(static_cast<size_t>(indent), ' ') : "{";
    for (const char c : members_) {
        if (c == '\n') out += separator;
        else out += c;
    }
    return out + (indent > 0 ? "\n}" : "}");
}

}  // namespace sdmesh::cli
