#include "engine/csv.h"

#include "engine/file_error.h"
#include "engine/input_file.h"

#include <charconv>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include <fmt/format.h>

namespace mb {
namespace {

bool IsBlank(char c) { return c == ' ' || c == '\t'; }

std::string_view TrimUnquoted(std::string_view s) {
  while (!s.empty() && IsBlank(s.front())) s.remove_prefix(1);
  while (!s.empty() && (IsBlank(s.back()) || s.back() == '\r')) s.remove_suffix(1);
  return s;
}

}  // namespace

CsvReader::CsvReader(std::string_view text) : text_(text) {
  if (text_.substr(0, 3) == "\xEF\xBB\xBF") pos_ = 3;  // UTF-8 byte-order mark
}

void CsvReader::ReadQuoted(Piece* piece) {
  const std::size_t n = text_.size();
  ++pos_;  // the opening quote
  const std::size_t start = pos_;
  std::size_t end = n;
  bool copied = false;
  const std::size_t buffer_start = buffer_.size();
  while (pos_ < n) {
    const char c = text_[pos_];
    if (c == '"' && pos_ + 1 < n && text_[pos_ + 1] == '"') {  // a doubled quote: one quote in the cell
      if (!copied) buffer_.append(text_.substr(start, pos_ - start));
      copied = true;
      buffer_ += '"';
      pos_ += 2;
      continue;
    }
    if (c == '"') {
      end = pos_++;
      break;
    }
    if (c == '\n') ++line_;
    if (copied) buffer_ += c;
    ++pos_;
  }
  while (pos_ < n && (IsBlank(text_[pos_]) || text_[pos_] == '\r')) ++pos_;
  if (pos_ < n && text_[pos_] != ',' && text_[pos_] != '\n') {  // text after the closing quote: kept as written
    if (!copied) buffer_.append(text_.substr(start, end - start));
    copied = true;
    const std::size_t next = text_.find_first_of(",\n", pos_);
    const std::size_t stop = next == std::string_view::npos ? n : next;
    buffer_.append(TrimUnquoted(text_.substr(pos_, stop - pos_)));
    pos_ = stop;
  }
  *piece = copied ? Piece{true, buffer_start, buffer_.size() - buffer_start} : Piece{false, start, end - start};
}

bool CsvReader::Next(CsvRecord* record) {
  const std::size_t n = text_.size();
  if (pos_ >= n) return false;
  record->cells.clear();
  record->line = line_;
  record->blank = false;
  patches_.clear();
  buffer_.clear();
  std::size_t p = pos_;
  while (p < n && (IsBlank(text_[p]) || text_[p] == '\r')) ++p;
  if (p == n || text_[p] == '\n') {
    record->blank = true;
    record->cells.emplace_back();
    pos_ = p == n ? n : p + 1;
    if (p < n) ++line_;
    return true;
  }
  const char* const data = text_.data();
  while (true) {
    while (pos_ < n && IsBlank(data[pos_])) ++pos_;
    if (pos_ < n && data[pos_] == '"') {
      Piece piece{true, 0, 0};
      ReadQuoted(&piece);
      if (piece.in_buffer) {
        patches_.emplace_back(record->cells.size(), piece);  // set below: the buffer may still grow
        record->cells.emplace_back();
      } else {
        record->cells.emplace_back(data + piece.offset, piece.size);
      }
    } else {
      std::size_t stop = pos_;
      while (stop < n && data[stop] != ',' && data[stop] != '\n') ++stop;
      record->cells.push_back(TrimUnquoted(text_.substr(pos_, stop - pos_)));
      pos_ = stop;
    }
    if (pos_ < n && data[pos_] == ',') {
      ++pos_;
      continue;
    }
    if (pos_ < n) {  // '\n'
      ++pos_;
      ++line_;
    }
    break;
  }
  const std::string_view buffer(buffer_);
  for (const auto& [cell, piece] : patches_) record->cells[cell] = buffer.substr(piece.offset, piece.size);
  return true;
}

std::vector<std::string> SplitCsvLine(std::string_view line) {
  CsvReader reader(line);
  CsvRecord record;
  if (!reader.Next(&record)) return {std::string()};
  return {record.cells.begin(), record.cells.end()};
}

std::string CsvCell(std::string_view text) {
  const bool padded = !text.empty() && (IsBlank(text.front()) || IsBlank(text.back()));
  if (!padded && text.find_first_of(",\"\n\r") == std::string_view::npos) return std::string(text);
  std::string out = "\"";
  for (const char c : text) {
    if (c == '"') out += '"';
    out += c;
  }
  return out + "\"";
}

std::string CsvLine(const std::vector<std::string>& cells) {
  std::string line;
  for (std::size_t i = 0; i < cells.size(); ++i) {
    if (i > 0) line += ',';
    line += CsvCell(cells[i]);
  }
  return line;
}

void AppendCsvNumber(double value, std::string* out) {
  char buf[32];
  const auto res = std::to_chars(buf, buf + sizeof(buf), value);  // shortest round trip
  out->append(buf, res.ptr);
}

CsvTextTable ReadCsvTextTable(const std::string& path) {
  const std::string text = ReadInputFile(path, "CSV table");  // a regular file within the size limit
  CsvTextTable table;
  table.source = path;
  CsvReader reader(text);
  CsvRecord record;
  while (reader.Next(&record)) {
    if (record.blank) continue;
    std::vector<std::string> cells(record.cells.begin(), record.cells.end());
    if (table.header.empty()) {
      table.header = std::move(cells);
      continue;
    }
    table.rows.push_back(std::move(cells));
    table.row_lines.push_back(record.line);
  }
  return table;
}

}  // namespace mb
