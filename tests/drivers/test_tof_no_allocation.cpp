// Proof that the ToF processing allocates nothing per frame: every
// operator new and (outside AddressSanitizer) every malloc on the test's
// thread is counted while hundreds of raw frames of both modes, lit,
// saturated and dark, go through it. The frames are made here from the
// correlation model itself (no simulator), so this runs on the robot's
// build too.
#include <cmath>
#include <vector>

#include "allocation_counter.hpp"
#include "cmocka_cpp.hpp"
#include "tof/processor.hpp"

namespace {

// Four phase steps of a return at range_m (plus the pixel's calibrated
// offset) of `amplitude_dn`, for each frequency of the mode, and a grey
// image; the calibration has no wiggle, so the phase is exact.
void make_frame(const tof::Calibration& cal, tof::Mode mode, double range_m, double amplitude_dn,
                std::uint64_t id, tof::RawFrame* raw) {
  raw->mode = mode;
  raw->frame_id = id;
  raw->sensor_temperature_c = static_cast<float>(cal.reference_temperature_c);
  for (int f = 0; f < tof::frequency_count(mode); ++f) {
    const double k = 4.0 * M_PI * cal.frequency[f].frequency_hz / tof::kSpeedOfLight_m_s;
    for (std::size_t i = 0; i < tof::kPixels; ++i) {
      // A little structure: every 7th column 3 cm farther.
      const double r = range_m + (i % 7 == 0 ? 0.03 : 0.0);
      const double phase =
          k * (r + tof::pixel_offset_m(cal, static_cast<std::uint32_t>(i / tof::kWidthPx),
                                       static_cast<std::uint32_t>(i % tof::kWidthPx))) +
          cal.frequency[f].phase_offset_rad;
      for (int step = 0; step < 4; ++step) {
        const double v = cal.black_level_dn + 1.4 * amplitude_dn +
                         amplitude_dn * std::cos(phase + step * M_PI / 2);
        raw->phase_image(f, step)[i] = static_cast<std::uint16_t>(std::fmin(std::lround(v), 4095));
      }
    }
  }
  for (std::size_t i = 0; i < tof::kPixels; ++i)
    raw->grey_image()[i] = static_cast<std::uint16_t>(cal.black_level_dn);
}

tof::Calibration calibration() {
  tof::Calibration c;
  c.lens = {111.3, 86.1, 206.0, 206.0, -0.25, 0.02, 0.0, 0.0008, -0.0005};
  c.frequency[0].frequency_hz = 60e6;
  c.frequency[0].phase_offset_rad = 0.7;
  c.frequency[1].frequency_hz = 80e6;
  c.frequency[1].phase_offset_rad = -1.2;
  c.pixel_offset_poly_m[0] = 0.01;
  c.pixel_offset_poly_m[3] = 0.004;
  return c;
}

void test_counter_counts(void**) {
  // A vector (its object and storage), which the compiler cannot elide as
  // it may a bare new/delete pair.
  alloc_counter::arm();
  std::vector<int>* v = new std::vector<int>(10);
  const long n = alloc_counter::disarm();
  delete v;
  assert_true(n >= 2);
}

void test_no_allocation_over_hundreds_of_frames(void**) {
  const tof::Calibration cal = calibration();
  tof::Processor processor(cal, tof::ProcessingConfig{});
  assert_int_equal(static_cast<int>(processor.init_status()), 0);
  // Lit at three distances (two across the 60 MHz wrap), saturated, dark.
  struct Case {
    tof::Mode mode;
    double range_m, amplitude_dn;
  };
  const Case cases[] = {{tof::Mode::kMode9, 1.2, 800},
                        {tof::Mode::kMode9, 3.1, 300},
                        {tof::Mode::kMode5, 0.6, 900},
                        {tof::Mode::kMode9, 0.8, 3000},
                        {tof::Mode::kMode5, 0.8, 2}};
  constexpr int kCases = sizeof cases / sizeof cases[0];
  static tof::RawFrame frames[kCases];
  for (int k = 0; k < kCases; ++k) {
    make_frame(cal, cases[k].mode, cases[k].range_m, cases[k].amplitude_dn,
               static_cast<std::uint64_t>(k), &frames[k]);
  }
  long valid = 0, saturated = 0, dark = 0;
  hal::DepthFrame depth;
  alloc_counter::arm();
  for (int n = 0; n < 300; ++n) {
    const tof::ProcessStatus s = processor.process(frames[n % kCases], &depth);
    if (s != tof::ProcessStatus::kOk) break;
    valid += processor.last_counts().of(tof::PixelState::kValid);
    saturated += processor.last_counts().of(tof::PixelState::kSaturated);
    dark += processor.last_counts().of(tof::PixelState::kDark);
  }
  const long allocations = alloc_counter::disarm();
  if (allocations != 0) print_error("%ld allocations while processing frames\n", allocations);
  assert_int_equal(allocations, 0);
  // Every path ran: 3 lit cases of 5, one saturated, one dark.
  assert_true(valid > 180L * static_cast<long>(tof::kPixels) * 9 / 10);
  assert_true(saturated > 50L * static_cast<long>(tof::kPixels));
  assert_true(dark > 50L * static_cast<long>(tof::kPixels));
  // The last lit frames' distances are the ones made.
  assert_int_equal(static_cast<int>(processor.process(frames[1], &depth)), 0);
  const std::size_t centre = 85 * tof::kWidthPx + 113;
  assert_near(processor.range_m()[centre], 3.1, 0.002);
}

}  // namespace

int main() {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_counter_counts),
      cmocka_unit_test(test_no_allocation_over_hundreds_of_frames),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
