#pragma once
// Parsing JSON that users (or strangers) wrote without letting its shape exhaust the machine: a nesting depth
// beyond kMaxJsonDepth is refused before the document is built (nlohmann-json builds, copies and destroys
// values recursively in places, so 100k nested arrays overflow the stack).

#include <istream>
#include <stdexcept>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

namespace mb {

/// Deepest nesting of arrays and objects accepted in any JSON file motionblocks reads (diagrams, sweeps, GP
/// models); real files nest fewer than 20 levels.
inline constexpr int kMaxJsonDepth = 256;

/// A JSON text nested deeper than kMaxJsonDepth.
class JsonDepthError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

/// Throws JsonDepthError (the message below) if `text` nests deeper than kMaxJsonDepth; a syntax error is left to
/// the real parse. Linear, non-recursive (a SAX pass that builds nothing).
void CheckJsonDepth(std::string_view text, const std::string& source, bool ignore_comments = false);

/// Throws nlohmann::json::parse_error (id 101, at the byte) if `text` holds a NUL byte: "a NUL byte at line L, column
/// C: …". No JSON text holds one (a string writes it \u0000), but nlohmann's parser takes it for the end of the input,
/// so a file truncated or padded with zeros after its closing brace was read as if whole (issue 41).
void RefuseNulBytes(std::string_view text);

/// Parses `text` as nlohmann::json::parse does (exceptions on, comments skipped if `ignore_comments`), after a
/// linear, non-recursive SAX pass that counts the nesting depth. `source` names the file in messages.
/// @throws JsonDepthError "<source>: JSON nested deeper than 256 levels (byte N) …" before anything is built;
/// nlohmann::json::parse_error for a syntax error or a NUL byte (RefuseNulBytes) (as json::parse, so callers keep
/// their own wording).
nlohmann::json ParseJsonLimited(std::string_view text, const std::string& source, bool ignore_comments = false);

/// The same for a whole stream (read to its end first).
nlohmann::json ParseJsonLimited(std::istream& in, const std::string& source, bool ignore_comments = false);

}  // namespace mb
