#pragma once
// Parsing JSON files that people write: a key given twice in one object is an error (RFC 8259 leaves it
// undefined and nlohmann-json silently keeps the last one, so a duplicated "stopTime" would be ignored).

#include <istream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

namespace mb {

/// The keys given twice in a JSON text, one problem each: "<json pointer>: the key 'k' is given twice in one
/// object (JSON keeps only the last); remove one". The pointer names the second occurrence.
class DuplicateKeyError : public std::runtime_error {
 public:
  explicit DuplicateKeyError(std::vector<std::string> problems);
  const std::vector<std::string>& problems() const { return problems_; }

 private:
  std::vector<std::string> problems_;
};

/// Parses `in` (read to its end) like nlohmann::json::parse (comments allowed when `ignore_comments`), after the
/// nesting-depth check of engine/json_limits.h. `source` names the file in messages.
/// @throws JsonDepthError beyond kMaxJsonDepth levels; nlohmann::json::parse_error on a syntax error or a NUL byte
/// (RefuseNulBytes, engine/json_limits.h);
/// DuplicateKeyError if an object repeats a key.
nlohmann::json ParseJsonRejectingDuplicateKeys(std::istream& in, const std::string& source, bool ignore_comments);

/// For a syntax error at byte `byte` (nlohmann::json::parse_error::byte, 1-based) of `text`: "; comments (// or /* */)
/// are not JSON: remove them (…)" when a comment starts there, else "".
std::string JsonCommentHint(std::string_view text, std::size_t byte);

}  // namespace mb
