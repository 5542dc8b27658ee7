// RFC 4180 CSV (comma separated, fields with a comma, quote or line break quoted, quotes
// doubled).
#pragma once

#include <string>
#include <vector>

namespace parity::bench {

struct CsvTable {
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
  // Index of a header column, or -1.
  int column(const std::string& name) const;
};

std::string formatCsv(const CsvTable& table);
// False with a one-line reason (line number) for an unterminated quote or a row whose field
// count differs from the header's.
bool parseCsv(const std::string& text, CsvTable* table, std::string* error);

}  // namespace parity::bench
