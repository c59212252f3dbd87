#pragma once
// Validating JSON documents against a JSON Schema (draft-07) with valijson (Debian's libvalijson-dev), with
// messages for people: each problem has the JSON pointer of the offending value, an unknown key names the keys
// allowed there and the closest one ("did you mean"), a value outside an enum lists the allowed values.

#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace valijson {
class Schema;
}

namespace mb {

/// One schema violation: `pointer` into the validated document ("" = the root), `message` says what and how to
/// fix it. `wrong_type` marks a value of the wrong JSON type (code reading the document would throw on it).
struct SchemaProblem {
  std::string pointer;
  std::string message;
  bool wrong_type = false;
  /// "<pointer>: <message>" ("/" for the root).
  std::string Text() const;
};

/// A compiled schema; Validate is const and may be called from several threads.
class JsonSchemaValidator {
 public:
  /// @throws std::invalid_argument if valijson cannot read `schema` (a programming error in the generator).
  explicit JsonSchemaValidator(nlohmann::json schema);
  ~JsonSchemaValidator();
  JsonSchemaValidator(const JsonSchemaValidator&) = delete;
  JsonSchemaValidator& operator=(const JsonSchemaValidator&) = delete;

  /// Every violation in `document`, deepest first within a branch; summaries of compound constraints ("failed
  /// to validate against child schema") are left out when a more precise problem explains them.
  std::vector<SchemaProblem> Validate(const nlohmann::json& document) const;

  const nlohmann::json& schema() const { return schema_json_; }

 private:
  nlohmann::json schema_json_;
  std::unique_ptr<valijson::Schema> schema_;
};

/// `own` problems ("<pointer>: message", from code that knows the document's meaning) followed by the schema
/// problems that none of them already reports: none at the same pointer or, with `own_covers_descendants`, at
/// a pointer below one of theirs.
std::vector<std::string> MergeProblems(std::vector<std::string> own, const std::vector<SchemaProblem>& schema,
                                       bool own_covers_descendants);

/// The unescaped reference tokens of a JSON pointer ("/a/0/b~1c" → a, 0, b/c).
std::vector<std::string> PointerTokens(const std::string& pointer);

}  // namespace mb
