// RFC 4180 CSV (comma separated, fields with a comma, quote or line break quoted, quotes
// doubled) and atomic text files.
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

// Writes to a temporary file in the same folder, then renames it over `path`: a reader sees the
// old file or the new one, never a part. False with "PATH: reason".
bool writeFileAtomic(const std::string& path, const std::string& contents, std::string* error);
bool readFile(const std::string& path, std::string* contents, std::string* error);

}  // namespace parity::bench
