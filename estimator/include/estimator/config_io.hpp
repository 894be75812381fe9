#pragma once
// Detector configuration files (JSON), read with the project's JSON
// reader (hal/formats): the estimator's own reader, kept out of the flight
// library (estimator_config_io links it). Keys are the DetectorConfig field
// names; "handrail" takes a kind ("iss" or "round") and a length, or the
// four geometry numbers. Unknown keys and out-of-range values are errors
// that name the key and line.
#include <string>

#include "estimator/config.hpp"
#include "formats/json.hpp"

namespace estimator {

bool load_detector_config(const std::string& path, DetectorConfig* cfg, std::string* error);
bool parse_detector_config(const std::string& text, const std::string& path, DetectorConfig* cfg,
                           std::string* error);
// The same from an already parsed object (a section of a larger file, whose
// name with a dot is `key_prefix`, e.g. "estimator.": errors name the key
// as the file spells it).
bool read_detector_config(const formats::JsonValue& object, const std::string& path,
                          DetectorConfig* cfg, std::string* error,
                          const std::string& key_prefix = "");

}  // namespace estimator
