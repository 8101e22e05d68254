#pragma once
// Command-line arguments of one subcommand: positionals, `--name value` options and flags.

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

class Args {
public:
    Args(std::vector<std::string> words, std::string command)
        : words_(std::move(words)), used_(words_.size(), false), command_(std::move(command)) {}

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
            if (i + 1 >= words_.size()) throw UsageError(command_ + ": " + std::string(name) + " needs a value");
            used_[i] = used_[i + 1] = true;
            return words_[i + 1];
        }
        return std::nullopt;
    }

    /// The value of `--name` as a number.
    std::optional<double> number(std::string_view name) {
        const auto text = option(name);
        if (!text) return std::nullopt;
        try {
            size_t end = 0;
            const double value = std::stod(*text, &end);
            if (end == text->size()) return value;
        } catch (const std::exception&) {
        }
        throw UsageError(command_ + ": " + std::string(name) + " expects a number, got '" + *text + "'");
    }

    /// The value of `--name` as one of named choices, `fallback` when absent, e.g.
    /// choice("--boundary", {std::pair{"strict", X::strict}, std::pair{"free", X::free}}, X::strict).
    template <class Enum, size_t N>
    Enum choice(std::string_view name, const std::pair<const char*, Enum> (&choices)[N], Enum fallback) {
        const auto value = option(name);
        if (!value) return fallback;
        std::string names;
        for (const auto& [text, result] : choices) {
            if (*value == text) return result;
            names += names.empty() ? text : std::string("|") + text;
        }
        throw UsageError(command_ + ": " + std::string(name) + " must be " + names + ", got '" + *value + "'");
    }

    /// Throws the one-line usage error for required options that are missing, e.g.
    /// missing("--out DIR is", usage) -> "sdmesh operators: --out DIR is required; usage: ...".
    [[noreturn]] void missing(std::string_view what, std::string_view usage) const {
        throw UsageError(command_ + ": " + std::string(what) + " required; usage: " + std::string(usage));
    }

    /// The remaining words, in order, once options and flags are consumed; `expected` of them.
    std::vector<std::string> positionals(size_t expected, std::string_view usage) {
        std::vector<std::string> rest;
        for (size_t i = 0; i < words_.size(); ++i) {
            if (used_[i]) continue;
            if (words_[i].starts_with("--"))
                throw UsageError(command_ + ": unknown option " + words_[i] + "; usage: " + std::string(usage));
            rest.push_back(words_[i]);
        }
        if (rest.size() != expected)
            throw UsageError(command_ + ": expected " + std::to_string(expected) + " argument(s); usage: " +
                             std::string(usage));
        return rest;
    }

private:
    std::vector<std::string> words_;
    std::vector<bool> used_;
    std::string command_;
};

}  // namespace sdmesh::cli
