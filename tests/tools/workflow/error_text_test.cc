// The rewording of library exceptions (tools/workflow/error_text.h): the inputs named, what to do,
// no library tag, never megabytes of input.

#include "tools/workflow/error_text.h"

#include <filesystem>
#include <ostream>
#include <sstream>
#include <new>
#include <stdexcept>
#include <string>
#include <system_error>

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "engine/terminal_text.h"
#include "engine/text_excerpt.h"

namespace mb {
namespace {

using ::testing::HasSubstr;
using ::testing::Not;
using ::testing::StartsWith;

TEST(ErrorText, JsonTypeErrorsLoseTheirTagAndNameTheInputs) {
  try {
    (void)nlohmann::json::parse(R"({"a": 1})")["a"].get<std::string>();
    FAIL() << "no type_error";
  } catch (const nlohmann::json::exception& e) {
    const std::string text = ErrorText(e, {"d.json", "log.csv"});
    EXPECT_THAT(text, StartsWith("unexpected JSON content (reading d.json, log.csv): (/a) type must be string, but "
                                 "is number. Check the file: a diagram against `motionblocks schema`"));
    EXPECT_THAT(text, Not(HasSubstr("[json.exception")));
  }
}

TEST(ErrorText, FilesystemErrorsSayThePathTheReasonAndWhatToDo) {
  const std::filesystem::filesystem_error e("cannot create directories", "out/x",
                                            std::make_error_code(std::errc::not_a_directory));
  EXPECT_EQ(ErrorText(e, {"d.json"}),
            "cannot use the file or folder out/x (reading d.json): Not a directory. Check that the path exists, is a "
            "folder where one is expected, and that you may read and write there (--out DIR chooses another output "
            "folder)");
}

TEST(ErrorText, OutOfMemorySaysHowToMakeTheJobSmaller) {
  EXPECT_EQ(ErrorText(std::bad_alloc(), {"huge.csv"}),
            "out of memory (reading huge.csv). The input or the run is too large for this machine: shorten the run or "
            "lower --max-steps / --max-runs, log fewer signals, or cut the measurement log");
}

TEST(ErrorText, BoostMathErrorsAreNumericalFailuresWithoutTheFunctionSignature) {
  const std::overflow_error e("Error in function boost::math::cyl_bessel_i<double>(double,double): numeric overflow");
  EXPECT_TRUE(IsLibraryNumericalError(e));
  EXPECT_EQ(ErrorText(e, {}),
            "a numerical routine failed: numeric overflow. A parameter is probably far out of range (a length scale, "
            "period or variance many orders from the data's): check the model's and the diagram's values");
  EXPECT_FALSE(IsLibraryNumericalError(std::runtime_error("plain")));
}

TEST(ErrorText, OwnMessagesStayButNeverEchoMegabytes) {
  EXPECT_EQ(ErrorText(std::invalid_argument("d.json: /elements/0: bad"), {"d.json"}), "d.json: /elements/0: bad");
  const std::string huge = "x: " + std::string(5'000'000, 'a');
  const std::string text = ErrorText(std::runtime_error(huge), {});
  EXPECT_LE(text.size(), kMaxErrorMessage + 40);
  EXPECT_THAT(text, HasSubstr("… (4996003 more bytes)"));
}

TEST(ErrorText, ExcerptKeepsShortTextAndCutsLongTextOnACharacterBoundary) {
  EXPECT_EQ(Excerpt("short"), "short");
  EXPECT_EQ(Excerpt(std::string(300, 'a')), std::string(200, 'a') + "… (100 more bytes)");
  EXPECT_EQ(Excerpt("aé", 2), "a… (2 more bytes)");  // 'é' is two bytes: not split
}

// Control bytes from a diagram or a log reach the terminal as visible escapes (issue 30): ESC, BEL, CR, DEL and the
// C1 controls (U+009B is a one-character CSI); newline, tab and UTF-8 letters stay.
TEST(TerminalText, ControlBytesAreEscapedAndTextStays) {
  EXPECT_EQ(EscapeControlBytes("a\x1b]0;title\x07z"), "a\\x1b]0;title\\x07z");
  EXPECT_EQ(EscapeControlBytes("over\rwrite\x7f"), "over\\x0dwrite\\x7f");
  EXPECT_EQ(EscapeControlBytes("csi\xc2\x9b" "31m"), "csi\\u009b31m");
  EXPECT_EQ(EscapeControlBytes("line 1\n\tline 2: 5 µm, é, ±"), "line 1\n\tline 2: 5 µm, é, ±");
}

TEST(TerminalText, AStreamThroughTheBufferIsEscapedWhateverTheChunks) {
  std::ostringstream target;
  ControlEscapingBuffer buffer(target.rdbuf());
  std::ostream out(&buffer);
  out << "name \x1b[2J" << '\x07' << "é" << "\xc2";  // a C1 control split across two writes
  out << "\x9b" "1m" << std::flush;
  out << "\xc2" << std::flush;  // a lone lead byte at a flush is written as it is
  EXPECT_EQ(target.str(), "name \\x1b[2J\\x07é\\u009b1m\xc2");
}

// Issue 30: no internal function name or library text without the inputs and what to check.
TEST(ErrorText, TheWhitenessTestIsNamedByItsMeaningNotItsFunctionOrBoost) {
  const std::string expected_tail =
      "Check the measured column's values and unit (values near 1e300 overflow) and that the model's output is "
      "finite along the record";
  EXPECT_EQ(ErrorText(std::invalid_argument("ResidualAutocorrelation: the residual is constant"), {"d.json", "m.csv"}),
            "the residual between the model and the measurement is no usable signal (reading d.json, m.csv): its "
            "whiteness test (Ljung–Box) found the residual is constant. " + expected_tail);
  const std::domain_error chi("Error in function boost::math::cdf(const chi_squared_distribution<double>&, double): "
                              "Chi Square parameter was -nan, but must be > 0 !");
  EXPECT_TRUE(IsLibraryNumericalError(chi));
  EXPECT_EQ(ErrorText(chi, {"d.json", "m.csv"}),
            "the residual between the model and the measurement is no usable signal (reading d.json, m.csv): its "
            "whiteness test (Ljung–Box) found Chi Square parameter was -nan, but must be > 0 !. " + expected_tail);
}

TEST(ErrorText, AnInternalCheckNamedByItsFunctionGetsTheInputsAndWhatToCheck) {
  EXPECT_EQ(ErrorText(std::invalid_argument("FitResidualGpr: the residual holds NaN or Inf"), {"d.json"}),
            "internal check FitResidualGpr failed (reading d.json): the residual holds NaN or Inf. The inputs led to a "
            "case the program does not handle: check their values and units (a column in mm read as m, values near "
            "1e300, a column that does not vary), and report it with the input files if they look right");
  EXPECT_THAT(ErrorText(std::invalid_argument("GprModel::Predict: x, xdot, mean and std must have one length"), {}),
              StartsWith("internal check GprModel::Predict failed: x, xdot"));
  // Own messages stay: a file name, a plain word, an acronym.
  for (const char* own : {"Diagram.json: 2 problems", "Payload: 3 kg", "CVODE: CVodeCreate failed", "d.json: x"}) {
    EXPECT_EQ(ErrorText(std::runtime_error(own), {"d.json"}), own);
  }
}

}  // namespace
}  // namespace mb
