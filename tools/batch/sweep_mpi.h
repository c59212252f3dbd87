#pragma once
// The MPI engine of a sweep: `mpirun -n N motionblocks sweep … --mpi`. Rank 0 hands out the runs one at a time (a
// work queue: a worker rank sends the row of its last run and gets the next run's index, or "done") and gathers the
// rows into one runs.csv and runs.json, as RunSweep writes them (resumable the same way); ranks 1 … N-1 simulate,
// one run at a time each. With a single rank, rank 0 runs the sweep itself, one run at a time. The queue balances
// runs of unequal cost by itself; every rank reads the diagram and sweep files itself (a shared file system, or
// the same paths on every node), and only rank 0 writes runs.csv (runs/<id>/signals.csv of --save-logs are written
// by the rank that ran the run, under the same --out).
//
// Built only when CMake finds MPI (sweep_mpi.cc, Debian's OpenMPI); otherwise sweep_mpi_unavailable.cc says how to
// get it. This header does not include mpi.h.

#include <filesystem>
#include <optional>

#include "tools/batch/sweep.h"

namespace mb {

/// Whether this build has the MPI engine.
bool SweepMpiAvailable();

/// Runs the sweep over the ranks of MPI_COMM_WORLD. Call it from every rank, once per process: it initialises MPI
/// (unless the caller did) and finalises it (if it initialised it). options.jobs is not used (one run per rank at a
/// time), options.progress only on rank 0. @returns the outcome on rank 0, std::nullopt on the other ranks (and on
/// every rank when rank 0 could not start: it throws and the others return).
/// @throws on rank 0, as RunSweep before any run; std::runtime_error if this build has no MPI. An error after the
/// runs started (an unwritable runs.csv, a worker that cannot read the diagram) is printed on stderr with the rank,
/// and the job is ended with MPI_Abort (the other ranks would wait for ever).
std::optional<SweepOutcome> RunSweepMpi(const std::filesystem::path& diagram, const SweepSpec& spec,
                                        const std::filesystem::path& out, const SweepOptions& options = {});

}  // namespace mb
