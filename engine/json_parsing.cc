#include "engine/json_parsing.h"

#include <iterator>
#include <set>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "engine/json_limits.h"

namespace mb {

using nlohmann::json;

DuplicateKeyError::DuplicateKeyError(std::vector<std::string> problems)
    : std::runtime_error(fmt::format("{}", fmt::join(problems, "; "))), problems_(std::move(problems)) {}

namespace {

std::string EscapePointerToken(const std::string& token) {
  std::string out;
  for (char c : token) {
    if (c == '~') {
      out += "~0";
    } else if (c == '/') {
      out += "~1";
    } else {
      out += c;
    }
  }
  return out;
}

/// A SAX handler (nlohmann::json::sax_parse) that follows the values read to know the JSON pointer of each and the
/// keys of every open object. A second pass over the text, after json::parse: linear in the text, whereas
/// nlohmann's callback parser scans the enclosing array at every object's end (quadratic: a diagram whose "notes"
/// held 400,000 small objects took 58 s to reach its type error).
class DuplicateKeyFinder {
 public:
  bool null() { return Value(); }
  bool boolean(bool /*value*/) { return Value(); }
  bool number_integer(json::number_integer_t /*value*/) { return Value(); }
  bool number_unsigned(json::number_unsigned_t /*value*/) { return Value(); }
  bool number_float(json::number_float_t /*value*/, const std::string& /*text*/) { return Value(); }
  bool string(std::string& /*value*/) { return Value(); }
  bool binary(json::binary_t& /*value*/) { return Value(); }
  bool start_object(std::size_t /*elements*/) { return Open(false); }
  bool start_array(std::size_t /*elements*/) { return Open(true); }
  bool end_object() { return Close(); }
  bool end_array() { return Close(); }
  bool key(std::string& key) {
    if (frames_.empty()) return true;
    Frame& top = frames_.back();
    top.key = key;
    if (!top.keys.insert(key).second) {
      problems_.push_back(fmt::format("{}: the key '{}' is given twice in one object (JSON keeps only the last); "
                                      "remove one",
                                      Pointer(), key));
    }
    return true;
  }
  bool parse_error(std::size_t /*position*/, const std::string& /*last_token*/, const json::exception& /*e*/) {
    return false;  // json::parse has already read the same text without an error
  }

  const std::vector<std::string>& problems() const { return problems_; }

 private:
  struct Frame {
    bool array = false;
    std::size_t next_index = 0;  // arrays: elements seen so far
    std::string key;             // objects: the key being read
    std::set<std::string> keys;  // objects: the keys seen so far
  };

  bool Value() {
    if (!frames_.empty() && frames_.back().array) ++frames_.back().next_index;
    return true;
  }
  bool Open(bool array) {
    Value();
    frames_.push_back(Frame{array, 0, {}, {}});
    return true;
  }
  bool Close() {
    if (!frames_.empty()) frames_.pop_back();
    return true;
  }

  std::string Pointer() const {
    std::string out;
    for (const auto& f : frames_) {
      out += "/" + (f.array ? std::to_string(f.next_index - 1) : EscapePointerToken(f.key));
    }
    return out;
  }

  std::vector<Frame> frames_;
  std::vector<std::string> problems_;
};

}  // namespace

json ParseJsonRejectingDuplicateKeys(std::istream& in, const std::string& source, bool ignore_comments) {
  const std::string text{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  RefuseNulBytes(text);
  CheckJsonDepth(text, source, ignore_comments);
  json out = json::parse(text, nullptr, /*allow_exceptions=*/true, ignore_comments);
  DuplicateKeyFinder finder;
  json::sax_parse(text, &finder, json::input_format_t::json, /*strict=*/true, ignore_comments);
  if (!finder.problems().empty()) throw DuplicateKeyError(finder.problems());
  return out;
}

std::string JsonCommentHint(std::string_view text, std::size_t byte) {
  if (byte == 0 || byte >= text.size() || text[byte - 1] != '/' || (text[byte] != '/' && text[byte] != '*')) return {};
  return "; comments (// or /* */) are not JSON: remove them (a diagram keeps its notes in \"description\" or "
         "\"notes\")";
}

}  // namespace mb
