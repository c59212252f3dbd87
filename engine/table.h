#pragma once
// The one table type of the project: named columns of doubles read from and written to CSV (engine/csv.h), with
// the file and the line of each row for messages. Measurement logs (models/diagnosis/measurement_log.h adds the
// time checks), simulation logs, GP training tables and predictions are Tables; the sweeps' runs.csv, whose cells
// are not all numbers, is read as engine/csv.h's CsvTextTable.
//
// The file format is the one of the measured records (e.g. the EMPS benchmark's diagrams/emps/data/DATA_EMPS.csv):
//   time_s,position_m,reference_m,input_V,force_N
//   0,7.45e-06,0.00010782208,2.538628089,89.23443221
// one header row with the column names (units in the names; RFC 4180 quotes allowed), then one row per sample of
// comma-separated numbers. Blank lines at the end are allowed.

#include <cstddef>
#include <functional>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include <Eigen/Core>

namespace mb {

// A table of equally long, named double columns, with the file it came from and the line of each row for
// messages. For logs and measurements (models/diagnosis/measurement_log.h: MeasurementLog), column 0 is the time [s].
// Invariants (checked by the constructor): at least one column, unique non-empty names, equal lengths.
class Table {
 public:
  // Builds a table from names and columns (same count, equal lengths).
  // `source` names where the data came from (a file path) and appears in error messages.
  // Throws std::invalid_argument when the counts or lengths differ or a name is empty or repeated.
  Table(std::vector<std::string> names, std::vector<Eigen::VectorXd> columns, std::string source = "<memory>");

  // Number of samples (rows).
  Eigen::Index rows() const { return columns_.empty() ? 0 : columns_.front().size(); }
  // Column names in file order (names()[0] is the time column of a measurement log).
  const std::vector<std::string>& names() const { return names_; }
  // Where the table came from (a file path or "<memory>").
  const std::string& source() const { return source_; }
  // True when a column of that exact name exists. O(1), as column().
  bool has_column(std::string_view name) const;
  // The column of that name. Throws std::invalid_argument naming the source and listing the columns
  // present when there is none.
  const Eigen::VectorXd& column(std::string_view name) const;
  // Column 0 (the time [s] of a measurement log).
  const Eigen::VectorXd& time() const { return columns_.front(); }

  // Appends a column (e.g. a derived velocity). Throws std::invalid_argument when the name exists
  // already or the length differs from rows().
  void AddColumn(std::string name, Eigen::VectorXd values);

  // How the log was taken in (rows merged, resampled, gaps), one sentence each, for reports.
  const std::vector<std::string>& notes() const { return notes_; }
  void AddNote(std::string note) { notes_.push_back(std::move(note)); }
  // The first row of each contiguous segment: a gap in time separates two (IntakeMeasurementLog). {0} for one
  // segment. Filters and derivatives run per segment, never across a gap.
  const std::vector<Eigen::Index>& segment_starts() const { return segment_starts_; }
  // Throws std::invalid_argument unless `starts` begins with 0 and increases strictly below rows().
  void SetSegmentStarts(std::vector<Eigen::Index> starts);
  // The 1-based line of the file each row was read from (ReadTable); empty for a table built in memory or
  // derived from one (merged, resampled).
  const std::vector<std::size_t>& row_lines() const { return row_lines_; }
  void SetRowLines(std::vector<std::size_t> lines);

 private:
  // Heterogeneous lookup by string_view: no temporary string per query.
  struct NameHash {
    using is_transparent = void;
    std::size_t operator()(std::string_view s) const noexcept { return std::hash<std::string_view>{}(s); }
  };
  std::vector<std::string> names_;
  std::vector<Eigen::VectorXd> columns_;
  std::string source_;
  std::vector<std::string> notes_;
  std::vector<Eigen::Index> segment_starts_{0};
  std::vector<std::size_t> row_lines_;
  std::unordered_map<std::string, std::size_t, NameHash, std::equal_to<>> index_;  // name → column
};

// What ReadTable checks.
struct TableReadOptions {
  // Columns that must be present.
  std::vector<std::string> required_columns;
  // What the file is, for the message when it cannot be opened ("<path>: cannot open the <kind> …").
  std::string kind = "table";
  // An unnamed first column (pandas' default DataFrame.to_csv writes the row index so: ",x,y") is the row index
  // and is dropped; false refuses it ("column 1 has no name").
  bool drop_unnamed_index = false;
};

// Reads a CSV table (format above): one double per cell, with the row lines recorded.
// Throws std::runtime_error when the file cannot be opened, and std::invalid_argument, with the file, the 1-based
// line number, the column name and a fix, for: an empty file or header, an empty or repeated column name, a header
// of numbers, a missing required column (the message lists the columns present), a row with a different number of
// cells, a blank line followed by data, a non-numeric cell, NaN or Inf, a value out of the range of a double.
// Parsing uses std::from_chars: 24,841 rows × 6 columns read in ~30 ms (Release, on a loaded 2-core machine).
Table ReadTable(const std::string& path, const TableReadOptions& options = {});

// Writes a Table as CSV (header row with RFC 4180 quoting where a name needs it, then rows; each number in the
// shortest form that reads back exactly, std::to_chars). Throws std::runtime_error when the file cannot be written
// (engine/output_file.h: WriteFileSafely).
void WriteTable(const Table& table, const std::string& path);
// The same CSV text, in memory.
std::string TableCsv(const Table& table);

}  // namespace mb
