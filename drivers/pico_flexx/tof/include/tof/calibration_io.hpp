#pragma once
// The calibration file: JSON, versioned, every key checked at load with
// errors that name the key and its line ("PATH:LINE: key 'lens.fx_px':
// ..."). Read at start-up (it allocates; not for a frame path). The format
// is in CALIBRATION.md beside this library.
#include <string>

#include "tof/calibration.hpp"

namespace tof {

// Parses a calibration from `text`; `path` only names it in errors. Unknown
// keys are refused (a misspelt key would otherwise be silently ignored).
bool parse_calibration(const std::string& text, const std::string& path, Calibration* out,
                       std::string* error);

// Reads (bounded, regular files only) and parses a calibration file.
bool load_calibration_file(const std::string& path, Calibration* out, std::string* error);

// The calibration as the file's JSON. Numbers are written with 17
// significant digits, so they read back exactly; the per-pixel table in
// micrometre steps (written in mm with three decimals).
std::string calibration_to_json(const Calibration& cal);

// Writes calibration_to_json to `path`; false with *error naming the path.
bool write_calibration_file(const std::string& path, const Calibration& cal, std::string* error);

}  // namespace tof
