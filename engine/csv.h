#pragma once
// The one CSV reader and writer of the project (RFC 4180: comma-separated cells, a cell in double quotes may hold
// commas, line breaks and doubled quotes ""). Logs, measurements (engine/table.h), the GP training tables and the
// sweeps' runs.csv (tools/batch/sweep.cc) all go through it.
//
// Reading: CRLF or LF line ends; a UTF-8 byte-order mark before the first record is skipped; spaces and tabs
// around an unquoted cell are dropped (a logger's "1.5, 2.0"); a line of only spaces and tabs is a blank record
// (CsvRecord::blank), which the caller accepts or refuses. Writing quotes a cell only when it must (a comma, a
// quote, a line break, or leading/trailing blanks that a reader would drop).

#include <cstddef>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace mb {

/// One record of a CSV text: its cells and the 1-based line where it starts.
struct CsvRecord {
  /// The cells, unquoted; views into the text or into the reader's buffer: valid until the next CsvReader::Next.
  std::vector<std::string_view> cells;
  std::size_t line = 0;  ///< 1-based line number of the record's first character
  bool blank = false;    ///< the line holds nothing but spaces and tabs (cells then is one empty cell)
};

/// Reads the records of a CSV text held in memory, one at a time (no copy of unquoted cells).
class CsvReader {
 public:
  /// `text` must outlive the reader. Skips a UTF-8 byte-order mark at its start.
  explicit CsvReader(std::string_view text);
  /// Reads the next record into `record`; false at the end of the text. Never throws on content: a quote left
  /// open runs to the end of the text.
  bool Next(CsvRecord* record);
  /// The line number the next record starts on (1-based).
  std::size_t line() const noexcept { return line_; }

 private:
  struct Piece {
    bool in_buffer;
    std::size_t offset, size;
  };
  void ReadQuoted(Piece* piece);
  std::string_view text_;
  std::size_t pos_ = 0;
  std::size_t line_ = 1;
  std::string buffer_;  // unescaped quoted cells that held a doubled quote
  std::vector<std::pair<std::size_t, Piece>> patches_;  // (cell index, its text in buffer_) for unescaped cells
};

/// The records of one line of CSV (a convenience for tests and short texts): SplitCsvLine("a,\"b,c\"") = {a, b,c}.
std::vector<std::string> SplitCsvLine(std::string_view line);

/// `text` as one CSV cell: unchanged, or in double quotes with inner quotes doubled when it holds a comma, a
/// quote, a line break or leading/trailing spaces or tabs.
std::string CsvCell(std::string_view text);
/// The cells joined by commas (each through CsvCell), without a line end.
std::string CsvLine(const std::vector<std::string>& cells);
/// Appends `value` in the shortest form that reads back exactly (std::to_chars).
void AppendCsvNumber(double value, std::string* out);

/// A whole CSV file as text cells: the header (first record) and the rows, each with the line it starts on.
/// For tables whose cells are not all numbers (the sweeps' runs.csv); numeric tables are engine/table.h's Table.
struct CsvTextTable {
  std::string source;                          ///< the file path, for messages
  std::vector<std::string> header;             ///< empty when the file is empty
  std::vector<std::vector<std::string>> rows;  ///< blank lines are skipped
  std::vector<std::size_t> row_lines;          ///< 1-based line of each row
};
/// Reads `path` as a CsvTextTable. @throws std::runtime_error "<path>: cannot open …" when it cannot be read.
CsvTextTable ReadCsvTextTable(const std::string& path);

}  // namespace mb
