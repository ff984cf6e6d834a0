// Text someone else sent, quoted into a message: at most a short prefix, control
// characters shown as '?'. A 20 000-character name echoed whole would overflow gRPC's
// status metadata (and a log line), turning a clear refusal into another error.
#pragma once

#include <string>
#include <string_view>

namespace omniview {

inline std::string quote_prefix(std::string_view text, size_t max_chars = 40) {
  std::string out = "'";
  for (size_t i = 0; i < text.size() && i < max_chars; ++i) {
    const unsigned char c = static_cast<unsigned char>(text[i]);
    out += (c < 0x20 || c == 0x7f) ? '?' : static_cast<char>(c);
  }
  out += "'";
  if (text.size() > max_chars) out += "... (" + std::to_string(text.size()) + " characters)";
  return out;
}

}  // namespace omniview
