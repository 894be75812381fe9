#pragma once
// A 5 x 7 pixel font for labels on debug images and charts: digits, capital
// letters (lower case is drawn as capitals) and common punctuation. Each
// glyph is 7 rows, top first; bit 4 is the leftmost column.
#include <cstdint>

namespace tools {

const std::uint8_t* font5x7_rows(char c);

}  // namespace tools
