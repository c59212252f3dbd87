// The MPI engine of a sweep (tools/batch/sweep_mpi.h): rank 0 serves a work queue, the other ranks simulate.

#include "tools/batch/sweep_mpi.h"

#include <chrono>
#include <cstdint>
#include <iostream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include <fmt/format.h>
#include <mpi.h>
#include <nlohmann/json.hpp>

#include "tools/batch/sweep_runner.h"

namespace mb {

namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {

enum Tag : int {
  kRow = 1,   // worker → rank 0: the row of its last run (empty: the first request)
  kWork = 2,  // rank 0 → worker: the position of the next run (one std::uint64_t)
  kDone = 3,  // rank 0 → worker: no run left (empty)
};

// MPI_Init … MPI_Finalize around the sweep, unless the caller initialised MPI.
class MpiSession {
 public:
  MpiSession() {
    int initialized = 0;
    MPI_Initialized(&initialized);
    if (!initialized) {
      MPI_Init(nullptr, nullptr);
      owner_ = true;
    }
    MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
    MPI_Comm_size(MPI_COMM_WORLD, &size_);
  }
  ~MpiSession() {
    if (owner_) MPI_Finalize();
  }
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;
  int rank() const { return rank_; }
  int size() const { return size_; }

 private:
  bool owner_ = false;
  int rank_ = 0;
  int size_ = 1;
};

[[noreturn]] void Abort(int rank, const std::exception& e) {
  std::cerr << fmt::format("motionblocks: error: sweep --mpi, rank {}: {}\n", rank, e.what()) << std::flush;
  MPI_Abort(MPI_COMM_WORLD, 1);
  std::abort();  // MPI_Abort does not return
}

// A row as text for MPI: numbers as "%.17g" text (exact, and NaN and infinities survive, unlike in JSON).
std::string RowMessage(std::size_t position, const SweepRow& row) {
  json metrics = json::object();
  for (const auto& [name, value] : row.metrics) metrics[name] = fmt::format("{:.17g}", value);
  return json{{"position", position},
              {"status", row.status},
              {"metrics", metrics},
              {"wall_time_s", fmt::format("{:.17g}", row.wall_time_s)},
              {"error", row.error}}
      .dump();
}

std::pair<std::size_t, SweepRow> ParseRowMessage(const std::string& text, const SweepSpec& spec) {
  const json j = json::parse(text);
  const std::size_t position = j.at("position").get<std::size_t>();
  const SweepRun run = spec.run(position);
  SweepRow row;
  row.id = run.id;
  row.assignments = run.assignments;
  row.status = j.at("status").get<std::string>();
  for (const auto& [name, value] : j.at("metrics").items()) row.metrics[name] = std::stod(value.get<std::string>());
  row.wall_time_s = std::stod(j.at("wall_time_s").get<std::string>());
  row.error = j.at("error").get<std::string>();
  return {position, std::move(row)};
}

// Rank 0's message to every rank: "" when it started, else its error.
std::string BroadcastText(std::string text) {
  int size = static_cast<int>(text.size());
  MPI_Bcast(&size, 1, MPI_INT, 0, MPI_COMM_WORLD);
  text.resize(static_cast<std::size_t>(size));
  MPI_Bcast(text.data(), size, MPI_CHAR, 0, MPI_COMM_WORLD);
  return text;
}

// Rank 0: answers each worker's request (carrying its last row) with the next position, until every worker is
// told "done". Polls with a short sleep: a blocking MPI_Probe spins a core that the workers need.
void ServeQueue(SweepRunner& runner, const SweepSpec& spec, const std::vector<std::size_t>& todo, int workers) {
  std::size_t next = 0;
  while (workers > 0) {
    MPI_Status status;
    int arrived = 0;
    for (MPI_Iprobe(MPI_ANY_SOURCE, kRow, MPI_COMM_WORLD, &arrived, &status); !arrived;
         MPI_Iprobe(MPI_ANY_SOURCE, kRow, MPI_COMM_WORLD, &arrived, &status)) {
      std::this_thread::sleep_for(std::chrono::microseconds(200));
    }
    int length = 0;
    MPI_Get_count(&status, MPI_CHAR, &length);
    std::string text(static_cast<std::size_t>(length), '\0');
    MPI_Recv(text.data(), length, MPI_CHAR, status.MPI_SOURCE, kRow, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    if (!text.empty()) {
      auto [position, row] = ParseRowMessage(text, spec);
      runner.Record(position, std::move(row));
    }
    if (next < todo.size()) {
      const std::uint64_t position = todo[next++];
      MPI_Send(&position, 1, MPI_UINT64_T, status.MPI_SOURCE, kWork, MPI_COMM_WORLD);
    } else {
      MPI_Send(nullptr, 0, MPI_UINT64_T, status.MPI_SOURCE, kDone, MPI_COMM_WORLD);
      --workers;
    }
  }
}

// Ranks > 0: ask, run, send the row back with the next request, until "done".
void Work(const SweepRunner& runner) {
  std::string row;  // empty: the first request
  for (;;) {
    MPI_Send(row.data(), static_cast<int>(row.size()), MPI_CHAR, 0, kRow, MPI_COMM_WORLD);
    MPI_Status status;
    std::uint64_t position = 0;
    MPI_Recv(&position, 1, MPI_UINT64_T, 0, MPI_ANY_TAG, MPI_COMM_WORLD, &status);
    if (status.MPI_TAG == kDone) return;
    row = RowMessage(position, runner.Execute(position));
  }
}

}  // namespace

bool SweepMpiAvailable() { return true; }

std::optional<SweepOutcome> RunSweepMpi(const fs::path& diagram, const SweepSpec& spec, const fs::path& out,
                                        const SweepOptions& options) {
  MpiSession mpi;
  SweepOptions rank_options = options;
  rank_options.progress = options.progress && mpi.rank() == 0;
  if (mpi.rank() != 0) {
    if (!BroadcastText("").empty()) return std::nullopt;  // rank 0 could not start: it reports why
    try {
      const SweepRunner runner(diagram, spec, out, rank_options);
      Work(runner);
    } catch (const std::exception& e) {
      Abort(mpi.rank(), e);
    }
    return std::nullopt;
  }
  std::unique_ptr<SweepRunner> runner;
  std::vector<std::size_t> todo;
  try {
    runner = std::make_unique<SweepRunner>(diagram, spec, out, rank_options);
    todo = runner->Start();
  } catch (const std::exception& e) {
    BroadcastText(e.what());
    throw;
  }
  BroadcastText("");
  try {
    if (mpi.size() == 1) {
      for (const std::size_t i : todo) runner->Record(i, runner->Execute(i));
    } else {
      ServeQueue(*runner, spec, todo, mpi.size() - 1);
    }
    return runner->Finish();
  } catch (const std::exception& e) {
    Abort(0, e);
  }
}

}  // namespace mb
