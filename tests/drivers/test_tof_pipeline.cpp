// The raw-frame pipeline (drivers/pico_flexx/pipeline): raw frame in,
// depth frame to the listener, the counts and the processing time the
// summary reports, the start-up refusals of a missing or malformed
// calibration file (the file and the key named), and no allocation per
// frame. Frames are made from the correlation model here (no simulator),
// so this runs on the robot's build too.
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include "allocation_counter.hpp"
#include "cmocka_cpp.hpp"
#include "pico_flexx/raw_depth_pipeline.hpp"
#include "tof/calibration_io.hpp"

namespace {

tof::Calibration calibration() {
  tof::Calibration c;
  c.lens = {111.3, 86.1, 206.0, 206.0, -0.25, 0.02, 0.0, 0.0008, -0.0005};
  c.frequency[0].frequency_hz = 60e6;
  c.frequency[0].phase_offset_rad = 0.7;
  c.frequency[1].frequency_hz = 80e6;
  c.frequency[1].phase_offset_rad = -1.2;
  return c;
}

// A flat return at range_m of amplitude_dn at every pixel (no wiggle in
// the calibration: the phase is exact).
void make_frame(const tof::Calibration& cal, double range_m, double amplitude_dn,
                tof::RawFrame* raw) {
  raw->mode = tof::Mode::kMode9;
  raw->sensor_temperature_c = static_cast<float>(cal.reference_temperature_c);
  for (int f = 0; f < 2; ++f) {
    const double k = 4.0 * M_PI * cal.frequency[f].frequency_hz / tof::kSpeedOfLight_m_s;
    const double phase = k * range_m + cal.frequency[f].phase_offset_rad;
    for (int step = 0; step < 4; ++step) {
      const double v = cal.black_level_dn + 1.4 * amplitude_dn +
                       amplitude_dn * std::cos(phase + step * M_PI / 2);
      const auto dn = static_cast<std::uint16_t>(std::fmin(std::lround(v), 4095));
      std::uint16_t* image = raw->phase_image(f, step);
      for (std::size_t i = 0; i < tof::kPixels; ++i) image[i] = dn;
    }
  }
  for (std::size_t i = 0; i < tof::kPixels; ++i) {
    raw->grey_image()[i] = static_cast<std::uint16_t>(cal.black_level_dn);
  }
}

// Each reading 700 us after the last: every frame "takes" 700 us.
class SteppingClock final : public hal::Clock {
 public:
  std::int64_t now_us() const override { return t_us_ += 700; }

 private:
  mutable std::int64_t t_us_ = 0;
};

class Recorder final : public hal::DepthDataListener {
 public:
  void on_new_data(const hal::DepthFrame& frame) override {
    ++frames;
    last_id = frame.frame_id;
    valid = hal::count_valid(frame);
    centre_z_m = frame.at(85, 112).z_m;
    centre_gray = frame.at(85, 112).gray_value;
  }
  int frames = 0;
  std::uint64_t last_id = 0;
  std::size_t valid = 0;
  float centre_z_m = 0.0f;
  std::uint16_t centre_gray = 0;
};

std::string temp_path(const char* name) {
  return "/tmp/hrp_tof_pipeline_" + std::to_string(getpid()) + "_" + name;
}

void test_delivers_and_counts(void**) {
  const tof::Calibration cal = calibration();
  SteppingClock clock;
  pico_flexx::RawDepthPipeline pipeline(cal, pico_flexx::PipelineConfig{}, clock);
  assert_int_equal(static_cast<int>(pipeline.init_status()), 0);
  assert_int_equal(pipeline.processing_median_us(), -1);
  Recorder recorder;
  pipeline.set_listener(&recorder);
  static tof::RawFrame lit, dark;
  make_frame(cal, 1.3, 800.0, &lit);
  make_frame(cal, 1.3, 1.0, &dark);  // below the 6 DN floor everywhere
  lit.frame_id = 41;
  assert_int_equal(static_cast<int>(pipeline.on_raw_frame(lit)),
                   static_cast<int>(pico_flexx::PipelineStatus::kOk));
  assert_int_equal(recorder.frames, 1);
  assert_int_equal(recorder.last_id, 41);
  assert_true(recorder.valid > tof::kPixels * 9 / 10);
  // The centre ray is near the optical axis: z close to the range.
  assert_near(recorder.centre_z_m, 1.3, 0.01);
  // The grey plane carries the processing's amplitude.
  assert_near(recorder.centre_gray, 800.0, 40.0);
  assert_int_equal(static_cast<int>(pipeline.on_raw_frame(dark)),
                   static_cast<int>(pico_flexx::PipelineStatus::kMostlyInvalid));
  assert_int_equal(recorder.frames, 2);  // delivered all the same
  const pico_flexx::PipelineCounts c = pipeline.counts();
  assert_int_equal(c.frames_in, 2);
  assert_int_equal(c.frames_delivered, 2);
  assert_int_equal(c.frames_mostly_invalid, 1);
  assert_int_equal(c.frames_dropped, 0);
  assert_true(c.pixels_by_state[static_cast<int>(tof::PixelState::kDark)] >= tof::kPixels);
  assert_int_equal(pipeline.processing_median_us(), 700);
  assert_string_equal(pico_flexx::to_string(pico_flexx::PipelineStatus::kMostlyInvalid),
                      "MOSTLY_INVALID");
}

void test_drops_a_frame_the_processing_refuses(void**) {
  tof::Calibration cal = calibration();
  cal.frequency_count = 1;  // a one-frequency unit cannot process MODE_9
  hal::ManualClock clock;
  pico_flexx::RawDepthPipeline pipeline(cal, pico_flexx::PipelineConfig{}, clock);
  Recorder recorder;
  pipeline.set_listener(&recorder);
  static tof::RawFrame raw;
  make_frame(calibration(), 1.0, 500.0, &raw);
  assert_int_equal(static_cast<int>(pipeline.on_raw_frame(raw)),
                   static_cast<int>(pico_flexx::PipelineStatus::kDropped));
  assert_int_equal(recorder.frames, 0);
  const pico_flexx::PipelineCounts c = pipeline.counts();
  assert_int_equal(c.frames_dropped, 1);
  assert_int_equal(static_cast<int>(c.last_drop),
                   static_cast<int>(tof::ProcessStatus::kModeNotCalibrated));
}

// A header's imager temperature far from the calibration's reference (a
// corrupt header, a failing sensor) would shift every depth by the drift
// correction with every pixel valid: the frame is dropped and counted,
// named; a frame at a cabin's temperature after it goes through.
void test_drops_a_frame_at_an_implausible_temperature(void**) {
  const tof::Calibration cal = calibration();
  hal::ManualClock clock;
  pico_flexx::RawDepthPipeline pipeline(cal, pico_flexx::PipelineConfig{}, clock);
  Recorder recorder;
  pipeline.set_listener(&recorder);
  static tof::RawFrame raw;
  make_frame(cal, 1.0, 500.0, &raw);
  for (float t_c : {300.0f, -60.0f, std::numeric_limits<float>::quiet_NaN()}) {
    raw.sensor_temperature_c = t_c;
    assert_int_equal(static_cast<int>(pipeline.on_raw_frame(raw)),
                     static_cast<int>(pico_flexx::PipelineStatus::kDropped));
  }
  assert_int_equal(recorder.frames, 0);
  pico_flexx::PipelineCounts c = pipeline.counts();
  assert_int_equal(c.frames_dropped, 3);
  assert_int_equal(static_cast<int>(c.last_drop),
                   static_cast<int>(tof::ProcessStatus::kImplausibleTemperature));
  assert_string_equal(tof::to_string(tof::ProcessStatus::kImplausibleTemperature),
                      "IMPLAUSIBLE_TEMPERATURE");
  raw.sensor_temperature_c = static_cast<float>(cal.reference_temperature_c) + 30.0f;
  assert_int_equal(static_cast<int>(pipeline.on_raw_frame(raw)),
                   static_cast<int>(pico_flexx::PipelineStatus::kOk));
  assert_int_equal(recorder.frames, 1);
  c = pipeline.counts();
  assert_int_equal(c.frames_delivered, 1);
  // A limit that is no limit is refused at start-up.
  pico_flexx::PipelineConfig bad;
  bad.processing.max_temperature_offset_k = 0.0f;
  pico_flexx::RawDepthPipeline refused(cal, bad, clock);
  assert_int_not_equal(static_cast<int>(refused.init_status()),
                       static_cast<int>(pico_flexx::PipelineStatus::kOk));
}

void test_refuses_bad_config(void**) {
  hal::ManualClock clock;
  pico_flexx::PipelineConfig config;
  config.mostly_invalid_below = 1.5f;
  pico_flexx::RawDepthPipeline pipeline(calibration(), config, clock);
  assert_int_equal(static_cast<int>(pipeline.init_status()),
                   static_cast<int>(pico_flexx::PipelineStatus::kBadConfig));
}

void test_start_up_refuses_missing_and_malformed_files(void**) {
  hal::ManualClock clock;
  std::string error;
  const std::string missing = temp_path("missing.json");
  assert_null(pico_flexx::open_raw_depth_pipeline(missing, {}, clock, &error).get());
  if (error.find(missing) == std::string::npos) print_error("error: %s\n", error.c_str());
  assert_true(error.find(missing) != std::string::npos);

  // A good file reads; the same file with one value out of range does not,
  // and the error names the file, the line and the key.
  const std::string good = temp_path("good.json");
  assert_true(tof::write_calibration_file(good, calibration(), &error));
  auto pipeline = pico_flexx::open_raw_depth_pipeline(good, {}, clock, &error);
  assert_non_null(pipeline.get());
  assert_near(pipeline->lens().fx_px, 206.0, 1e-9);
  std::string text = tof::calibration_to_json(calibration());
  const std::size_t at = text.find("\"fx_px\": 206");
  assert_true(at != std::string::npos);
  text.replace(at, 12, "\"fx_px\": -3");
  const std::string bad = temp_path("bad.json");
  {
    std::FILE* f = std::fopen(bad.c_str(), "w");
    assert_non_null(f);
    std::fputs(text.c_str(), f);
    std::fclose(f);
  }
  error.clear();
  assert_null(pico_flexx::open_raw_depth_pipeline(bad, {}, clock, &error).get());
  if (error.find(bad + ":") == std::string::npos || error.find("lens.fx_px") == std::string::npos)
    print_error("error: %s\n", error.c_str());
  assert_true(error.find(bad + ":") != std::string::npos);
  assert_true(error.find("key 'lens.fx_px'") != std::string::npos);
  std::remove(good.c_str());
  std::remove(bad.c_str());
}

void test_no_allocation_per_frame(void**) {
  const tof::Calibration cal = calibration();
  hal::ManualClock clock;
  pico_flexx::RawDepthPipeline pipeline(cal, pico_flexx::PipelineConfig{}, clock);
  Recorder recorder;
  pipeline.set_listener(&recorder);
  static tof::RawFrame frames[2];
  make_frame(cal, 0.9, 700.0, &frames[0]);
  make_frame(cal, 2.7, 300.0, &frames[1]);
  alloc_counter::arm();
  for (int n = 0; n < 200; ++n) {
    (void)pipeline.on_raw_frame(frames[n % 2]);
    if (n % 50 == 0) (void)pipeline.processing_median_us();
    (void)pipeline.counts();
  }
  const long allocations = alloc_counter::disarm();
  if (allocations != 0) print_error("%ld allocations over 200 frames\n", allocations);
  assert_int_equal(allocations, 0);
  assert_int_equal(recorder.frames, 200);
}

}  // namespace

int main() {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_delivers_and_counts),
      cmocka_unit_test(test_drops_a_frame_the_processing_refuses),
      cmocka_unit_test(test_drops_a_frame_at_an_implausible_temperature),
      cmocka_unit_test(test_refuses_bad_config),
      cmocka_unit_test(test_start_up_refuses_missing_and_malformed_files),
      cmocka_unit_test(test_no_allocation_per_frame),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
