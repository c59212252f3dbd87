#pragma once
// Counts heap allocations, to prove that a real-time path allocates nothing. Link tests/alloc_counter.cc into
// the test executable (it replaces the global operator new/delete, so one such executable per test program).

namespace mb::testing {

/// Number of global operator new / new[] calls since the program started (all threads). Take the difference
/// around the code under test.
long AllocationCount() noexcept;

}  // namespace mb::testing
