#include "tools/report/output_files.h"

#include <cstdio>
#include <fstream>
#include <iostream>
#include <stdexcept>

#include <fmt/format.h>

#include "engine/diagram_document.h"
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

std::vector<std::string> WriteDiagramFile(const nlohmann::json& diagram, const fs::path& diagram_folder,
                                          const fs::path& path) {
  DiagramDocument document(diagram, diagram_folder);
  const std::vector<std::string> outside = document.RelocateFiles(fs::absolute(path).parent_path());
  WriteJsonFile(document.json(), path);
  return outside;
}

}  // namespace mb
