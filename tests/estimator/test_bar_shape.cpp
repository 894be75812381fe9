// The tests of a bar's shape beyond its height, on hand-made distances:
// its side face seen from the side (bar_profile.hpp) and the clearance
// under it (bar_clearance.hpp).
#include <Eigen/Geometry>
#include <cmath>
#include <vector>

#include "cmocka_cpp.hpp"
#include "estimator/bar_clearance.hpp"
#include "estimator/bar_profile.hpp"

using namespace estimator;

namespace {

// The profile test's two measures on known numbers: the obliquity across
// the bar from the ray to the line's visible middle, and the 10th to 90th
// percentile of the inliers' heights. The ISS bar seen 25 deg from its side
// shows heights down its side face and passes; a cable's top half (the
// same front, 1 cm deep) does not; face-on (10 deg) or with a round bar
// geometry the test says nothing.
void test_bar_profile(void**) {
  Workspace ws(1000);
  IndexList inliers(1000);
  Plane wall;
  wall.normal = Eigen::Vector3f(0.0f, 0.0f, -1.0f);  // a wall at z = 0.6 facing the camera
  wall.d = 0.6f;
  CenterLine line;
  line.axis = Eigen::Vector3f::UnitX();  // across the bar: image y
  line.t_min_m = -0.2f;
  line.t_max_m = 0.2f;
  const auto place_middle = [&](float obliquity_deg) {
    const float z = 0.6f - 0.07f;
    line.point = Eigen::Vector3f(0.0f, z * std::tan(obliquity_deg * 3.14159265f / 180.0f), z);
  };
  const auto fill_heights = [&](float lowest_m, float highest_m) {
    inliers.clear();
    for (int k = 0; k < 200; ++k) {
      ws.signed_distance_m[k] = lowest_m + (highest_m - lowest_m) * static_cast<float>(k) / 199.0f;
      inliers.push(k);
    }
  };
  DetectorConfig cfg;  // the ISS bar
  place_middle(25.0f);
  fill_heights(0.044f, 0.0785f);  // down the side face to the bar's back
  BarProfile p = measure_bar_profile(ws, wall, line, inliers);
  assert_near(p.obliquity_rad, 25.0f * 3.14159265f / 180.0f, 1e-4f);
  assert_near(p.spread_m, 0.8f * (0.0785f - 0.044f), 0.0015f);
  assert_int_equal(p.count, 200);
  assert_true(profile_fits_bar(p, cfg));
  fill_heights(0.0685f, 0.0785f);  // a 2 cm cable's top half
  p = measure_bar_profile(ws, wall, line, inliers);
  assert_near(p.spread_m, 0.008f, 0.0015f);
  assert_false(profile_fits_bar(p, cfg));
  place_middle(10.0f);
  p = measure_bar_profile(ws, wall, line, inliers);
  assert_true(profile_fits_bar(p, cfg));  // face-on enough: no verdict
  place_middle(25.0f);
  cfg.handrail = paper_round_handrail();
  assert_true(profile_fits_bar(measure_bar_profile(ws, wall, line, inliers), cfg));
  // Along the bar the view's angle is no obliquity across it.
  line.axis = Eigen::Vector3f::UnitY();
  assert_near(measure_bar_profile(ws, wall, line, inliers).obliquity_rad, 0.0f, 1e-4f);
  inliers.clear();
  p = measure_bar_profile(ws, wall, line, inliers);
  assert_int_equal(p.count, 0);
  assert_true(profile_fits_bar(p, DetectorConfig{}));
}

// The clearance under the bar on a 24 x 20 image: the line's inliers a
// column two pixels wide (image columns 10 and 11), 6 cm above the wall,
// the bar's lower side face one more pixel (4 cm) on the right, then the
// silhouette's own pixel. Past it, two pixels in the clearance band are a
// side face reaching down (a fin); the wall there, or a single pixel in the
// band (a flying pixel), is a bar's clearance.
void test_bar_clearance(void**) {
  constexpr int kW = 24, kH = 20;
  std::vector<CloudPoint> pts(kW * kH);
  OrganizedCloud cloud;
  cloud.points = pts.data();
  cloud.width = kW;
  cloud.height = kH;
  Workspace ws(pts.size());
  IndexList inliers(pts.size());
  PixelScale scale;
  scale.ok = true;
  scale.fx_px = scale.fy_px = 200.0f;
  CenterLine line;
  line.point = Eigen::Vector3f(0.0f, 0.0f, 0.55f);
  line.axis = Eigen::Vector3f::UnitY();  // along image columns: the walks go along rows
  // The cloud's points are all at the origin: every inlier lies 0 along
  // the line, in the middle of its extent.
  line.t_min_m = -0.1f;
  line.t_max_m = 0.1f;
  const auto fill = [&](float band_right_m, int band_pixels) {
    inliers.clear();
    for (int r = 0; r < kH; ++r) {
      for (int c = 0; c < kW; ++c) {
        float h = 0.0f;
        if (c == 10 || c == 11) h = 0.06f;
        if (c == 12) h = 0.04f;
        if (c == 13) h = 0.025f;  // the silhouette's pixel, skipped
        if (c >= 14 && c < 14 + band_pixels) h = band_right_m;
        ws.signed_distance_m[r * kW + c] = h;
        if (c == 10 || c == 11) inliers.push(r * kW + c);
      }
    }
  };
  const DetectorConfig cfg;  // the ISS bar: band 1.2 to 3 cm
  fill(0.02f, 2);
  BarClearance b = measure_bar_clearance(cloud, cfg, scale, ws, line, inliers, 0.0f);
  assert_true(b.walks_rows);
  // Every inlier walks both ways.
  assert_int_equal(b.walks[0], 2 * kH);
  assert_int_equal(b.walks[1], 2 * kH);
  assert_int_equal(b.solid[0], 0);
  assert_int_equal(b.solid[1], 2 * kH);
  assert_false(clearance_fits_bar(b, cfg));
  // Measured from a mount 1 cm higher the band is 2.2 to 4 cm above the
  // search's wall: the 2 cm face is below it.
  b = measure_bar_clearance(cloud, cfg, scale, ws, line, inliers, 0.01f);
  assert_int_equal(b.walks[1], 2 * kH);
  assert_int_equal(b.solid[1], 0);
  assert_true(clearance_fits_bar(b, cfg));
  fill(0.0f, 2);  // the wall behind the bar
  b = measure_bar_clearance(cloud, cfg, scale, ws, line, inliers, 0.0f);
  assert_int_equal(b.solid[1], 0);
  assert_true(clearance_fits_bar(b, cfg));
  fill(0.02f, 1);  // one pixel in the band: a flying pixel, not a face
  b = measure_bar_clearance(cloud, cfg, scale, ws, line, inliers, 0.0f);
  assert_int_equal(b.solid[1], 0);
  // A short view: every inlier within a leg's length (4.5 cm) of an end,
  // where a leg, solid down to the mount, may stand.
  fill(0.02f, 2);
  line.t_min_m = -0.04f;
  line.t_max_m = 0.04f;
  b = measure_bar_clearance(cloud, cfg, scale, ws, line, inliers, 0.0f);
  assert_int_equal(b.walks[1], 0);
  assert_true(clearance_fits_bar(b, cfg));
  line.t_min_m = -0.1f;
  line.t_max_m = 0.1f;
  // Too few inliers to judge.
  inliers.clear();
  for (int r = 0; r < 5; ++r) inliers.push(r * kW + 11);
  b = measure_bar_clearance(cloud, cfg, scale, ws, line, inliers, 0.0f);
  assert_int_equal(b.solid[1], 5);
  assert_true(clearance_fits_bar(b, cfg));
}

}  // namespace

int main() {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_bar_profile),
      cmocka_unit_test(test_bar_clearance),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
