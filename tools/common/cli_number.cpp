#include "cli_number.hpp"

#include <cctype>
#include <cerrno>
#include <cstdlib>

namespace tools {

bool parse_whole_number(const std::string& text, long long min, long long max, long long* out,
                        std::string* error) {
  // strtoll would skip leading blanks and take a sign and digits only;
  // the text must be the number, nothing around it.
  const bool starts_well =
      !text.empty() && (std::isdigit(static_cast<unsigned char>(text[0])) || text[0] == '-');
  char* end = nullptr;
  errno = 0;
  const long long v = std::strtoll(text.c_str(), &end, 10);
  if (!starts_well || end == text.c_str() || *end != '\0' || errno == ERANGE || v < min ||
      v > max) {
    *error = "must be a whole number from " + std::to_string(min) + " to " + std::to_string(max) +
             ", not '" + text + "'";
    return false;
  }
  *out = v;
  return true;
}

}  // namespace tools
