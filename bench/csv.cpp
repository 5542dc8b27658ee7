#include "bench/csv.h"

namespace parity::bench {

int CsvTable::column(const std::string& name) const {
  for (size_t i = 0; i < header.size(); ++i)
    if (header[i] == name) return static_cast<int>(i);
  return -1;
}

namespace {

void appendField(std::string& out, const std::string& field) {
  if (field.find_first_of(",\"\r\n") == std::string::npos) {
    out += field;
    return;
  }
  out += '"';
  for (char c : field) {
    if (c == '"') out += '"';
    out += c;
  }
  out += '"';
}

void appendRow(std::string& out, const std::vector<std::string>& row) {
  for (size_t i = 0; i < row.size(); ++i) {
    if (i) out += ',';
    appendField(out, row[i]);
  }
  out += '\n';
}

}  // namespace

std::string formatCsv(const CsvTable& table) {
  std::string out;
  appendRow(out, table.header);
  for (const auto& row : table.rows) appendRow(out, row);
  return out;
}

bool parseCsv(const std::string& text, CsvTable* table, std::string* error) {
  std::vector<std::vector<std::string>> records;
  std::vector<std::string> record;
  std::string field;
  bool quoted = false, fieldStarted = false;
  size_t line = 1, recordLine = 1;
  for (size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (quoted) {
      if (c == '"') {
        if (i + 1 < text.size() && text[i + 1] == '"') {
          field += '"';
          ++i;
        } else {
          quoted = false;
        }
      } else {
        if (c == '\n') ++line;
        field += c;
      }
      continue;
    }
    if (c == '"' && field.empty()) {
      quoted = fieldStarted = true;
    } else if (c == ',') {
      record.push_back(std::move(field));
      field.clear();
      fieldStarted = true;
    } else if (c == '\r') {
      continue;
    } else if (c == '\n') {
      if (fieldStarted || !field.empty() || !record.empty()) {
        record.push_back(std::move(field));
        records.push_back(std::move(record));
      }
      field.clear();
      record.clear();
      fieldStarted = false;
      recordLine = ++line;
    } else {
      field += c;
      fieldStarted = true;
    }
  }
  if (quoted) {
    *error = "line " + std::to_string(recordLine) + ": unterminated quoted field";
    return false;
  }
  if (fieldStarted || !field.empty() || !record.empty()) {
    record.push_back(std::move(field));
    records.push_back(std::move(record));
  }
  if (records.empty()) {
    *error = "no header line";
    return false;
  }
  table->header = std::move(records.front());
  table->rows.assign(std::make_move_iterator(records.begin() + 1), std::make_move_iterator(records.end()));
  for (size_t r = 0; r < table->rows.size(); ++r) {
    if (table->rows[r].size() != table->header.size()) {
      *error = "record " + std::to_string(r + 2) + " has " + std::to_string(table->rows[r].size()) + " fields, the header " +
               std::to_string(table->header.size());
      return false;
    }
  }
  return true;
}

}  // namespace parity::bench
