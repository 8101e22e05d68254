#pragma once
// Command-line arguments of one subcommand: positionals, `--name value` options and flags.

#include <cmath>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace sdmesh::cli {

/// A malformed command line (exit code 2).
class UsageError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// Its errors name the option and the value at fault; main() prefixes them with the command.
class Args {
public:
    explicit Args(std::vector<std::string> words) : words_(std::move(words)), used_(words_.size(), false) {}

    /// True if `--name` is present (consumed).
    bool flag(std::string_view name) {
        for (size_t i = 0; i < words_.size(); ++i)
            if (!used_[i] && words_[i] == name) return used_[i] = true;
        return false;
    }

    /// The value after `--name`, if present (both consumed).
    std::optional<std::string> option(std::string_view name) {
        for (size_t i = 0; i < words_.size(); ++i) {
            if (used_[i] || words_[i] != name) continue;
            if (i + 1 >= words_.size()) throw UsageError(std::string(name) + " needs a value");
            used_[i] = used_[i + 1] = true;
            return words_[i + 1];
        }
        return std::nullopt;
    }

    /// The value of `--name` as a number.
    std::optional<double> number(std::string_view name) {
        const auto text = option(name);
        if (!text) return std::nullopt;
        if (const auto value = parse_number(*text)) return value;
        throw UsageError(std::string(name) + " expects a number, got '" + *text + "'");
    }

    /// The value of `--name` as a whole number in [least, most] (a count, a budget).
    std::optional<long long> whole_number(std::string_view name, long long least, long long most) {
        const auto text = option(name);
        if (!text) return std::nullopt;
        // Doubles hold every whole number up to 2^53, far beyond any count the commands take.
        if (const auto value = parse_number(*text);
            value && *value == std::floor(*value) && *value >= double(least) && *value <= double(most))
            return static_cast<long long>(*value);
        throw UsageError(std::string(name) + " expects a whole number from " + std::to_string(least) + " to " +
                         std::to_string(most) + ", got '" + *text + "'");
    }

    /// The value of `--name` as one of named choices, if present, e.g.
    /// choice("--boundary", {std::pair{"strict", X::strict}, std::pair{"free", X::free}}).
    template <class Enum, size_t N>
    std::optional<Enum> choice(std::string_view name, const std::pair<const char*, Enum> (&choices)[N]) {
        const auto value = option(name);
        if (!value) return std::nullopt;
        std::string names;
        for (const auto& [text, result] : choices) {
            if (*value == text) return result;
            names += names.empty() ? text : std::string("|") + text;
        }
        throw UsageError(std::string(name) + " must be " + names + ", got '" + *value + "'");
    }

    /// Throws the one-line usage error for required options that are missing, e.g.
    /// missing("--out DIR is", usage) -> "--out DIR is required; usage: ...".
    [[noreturn]] static void missing(std::string_view what, std::string_view usage) {
        throw UsageError(std::string(what) + " required; usage: " + std::string(usage));
    }

    /// The remaining words, in order, once options and flags are consumed; `expected` of them.
    std::vector<std::string> positionals(size_t expected, std::string_view usage) {
        std::vector<std::string> rest;
        for (size_t i = 0; i < words_.size(); ++i) {
            if (used_[i]) continue;
            if (words_[i].starts_with("--"))
                throw UsageError("unknown option " + words_[i] + "; usage: " + std::string(usage));
            rest.push_back(words_[i]);
        }
        if (rest.size() != expected)
            throw UsageError("expected " + std::to_string(expected) + " argument(s); usage: " + std::string(usage));
        return rest;
    }

private:
    static std::optional<double> parse_number(const std::string& text) {
        try {
            size_t end = 0;
            const double value = std::stod(text, &end);
            if (end == text.size()) return value;
        } catch (const std::exception&) {
        }
        return std::nullopt;
    }

    std::vector<std::string> words_;
    std::vector<bool> used_;
};

}  // namespace sdmesh::cli
