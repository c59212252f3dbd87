#include "hw/board_registry.h"

namespace mb {

BoardRegistry& BoardRegistry::Global() {
  static BoardRegistry registry;
  return registry;
}

}  // namespace mb
