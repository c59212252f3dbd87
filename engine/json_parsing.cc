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

/// Follows the parser's events to know the JSON pointer of the value being read and the keys of every open
/// object.
class DuplicateKeyFinder {
 public:
  bool operator()(int /*depth*/, json::parse_event_t event, json& parsed) {
    switch (event) {
      case json::parse_event_t::object_start:
      case json::parse_event_t::array_start:
        CountArrayElement();
        frames_.push_back(Frame{event == json::parse_event_t::array_start, 0, {}, {}});
        break;
      case json::parse_event_t::object_end:
      case json::parse_event_t::array_end:
        if (!frames_.empty()) frames_.pop_back();
        break;
      case json::parse_event_t::key:
        if (!frames_.empty() && parsed.is_string()) {
          Frame& top = frames_.back();
          top.key = parsed.get<std::string>();
          if (!top.keys.insert(top.key).second) {
            problems_.push_back(fmt::format("{}: the key '{}' is given twice in one object (JSON keeps only the "
                                            "last); remove one",
                                            Pointer(), top.key));
          }
        }
        break;
      case json::parse_event_t::value:
        CountArrayElement();
        break;
    }
    return true;
  }

  const std::vector<std::string>& problems() const { return problems_; }

 private:
  struct Frame {
    bool array = false;
    std::size_t next_index = 0;  // arrays: elements seen so far
    std::string key;             // objects: the key being read
    std::set<std::string> keys;  // objects: the keys seen so far
  };

  void CountArrayElement() {
    if (!frames_.empty() && frames_.back().array) ++frames_.back().next_index;
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
  CheckJsonDepth(text, source, ignore_comments);
  auto finder = std::make_shared<DuplicateKeyFinder>();  // the callback is copied into std::function
  json out = json::parse(
      text, [finder](int depth, json::parse_event_t event, json& parsed) { return (*finder)(depth, event, parsed); },
      /*allow_exceptions=*/true, ignore_comments);
  if (!finder->problems().empty()) throw DuplicateKeyError(finder->problems());
  return out;
}

}  // namespace mb
