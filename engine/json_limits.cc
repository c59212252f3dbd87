#include "engine/json_limits.h"

#include <algorithm>
#include <iterator>

#include <fmt/format.h>

namespace mb {

namespace {

using nlohmann::json;

// Counts the nesting depth and stops the SAX parse (returns false) at the first level beyond the limit.
class DepthCounter final : public nlohmann::json_sax<json> {
 public:
  bool null() override { return true; }
  bool boolean(bool) override { return true; }
  bool number_integer(number_integer_t) override { return true; }
  bool number_unsigned(number_unsigned_t) override { return true; }
  bool number_float(number_float_t, const string_t&) override { return true; }
  bool string(string_t&) override { return true; }
  bool binary(binary_t&) override { return true; }
  bool start_object(std::size_t) override { return Enter(); }
  bool key(string_t&) override { return true; }
  bool end_object() override { return Leave(); }
  bool start_array(std::size_t) override { return Enter(); }
  bool end_array() override { return Leave(); }
  bool parse_error(std::size_t, const std::string&, const nlohmann::detail::exception&) override {
    syntax_error_ = true;
    return false;  // the real parse reports it, with its own wording
  }

  bool too_deep() const { return too_deep_; }

 private:
  bool Enter() {
    if (++depth_ <= kMaxJsonDepth) return true;
    too_deep_ = true;
    return false;
  }
  bool Leave() {
    --depth_;
    return true;
  }
  int depth_ = 0;
  bool too_deep_ = false;
  bool syntax_error_ = false;
};

}  // namespace

void CheckJsonDepth(std::string_view text, const std::string& source, bool ignore_comments) {
  DepthCounter counter;
  json::sax_parse(text, &counter, json::input_format_t::json, /*strict=*/true, ignore_comments);
  if (counter.too_deep()) {
    throw JsonDepthError(fmt::format("{}: JSON nested deeper than {} levels of arrays/objects; refusing to read it "
                                     "(real diagrams, sweeps and models nest fewer than 20: is the file generated "
                                     "wrongly?)",
                                     source, kMaxJsonDepth));
  }
}

void RefuseNulBytes(std::string_view text) {
  const auto nul = text.find('\0');
  if (nul == std::string_view::npos) return;
  const std::string_view before = text.substr(0, nul);
  const auto line = 1 + static_cast<std::size_t>(std::count(before.begin(), before.end(), '\n'));
  const auto line_start = before.rfind('\n');
  const std::size_t column = line_start == std::string_view::npos ? nul + 1 : nul - line_start;
  const bool only_zeros_follow = text.find_first_not_of('\0', nul) == std::string_view::npos;
  throw json::parse_error::create(
      101, nul + 1,
      fmt::format("a NUL byte at line {}, column {}{}: no JSON text holds one (is the file truncated, padded with "
                  "zeros or binary?); restore the file",
                  line, column, only_zeros_follow ? fmt::format(" (and {} more to the end of the file)", text.size() - nul - 1) : ""),
      nullptr);
}

json ParseJsonLimited(std::string_view text, const std::string& source, bool ignore_comments) {
  RefuseNulBytes(text);
  CheckJsonDepth(text, source, ignore_comments);
  return json::parse(text, nullptr, /*allow_exceptions=*/true, ignore_comments);
}

json ParseJsonLimited(std::istream& in, const std::string& source, bool ignore_comments) {
  const std::string text{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  return ParseJsonLimited(std::string_view(text), source, ignore_comments);
}

}  // namespace mb
