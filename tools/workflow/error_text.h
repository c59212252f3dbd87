#pragma once
// The user's last word on an error, at the command line (tools/main.cc) and in Python (python/bind_errors.cc): texts
// of the libraries underneath — nlohmann::json's
// "[json.exception.type_error.302] …", std::filesystem's "filesystem error: …", Boost.Math's "Error in function
// boost::math::…", std::bad_alloc's "std::bad_alloc" — reworded with the command's input files and what to do, and
// every message capped so that it never echoes megabytes of input.

#include <exception>
#include <string>
#include <vector>

namespace mb {

/// The user's message for `e`, a library exception no command caught: what happened, in the inputs `inputs`, and
/// what to do. Texts of own exceptions (DiagramError, std::invalid_argument, …) are returned as they are, except an
/// internal check's that starts with its function's name ("FitResidualGpr: …", "Class::Method: …"; the residual's
/// whiteness test, ResidualAutocorrelation and Boost's "Chi Square parameter", by its meaning): reworded with the
/// inputs and what to check. Every message is cut to at most kMaxErrorMessage bytes (Excerpt).
std::string ErrorText(const std::exception& e, const std::vector<std::string>& inputs);

/// Longest message printed for one error: long enough for every problem of a diagram, short of a megabyte echo.
inline constexpr std::size_t kMaxErrorMessage = 4000;

/// Whether `e` is a numerical failure of a library routine (Boost.Math's overflow or domain errors): exit code 3.
bool IsLibraryNumericalError(const std::exception& e);

}  // namespace mb
