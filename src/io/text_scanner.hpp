#pragma once
// A cursor over the text of OBJ, OFF, ascii PLY and ascii STL files.
//
// The whole (decompressed) file is in memory; the scanner walks it in place, parses numbers with
// std::from_chars (locale-independent, exact, no allocation) and counts lines so that every error
// names "<file>:<line>". Formats are line-oriented: a record is read from one line, then
// next_line() skips whatever is left on it (colors, texture indices, comments).
// A line ends with LF, CR LF or a lone CR (classic Mac OS), as Python's universal newlines.

#include <algorithm>
#include <charconv>
#include <cstring>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <system_error>

#include "io/errors.hpp"

namespace sdmesh::io {

/// `text` without a leading UTF-8 byte order mark, which Windows editors and exporters write.
inline std::string_view without_utf8_bom(std::string_view text) {
    constexpr std::string_view kBom = "\xEF\xBB\xBF";
    return text.substr(0, kBom.size()) == kBom ? text.substr(kBom.size()) : text;
}

class TextScanner {
public:
    /// `hash_comments`: '#' starts a comment that runs to the end of the line (OBJ, OFF).
    /// A byte order mark at the start of `text` is skipped.
    TextScanner(std::string_view text, std::string_view file, bool hash_comments)
        : pos_(without_utf8_bom(text).data()), end_(text.data() + text.size()), file_(file),
          hash_comments_(hash_comments) {}

    [[nodiscard]] bool at_end() const { return pos_ == end_; }
    [[nodiscard]] long long line() const { return line_; }
    [[nodiscard]] const char* position() const { return pos_; }
    [[nodiscard]] std::size_t remaining() const { return static_cast<std::size_t>(end_ - pos_); }

    /// Skips blanks on the current line. A backslash right before the newline continues the line
    /// (OBJ allows it; elsewhere it does no harm).
    void skip_blanks() {
        while (pos_ != end_) {
            if (is_blank(*pos_)) {
                ++pos_;
            } else if (*pos_ == '\\' && pos_ + 1 != end_ && is_line_break(pos_[1])) {
                ++pos_;
                skip_line_break();
            } else {
                break;
            }
        }
    }

    /// At a newline, a comment or the end of the text (call after skip_blanks()).
    [[nodiscard]] bool at_line_end() const {
        return pos_ == end_ || is_line_break(*pos_) || (hash_comments_ && *pos_ == '#');
    }

    /// Moves to the start of the next line, dropping the rest of this one.
    void next_line() {
        pos_ = std::min(next_of('\n', next_lf_), next_of('\r', next_cr_));
        skip_line_break();
    }

    /// Skips blank and comment-only lines; afterwards the cursor is on the first token of a line.
    /// Returns false when the text ends first.
    bool skip_empty_lines() {
        for (;;) {
            skip_blanks();
            if (!at_line_end()) return true;
            if (at_end()) return false;
            next_line();
        }
    }

    /// Requires that nothing but blanks or a comment is left on the line, then moves past it.
    void finish_line() {
        skip_blanks();
        if (!at_line_end()) fail("unexpected " + quoted(token()) + " at the end of the line");
        next_line();
    }

    /// The next whitespace-delimited token on the line; empty at the end of the line. A '#' that
    /// continues an old MSVC spelling of infinity or NaN ("-1.#IND00") does not start a comment.
    std::string_view token() {
        skip_blanks();
        const char* first = pos_;
        for (;;) {
            while (pos_ != end_ && !is_delimiter(*pos_)) ++pos_;
            if (pos_ == end_ || *pos_ != '#') [[likely]]
                break;
            if (!msvc_non_finite({first, static_cast<std::size_t>(end_ - first)})) break;
            ++pos_;
        }
        return {first, static_cast<std::size_t>(pos_ - first)};
    }

    /// The next token as a double; `what` names the expected value in the error message.
    double read_double(std::string_view what) {
        std::string_view tok = token();
        if (tok.empty()) fail("expected " + std::string(what));
        return parse_double(tok);
    }

    /// The next token as a decimal integer.
    long long read_integer(std::string_view what) {
        std::string_view tok = token();
        if (tok.empty()) fail("expected " + std::string(what));
        long long value = 0;
        if (parse_integer_prefix(tok, value) != tok.size()) fail("bad integer " + quoted(tok));
        return value;
    }

    /// Parses a whole token as a double. Non-finite spellings (nan, inf) are accepted: checking
    /// them is validation's job. Values out of double range (1e999) are errors.
    double parse_double(std::string_view tok) const {
        const char* first = tok.data();
        const char* last = first + tok.size();
        first = skip_plus(first, last);
        double value = 0;
        auto [ptr, ec] = std::from_chars(first, last, value);
        if (ec == std::errc::result_out_of_range) fail("number out of double range " + quoted(tok));
        if (ec == std::errc() && ptr == last) return value;
        if (const auto msvc = msvc_non_finite(tok); msvc && tok.find_first_not_of('0', msvc->length) == tok.npos)
            return msvc->value;
        fail("bad number " + quoted(tok));
    }

    /// Parses a decimal integer at the start of `tok`; returns how many characters it used
    /// (0 when there is no integer there). Overflow is an error.
    std::size_t parse_integer_prefix(std::string_view tok, long long& value) const {
        const char* first = tok.data();
        const char* last = first + tok.size();
        first = skip_plus(first, last);
        auto [ptr, ec] = std::from_chars(first, last, value);
        if (ec == std::errc::result_out_of_range) fail("integer out of range " + quoted(tok));
        if (ec != std::errc()) return 0;
        return static_cast<std::size_t>(ptr - tok.data());
    }

    /// Names the record being read (ascii PLY), for error messages:
    /// "<file>:<line>: <element> <index>: <what>".
    void set_location(std::string_view element, long long index) {
        element_ = element;
        index_ = index;
    }

    [[noreturn]] void fail(std::string_view what) const {
        if (element_.empty()) throw_at_line(file_, line_, what);
        throw_at_line(file_, line_, std::string(element_) + " " + std::to_string(index_) + ": " + std::string(what));
    }

private:
    // Old MSVC runtimes print infinity as "1.#INF", NaN as "1.#IND", "1.#QNAN" or "1.#SNAN",
    // signed and padded with zeros ("-1.#IND00"). The value such a spelling at the start of
    // `text` stands for, and its length without the padding.
    struct MsvcNonFinite {
        double value;
        std::size_t length;
    };
    static std::optional<MsvcNonFinite> msvc_non_finite(std::string_view text) {
        const std::size_t sign = !text.empty() && (text[0] == '-' || text[0] == '+') ? 1 : 0;
        if (text.substr(sign, 3) != "1.#") return std::nullopt;
        const double unit = sign == 1 && text[0] == '-' ? -1.0 : 1.0;
        constexpr double inf = std::numeric_limits<double>::infinity(), nan = std::numeric_limits<double>::quiet_NaN();
        for (const auto& [word, value] : {std::pair{std::string_view("INF"), inf}, std::pair{std::string_view("IND"), nan},
                                          std::pair{std::string_view("QNAN"), nan}, std::pair{std::string_view("SNAN"), nan}})
            if (text.substr(sign + 3).starts_with(word)) return MsvcNonFinite{unit * value, sign + 3 + word.size()};
        return std::nullopt;
    }
    // from_chars rejects a leading '+', which some writers emit; "+-1" stays an error.
    static const char* skip_plus(const char* first, const char* last) {
        return last - first >= 2 && first[0] == '+' && first[1] != '-' ? first + 1 : first;
    }
    static bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\v' || c == '\f'; }
    static bool is_line_break(char c) { return c == '\n' || c == '\r'; }
    bool is_delimiter(char c) const { return is_blank(c) || is_line_break(c) || (hash_comments_ && c == '#'); }
    // The first `c` at or after pos_ (end_ if none). `found` keeps the last answer, so that each
    // character is searched for once over the whole text, not once a line (a text of CR lines
    // has no LF: searching for one from every line would be quadratic).
    const char* next_of(char c, const char*& found) const {
        if (found == nullptr || found < pos_) {
            const void* at = std::memchr(pos_, c, remaining());
            found = at != nullptr ? static_cast<const char*>(at) : end_;
        }
        return found;
    }
    // From a line break (LF, CR LF or CR) or the end of the text, to the start of the next line.
    void skip_line_break() {
        if (pos_ == end_) return;
        if (*pos_ == '\r' && pos_ + 1 != end_ && pos_[1] == '\n') ++pos_;
        ++pos_;
        ++line_;
    }

    const char* pos_;
    const char* end_;
    std::string_view file_;
    bool hash_comments_;
    const char* next_lf_ = nullptr;  // see next_of()
    const char* next_cr_ = nullptr;
    long long line_ = 1;
    std::string_view element_;
    long long index_ = 0;
};

}  // namespace sdmesh::io
