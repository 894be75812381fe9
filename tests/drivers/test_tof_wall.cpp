// The raw path on flat walls: the simulator's raw phase images through the
// robot's ToF processing, against the exact ranges. Bias and noise at 0.3,
// 0.5, 1, 2 and 3.5 m in both kinds of use case (the data sheet: noise <=
// 1 % of distance at 0.5..4 m in MODE_9 at 5 fps, <= 2 % at 0.1..1 m in
// MODE_5 at 45 fps; required here: bias <= 2 mm after calibration), and MODE_9
// unwrapping across both frequencies' ambiguity distances (wrong unwraps
// <= 0.01 % of valid pixels up to 4 m). Prints the table the README quotes.
#include <cmath>
#include <cstdio>

#include "cmocka_cpp.hpp"
#include "tof_rig.hpp"

using tof_rig::Rig;
using tof_rig::Stats;

namespace {

constexpr int kFrames = 4;

Stats wall_stats(Rig& rig, const sim_hal::Scene& scene, const tof_rig::UseCase& uc) {
  Stats s;
  for (int f = 0; f < kFrames; ++f) {
    assert_true(rig.capture(scene, uc, static_cast<std::uint64_t>(f)));
    s.add(rig);
  }
  return s;
}

void print_row(const tof_rig::UseCase& uc, double d, const Stats& s) {
  std::printf(
      "%-17s %5.2f m  bias %+6.2f mm  noise %6.2f mm (%5.2f %%)  reported %6.2f mm  valid %5.1f %% "
      " wrong %ld\n",
      uc.name, d, s.bias_m() * 1e3, s.noise_m() * 1e3, 100.0 * s.noise_m() / d,
      s.mean_reported_noise_m() * 1e3, 100.0 * s.valid_fraction(), s.wrong_unwrap);
}

void test_mode9_walls(void**) {
  Rig rig;
  for (double d : {0.3, 0.5, 1.0, 2.0, 3.5}) {
    const Stats s = wall_stats(rig, tof_rig::wall_scene(d), tof_rig::kMode9_5fps);
    print_row(tof_rig::kMode9_5fps, d, s);
    assert_true(s.valid_fraction() > 0.95);
    assert_int_equal(s.wrong_unwrap, 0);
    assert_near(s.bias_m(), 0.0, 0.002);
    assert_true(s.noise_m() <= 0.01 * d);
    // The noise each point reports is the noise it has (within 30 %).
    assert_near(s.mean_reported_noise_m() / s.noise_m(), 1.0, 0.3);
  }
}

void test_mode5_walls(void**) {
  Rig rig;
  for (double d : {0.3, 0.5, 1.0, 2.0}) {
    const Stats s = wall_stats(rig, tof_rig::wall_scene(d), tof_rig::kMode5_45fps);
    print_row(tof_rig::kMode5_45fps, d, s);
    assert_true(s.valid_fraction() > 0.95);
    assert_near(s.bias_m(), 0.0, 0.002);
    if (d <= 1.0) assert_true(s.noise_m() <= 0.02 * d);
  }
  // One frequency cannot tell 3.5 m from 3.5 m less its unambiguous range
  // (2.498 m at 60 MHz): MODE_5 reports the alias, as documented.
  assert_true(rig.capture(tof_rig::wall_scene(3.5), tof_rig::kMode5_45fps, 0));
  const double u = tof::unambiguous_range_m(60e6);
  const float* r = rig.processor.range_m();
  const std::vector<float>& truth = rig.renderer.true_range_m();
  long aliased = 0, valid = 0;
  double shift = 0.0;
  for (std::size_t i = 0; i < tof::kPixels; ++i) {
    if (r[i] <= 0.0f) continue;
    ++valid;
    shift += truth[i] - r[i];
    aliased += std::fabs(truth[i] - r[i] - u) < 0.15;
  }
  std::printf("%-17s %5.2f m  reads %.4f m nearer on average (one frequency: aliased by %.4f m)\n",
              tof_rig::kMode5_45fps.name, 3.5, shift / std::max(valid, 1L), u);
  assert_true(valid > static_cast<long>(tof::kPixels) / 2);
  assert_int_equal(aliased, valid);
  assert_near(shift / valid, u, 0.003);
}

// A wall turned 62 deg about the vertical: across the image its ranges run
// from under 1 m to well past 4 m, through 1.874 m (80 MHz wraps) and
// 2.498 m (60 MHz wraps). Up to 4 m no pixel may be unwrapped wrongly.
void test_mode9_unwraps_across_ambiguity(void**) {
  Rig rig;
  const sim_hal::Scene scene = tof_rig::wall_scene(1.6, 62.0);
  long valid = 0, wrong = 0, beyond_80 = 0, beyond_60 = 0;
  for (int f = 0; f < 20; ++f) {
    assert_true(rig.capture(scene, tof_rig::kMode9_5fps, static_cast<std::uint64_t>(f)));
    const float* r = rig.processor.range_m();
    const std::vector<float>& truth = rig.renderer.true_range_m();
    for (std::size_t i = 0; i < tof::kPixels; ++i) {
      if (r[i] <= 0.0f || truth[i] > 4.0f) continue;
      ++valid;
      wrong += std::fabs(r[i] - truth[i]) > 0.3f;
      beyond_80 += truth[i] > 1.9f;
      beyond_60 += truth[i] > 2.55f;
    }
  }
  std::printf(
      "unwrapping, tilted wall up to 4 m: %ld valid pixels over 20 frames (%ld past 1.874 m, %ld "
      "past 2.498 m), %ld wrong (%.4f %%)\n",
      valid, beyond_80, beyond_60, wrong, 100.0 * wrong / std::max(valid, 1L));
  assert_true(beyond_60 > valid / 10);  // the scene does cross both ambiguities
  assert_true(beyond_80 > beyond_60);
  assert_true(wrong * 10000 <= valid);
}

// Root-mean-square error of a processor's last distances against truth.
double rms_error_m(const tof::Processor& p, const std::vector<float>& truth) {
  double sum2 = 0.0;
  long n = 0;
  for (std::size_t i = 0; i < tof::kPixels; ++i) {
    const float r = p.range_m()[i];
    if (r > 0.0f && truth[i] > 0.0f) {
      sum2 += (r - truth[i]) * (r - truth[i]);
      ++n;
    }
  }
  return n ? std::sqrt(sum2 / n) : 1e9;
}

// The calibration matters: the same frames processed with a calibration
// that leaves out the temperature drift (the camera 10 K warmer than at
// calibration) are biased by the drift, and without the wiggling the
// error grows (over a wall whose ranges span 1 to 1.3 m the wiggle's 4th
// harmonic goes through several periods).
void test_calibration_terms_are_applied(void**) {
  sim_hal::RawRenderSettings settings;
  settings.sensor_temperature_c = 35.0;
  Rig rig(settings);
  const sim_hal::Scene scene = tof_rig::wall_scene(1.0);
  tof::Calibration no_drift = rig.truth;
  no_drift.temperature_drift_m_per_k = 0.0;
  tof::Processor without_drift(no_drift, tof::ProcessingConfig{});
  Stats with, without;
  for (int f = 0; f < kFrames; ++f) {
    assert_true(rig.capture(scene, tof_rig::kMode9_5fps, static_cast<std::uint64_t>(f)));
    with.add(rig);
    assert_int_equal(static_cast<int>(without_drift.process(rig.raw, &rig.depth)), 0);
  }
  // The second processor's distances are in its own buffer.
  double sum = 0.0;
  long n = 0;
  const float* r = without_drift.range_m();
  for (std::size_t i = 0; i < tof::kPixels; ++i) {
    if (r[i] > 0.0f) {
      sum += r[i] - rig.renderer.true_range_m()[i];
      ++n;
    }
  }
  const double drift_m = rig.truth.temperature_drift_m_per_k * 10.0;
  assert_near(with.bias_m(), 0.0, 0.002);
  assert_near(sum / n, drift_m, 0.002);
  assert_true(std::fabs(drift_m) > 0.006);

  tof::Calibration no_wiggle = rig.truth;
  for (tof::FrequencyCalibration& f : no_wiggle.frequency) {
    for (int h = 0; h < tof::kWiggleHarmonics; ++h) f.wiggle_cos_rad[h] = f.wiggle_sin_rad[h] = 0.0;
  }
  tof::Processor without_wiggle(no_wiggle, tof::ProcessingConfig{});
  // In MODE_5 the one frequency's wiggle shows in full (in MODE_9 the two
  // frequencies' wiggles partly average out).
  double rms_with[2], rms_without[2];
  const tof_rig::UseCase* cases[2] = {&tof_rig::kMode9_5fps, &tof_rig::kMode5_45fps};
  for (int k = 0; k < 2; ++k) {
    assert_true(rig.capture(scene, *cases[k], 0));
    assert_int_equal(static_cast<int>(without_wiggle.process(rig.raw, &rig.depth)), 0);
    rms_with[k] = rms_error_m(rig.processor, rig.renderer.true_range_m());
    rms_without[k] = rms_error_m(without_wiggle, rig.renderer.true_range_m());
    std::printf("1 m wall, %s: rms error %.2f mm calibrated, %.2f mm without the wiggling\n",
                cases[k]->name, rms_with[k] * 1e3, rms_without[k] * 1e3);
  }
  std::printf("1 m wall, MODE_9: bias %.2f mm without the temperature drift (10 K)\n",
              sum / n * 1e3);
  assert_true(rms_without[1] > 1.5 * rms_with[1]);
  assert_true(rms_without[0] > rms_with[0]);
}

}  // namespace

int main() {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_mode9_walls),
      cmocka_unit_test(test_mode5_walls),
      cmocka_unit_test(test_mode9_unwraps_across_ambiguity),
      cmocka_unit_test(test_calibration_terms_are_applied),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
