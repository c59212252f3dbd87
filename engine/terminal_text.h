#pragma once
// Text that reaches a terminal (issue 30): names, paths and messages come from diagrams, logs and file names that
// someone else wrote, and a terminal obeys the control bytes in them (ESC starts a command that may recolour,
// retitle or rewrite the screen, BEL rings, CR overwrites the line). The command line writes its standard output and
// error through ControlEscapingBuffer (tools/main.cc), so every message shows such bytes as visible escapes; text
// written another way (a progress line's own "\r") escapes its user part with EscapeControlBytes. Header-only.

#include <cstddef>
#include <streambuf>
#include <string>
#include <string_view>

#include <fmt/format.h>

namespace mb {

namespace terminal_text_detail {

constexpr unsigned char kUtf8C1Lead = 0xC2;  // U+0080…U+00BF; U+0080…U+009F are the C1 controls (0x9B: CSI)

// A C0 control other than newline and tab, or DEL.
inline bool IsC0Control(unsigned char c) { return (c < 0x20 && c != '\n' && c != '\t') || c == 0x7F; }

// The second byte of a C1 control written in UTF-8 (after 0xC2).
inline bool IsC1Continuation(unsigned char c) { return c >= 0x80 && c <= 0x9F; }

}  // namespace terminal_text_detail

/// `text` with every control byte a terminal would obey written visibly: C0 controls other than newline and tab,
/// and DEL, as "\xNN" (ESC as \x1b, BEL as \x07, CR as \x0d); the C1 controls U+0080…U+009F as "\u00NN". Every other
/// byte (UTF-8 letters, symbols) is kept.
inline std::string EscapeControlBytes(std::string_view text) {
  using namespace terminal_text_detail;
  std::string out;
  out.reserve(text.size());
  for (std::size_t i = 0; i < text.size(); ++i) {
    const auto c = static_cast<unsigned char>(text[i]);
    if (IsC0Control(c)) {
      out += fmt::format("\\x{:02x}", c);
    } else if (c == kUtf8C1Lead && i + 1 < text.size() && IsC1Continuation(static_cast<unsigned char>(text[i + 1]))) {
      out += fmt::format("\\u00{:02x}", static_cast<unsigned char>(text[++i]));
    } else {
      out += text[i];
    }
  }
  return out;
}

/// A stream buffer that writes everything to `target` with control bytes escaped as EscapeControlBytes does, as it
/// comes (unbuffered: output stays in order with what else writes to `target`). Install it on std::cout and
/// std::cerr (rdbuf) for as long as it lives.
class ControlEscapingBuffer : public std::streambuf {
 public:
  explicit ControlEscapingBuffer(std::streambuf* target) : target_(target) {}
  ControlEscapingBuffer(const ControlEscapingBuffer&) = delete;
  ControlEscapingBuffer& operator=(const ControlEscapingBuffer&) = delete;
  ~ControlEscapingBuffer() override { FlushPending(); }

 protected:
  int_type overflow(int_type c) override {
    if (traits_type::eq_int_type(c, traits_type::eof())) return traits_type::not_eof(c);
    const char ch = traits_type::to_char_type(c);
    return Write(&ch, 1) ? c : traits_type::eof();
  }

  std::streamsize xsputn(const char* s, std::streamsize n) override { return Write(s, n) ? n : 0; }

  int sync() override {
    FlushPending();
    return target_->pubsync();
  }

 private:
  // Writes `n` bytes of `s`, escaped; a 0xC2 at the end is held until the next byte shows whether it starts a C1
  // control.
  bool Write(const char* s, std::streamsize n) {
    using namespace terminal_text_detail;
    std::string out;
    for (std::streamsize i = 0; i < n; ++i) {
      const auto c = static_cast<unsigned char>(s[i]);
      if (pending_lead_) {
        pending_lead_ = false;
        if (IsC1Continuation(c)) {
          out += fmt::format("\\u00{:02x}", c);
          continue;
        }
        out += static_cast<char>(kUtf8C1Lead);
      }
      if (c == kUtf8C1Lead) {
        pending_lead_ = true;
      } else if (IsC0Control(c)) {
        out += fmt::format("\\x{:02x}", c);
      } else {
        out += s[i];
      }
    }
    return target_->sputn(out.data(), static_cast<std::streamsize>(out.size())) ==
           static_cast<std::streamsize>(out.size());
  }

  void FlushPending() {
    if (!pending_lead_) return;
    pending_lead_ = false;
    target_->sputc(static_cast<char>(terminal_text_detail::kUtf8C1Lead));
  }

  std::streambuf* target_;
  bool pending_lead_ = false;
};

}  // namespace mb
