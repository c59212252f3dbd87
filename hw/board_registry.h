#pragma once
// The process-wide board the HIL blocks talk to. `motionblocks hil` attaches the opened board before it builds
// the diagram; the blocks (blocks/encoder_input.h, blocks/analog_output.h) look it up in their constructors,
// so the engine never knows about hardware and a diagram with HIL blocks fails to build, with a clear message,
// when no board is attached.

#include "hw/board.h"

namespace mb {

class BoardRegistry {
 public:
  /// The process-wide registry.
  static BoardRegistry& Global();

  /// Attaches `board` (not owned; it must outlive every block built while attached). Replaces any other.
  void Attach(IoBoard* board) noexcept { board_ = board; }
  void Detach() noexcept { board_ = nullptr; }
  /// The attached board, or nullptr.
  IoBoard* board() const noexcept { return board_; }

 private:
  IoBoard* board_ = nullptr;
};

/// Attaches a board for the lifetime of this object (RAII around BoardRegistry::Attach/Detach).
class ScopedBoardAttachment {
 public:
  explicit ScopedBoardAttachment(IoBoard& board) { BoardRegistry::Global().Attach(&board); }
  ~ScopedBoardAttachment() { BoardRegistry::Global().Detach(); }
  ScopedBoardAttachment(const ScopedBoardAttachment&) = delete;
  ScopedBoardAttachment& operator=(const ScopedBoardAttachment&) = delete;
};

}  // namespace mb
