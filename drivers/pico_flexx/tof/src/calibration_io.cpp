#include "tof/calibration_io.hpp"

#include <cmath>
#include <cstdio>
#include <string_view>

#include "formats/json.hpp"
#include "formats/text_file.hpp"
#include "tof/raw_frame.hpp"

namespace tof {
namespace {

using formats::JsonValue;

// Walks the document; every error names the file, the line and the key's
// full name ("frequencies[1].wiggle_cos_rad").
class Reader {
 public:
  explicit Reader(const std::string& path, std::string* error) : path_(path), error_(error) {}

  bool fail(const JsonValue& v, const std::string& key, const std::string& what) {
    *error_ = path_ + ":" + std::to_string(v.line) + ": key '" + key + "': " + what;
    return false;
  }

  // Every member of `obj` must be one of `allowed`.
  bool only_keys(const JsonValue& obj, const std::string& prefix,
                 std::initializer_list<std::string_view> allowed) {
    for (const auto& [name, value] : obj.members) {
      bool known = false;
      for (std::string_view a : allowed) known = known || name == a;
      if (!known) return fail(value, prefix + name, "unknown key");
    }
    return true;
  }

  const JsonValue* member(const JsonValue& obj, const std::string& prefix, const char* name,
                          JsonValue::Type type) {
    const JsonValue* v = obj.find(name);
    if (v == nullptr) {
      fail(obj, prefix + name, "missing");
      return nullptr;
    }
    if (v->type != type) {
      fail(*v, prefix + name, std::string("must be ") + formats::to_string(type));
      return nullptr;
    }
    return v;
  }

  // A number in [lo, hi].
  bool number(const JsonValue& obj, const std::string& prefix, const char* name, double lo,
              double hi, double* out) {
    const JsonValue* v = member(obj, prefix, name, JsonValue::Type::kNumber);
    if (v == nullptr) return false;
    if (!(v->number >= lo && v->number <= hi)) {
      char range[96];
      std::snprintf(range, sizeof range, "%.17g is outside [%g, %g]", v->number, lo, hi);
      return fail(*v, prefix + name, range);
    }
    *out = v->number;
    return true;
  }

  // An array of exactly n numbers, each in [lo, hi].
  bool numbers(const JsonValue& obj, const std::string& prefix, const char* name, std::size_t n,
               double lo, double hi, double* out) {
    const JsonValue* v = member(obj, prefix, name, JsonValue::Type::kArray);
    if (v == nullptr) return false;
    if (v->items.size() != n) {
      return fail(
          *v, prefix + name,
          "must hold " + std::to_string(n) + " numbers, not " + std::to_string(v->items.size()));
    }
    for (std::size_t k = 0; k < n; ++k) {
      const JsonValue& item = v->items[k];
      if (!item.is_number() || !(item.number >= lo && item.number <= hi)) {
        char what[96];
        std::snprintf(what, sizeof what, "must be a number in [%g, %g]", lo, hi);
        return fail(item, prefix + name + "[" + std::to_string(k) + "]", what);
      }
      out[k] = item.number;
    }
    return true;
  }

 private:
  const std::string& path_;
  std::string* error_;
};

bool read_lens(Reader& r, const JsonValue& doc, Calibration* cal) {
  const JsonValue* lens = r.member(doc, "", "lens", JsonValue::Type::kObject);
  if (lens == nullptr) return false;
  hal::LensParameters& l = cal->lens;
  const std::string p = "lens.";
  return r.only_keys(*lens, p,
                     {"fx_px", "fy_px", "cx_px", "cy_px", "k1", "k2", "k3", "p1", "p2"}) &&
         r.number(*lens, p, "fx_px", 1.0, 10000.0, &l.fx_px) &&
         r.number(*lens, p, "fy_px", 1.0, 10000.0, &l.fy_px) &&
         r.number(*lens, p, "cx_px", 0.0, kWidthPx, &l.cx_px) &&
         r.number(*lens, p, "cy_px", 0.0, kHeightPx, &l.cy_px) &&
         r.number(*lens, p, "k1", -10.0, 10.0, &l.k1) &&
         r.number(*lens, p, "k2", -10.0, 10.0, &l.k2) &&
         r.number(*lens, p, "k3", -10.0, 10.0, &l.k3) &&
         r.number(*lens, p, "p1", -1.0, 1.0, &l.p1) && r.number(*lens, p, "p2", -1.0, 1.0, &l.p2);
}

bool read_frequencies(Reader& r, const JsonValue& doc, Calibration* cal) {
  const JsonValue* list = r.member(doc, "", "frequencies", JsonValue::Type::kArray);
  if (list == nullptr) return false;
  if (list->items.empty() || list->items.size() > kMaxFrequencies) {
    return r.fail(*list, "frequencies", "must hold 1 or 2 frequencies");
  }
  cal->frequency_count = static_cast<int>(list->items.size());
  for (std::size_t f = 0; f < list->items.size(); ++f) {
    const JsonValue& item = list->items[f];
    const std::string p = "frequencies[" + std::to_string(f) + "].";
    if (!item.is_object()) return r.fail(item, p.substr(0, p.size() - 1), "must be an object");
    FrequencyCalibration& fc = cal->frequency[f];
    if (!r.only_keys(item, p,
                     {"frequency_hz", "phase_offset_rad", "wiggle_cos_rad", "wiggle_sin_rad"}) ||
        !r.number(item, p, "frequency_hz", 1e6, 200e6, &fc.frequency_hz) ||
        !r.number(item, p, "phase_offset_rad", -7.0, 7.0, &fc.phase_offset_rad) ||
        !r.numbers(item, p, "wiggle_cos_rad", kWiggleHarmonics, -0.1, 0.1, fc.wiggle_cos_rad) ||
        !r.numbers(item, p, "wiggle_sin_rad", kWiggleHarmonics, -0.1, 0.1, fc.wiggle_sin_rad)) {
      return false;
    }
  }
  if (cal->frequency_count == 2 &&
      std::fabs(cal->frequency[0].frequency_hz - cal->frequency[1].frequency_hz) < 1e6) {
    return r.fail(list->items[1], "frequencies[1].frequency_hz",
                  "must differ from frequencies[0] by 1 MHz or more");
  }
  return true;
}

bool read_pixel_offset(Reader& r, const JsonValue& doc, Calibration* cal) {
  const JsonValue* po = r.member(doc, "", "pixel_offset", JsonValue::Type::kObject);
  if (po == nullptr) return false;
  if (!r.only_keys(*po, "pixel_offset.", {"poly_m", "table_mm"}) ||
      !r.numbers(*po, "pixel_offset.", "poly_m", kOffsetPolyTerms, -1.0, 1.0,
                 cal->pixel_offset_poly_m)) {
    return false;
  }
  cal->pixel_offset_m.clear();
  const JsonValue* table = po->find("table_mm");
  if (table == nullptr) return true;
  if (!table->is_array() || table->items.size() != kPixels) {
    return r.fail(
        *table, "pixel_offset.table_mm",
        "must be an array of " + std::to_string(kPixels) + " numbers (224 x 171, row major)");
  }
  cal->pixel_offset_m.resize(kPixels);
  for (std::size_t i = 0; i < kPixels; ++i) {
    const JsonValue& v = table->items[i];
    if (!v.is_number() || !(std::fabs(v.number) <= 1000.0)) {
      return r.fail(v, "pixel_offset.table_mm[" + std::to_string(i) + "]",
                    "must be a number in [-1000, 1000]");
    }
    cal->pixel_offset_m[i] = static_cast<float>(v.number * 1e-3);
  }
  return true;
}

bool read_document(Reader& r, const JsonValue& doc, Calibration* cal) {
  if (!doc.is_object()) return r.fail(doc, "(document)", "must be an object");
  if (!r.only_keys(doc, "",
                   {"format_version", "serial", "size_px", "lens", "frequencies", "pixel_offset",
                    "temperature", "noise_model"})) {
    return false;
  }
  double version = 0.0;
  if (!r.number(doc, "", "format_version", 0.0, 1e9, &version)) return false;
  if (version != kCalibrationFormatVersion) {
    return r.fail(*doc.find("format_version"), "format_version",
                  "this reader knows version " + std::to_string(kCalibrationFormatVersion));
  }
  cal->format_version = kCalibrationFormatVersion;
  if (const JsonValue* serial = doc.find("serial"); serial != nullptr && !serial->is_string()) {
    return r.fail(*serial, "serial", "must be a string");
  }
  double size[2] = {0.0, 0.0};
  if (!r.numbers(doc, "", "size_px", 2, 0.0, 1e6, size)) return false;
  if (size[0] != kWidthPx || size[1] != kHeightPx) {
    return r.fail(*doc.find("size_px"), "size_px", "must be [224, 171] (the Pico Flexx's imager)");
  }
  if (!read_lens(r, doc, cal) || !read_frequencies(r, doc, cal) ||
      !read_pixel_offset(r, doc, cal)) {
    return false;
  }
  const JsonValue* t = r.member(doc, "", "temperature", JsonValue::Type::kObject);
  if (t == nullptr || !r.only_keys(*t, "temperature.", {"reference_c", "drift_m_per_k"}) ||
      !r.number(*t, "temperature.", "reference_c", -150.0, 150.0, &cal->reference_temperature_c) ||
      !r.number(*t, "temperature.", "drift_m_per_k", -0.01, 0.01,
                &cal->temperature_drift_m_per_k)) {
    return false;
  }
  const JsonValue* n = r.member(doc, "", "noise_model", JsonValue::Type::kObject);
  const std::string p = "noise_model.";
  return n != nullptr &&
         r.only_keys(*n, p, {"black_level_dn", "conversion_gain_e_per_dn", "read_noise_dn"}) &&
         r.number(*n, p, "black_level_dn", 0.0, kMaxSampleDn - 1, &cal->black_level_dn) &&
         r.number(*n, p, "conversion_gain_e_per_dn", 1e-3, 999.0, &cal->conversion_gain_e_per_dn) &&
         r.number(*n, p, "read_noise_dn", 0.0, 999.0, &cal->read_noise_dn);
}

}  // namespace

bool parse_calibration(const std::string& text, const std::string& path, Calibration* out,
                       std::string* error) {
  JsonValue doc;
  std::string parse_error;
  if (!formats::parse_json(text, &doc, &parse_error)) {
    *error = path + ": " + parse_error;
    return false;
  }
  Calibration cal;
  Reader r(path, error);
  if (!read_document(r, doc, &cal)) return false;
  // Each key was range-checked above; this catches what only shows in
  // combination (the wiggle's total slope).
  if (const CalibrationStatus s = check_calibration(cal); s != CalibrationStatus::kOk) {
    const JsonValue* f = doc.find("frequencies");
    *error =
        path + ":" + std::to_string(f ? f->line : doc.line) + ": key 'frequencies': " +
        (s == CalibrationStatus::kBadWiggle
             ? std::string("the wiggle coefficients' total slope, sum of h (|cos| + |sin|), must "
                           "stay at or below 0.5")
             : std::string("inconsistent calibration: ") + to_string(s));
    return false;
  }
  *out = std::move(cal);
  return true;
}

bool load_calibration_file(const std::string& path, Calibration* out, std::string* error) {
  std::string text;
  if (formats::read_file_bounded(path, formats::kMaxTextFileBytes, &text, error) !=
      formats::FileStatus::kOk) {
    return false;
  }
  return parse_calibration(text, path, out, error);
}

}  // namespace tof
