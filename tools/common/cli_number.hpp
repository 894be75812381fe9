#pragma once
// A whole number from the command line, all of it: "abc", "2x", "" and
// values outside [min, max] are refused (std::atol took "abc" as 0 and
// "2x" as 2, so hreval --max-frames abc ran nothing and said nothing).
#include <string>

namespace tools {

// True with *out set when `text` is a base-10 integer within [min, max];
// else false with *error saying what is wrong, e.g. "must be a whole number
// from 1 to 1000000, not 'abc'".
bool parse_whole_number(const std::string& text, long long min, long long max, long long* out,
                        std::string* error);

}  // namespace tools
