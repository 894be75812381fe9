// The bar-first candidates (bar_runs.hpp) on a hand-made scene seen
// face-on: a wall 1 m away, and on it, running top to bottom of the image,
// an ISS bar (1.9 cm across, front 8 cm proud), a cable lying on the wall
// (2.5 cm), a box as proud as the bar but 15 cm wide, and a bar standing
// on a face 5 cm deeper than the wall (its front 3 cm over the wall). The
// two bars' pixels are candidates and nothing else is: what a pixel stands
// out from is read beside it, with no window over any plane.
#include <cmath>
#include <vector>

#include "cmocka_cpp.hpp"
#include "estimator/bar_runs.hpp"

using namespace estimator;

namespace {

constexpr int kW = 224, kH = 171;
constexpr float kF = 186.0f;  // the Pico Flexx's focal length, pixels
constexpr float kWallZ = 1.0f;

struct Feature {
  float x_lo, x_hi;  // across the image, metres at the wall
  float height_m;    // its front over the wall (negative: a recess)
};

struct Scene {
  std::vector<CloudPoint> points = std::vector<CloudPoint>(kW * kH);
  OrganizedCloud cloud;
  Workspace ws{kW * kH};
  PixelScale scale;
};

// Each pixel's ray meets the scene's front at z = wall - height; the
// height is looked up where the ray crosses that depth (flat fronts, no
// side faces: seen face-on).
void build(Scene* s, const std::vector<Feature>& features) {
  for (int r = 0; r < kH; ++r) {
    for (int c = 0; c < kW; ++c) {
      const float u = (c - 0.5f * kW) / kF, v = (r - 0.5f * kH) / kF;
      // The wall, or a recess in it where the ray crosses the recess's
      // depth within its strip; then the nearest front whose strip the ray
      // crosses at that front's depth.
      float z = kWallZ;
      for (const Feature& f : features) {
        const float zf = kWallZ - f.height_m;
        const float x = u * zf;
        if (f.height_m < 0.0f && x >= f.x_lo && x < f.x_hi) z = zf;
      }
      for (const Feature& f : features) {
        const float zf = kWallZ - f.height_m;
        const float x = u * zf;
        if (x >= f.x_lo && x < f.x_hi && zf < z) z = zf;
      }
      CloudPoint& p = s->points[r * kW + c];
      p = CloudPoint{u * z, v * z, z, 0.001f, 100, 200};
      s->ws.signed_distance_m[r * kW + c] = kWallZ - z;
      s->ws.gap_widen_m[r * kW + c] = 2.0f * p.noise_m;  // as the distance pass leaves it
      s->ws.flags[r * kW + c] = kFlagValid;
    }
  }
  s->cloud.points = s->points.data();
  s->cloud.width = kW;
  s->cloud.height = kH;
  s->scale.ok = true;
  s->scale.fx_px = s->scale.fy_px = kF;
  s->scale.cx_px = 0.5f * kW;
  s->scale.cy_px = 0.5f * kH;
}

// How many of the candidates lie in the strip [x_lo, x_hi).
int candidates_in(const Scene& s, float x_lo, float x_hi) {
  int n = 0;
  for (std::int32_t i : s.ws.side) n += s.points[i].x_m >= x_lo && s.points[i].x_m < x_hi;
  return n;
}

void test_bars_are_candidates_and_clutter_is_not(void**) {
  Scene s;
  const std::vector<Feature> features = {
      {-0.30f, -0.281f, 0.08f},   // the ISS bar, front 8 cm proud
      {-0.10f, -0.075f, 0.025f},  // a cable lying on the wall
      {0.05f, 0.20f, 0.08f},      // a box as proud as the bar
      {0.25f, 0.40f, -0.05f},     // a face 5 cm deeper than the wall ...
      {0.32f, 0.339f, 0.03f},     // ... and a bar on it
  };
  build(&s, features);
  find_bar_runs(s.cloud, DetectorConfig{}, s.scale, s.ws);
  // The bars: every row holds three or four of each bar's pixels (its
  // front face, 1.9 cm at 0.92 m: 3.8 pixels).
  const int bar = candidates_in(s, -0.32f, -0.26f);
  const int deep_bar = candidates_in(s, 0.30f, 0.36f);
  print_message("candidates: bar %d, bar on the deeper face %d, of %d rows\n", bar, deep_bar, kH);
  assert_true(bar >= 3 * kH);
  assert_true(deep_bar >= 3 * kH);
  // Nothing else: the cable rises too little, the box is too wide, the
  // walls and faces are flat.
  assert_int_equal(static_cast<int>(s.ws.side.size()), bar + deep_bar);
  // Found along rows (a bar running down the image is crossed by rows); a
  // column runs into the image's edges and has no width.
  for (std::int32_t i : s.ws.side) {
    assert_true(s.ws.flags[i] & kFlagCrossX);
    assert_false(s.ws.flags[i] & kFlagCrossY);
    assert_true(s.ws.flags[i] & kFlagSide);
  }
  // The list is in ascending order (what the line search expects).
  for (std::size_t k = 1; k < s.ws.side.size(); ++k) assert_true(s.ws.side[k - 1] < s.ws.side[k]);
}

// Invalid pixels end a run: a bar with no valid pixel beside it on either
// side is no candidate (nothing says it stands out); one valid side is
// enough.
void test_invalid_surroundings(void**) {
  Scene s;
  build(&s, {{-0.30f, -0.281f, 0.08f}});
  find_bar_runs(s.cloud, DetectorConfig{}, s.scale, s.ws);
  const std::size_t with_both_sides = s.ws.side.size();
  assert_true(with_both_sides >= 2u * kH);
  // Blank the wall left of the bar: the right side still shows the drop.
  for (int r = 0; r < kH; ++r) {
    for (int c = 0; c < kW; ++c) {
      const int i = r * kW + c;
      const bool wall = s.ws.signed_distance_m[i] < 0.04f;
      if (wall && s.points[i].x_m < -0.29f) s.ws.signed_distance_m[i] = -INFINITY;
    }
  }
  find_bar_runs(s.cloud, DetectorConfig{}, s.scale, s.ws);
  assert_int_equal(s.ws.side.size(), with_both_sides);
  // Both sides blank: nothing.
  for (int r = 0; r < kH; ++r) {
    for (int c = 0; c < kW; ++c) {
      const int i = r * kW + c;
      const bool wall = s.ws.signed_distance_m[i] < 0.04f;
      if (wall && s.points[i].x_m > -0.29f) s.ws.signed_distance_m[i] = -INFINITY;
    }
  }
  find_bar_runs(s.cloud, DetectorConfig{}, s.scale, s.ws);
  assert_int_equal(s.ws.side.size(), 0);
}

// The least rise: a handrail's back face stands 3.75 cm over its surface
// at the least (5.5 cm centre line, 3.5 cm bar), less a centimetre.
void test_least_rise(void**) {
  assert_float_equal(bar_run_min_rise_m(DetectorConfig{}), 0.0275f, 1e-5f);
  Scene s;
  build(&s, {{-0.30f, -0.281f, 0.030f}, {0.10f, 0.119f, 0.026f}});
  find_bar_runs(s.cloud, DetectorConfig{}, s.scale, s.ws);
  assert_true(candidates_in(s, -0.32f, -0.26f) >= 2 * kH);
  assert_int_equal(candidates_in(s, 0.08f, 0.14f), 0);
}

}  // namespace

int main() {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_bars_are_candidates_and_clutter_is_not),
      cmocka_unit_test(test_invalid_surroundings),
      cmocka_unit_test(test_least_rise),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
