#pragma once
// Line-aware tokenizer over an in-memory text, shared by the text readers.
// Every error it raises names the source and the 1-based line.

#include <icrkit/core/error.hpp>

#include <charconv>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <string>
#include <string_view>
#include <system_error>
#include <type_traits>

namespace icrkit::io::detail {

inline bool isBlank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v'; }

/// Parses the whole token as a number of type T; false when it is not one.
template <typename T>
bool parseNumber(std::string_view token, T& value) {
  if (token.empty()) return false;
  const char* first = token.data();
  const char* last = token.data() + token.size();
  if (*first == '+') ++first;  // from_chars rejects a leading '+', files use it
  if constexpr (std::is_floating_point_v<T>) {
    // from_chars accepts "nan"/"inf"; they are read here and rejected by the
    // callers that require finite values, with a precise message.
    auto [ptr, ec] = std::from_chars(first, last, value, std::chars_format::general);
    if (ec == std::errc::result_out_of_range) {
      // Subnormal or overflowing literals: strtod gives the nearest value.
      std::string copy(first, last);
      char* end = nullptr;
      value = static_cast<T>(std::strtod(copy.c_str(), &end));
      return end == copy.c_str() + copy.size();
    }
    return ec == std::errc() && ptr == last;
  } else {
    auto [ptr, ec] = std::from_chars(first, last, value);
    return ec == std::errc() && ptr == last;
  }
}

class TextScanner {
public:
  TextScanner(std::string_view text, const std::string& source, std::size_t first_line = 1)
      : text_(text), source_(source), line_(first_line) {}

  const std::string& source() const { return source_; }
  std::size_t line() const { return line_; }
  std::size_t offset() const { return pos_; }
  bool atEnd() const { return pos_ >= text_.size(); }

  /// Next whitespace-separated token, crossing line ends; empty at the end.
  std::string_view nextToken() {
    skipWhitespace(true);
    return takeToken();
  }

  /// Next token on the current line; empty when the line has no more.
  std::string_view nextTokenOnLine() {
    skipWhitespace(false);
    return takeToken();
  }

  /// The rest of the current line (without its line end), moving past it.
  std::string_view restOfLine() {
    std::size_t start = pos_;
    while (pos_ < text_.size() && text_[pos_] != '\n') ++pos_;
    std::string_view rest = text_.substr(start, pos_ - start);
    if (!rest.empty() && rest.back() == '\r') rest.remove_suffix(1);
    if (pos_ < text_.size()) {
      ++pos_;
      ++line_;
    }
    return rest;
  }

  /// Reads the next token (crossing lines) as T or throws, naming `what`.
  template <typename T>
  T expectNumber(const std::string& what) {
    std::string_view token = nextToken();
    if (token.empty()) fail("unexpected end of data, expected " + what);
    T value{};
    if (!parseNumber(token, value)) fail("expected " + what + ", found '" + clip(token) + "'");
    return value;
  }

  [[noreturn]] void fail(const std::string& detail) const {
    throw InputError(source_, "line " + std::to_string(line_), detail);
  }

  /// A token shortened for an error message.
  static std::string clip(std::string_view token) {
    constexpr std::size_t max_length = 40;
    std::string s(token.substr(0, max_length));
    for (char& c : s)
      if (static_cast<unsigned char>(c) < 32 || static_cast<unsigned char>(c) > 126) c = '?';
    if (token.size() > max_length) s += "...";
    return s;
  }

private:
  void skipWhitespace(bool cross_lines) {
    while (pos_ < text_.size()) {
      char c = text_[pos_];
      if (c == '\n') {
        if (!cross_lines) return;
        ++line_;
      } else if (!isBlank(c)) {
        return;
      }
      ++pos_;
    }
  }
  std::string_view takeToken() {
    std::size_t start = pos_;
    while (pos_ < text_.size() && !isBlank(text_[pos_]) && text_[pos_] != '\n') ++pos_;
    return text_.substr(start, pos_ - start);
  }

  std::string_view text_;
  const std::string& source_;
  std::size_t line_;
  std::size_t pos_ = 0;
};

/// Splits a line into whitespace-separated tokens (no allocation beyond the vector).
template <typename Container>
void splitTokens(std::string_view line, Container& tokens) {
  tokens.clear();
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (isBlank(line[i]) || line[i] == '\n')) ++i;
    std::size_t start = i;
    while (i < line.size() && !isBlank(line[i]) && line[i] != '\n') ++i;
    if (i > start) tokens.push_back(line.substr(start, i - start));
  }
}

/// Shortest decimal text that reads back to exactly `value`.
inline std::string formatRoundTrip(double value) {
  char buffer[32];
  auto [ptr, ec] = std::to_chars(buffer, buffer + sizeof buffer, value);
  (void)ec;
  return std::string(buffer, ptr);
}

/// Appends the shortest round-trip text of `value` to `out`.
inline void appendRoundTrip(std::string& out, double value) {
  char buffer[32];
  auto [ptr, ec] = std::to_chars(buffer, buffer + sizeof buffer, value);
  (void)ec;
  out.append(buffer, ptr);
}
inline void appendRoundTrip(std::string& out, float value) {
  char buffer[32];
  auto [ptr, ec] = std::to_chars(buffer, buffer + sizeof buffer, value);
  (void)ec;
  out.append(buffer, ptr);
}

}  // namespace icrkit::io::detail
