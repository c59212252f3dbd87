#include "tools/report/output_files.h"

#include <cstdio>
#include <fstream>
#include <iostream>
#include <stdexcept>

#include <fmt/format.h>
#include <unistd.h>

#include "engine/output_file.h"
#include "models/diagnosis/measurement_log.h"

namespace mb {

namespace fs = std::filesystem;

void WriteSignalLog(const SignalLog& log, const fs::path& path) {
  std::vector<std::string> names = {"time_s"};
  std::vector<Eigen::VectorXd> columns = {Eigen::Map<const Eigen::VectorXd>(
      log.time.data(), static_cast<Eigen::Index>(log.time.size()))};
  for (std::size_t i = 0; i < log.names.size(); ++i) {
    names.push_back(log.names[i]);
    columns.emplace_back(Eigen::Map<const Eigen::VectorXd>(log.columns[i].data(),
                                                           static_cast<Eigen::Index>(log.columns[i].size())));
  }
  WriteMeasurementLog(MeasurementLog(names, columns, path.string()), path.string());
}

void WriteJsonFile(const nlohmann::json& j, const fs::path& path) {
  WriteFileSafely(path, j.dump(2) + "\n");
}

ProgressLine::ProgressLine(std::string label) : label_(std::move(label)), tty_(isatty(fileno(stderr)) != 0) {}

void ProgressLine::Update(double fraction) {
  const int percent = static_cast<int>(100.0 * std::clamp(fraction, 0.0, 1.0));
  if (percent == last_percent_) return;
  if (tty_) {
    std::cerr << fmt::format("\r{}  {:3d} %", label_, percent) << std::flush;
  } else if ((last_percent_ < 0 && percent >= 0) || (last_percent_ < 50 && percent >= 50)) {
    std::cerr << fmt::format("{}  {:3d} %\n", label_, percent);
  }
  last_percent_ = percent;
}

void ProgressLine::Done() {
  if (tty_) std::cerr << fmt::format("\r{}  100 %\n", label_);
  else std::cerr << fmt::format("{}  done\n", label_);
}

}  // namespace mb
