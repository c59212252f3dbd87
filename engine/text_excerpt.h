#pragma once
// What an error message may quote of a user's input: never megabytes of it (issue 11). Header-only.

#include <cstddef>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

namespace mb {

/// Most characters of user input an error message quotes (a --set value, a JSON excerpt, a CSV cell).
inline constexpr std::size_t kMaxQuotedInput = 200;

/// `text` whole if it has at most `max_bytes` bytes, else its first `max_bytes` bytes (not splitting a UTF-8
/// character) followed by "… (N more bytes)".
inline std::string Excerpt(std::string_view text, std::size_t max_bytes = kMaxQuotedInput) {
  if (text.size() <= max_bytes) return std::string(text);
  std::size_t cut = max_bytes;
  while (cut > 0 && (static_cast<unsigned char>(text[cut]) & 0xC0U) == 0x80U) --cut;  // a continuation byte
  return std::string(text.substr(0, cut)) + "… (" + std::to_string(text.size() - cut) + " more bytes)";
}

/// nlohmann::json's message without its "[json.exception.parse_error.101] " tag, cut to 300 bytes: a syntax error's
/// "last read: '…'" may be a whole long string of the input.
inline std::string JsonErrorText(const nlohmann::json::exception& e) {
  const std::string_view text = e.what();
  const auto close = text.find("] ");
  const bool tagged = text.substr(0, 16) == "[json.exception." && close != std::string_view::npos;
  return Excerpt(tagged ? text.substr(close + 2) : text, 300);
}

}  // namespace mb
