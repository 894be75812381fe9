#pragma once
// royale::String: royale's own string class, here the standard string with
// royale's conversions added (toStdString, fromStdString, fromCArray), so
// an application may use either interface and pass it where a std::string
// is taken.
#include <string>
#include <utility>

namespace royale {

class String : public std::string {
 public:
  using std::string::string;
  String() = default;
  String(const std::string& s) : std::string(s) {}  // NOLINT: implicit, so a standard one passes
  String(std::string&& s) : std::string(std::move(s)) {}  // NOLINT: as above

  std::string toStdString() const { return *this; }
  static String fromStdString(const std::string& s) { return String(s); }
  static String fromCArray(const char* s) { return String(s != nullptr ? s : ""); }
};

}  // namespace royale
