// The MPI engine when CMake found no MPI: it says how to get one (tools/batch/sweep_mpi.h).

#include <stdexcept>

#include "tools/batch/sweep_mpi.h"

namespace mb {

bool SweepMpiAvailable() { return false; }

std::optional<SweepOutcome> RunSweepMpi(const std::filesystem::path&, const SweepSpec&, const std::filesystem::path&,
                                        const SweepOptions&) {
  throw std::runtime_error(
      "sweep --mpi: this motionblocks was built without MPI: install OpenMPI (apt install libopenmpi-dev "
      "openmpi-bin, or scripts/install-deps.sh) and build again, or use --shard K/N");
}

}  // namespace mb
