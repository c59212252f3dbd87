#include "tools/report/output_files.h"

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <stdexcept>

#include <fmt/format.h>

#include "engine/diagram_document.h"
#include "engine/output_file.h"
#include "engine/text_excerpt.h"
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

void CreateParentFolder(const fs::path& file) {
  const fs::path parent = file.parent_path();
  if (!parent.empty()) fs::create_directories(parent);
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

bool FileNameMatches(std::string_view name, std::string_view pattern) {
  const auto star = pattern.find('*');
  if (star == std::string_view::npos) return name == pattern;
  const std::string_view head = pattern.substr(0, star), rest = pattern.substr(star + 1);
  if (!name.starts_with(head)) return false;
  for (std::size_t at = head.size(); at <= name.size(); ++at) {  // '*' takes name[head.size(), at)
    if (FileNameMatches(name.substr(at), rest)) return true;
  }
  return false;
}

std::vector<fs::path> OutputFilesIn(const fs::path& folder, const std::vector<std::string>& names) {
  std::vector<fs::path> subfolders;  // "" (the folder itself) and each named subfolder, once
  for (const auto& name : names) {
    const fs::path sub = fs::path(name).parent_path();
    if (std::find(subfolders.begin(), subfolders.end(), sub) == subfolders.end()) subfolders.push_back(sub);
  }
  std::vector<fs::path> found;
  for (const auto& sub : subfolders) {
    const fs::path dir = sub.empty() ? folder : folder / sub;
    std::error_code error;
    if (!fs::is_directory(dir, error)) continue;
    for (const auto& entry : fs::directory_iterator(dir, error)) {
      if (!entry.is_regular_file(error)) continue;
      const std::string file = entry.path().filename().string();
      for (const auto& name : names) {
        if (fs::path(name).parent_path() != sub) continue;
        const std::string pattern = fs::path(name).filename().string();
        if (FileNameMatches(file, pattern) || FileNameMatches(file, pattern + ".tmp*")) {
          found.push_back(entry.path());
          break;
        }
      }
    }
  }
  return found;
}

namespace {

// `path` made absolute with "..", "." and symbolic links resolved as far as it exists (weakly_canonical); the
// lexically normal absolute path if that fails (a permission error on the way).
fs::path Resolved(const fs::path& path) {
  std::error_code error;
  const fs::path absolute = fs::absolute(path, error);
  if (error) return path.lexically_normal();
  fs::path resolved = fs::weakly_canonical(absolute, error);
  if (error || resolved.empty()) return absolute.lexically_normal();
  return resolved;
}

// The names a path goes by: resolved through and through, and with only its folder resolved (a symbolic link as the
// file itself names the link, which an output written by rename replaces).
std::vector<fs::path> Spellings(const fs::path& path) {
  const fs::path name = path.filename();
  std::vector<fs::path> out{Resolved(path)};
  if (!name.empty() && name != "." && name != "..") {
    out.push_back(Resolved(path.parent_path().empty() ? fs::path(".") : path.parent_path()) / name);
  }
  return out;
}

bool SameFile(const fs::path& a, const fs::path& b) {
  std::error_code error;
  if (fs::exists(a, error) && fs::exists(b, error) && fs::equivalent(a, b, error) && !error) return true;
  for (const auto& sa : Spellings(a)) {
    for (const auto& sb : Spellings(b)) {
      if (sa == sb) return true;
    }
  }
  return false;
}

}  // namespace

void RequireReportFolderName(const std::string& option, const fs::path& folder) {
  const std::string text = folder.string();
  const auto at = text.find_first_of("?#*[]");
  if (at == std::string::npos) return;
  throw std::invalid_argument(fmt::format(
      "{} {}: a report folder's path may not hold '?', '#', '*', '[' or ']' (it holds '{}'): a browser takes '?' and "
      "'#' in the report's address for the end of its path, so its pictures would go missing, and a shell expands "
      "'*', '?' and '[…]' in the commands that redraw them; nothing was done: choose another {}",
      option, Excerpt(text), text[at], option));
}

void RefuseOutputsOverInputs(const std::vector<CommandFile>& inputs, const std::vector<CommandFile>& outputs,
                             const std::vector<OutputFolder>& folders) {
  for (const auto& folder : folders) {
    if (!folder.folder.empty()) RequireReportFolderName(folder.option, folder.folder);
  }
  for (const auto& in : inputs) {
    if (in.path.empty()) continue;
    for (const auto& out : outputs) {
      if (out.path.empty() || !SameFile(in.path, out.path)) continue;
      throw OutputReplacesInputError(fmt::format(
          "{} {} is the input {} {}: writing it would destroy the input; nothing was done: write the output elsewhere "
          "(another {})",
          out.option, out.path.string(), in.option, in.path.string(), out.option));
    }
    for (const auto& folder : folders) {
      if (folder.folder.empty()) continue;
      for (const auto& pattern : folder.names) {
        // "plot/*.dat": the subfolder resolved as the writer will reach it (a symbolic link followed), then the name.
        const fs::path sub = fs::path(pattern).parent_path();
        const fs::path resolved_folder = Resolved(sub.empty() ? folder.folder : folder.folder / sub);
        const std::string file_pattern = fs::path(pattern).filename().string();
        for (const auto& spelling : Spellings(in.path)) {
          const std::string file = spelling.filename().string();
          if (spelling.parent_path() != resolved_folder || !FileNameMatches(file, file_pattern)) continue;
          const std::string name = (sub / file).generic_string();
          throw OutputReplacesInputError(fmt::format(
              "{} {} holds the input {} {}, and the command writes {} there: it would destroy the input; nothing was "
              "done: choose another {} folder (or move the input out of it)",
              folder.option, folder.folder.string(), in.option, in.path.string(),
              pattern == name ? name : fmt::format("{} ({})", name, pattern), folder.option));
        }
      }
    }
  }
}

}  // namespace mb
