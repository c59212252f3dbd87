#include "engine/table.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include <fmt/format.h>

#include "engine/csv.h"
#include "engine/file_error.h"
#include "engine/input_file.h"
#include "engine/output_file.h"

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

}  // namespace

Table::Table(std::vector<std::string> names, std::vector<Eigen::VectorXd> columns, std::string source)
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

bool Table::has_column(std::string_view name) const { return index_.find(name) != index_.end(); }

const Eigen::VectorXd& Table::column(std::string_view name) const {
  const auto it = index_.find(name);
  if (it == index_.end()) {
    throw std::invalid_argument(fmt::format("{}: no column '{}'; the columns present are: {}", source_,
                                            name, JoinNames(names_)));
  }
  return columns_[it->second];
}

void Table::AddColumn(std::string name, Eigen::VectorXd values) {
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

void Table::SetSegmentStarts(std::vector<Eigen::Index> starts) {
  bool ok = !starts.empty() && starts.front() == 0;
  for (std::size_t i = 1; ok && i < starts.size(); ++i) ok = starts[i] > starts[i - 1] && starts[i] < rows();
  if (!ok) {
    throw std::invalid_argument(fmt::format(
        "{}: segment starts must begin with row 0 and increase strictly below the {} rows", source_, rows()));
  }
  segment_starts_ = std::move(starts);
}

void Table::SetRowLines(std::vector<std::size_t> lines) {
  if (!lines.empty() && lines.size() != static_cast<std::size_t>(rows())) {
    throw std::invalid_argument(fmt::format("{}: {} row lines for {} rows", source_, lines.size(), rows()));
  }
  row_lines_ = std::move(lines);
}

namespace {

// The header's column names (line 1): each named, not numbers, the required ones present.
std::vector<std::string> ParseHeader(const std::vector<std::string_view>& cells, const std::string& path,
                                     const TableReadOptions& options) {
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

// One cell as a finite double; the messages name the file, line and column and say how to fix it.
double ParseCell(std::string_view written, const std::string& path, std::size_t line, const std::string& column) {
  std::string_view cell = written;
  if (!cell.empty() && cell.front() == '+') cell.remove_prefix(1);
  double value = 0.0;
  const auto res = std::from_chars(cell.data(), cell.data() + cell.size(), value);
  if (res.ec == std::errc::result_out_of_range) {
    throw std::invalid_argument(fmt::format(
        "{}: line {}, column '{}': '{}' is out of the range of a double; fix the value", path, line, column, written));
  }
  if (res.ec != std::errc() || res.ptr != cell.data() + cell.size() || cell.empty()) {
    throw std::invalid_argument(fmt::format(
        "{}: line {}, column '{}': '{}' is not a number; write a decimal number such as 1.5e-3 "
        "(dot as decimal separator, comma between cells)",
        path, line, column, written));
  }
  if (!std::isfinite(value)) {
    throw std::invalid_argument(fmt::format(
        "{}: line {}, column '{}': the value is {} (NaN or Inf); remove the row or fill the value "
        "(e.g. interpolate) before comparing",
        path, line, column, written));
  }
  return value;
}

// A regular file within the input size limit only (engine/input_file.h).
std::string ReadWholeFile(const std::string& path, const TableReadOptions& options) {
  return ReadInputFile(path, options.kind);
}

}  // namespace

Table ReadTable(const std::string& path, const TableReadOptions& options) {
  const std::string text = ReadWholeFile(path, options);
  CsvReader reader(text);
  CsvRecord record;
  if (!reader.Next(&record) || record.blank) {
    throw std::invalid_argument(fmt::format(
        "{}: the file is empty or its first line is blank; the first line must be a header such as "
        "'time_s,position_m,force_N'",
        path));
  }
  // pandas' default to_csv: an unnamed first column holding the row index.
  const std::size_t skip = options.drop_unnamed_index && record.cells.size() > 1 && record.cells[0].empty() ? 1 : 0;
  std::vector<std::string> names = ParseHeader(
      std::vector<std::string_view>(record.cells.begin() + static_cast<std::ptrdiff_t>(skip), record.cells.end()),
      path, options);
  const std::size_t ncols = names.size();
  std::vector<std::vector<double>> data(ncols);
  const std::size_t reserve = static_cast<std::size_t>(std::count(text.begin(), text.end(), '\n')) + 1;
  for (auto& c : data) c.reserve(reserve);
  std::vector<std::size_t> line_of_row;
  line_of_row.reserve(reserve);

  std::size_t blank_line = 0;  // the first blank line seen (0: none)
  while (reader.Next(&record)) {
    if (record.blank) {
      if (blank_line == 0) blank_line = record.line;
      continue;
    }
    if (blank_line != 0) {
      throw std::invalid_argument(fmt::format(
          "{}: line {} is blank but data follows on line {}; remove the blank line", path, blank_line, record.line));
    }
    if (record.cells.size() != ncols + skip) {
      throw std::invalid_argument(fmt::format(
          "{}: line {} has {} cells but the header has {} columns ({}); every row needs one number per "
          "column",
          path, record.line, record.cells.size(), ncols + skip, JoinNames(names)));
    }
    for (std::size_t j = 0; j < ncols; ++j) {
      data[j].push_back(ParseCell(record.cells[j + skip], path, record.line, names[j]));
    }
    line_of_row.push_back(record.line);
  }
  const auto nrows = static_cast<Eigen::Index>(line_of_row.size());
  std::vector<Eigen::VectorXd> columns(ncols);
  for (std::size_t j = 0; j < ncols; ++j) columns[j] = Eigen::Map<const Eigen::VectorXd>(data[j].data(), nrows);
  Table table(std::move(names), std::move(columns), path);
  table.SetRowLines(std::move(line_of_row));
  return table;
}

std::string TableCsv(const Table& table) {
  const auto& names = table.names();
  std::string text = CsvLine(names) + "\n";
  std::vector<const Eigen::VectorXd*> cols;
  for (const auto& n : names) cols.push_back(&table.column(n));
  text.reserve(text.size() + static_cast<std::size_t>(table.rows()) * names.size() * 24);
  for (Eigen::Index i = 0; i < table.rows(); ++i) {
    for (std::size_t j = 0; j < cols.size(); ++j) {
      AppendCsvNumber((*cols[j])(i), &text);
      text += j + 1 < cols.size() ? ',' : '\n';
    }
  }
  return text;
}

void WriteTable(const Table& table, const std::string& path) { WriteFileSafely(path, TableCsv(table)); }

}  // namespace mb
