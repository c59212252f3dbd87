#pragma once
// The message of the exception a callable throws, for tests that check error texts exactly.

#include <exception>
#include <string>
#include <utility>

namespace mb::testing {

/// e.what() of the exception of type E (default: any std::exception) that f() throws, or "no exception".
/// Another exception type propagates (the test fails with it).
template <typename E = std::exception, typename F>
std::string ErrorOf(F&& f) {
  try {
    std::forward<F>(f)();
  } catch (const E& e) {
    return e.what();
  }
  return "no exception";
}

}  // namespace mb::testing
