// Splits text into whitespace-separated tokens and lines, counting lines for error messages.
#pragma once

#include <cstddef>
#include <string_view>

namespace omniview::cloud_io {

class TextCursor {
 public:
  explicit TextCursor(std::string_view text, size_t first_line = 1) : text_(text), line_(first_line) {}

  // Next token on any line; empty at the end.
  std::string_view token() {
    while (pos_ < text_.size() && is_space(text_[pos_])) {
      if (text_[pos_] == '\n') ++line_;
      ++pos_;
    }
    const size_t start = pos_;
    while (pos_ < text_.size() && !is_space(text_[pos_])) ++pos_;
    return text_.substr(start, pos_ - start);
  }
  // The rest of the current line without its end (\n or \r\n); moves past it.
  std::string_view line() {
    const size_t start = pos_;
    while (pos_ < text_.size() && text_[pos_] != '\n') ++pos_;
    std::string_view l = text_.substr(start, pos_ - start);
    if (pos_ < text_.size()) {
      ++pos_;
      ++line_;
    }
    if (!l.empty() && l.back() == '\r') l.remove_suffix(1);
    return l;
  }
  bool at_end() const { return pos_ >= text_.size(); }
  size_t offset() const { return pos_; }
  size_t line_number() const { return line_; }

  static bool is_space(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\f' || c == '\v'; }

 private:
  std::string_view text_;
  size_t pos_ = 0;
  size_t line_ = 1;
};

// Splits one line into words.
template <typename F>
void for_each_word(std::string_view line, F&& f) {
  size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && TextCursor::is_space(line[i])) ++i;
    const size_t start = i;
    while (i < line.size() && !TextCursor::is_space(line[i])) ++i;
    if (i > start) f(line.substr(start, i - start));
  }
}

}  // namespace omniview::cloud_io
