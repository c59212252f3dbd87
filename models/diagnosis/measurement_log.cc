#include "models/diagnosis/measurement_log.h"

#include "engine/output_file.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include <fmt/format.h>

namespace mb {
namespace {

// The names for a message, at most the first 30 (a log of 200k columns must not print them all).
std::string JoinNames(const std::vector<std::string>& names) {
  constexpr std::size_t kMaxListed = 30;
  std::string out;
  for (std::size_t i = 0; i < names.size() && i < kMaxListed; ++i) {
    if (!out.empty()) out += ", ";
    out += names[i];
  }
  if (names.size() > kMaxListed) out += fmt::format(", … ({} more)", names.size() - kMaxListed);
  return out;
}

std::string_view Trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) s.remove_suffix(1);
  return s;
}

// Splits one line at commas into trimmed cells (no quoting: the logs hold numbers only).
void SplitCells(std::string_view line, std::vector<std::string_view>* cells) {
  cells->clear();
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = line.find(',', start);
    if (comma == std::string_view::npos) {
      cells->push_back(Trim(line.substr(start)));
      return;
    }
    cells->push_back(Trim(line.substr(start, comma - start)));
    start = comma + 1;
  }
}

}  // namespace

MeasurementLog::MeasurementLog(std::vector<std::string> names, std::vector<Eigen::VectorXd> columns,
                               std::string source)
    : names_(std::move(names)), columns_(std::move(columns)), source_(std::move(source)) {
  if (names_.empty() || names_.size() != columns_.size()) {
    throw std::invalid_argument(fmt::format(
        "{}: a measurement log needs at least one column and one name per column (got {} names, {} "
        "columns)",
        source_, names_.size(), columns_.size()));
  }
  index_.reserve(names_.size());
  for (std::size_t j = 0; j < names_.size(); ++j) {
    if (names_[j].empty()) {
      throw std::invalid_argument(fmt::format("{}: column {} has an empty name; name every column",
                                              source_, j + 1));
    }
    if (!index_.emplace(names_[j], j).second) {
      throw std::invalid_argument(fmt::format(
          "{}: column name '{}' appears twice; rename one of them", source_, names_[j]));
    }
    if (columns_[j].size() != columns_[0].size()) {
      throw std::invalid_argument(fmt::format(
          "{}: column '{}' has {} values but '{}' has {}; all columns must be equally long", source_,
          names_[j], columns_[j].size(), names_[0], columns_[0].size()));
    }
  }
}

bool MeasurementLog::has_column(std::string_view name) const { return index_.find(name) != index_.end(); }

const Eigen::VectorXd& MeasurementLog::column(std::string_view name) const {
  const auto it = index_.find(name);
  if (it == index_.end()) {
    throw std::invalid_argument(fmt::format("{}: no column '{}'; the columns present are: {}", source_,
                                            name, JoinNames(names_)));
  }
  return columns_[it->second];
}

void MeasurementLog::AddColumn(std::string name, Eigen::VectorXd values) {
  if (name.empty() || has_column(name)) {
    throw std::invalid_argument(fmt::format(
        "{}: cannot add column '{}': the name is empty or exists already", source_, name));
  }
  if (values.size() != rows()) {
    throw std::invalid_argument(fmt::format("{}: cannot add column '{}' with {} values to a log of {} rows",
                                            source_, name, values.size(), rows()));
  }
  index_.emplace(name, names_.size());
  names_.push_back(std::move(name));
  columns_.push_back(std::move(values));
}

void MeasurementLog::SetSegmentStarts(std::vector<Eigen::Index> starts) {
  bool ok = !starts.empty() && starts.front() == 0;
  for (std::size_t i = 1; ok && i < starts.size(); ++i) ok = starts[i] > starts[i - 1] && starts[i] < rows();
  if (!ok) {
    throw std::invalid_argument(fmt::format(
        "{}: segment starts must begin with row 0 and increase strictly below the {} rows", source_, rows()));
  }
  segment_starts_ = std::move(starts);
}

namespace {

// The header's column names (line 1): each named, not numbers, the required ones present.
std::vector<std::string> ParseHeader(std::string_view line, const std::string& path,
                                     const MeasurementLogOptions& options) {
  std::vector<std::string_view> cells;
  SplitCells(line, &cells);
  std::vector<std::string> names(cells.begin(), cells.end());
  for (std::size_t j = 0; j < names.size(); ++j) {
    if (names[j].empty()) {
      throw std::invalid_argument(fmt::format(
          "{}: line 1 (header): column {} has no name; give every column a name", path, j + 1));
    }
    double unused = 0.0;
    const auto res = std::from_chars(names[j].data(), names[j].data() + names[j].size(), unused);
    if (res.ec == std::errc() && res.ptr == names[j].data() + names[j].size()) {
      throw std::invalid_argument(fmt::format(
          "{}: line 1 is numbers, not a header; add a header row with the column names (e.g. "
          "'time_s,position_m,force_N')",
          path));
    }
  }
  std::vector<std::string> missing;
  for (const auto& req : options.required_columns) {
    if (std::find(names.begin(), names.end(), req) == names.end()) missing.push_back(req);
  }
  if (!missing.empty()) {
    throw std::invalid_argument(fmt::format(
        "{}: missing required column(s) {}; the columns present are: {}. Rename the column in the "
        "header or choose the column names in the command's options",
        path, JoinNames(missing), JoinNames(names)));
  }
  return names;
}

// Time (the first column) strictly increasing, without gaps above max_gap_ratio × the median step.
void CheckTimeColumn(const std::vector<double>& t, const std::vector<std::size_t>& line_of_row, const std::string& path,
                     const std::string& time_name, const MeasurementLogOptions& options) {
  const std::size_t nrows = t.size();
  for (std::size_t i = 1; i < nrows; ++i) {
    if (!(t[i] > t[i - 1]) && !(options.allow_repeated_times && t[i] == t[i - 1])) {
      throw std::invalid_argument(fmt::format(
          "{}: line {}, column '{}': time {} does not increase (previous row, line {}, has {}); sort the "
          "rows by time and remove repeated samples",
          path, line_of_row[i], time_name, t[i], line_of_row[i - 1], t[i - 1]));
    }
  }
  if (options.max_gap_ratio > 0.0 && nrows >= 3) {
    std::vector<double> steps(nrows - 1);
    for (std::size_t i = 1; i < nrows; ++i) steps[i - 1] = t[i] - t[i - 1];
    std::vector<double> sorted = steps;
    std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(sorted.size() / 2),
                     sorted.end());
    const double median = sorted[sorted.size() / 2];
    std::string where;
    std::size_t count = 0;
    for (std::size_t i = 0; i < steps.size(); ++i) {
      if (steps[i] > options.max_gap_ratio * median) {
        if (count < 5) {
          where += fmt::format("{}after t = {} s (line {}, step {} s)", count ? "; " : "", t[i],
                               line_of_row[i], steps[i]);
        }
        ++count;
      }
    }
    if (count > 0) {
      throw std::invalid_argument(fmt::format(
          "{}: column '{}': {} gap(s) in time larger than {} × the median step {} s: {}{}. Split the log "
          "at the gaps or resample it to a uniform step",
          path, time_name, count, options.max_gap_ratio, median, where, count > 5 ? "; ..." : ""));
    }
  }
}

}  // namespace

MeasurementLog ReadMeasurementLog(const std::string& path, const MeasurementLogOptions& options) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    throw std::runtime_error(fmt::format(
        "{}: cannot open the measurement log (missing file or no permission); check the path", path));
  }
  std::ostringstream buffer;
  buffer << in.rdbuf();
  const std::string text = buffer.str();
  const std::string_view all(text);

  std::size_t pos = 0;
  std::size_t line_no = 0;
  auto next_line = [&](std::string_view* line) {
    if (pos >= all.size()) return false;
    std::size_t end = all.find('\n', pos);
    if (end == std::string_view::npos) end = all.size();
    *line = all.substr(pos, end - pos);
    pos = end + 1;
    ++line_no;
    return true;
  };

  std::string_view line;
  if (!next_line(&line) || Trim(line).empty()) {
    throw std::invalid_argument(fmt::format(
        "{}: the file is empty or its first line is blank; the first line must be a header such as "
        "'time_s,position_m,force_N'",
        path));
  }
  if (line.size() >= 3 && line.substr(0, 3) == "\xEF\xBB\xBF") line.remove_prefix(3);  // UTF-8 BOM
  std::vector<std::string> names = ParseHeader(line, path, options);
  std::vector<std::string_view> cells;

  const std::size_t ncols = names.size();
  std::vector<std::vector<double>> data(ncols);
  const std::size_t reserve = static_cast<std::size_t>(std::count(all.begin(), all.end(), '\n')) + 1;
  for (auto& c : data) c.reserve(reserve);
  std::vector<std::size_t> line_of_row;
  line_of_row.reserve(reserve);

  bool blank_seen = false;
  std::size_t blank_line = 0;
  while (next_line(&line)) {
    if (Trim(line).empty()) {
      if (!blank_seen) blank_line = line_no;
      blank_seen = true;
      continue;
    }
    if (blank_seen) {
      throw std::invalid_argument(fmt::format(
          "{}: line {} is blank but data follows on line {}; remove the blank line", path, blank_line,
          line_no));
    }
    SplitCells(line, &cells);
    if (cells.size() != ncols) {
      throw std::invalid_argument(fmt::format(
          "{}: line {} has {} cells but the header has {} columns ({}); every row needs one number per "
          "column",
          path, line_no, cells.size(), ncols, JoinNames(names)));
    }
    for (std::size_t j = 0; j < ncols; ++j) {
      std::string_view cell = cells[j];
      if (!cell.empty() && cell.front() == '+') cell.remove_prefix(1);
      double value = 0.0;
      const auto res = std::from_chars(cell.data(), cell.data() + cell.size(), value);
      if (res.ec == std::errc::result_out_of_range) {
        throw std::invalid_argument(fmt::format(
            "{}: line {}, column '{}': '{}' is out of the range of a double; fix the value", path,
            line_no, names[j], cells[j]));
      }
      if (res.ec != std::errc() || res.ptr != cell.data() + cell.size() || cell.empty()) {
        throw std::invalid_argument(fmt::format(
            "{}: line {}, column '{}': '{}' is not a number; write a decimal number such as 1.5e-3 "
            "(dot as decimal separator, comma between cells)",
            path, line_no, names[j], cells[j]));
      }
      if (!std::isfinite(value)) {
        throw std::invalid_argument(fmt::format(
            "{}: line {}, column '{}': the value is {} (NaN or Inf); remove the row or fill the value "
            "(e.g. interpolate) before comparing",
            path, line_no, names[j], cells[j]));
      }
      data[j].push_back(value);
    }
    line_of_row.push_back(line_no);
  }

  const std::size_t nrows = data[0].size();
  if (static_cast<Eigen::Index>(nrows) < options.min_rows) {
    throw std::invalid_argument(fmt::format(
        "{}: only {} data row(s), at least {} are needed; record a longer log", path, nrows,
        options.min_rows));
  }

  CheckTimeColumn(data[0], line_of_row, path, names[0], options);

  std::vector<Eigen::VectorXd> columns(ncols);
  for (std::size_t j = 0; j < ncols; ++j) {
    columns[j] = Eigen::Map<const Eigen::VectorXd>(data[j].data(), static_cast<Eigen::Index>(nrows));
  }
  return MeasurementLog(std::move(names), std::move(columns), path);
}

void WriteMeasurementLog(const MeasurementLog& log, const std::string& path) {
  std::string text;
  const auto& names = log.names();
  for (std::size_t j = 0; j < names.size(); ++j) {
    text += names[j];
    text += j + 1 < names.size() ? ',' : '\n';
  }
  std::vector<const Eigen::VectorXd*> cols;
  for (const auto& n : names) cols.push_back(&log.column(n));
  text.reserve(text.size() + static_cast<std::size_t>(log.rows()) * names.size() * 24);
  char buf[32];
  for (Eigen::Index i = 0; i < log.rows(); ++i) {
    for (std::size_t j = 0; j < cols.size(); ++j) {
      const auto res = std::to_chars(buf, buf + sizeof(buf), (*cols[j])(i));  // shortest round trip
      text.append(buf, res.ptr);
      text += j + 1 < cols.size() ? ',' : '\n';
    }
  }
  WriteFileSafely(path, text);
}

}  // namespace mb
