// The ToF calibration file: a round trip keeps every value; each kind of
// malformed file is refused with the key (and its line) named; the
// processor refuses a calibration that check_calibration refuses.
#include <cstdio>
#include <string>

#include "cmocka_cpp.hpp"
#include "tof/calibration_io.hpp"
#include "tof/processor.hpp"

namespace {

// A calibration with every field away from its default.
tof::Calibration sample_calibration(bool with_table) {
  tof::Calibration c;
  c.lens = {111.3, 86.1, 206.0, 205.5, -0.25, 0.02, 0.001, 0.0008, -0.0005};
  c.frequency[0].frequency_hz = 60e6;
  c.frequency[0].phase_offset_rad = 0.812345678901234;
  c.frequency[1].frequency_hz = 80e6;
  c.frequency[1].phase_offset_rad = -1.1;
  const double cos0[4] = {0.001, 0.002, 0.003, 0.004}, sin0[4] = {-0.0013, 0.0005, 0.0, 0.0007};
  const double cos1[4] = {0.0014, -0.002, 0.0, 0.012}, sin1[4] = {0.0, 0.0002, 0.0004, -0.008};
  for (int h = 0; h < tof::kWiggleHarmonics; ++h) {
    c.frequency[0].wiggle_cos_rad[h] = cos0[h];
    c.frequency[0].wiggle_sin_rad[h] = sin0[h];
    c.frequency[1].wiggle_cos_rad[h] = cos1[h];
    c.frequency[1].wiggle_sin_rad[h] = sin1[h];
  }
  const double poly[6] = {0.012, 0.001, -0.002, 0.004, 0.0005, 0.003};
  for (int k = 0; k < 6; ++k) c.pixel_offset_poly_m[k] = poly[k];
  if (with_table) {
    c.pixel_offset_m.resize(tof::kPixels);
    for (std::size_t i = 0; i < tof::kPixels; ++i) {
      c.pixel_offset_m[i] = static_cast<float>(static_cast<int>(i % 97) - 48) * 1e-5f;
    }
  }
  c.reference_temperature_c = 24.5;
  c.temperature_drift_m_per_k = 0.0011;
  c.black_level_dn = 210.0;
  c.conversion_gain_e_per_dn = 15.5;
  c.read_noise_dn = 2.5;
  return c;
}

void test_round_trip(void**) {
  for (bool with_table : {false, true}) {
    const tof::Calibration c = sample_calibration(with_table);
    assert_int_equal(static_cast<int>(tof::check_calibration(c)), 0);
    const std::string path = "/tmp/test_tof_calibration_" + std::to_string(with_table) + ".json";
    std::string error;
    assert_true(tof::write_calibration_file(path, c, &error));
    tof::Calibration back;
    if (!tof::load_calibration_file(path, &back, &error)) print_error("%s\n", error.c_str());
    assert_true(error.empty());
    std::remove(path.c_str());
    assert_true(back.lens.fx_px == c.lens.fx_px && back.lens.fy_px == c.lens.fy_px);
    assert_true(back.lens.cx_px == c.lens.cx_px && back.lens.cy_px == c.lens.cy_px);
    assert_true(back.lens.k1 == c.lens.k1 && back.lens.k2 == c.lens.k2 &&
                back.lens.k3 == c.lens.k3);
    assert_true(back.lens.p1 == c.lens.p1 && back.lens.p2 == c.lens.p2);
    assert_int_equal(back.frequency_count, 2);
    for (int f = 0; f < 2; ++f) {
      assert_true(back.frequency[f].frequency_hz == c.frequency[f].frequency_hz);
      assert_true(back.frequency[f].phase_offset_rad == c.frequency[f].phase_offset_rad);
      for (int h = 0; h < tof::kWiggleHarmonics; ++h) {
        assert_true(back.frequency[f].wiggle_cos_rad[h] == c.frequency[f].wiggle_cos_rad[h]);
        assert_true(back.frequency[f].wiggle_sin_rad[h] == c.frequency[f].wiggle_sin_rad[h]);
      }
    }
    for (int k = 0; k < 6; ++k)
      assert_true(back.pixel_offset_poly_m[k] == c.pixel_offset_poly_m[k]);
    assert_int_equal(back.pixel_offset_m.size(), c.pixel_offset_m.size());
    for (std::size_t i = 0; i < c.pixel_offset_m.size(); ++i) {
      assert_near(back.pixel_offset_m[i], c.pixel_offset_m[i], 0.6e-6);  // micrometre steps
    }
    assert_true(back.reference_temperature_c == c.reference_temperature_c);
    assert_true(back.temperature_drift_m_per_k == c.temperature_drift_m_per_k);
    assert_true(back.black_level_dn == c.black_level_dn);
    assert_true(back.conversion_gain_e_per_dn == c.conversion_gain_e_per_dn);
    assert_true(back.read_noise_dn == c.read_noise_dn);
    // Small without the table; the table costs about 6 bytes a pixel.
    const std::size_t bytes = tof::calibration_to_json(c).size();
    assert_true(with_table ? bytes < 7 * tof::kPixels : bytes < 2000);
  }
}

// Replaces the first `from` in the good file's text with `to` and expects
// a refusal that names `key` at `line` (0: any line).
void expect_refused(const char* from, const char* to, const char* key, int line = 0) {
  std::string text = tof::calibration_to_json(sample_calibration(false));
  const std::size_t at = text.find(from);
  assert_true(at != std::string::npos);
  text.replace(at, std::string(from).size(), to);
  tof::Calibration out;
  std::string error;
  assert_false(tof::parse_calibration(text, "cal.json", &out, &error));
  const std::string want_key = std::string("key '") + key + "'";
  if (error.find(want_key) == std::string::npos)
    print_error("%s lacks %s\n", error.c_str(), want_key.c_str());
  assert_true(error.find(want_key) != std::string::npos);
  if (line > 0) {
    const std::string want_line = "cal.json:" + std::to_string(line) + ":";
    if (error.find(want_line) != 0)
      print_error("%s: not at %s\n", error.c_str(), want_line.c_str());
    assert_true(error.find(want_line) == 0);
  }
}

void test_malformed_files_name_the_key(void**) {
  expect_refused("\"format_version\": 1", "\"format_version\": 2", "format_version", 2);
  expect_refused("\"format_version\": 1,", "", "format_version");
  expect_refused("\"fx_px\": 206", "\"fx_px\": -206", "lens.fx_px", 4);
  expect_refused("\"fx_px\": 206", "\"fx_px\": \"206\"", "lens.fx_px", 4);
  expect_refused("\"k1\": -0.25", "\"kone\": -0.25", "lens.kone", 5);
  expect_refused("\"frequency_hz\": 80000000", "\"frequency_hz\": 60000000",
                 "frequencies[1].frequency_hz");
  expect_refused("\"frequency_hz\": 60000000", "\"frequency_hz\": 6e12",
                 "frequencies[0].frequency_hz", 7);
  expect_refused("\"wiggle_cos_rad\": [0.001, ", "\"wiggle_cos_rad\": [",
                 "frequencies[0].wiggle_cos_rad", 8);
  expect_refused("\"wiggle_sin_rad\": [-0.0013,", "\"wiggle_sin_rad\": [true,",
                 "frequencies[0].wiggle_sin_rad[0]", 9);
  expect_refused("\"poly_m\": [", "\"table_mm\": [1, 2], \"poly_m\": [", "pixel_offset.table_mm");
  expect_refused("\"drift_m_per_k\": 0.0011", "\"drift_m_per_k\": 0.5",
                 "temperature.drift_m_per_k");
  expect_refused("\"read_noise_dn\": 2.5", "\"read_noise_dn\": -1", "noise_model.read_noise_dn");
  expect_refused("\"size_px\": [224, 171]", "\"size_px\": [320, 240]", "size_px", 3);
  // Values each in range whose wiggle together cannot be inverted.
  expect_refused("\"wiggle_cos_rad\": [0.001, 0.002, 0.003, 0.004]",
                 "\"wiggle_cos_rad\": [0.09, 0.09, 0.09, 0.09]", "frequencies");
  // Not JSON at all: the parser's line.
  tof::Calibration out;
  std::string error;
  assert_false(tof::parse_calibration("{\n\"lens\": ,\n}", "cal.json", &out, &error));
  assert_true(error.find("cal.json: line 2") == 0);
  assert_false(tof::load_calibration_file("/nonexistent/cal.json", &out, &error));
  assert_true(error.find("/nonexistent/cal.json") != std::string::npos);
}

void test_processor_refuses_bad_calibration(void**) {
  tof::Calibration c = sample_calibration(false);
  c.lens.fx_px = 0.0;
  assert_int_equal(static_cast<int>(tof::check_calibration(c)),
                   static_cast<int>(tof::CalibrationStatus::kBadLens));
  tof::Processor p(c, tof::ProcessingConfig{});
  assert_int_equal(static_cast<int>(p.init_status()),
                   static_cast<int>(tof::ProcessStatus::kBadCalibration));
  tof::RawFrame raw;
  hal::DepthFrame depth;
  assert_int_equal(static_cast<int>(p.process(raw, &depth)),
                   static_cast<int>(tof::ProcessStatus::kNotInitialized));
  // An unwrapping tolerance as wide as the frequencies' wrong candidates
  // are apart (0.625 m for 60 and 80 MHz) would be guessing.
  tof::ProcessingConfig wide;
  wide.unwrap_max_tolerance_m = 0.32f;
  tof::Processor q(sample_calibration(false), wide);
  assert_int_equal(static_cast<int>(q.init_status()),
                   static_cast<int>(tof::ProcessStatus::kBadConfig));
  // One frequency: MODE_9 frames are refused, MODE_5 taken.
  tof::Calibration one = sample_calibration(false);
  one.frequency_count = 1;
  tof::Processor r(one, tof::ProcessingConfig{});
  assert_int_equal(static_cast<int>(r.init_status()), 0);
  raw.mode = tof::Mode::kMode9;
  assert_int_equal(static_cast<int>(r.process(raw, &depth)),
                   static_cast<int>(tof::ProcessStatus::kModeNotCalibrated));
  raw.mode = tof::Mode::kMode5;
  assert_int_equal(static_cast<int>(r.process(raw, &depth)), 0);
  assert_string_equal(tof::to_string(tof::ProcessStatus::kModeNotCalibrated),
                      "MODE_NOT_CALIBRATED");
  assert_string_equal(tof::to_string(tof::CalibrationStatus::kBadWiggle), "BAD_WIGGLE");
  assert_string_equal(tof::to_string(tof::PixelState::kFlying), "FLYING");
}

}  // namespace

int main() {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_round_trip),
      cmocka_unit_test(test_malformed_files_name_the_key),
      cmocka_unit_test(test_processor_refuses_bad_calibration),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
