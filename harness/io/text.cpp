#include "harness/io/text.h"

#include <ctime>

namespace parity::harness {

std::string oneLine(std::string text, size_t maxChars) {
  while (!text.empty() && (text.back() == '\n' || text.back() == '\r' || text.back() == ' ')) text.pop_back();
  for (char& c : text)
    if (c == '\n' || c == '\r') c = ' ';
  if (text.size() > maxChars) text = text.substr(0, maxChars) + "...";
  return text;
}

std::string nowIso() {
  std::time_t t = std::time(nullptr);
  char buf[32];
  std::strftime(buf, sizeof(buf), "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&t));
  return buf;
}

}  // namespace parity::harness
