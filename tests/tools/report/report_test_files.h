#pragma once
// What the report tests do with the files a report writes: a fresh folder per process, a file read whole, a string
// counted in a page, the chart specifications a page embeds.
#include <cstddef>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <unistd.h>

#include <nlohmann/json.hpp>

namespace mb::report_test {

/// An empty folder <temp>/<name>_<pid> (removed first if an earlier run left it).
inline std::filesystem::path Folder(const std::string& name) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / (name + "_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

/// The file's bytes ("" when it cannot be read).
inline std::string Read(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

/// How often `what` occurs in `text`, overlaps counted.
inline std::size_t Count(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (auto at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

/// The charts' specifications an interactive report embeds (ChartJson, tools/report/chart_data.h: the JSON array in
/// <script id="mb-charts">), or null when the page embeds none (no charting library installed).
inline nlohmann::json EmbeddedCharts(const std::string& page) {
  const std::string open = "<script type=\"application/json\" id=\"mb-charts\">";
  const std::size_t from = page.find(open);
  if (from == std::string::npos) return nlohmann::json();
  const std::size_t begin = from + open.size();
  return nlohmann::json::parse(page.substr(begin, page.find("</script>", begin) - begin));
}

}  // namespace mb::report_test
