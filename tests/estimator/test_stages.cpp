// Each stage of the detector on small analytic scenes.
#include <Eigen/Geometry>
#include <cmath>
#include <vector>

#include "cmocka_cpp.hpp"
#include "estimator/handrail_detector.hpp"
#include "estimator/handrail_filters.hpp"
#include "estimator/handrail_pose.hpp"
#include "estimator/line_estimation.hpp"
#include "estimator/plane_estimation.hpp"
#include "synthetic_cloud.hpp"

using namespace estimator;
using testing_support::SyntheticScene;

namespace {

constexpr double kWall = 0.6;
constexpr double kOffset = 0.065 + 0.0175;  // the paper's bar centre line

DetectorConfig test_config(float bar_length = 0.3f) {
  DetectorConfig cfg;
  cfg.handrail = paper_round_handrail(bar_length);
  cfg.max_width = 160;
  cfg.max_height = 120;
  return cfg;
}

SyntheticScene bar_scene(double noise = 0.0) {
  SyntheticScene s;
  s.cylinders.push_back(testing_support::vertical_bar(kWall, kOffset, 0.3));
  s.noise_m = noise;
  return s;
}

// Runs the stages up to the filters on a scene; returns the wall.
Plane run_filters(const OrganizedCloud& cloud, const DetectorConfig& cfg, Workspace& ws,
                  PixelScale* scale, FrontFace front_face = FrontFace::kOnSearchedSurface) {
  assert_true(sample_valid_points(cloud, cfg, ws) > 1000);
  Random rng(7);
  *scale = estimate_pixel_scale(cloud, ws.sample);
  const PlaneEstimate plane = estimate_plane(cloud, cfg, rng, ws);
  assert_true(plane.found);
  std::uint32_t valid_pixels = 0;
  assert_true(gap_distance_test(cloud, cfg, plane.plane, ws, &valid_pixels) > 0);
  assert_true(valid_pixels > cloud.size() / 2);
  cross_point_test(cloud, cfg, plane.plane, *scale, ws);
  side_width_test(cloud, cfg, *scale, ws, front_face);
  return plane.plane;
}

// The one pass judges every pixel the same way whether it falls in a block
// of four or in the scalar tail: a 7 x 3 cloud (five blocks and one pixel)
// with the wall, raised, noisy and invalid pixels in both.
void test_gap_pass_judges_each_pixel_including_the_tail(void**) {
  const DetectorConfig cfg = test_config();
  const float lo = gap_min_m(cfg), hi = gap_max_m(cfg);
  const float raised = 0.5f * (lo + hi);
  Plane wall;  // z = 0.6 m, normal toward the camera
  wall.normal = Eigen::Vector3f(0.0f, 0.0f, -1.0f);
  wall.d = 0.6f;
  std::vector<CloudPoint> pts(21, CloudPoint{0.0f, 0.0f, 0.6f, 0.001f, 100, 255});
  auto at_height = [&](int i, float s_m) { pts[static_cast<std::size_t>(i)].z_m = 0.6f - s_m; };
  at_height(2, raised);
  at_height(20, raised);  // the tail
  // Just below the window, let in by its own noise (2 sigma = 1 cm).
  at_height(6, lo - 0.005f);
  pts[6].noise_m = 0.005f;
  at_height(7, lo - 0.005f);  // the same height with little noise stays out
  pts[9].confidence = 0;
  pts[13].x_m = std::nanf("");
  pts[17].z_m = 5.0f;  // beyond max_range
  OrganizedCloud cloud;
  cloud.width = 7;
  cloud.height = 3;
  cloud.points = pts.data();
  Workspace ws(cloud.size());
  std::uint32_t valid = 0;
  const std::uint32_t plane_inliers = gap_distance_test(cloud, cfg, wall, ws, &valid);
  assert_int_equal(valid, 18);
  assert_int_equal(plane_inliers, 14);  // the valid pixels on the wall
  assert_int_equal(ws.gap.size(), 3);
  assert_int_equal(ws.gap[0], 2);
  assert_int_equal(ws.gap[1], 6);
  assert_int_equal(ws.gap[2], 20);
  for (std::size_t i : {9u, 13u, 17u}) {
    assert_int_equal(ws.flags[i], 0);
    assert_true(std::isinf(ws.signed_distance_m[i]) && ws.signed_distance_m[i] < 0.0f);
  }
  assert_int_equal(ws.flags[0], kFlagValid | kFlagPlane | kFlagWall);
  assert_int_equal(ws.flags[20], kFlagValid | kFlagGap);
  assert_near(ws.signed_distance_m[20], raised, 1e-6);
  assert_int_equal(ws.flags[7], kFlagValid);
}

// The pass against a plain per-pixel statement of eq. 1 and the flags, on
// a frame of random heights, noise and dropouts sized so that the pass's
// blocks of sixteen, its blocks of four and its scalar tail all run (37 x 11
// pixels: 25 blocks of sixteen, one of four, three more): every flag,
// distance, widening and inverse depth, the counts, and the gap list in
// pixel order; then the shifted pass, with the plane kept in its list and
// left out of it.
void test_gap_pass_matches_a_scalar_reference(void**) {
  const DetectorConfig cfg = test_config();
  const float lo = gap_min_m(cfg), hi = gap_max_m(cfg);
  Plane wall;
  wall.normal = Eigen::Vector3f(0.1f, -0.2f, -1.0f).normalized();
  wall.d = 0.6f;
  const int width = 37, height = 11;
  std::vector<CloudPoint> pts(static_cast<std::size_t>(width * height));
  std::uint32_t state = 12345u;
  auto uniform = [&state](float a, float b) {
    state = state * 1664525u + 1013904223u;
    return a + (b - a) * static_cast<float>(state >> 8) / 16777216.0f;
  };
  for (std::size_t i = 0; i < pts.size(); ++i) {
    // A point at height h over the wall along the camera's ray through
    // (x, y) = (u, v) z.
    const float u = uniform(-0.4f, 0.4f), v = uniform(-0.3f, 0.3f);
    const float h = uniform(-0.03f, 0.12f);
    const Eigen::Vector3f ray(u, v, 1.0f);
    const float z = (h - wall.d) / wall.normal.dot(ray);
    pts[i] = CloudPoint{u * z, v * z, z, uniform(-0.005f, 0.03f), 100, 255};
    const float dice = uniform(0.0f, 1.0f);
    if (dice < 0.05f) pts[i].confidence = 0;
    if (dice > 0.97f) pts[i].noise_m = std::nanf("");
    if (dice > 0.95f && dice < 0.96f) pts[i].z_m = std::nanf("");
  }
  OrganizedCloud cloud;
  cloud.width = width;
  cloud.height = height;
  cloud.points = pts.data();
  Workspace ws(cloud.size());
  std::uint32_t valid = 0;
  const std::uint32_t plane_inliers = gap_distance_test(cloud, cfg, wall, ws, &valid);

  struct Expected {
    float s_m = -INFINITY;  // the pass's distance: -infinity where invalid
    float widen_m = 0.0f;
    std::uint8_t flags = 0;
  };
  auto classify = [&](float s0_m, bool is_valid, float widen_m, float offset_m) {
    Expected e;
    if (!is_valid) return e;
    e.s_m = s0_m - offset_m;
    e.widen_m = widen_m;
    e.flags = kFlagValid;
    if (std::fabs(s0_m) < cfg.plane_inlier_m) e.flags |= kFlagPlane;
    if (e.s_m >= lo - widen_m && e.s_m <= hi + widen_m) e.flags |= kFlagGap;
    if (e.s_m < cfg.wall_tolerance_m) e.flags |= kFlagWall;
    return e;
  };
  std::vector<Expected> plain(pts.size());
  std::uint32_t want_valid = 0, want_plane = 0;
  std::vector<std::int32_t> want_gap;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const CloudPoint& p = pts[i];
    const float s =
        wall.normal.x() * p.x_m + wall.normal.y() * p.y_m + wall.normal.z() * p.z_m + wall.d;
    const bool is_valid =
        p.confidence != 0 && p.z_m >= cfg.min_range_m && p.z_m <= cfg.max_range_m && !std::isnan(s);
    const float noise = p.noise_m > 0.0f ? std::fmin(p.noise_m, 0.02f) : 0.0f;
    plain[i] = classify(s, is_valid, 2.0f * noise, 0.0f);
    want_valid += is_valid;
    want_plane += (plain[i].flags & kFlagPlane) != 0;
    if (plain[i].flags & kFlagGap) want_gap.push_back(static_cast<std::int32_t>(i));
    assert_int_equal(ws.flags[i], plain[i].flags);
    if (!is_valid) {
      assert_true(std::isinf(ws.signed_distance_m[i]) && ws.signed_distance_m[i] < 0.0f);
      continue;
    }
    assert_float_equal(ws.signed_distance_m[i], s, 0.0f);
    assert_float_equal(ws.gap_widen_m[i], 2.0f * noise, 0.0f);
    assert_float_equal(ws.inverse_depth_per_m[i], 1.0f / p.z_m, 0.0f);
  }
  assert_int_equal(valid, want_valid);
  assert_int_equal(plane_inliers, want_plane);
  assert_true(want_gap.size() > 50 && want_plane > 20);  // every kind is there
  assert_int_equal(ws.gap.size(), want_gap.size());
  for (std::size_t k = 0; k < want_gap.size(); ++k) assert_int_equal(ws.gap[k], want_gap[k]);

  keep_plane_pass(cloud, ws);
  // A search 4 cm below the plane leaves the plane's pixels out of its list,
  // one 8 cm below keeps them (its window reaches down to the plane's band).
  assert_true(plane_left_out_of_gap_list(cfg, -0.04f));
  assert_false(plane_left_out_of_gap_list(cfg, -0.08f));
  for (const float offset : {0.013f, -0.04f, -0.08f}) {
    const bool plane_out = plane_left_out_of_gap_list(cfg, offset);
    gap_distance_shifted(cloud, cfg, offset, ws, &valid);
    assert_int_equal(valid, want_valid);
    std::vector<std::int32_t> listed;
    std::size_t plane_listed = 0;
    for (std::size_t i = 0; i < pts.size(); ++i) {
      const Expected e = classify(plain[i].s_m, plain[i].flags != 0, plain[i].widen_m, offset);
      assert_int_equal(ws.flags[i], e.flags);
      if (e.flags == 0) continue;
      assert_float_equal(ws.signed_distance_m[i], e.s_m, 0.0f);
      if ((e.flags & kFlagGap) && !(plane_out && (e.flags & kFlagPlane))) {
        listed.push_back(static_cast<std::int32_t>(i));
        plane_listed += (e.flags & kFlagPlane) != 0;
      }
    }
    assert_int_equal(ws.gap.size(), listed.size());
    for (std::size_t k = 0; k < listed.size(); ++k) assert_int_equal(ws.gap[k], listed[k]);
    if (!plane_out) assert_true(offset > 0.0f || plane_listed > 10);
  }

  // Faces in view as the probes' wall. Faces 1.5, 3 and 4.5 cm
  // and 7 cm over the plane; on the plane's own search the 3 and 4.5 cm
  // faces stand between the wall tolerance and the gap window (5.7 cm for
  // the paper's handrail), the 1.5 cm one is wall anyway and the 7 cm one
  // lies in the window. A pixel on a face (within 5 mm plus half its
  // widening) below the window is wall; nothing else changes. On a mount
  // 2 cm below the plane the 4.5 cm face stands in the window, and the 1.5
  // and 3 cm ones count.
  const float faces_m[] = {0.015f, 0.03f, 0.045f, 0.07f};
  assert_true(faces_beside_mount(cfg, 0.0f, faces_m, 4));
  assert_false(faces_beside_mount(cfg, 0.0f, faces_m, 1));
  assert_false(faces_beside_mount(cfg, 0.0f, faces_m + 3, 1));
  assert_false(faces_beside_mount(cfg, -0.04f, faces_m + 1, 1));
  for (const float offset : {0.0f, -0.02f}) {
    gap_distance_shifted(cloud, cfg, offset, ws, &valid, faces_m, 4);
    std::size_t face_walls = 0;
    for (std::size_t i = 0; i < pts.size(); ++i) {
      Expected e = classify(plain[i].s_m, plain[i].flags != 0, plain[i].widen_m, offset);
      if (e.flags != 0 && !(e.flags & kFlagWall) && e.s_m < lo - e.widen_m) {
        for (const float face : faces_m) {
          const bool counts = face - offset >= cfg.wall_tolerance_m && face - offset < lo;
          if (counts && std::fabs(plain[i].s_m - face) <= 0.005f + 0.5f * e.widen_m) {
            e.flags |= kFlagWall;
            ++face_walls;
          }
        }
      }
      assert_int_equal(ws.flags[i], e.flags);
    }
    assert_true(face_walls > 10);  // the rule was exercised
  }
}

void test_pixel_scale_recovers_projection(void**) {
  SyntheticScene s;
  std::vector<CloudPoint> pts;
  const OrganizedCloud cloud = testing_support::render(s, &pts);
  Workspace ws(cloud.size());
  IndexList all(cloud.size());
  for (std::size_t i = 0; i < cloud.size(); ++i) all.push(static_cast<std::int32_t>(i));
  const PixelScale scale = estimate_pixel_scale(cloud, all);
  assert_true(scale.ok);
  assert_near(scale.fx_px, s.f_px, 0.01);
  assert_near(scale.cx_px, s.cx, 0.01);
  assert_near(scale.cy_px, s.cy, 0.01);
}

void test_filters_keep_the_bar_and_drop_a_thin_cable(void**) {
  SyntheticScene s = bar_scene();
  // A 6 mm cable at the bar's height, 12 cm to the side: passes the gap test;
  // its raised run is narrower than the side width test allows, so the
  // cross test does not even probe it.
  s.cylinders.push_back(testing_support::vertical_bar(kWall, kOffset, 0.3, 0.003, 0.12));
  std::vector<CloudPoint> pts;
  const OrganizedCloud cloud = testing_support::render(s, &pts);
  const DetectorConfig cfg = test_config();
  Workspace ws(cloud.size());
  PixelScale scale;
  run_filters(cloud, cfg, ws, &scale);
  // Centre pixel of the bar and of the cable, in the middle row.
  const int row = 61;
  const int bar_col = static_cast<int>(std::lround(s.cx + s.f_px * 0.0 / (kWall - kOffset)));
  const int cable_col = static_cast<int>(std::lround(s.cx + s.f_px * 0.12 / (kWall - kOffset)));
  const std::uint8_t bar = ws.flags[row * 160 + bar_col];
  const std::uint8_t cable = ws.flags[row * 160 + cable_col];
  const std::uint8_t wall = ws.flags[row * 160 + 5];
  assert_true(bar & kFlagGap);
  assert_true(bar & kFlagCrossX);
  assert_false(bar & kFlagCrossY);  // along the bar, the probes land on the bar
  assert_true(bar & kFlagSide);
  assert_true(cable & kFlagGap);
  assert_false(cable & (kFlagCrossX | kFlagCrossY));
  assert_false(cable & kFlagSide);
  assert_false(wall & kFlagGap);
  assert_true(ws.side.size() > 100);
}

// The side width test's front-face window. A bar standing 2 cm lower than
// a handrail's height above the wall is a handrail only on a face 2 cm
// deeper, shown beside it (here a 12 cm band of the wall behind the bar,
// pushed back): it passes only where the search allows deeper faces. Over
// the wall itself it is a cable, refused either way; a bar 1.5 cm higher
// is refused either way.
// Moves a rendered point along its camera ray to `depth_change_m` further
// from the camera (negative: nearer), as a face at another depth shows it.
void move_along_ray(CloudPoint* p, double depth_change_m) {
  const float scale = static_cast<float>((kWall + depth_change_m) / kWall);
  p->x_m *= scale;
  p->y_m *= scale;
  p->z_m *= scale;
}

std::size_t side_pixels(double offset_m, double band_behind_m, FrontFace front_face) {
  SyntheticScene s;
  s.cylinders.push_back(testing_support::vertical_bar(kWall, offset_m, 0.3));
  std::vector<CloudPoint> pts;
  const OrganizedCloud cloud = testing_support::render(s, &pts);
  for (CloudPoint& p : pts) {
    // Wall points of the band move back along their rays.
    if (std::fabs(p.z_m - kWall) > 1e-4 || std::fabs(p.x_m) > 0.06) continue;
    move_along_ray(&p, band_behind_m);
  }
  const DetectorConfig cfg = test_config();
  Workspace ws(cloud.size());
  PixelScale scale;
  const Plane wall = run_filters(cloud, cfg, ws, &scale, front_face);
  // The wall itself, not the band, and the bar passed the tests before:
  // what is judged below is the side test's own window.
  assert_true(std::fabs(wall.signed_distance(Eigen::Vector3f(0, 0, kWall))) < 0.002f);
  assert_true(ws.cross.size() > 50);
  return ws.side.size();
}

void test_side_width_front_window_allows_deeper_faces_only_when_asked(void**) {
  constexpr FrontFace kSearched = FrontFace::kOnSearchedSurface;
  constexpr FrontFace kDeeper = FrontFace::kOnSearchedOrDeeper;
  assert_true(side_pixels(kOffset, 0.0, kSearched) > 100);
  assert_true(side_pixels(kOffset, 0.0, kDeeper) > 100);
  assert_int_equal(side_pixels(kOffset - 0.02, 0.02, kSearched), 0);
  assert_true(side_pixels(kOffset - 0.02, 0.02, kDeeper) > 100);
  assert_int_equal(side_pixels(kOffset - 0.02, 0.0, kSearched), 0);
  assert_int_equal(side_pixels(kOffset - 0.02, 0.0, kDeeper), 0);
  assert_int_equal(side_pixels(kOffset + 0.015, 0.0, kSearched), 0);
  assert_int_equal(side_pixels(kOffset + 0.015, 0.0, kDeeper), 0);
}

// The cross test's probes on a rack wall: a face 3 cm proud of the wall
// (not wall, not at the bar's height) stands 7 cm beside the bar, where the
// right-hand probe lands (8.5 cm out). The wall between the bar and the
// face is in the probe's segment (half the offset out to all of it), and
// the bar passes. With the face's pixels left on the wall only every other
// column (a noisy raised surface), no two wall pixels stand in a row and
// the bar fails.
std::uint8_t bar_flags_beside_face(bool speckled) {
  SyntheticScene s = bar_scene();
  std::vector<CloudPoint> pts;
  const OrganizedCloud cloud = testing_support::render(s, &pts);
  for (std::size_t k = 0; k < pts.size(); ++k) {
    CloudPoint& p = pts[k];
    const bool on_wall = std::fabs(p.z_m - kWall) < 1e-4;
    const double face_from_m = speckled ? 0.025 : 0.07;
    if (!on_wall || p.x_m < face_from_m || p.x_m > 0.25) continue;
    if (speckled && (k % 160) % 2 == 0) continue;
    move_along_ray(&p, -0.03);
  }
  const DetectorConfig cfg = test_config();
  Workspace ws(cloud.size());
  PixelScale scale;
  const Plane wall = run_filters(cloud, cfg, ws, &scale);
  assert_true(std::fabs(wall.signed_distance(Eigen::Vector3f(0, 0, kWall))) < 0.002f);
  const int bar_col = static_cast<int>(std::lround(s.cx));
  return ws.flags[61 * 160 + bar_col];
}

void test_cross_probe_finds_the_wall_past_a_taller_face(void**) {
  const std::uint8_t clear = bar_flags_beside_face(false);
  assert_true(clear & kFlagGap);
  assert_true(clear & kFlagCrossX);
  const std::uint8_t speckled = bar_flags_beside_face(true);
  assert_true(speckled & kFlagGap);
  assert_false(speckled & kFlagCrossX);
}

// The column probes count rows in a byte, and a probe can span more rows
// than a byte holds in a tall frame seen through a long lens. A 1,500-row
// strip, 4,000 px focal length: a bar 270 rows tall, 8 cm in front of the
// wall; below it a shelf off the wall, then the wall again from row
// wall_from. The downward probe of a pixel near the bar's top searches
// rows 327 to 652 below it (over 255 rows). The wall 300 rows into that
// window is found, 100 rows in too; the wall 15 rows past its end is not
// (a saturated count taken at its word would say it is).
std::uint8_t cross_flags_in_tall_frame(int wall_from) {
  const int width = 8, height = 1500, bar_top = 700, bar_rows = 270;
  const float focal_px = 4000.0f, wall_m = 0.6f;
  const DetectorConfig cfg = test_config();
  const float bar_s_m = cfg.handrail.bar_center_offset_m, shelf_s_m = 0.03f;
  std::vector<CloudPoint> pts(static_cast<std::size_t>(width * height));
  for (int r = 0; r < height; ++r) {
    float s_m = 0.0f;
    if (r >= bar_top && r < bar_top + bar_rows) s_m = bar_s_m;
    if (r >= bar_top + bar_rows && r < wall_from) s_m = shelf_s_m;
    const float z = wall_m - s_m;
    for (int c = 0; c < width; ++c) {
      pts[static_cast<std::size_t>(r * width + c)] = CloudPoint{
          (c - 3.5f) / focal_px * z, (r - 0.5f * height) / focal_px * z, z, 0.001f, 100, 255};
    }
  }
  OrganizedCloud cloud;
  cloud.width = width;
  cloud.height = height;
  cloud.points = pts.data();
  Plane wall;
  wall.normal = Eigen::Vector3f(0.0f, 0.0f, -1.0f);
  wall.d = wall_m;
  PixelScale scale;
  scale.ok = true;
  scale.fx_px = scale.fy_px = focal_px;
  scale.cx_px = 3.5f;
  scale.cy_px = 0.5f * height;
  // The probe's reach at the bar (eq. 2 on a wall facing the camera).
  const float offset_px = focal_px * cross_distance_m(cfg) / (wall_m - bar_s_m);
  assert_true(offset_px > 640.0f && offset_px < 665.0f);
  Workspace ws(cloud.size());
  std::uint32_t valid = 0;
  gap_distance_test(cloud, cfg, wall, ws, &valid);
  cross_point_test(cloud, cfg, wall, scale, ws);
  const std::uint8_t flags = ws.flags[static_cast<std::size_t>((bar_top + 10) * width + 3)];
  assert_true(flags & kFlagGap);
  return flags;
}

void test_cross_probe_reaches_past_a_bytes_count(void**) {
  const int window_from = 710 + 327, window_to = 710 + 652;
  assert_true(cross_flags_in_tall_frame(window_from + 100) & kFlagCrossY);
  assert_true(cross_flags_in_tall_frame(window_from + 300) & kFlagCrossY);
  assert_false(cross_flags_in_tall_frame(window_to + 15) & kFlagCrossY);
}

void test_candidates_cluster_and_select(void**) {
  SyntheticScene s = bar_scene();
  std::vector<CloudPoint> pts;
  const OrganizedCloud cloud = testing_support::render(s, &pts);
  const DetectorConfig cfg = test_config();
  Workspace ws(cloud.size());
  PixelScale scale;
  const Plane wall = run_filters(cloud, cfg, ws, &scale);
  Random rng(11);
  LineModel cand[2];
  project_to_wall(cloud, wall, ws);
  estimate_handrail_candidates(cloud, cfg, wall, rng, ws, ws.side, cand);
  const int k = cand[0].score >= cand[1].score ? 0 : 1;
  assert_true(cand[k].valid);
  assert_near(cand[k].psi_rad, 0.0, 0.05);  // along image y
  collect_line_inliers(cloud, cfg, wall, ws, cand[k], ws.side, ws.line[0]);
  const Cluster c = cluster_along_line(cloud, cfg, cand[k], ws.line[0], ws.line_t_m.get());
  assert_near(c.length_m(), 0.3, 0.02);
  assert_int_equal(c.count, ws.line[0].size());
  CenterLine centre;
  assert_true(estimate_center_line(cloud, cfg, wall, ws.line[0], ws, &centre));
  assert_near(centre.point.x(), 0.0, 0.002);
  assert_near(wall.signed_distance(centre.point), kOffset, 1e-4);
  // Front face of the round bar: its crown, 10 cm off the wall (the mode of
  // a curved face reads a little low).
  assert_near(centre.front_height_m, kOffset + 0.0175, 0.005);
  assert_true(bar_front_height_test(cfg, centre));
  // The same bar read as the ISS bar (front at 7.85 cm) is at the wrong height.
  DetectorConfig iss = cfg;
  iss.handrail = iss_handrail(0.3f);
  assert_false(bar_front_height_test(iss, centre));

  // Algorithm 1's selection by the gripper angle.
  LineModel two[2];
  two[0].psi_rad = 0.0f;
  two[1].psi_rad = static_cast<float>(M_PI / 2);
  bool usable[2] = {true, true};
  DetectorConfig g = cfg;
  g.gripper_angle_rad = static_cast<float>(M_PI / 2);
  assert_int_equal(select_by_gripper_angle(g, two, usable), 1);
  g.gripper_angle_rad = 0.1f;
  assert_int_equal(select_by_gripper_angle(g, two, usable), 0);
  usable[0] = false;
  assert_int_equal(select_by_gripper_angle(g, two, usable), 1);
  usable[1] = false;
  assert_int_equal(select_by_gripper_angle(g, two, usable), -1);
}

void test_cluster_splits_at_gaps(void**) {
  // Two collinear bars 10 cm apart: the larger run wins.
  SyntheticScene s;
  s.cylinders.push_back({0.0, -0.16, kWall - kOffset, 0, 1, 0, 0.0175, 0.0, 0.12});
  s.cylinders.push_back({0.0, 0.06, kWall - kOffset, 0, 1, 0, 0.0175, 0.0, 0.10});
  std::vector<CloudPoint> pts;
  const OrganizedCloud cloud = testing_support::render(s, &pts);
  const DetectorConfig cfg = test_config();
  Workspace ws(cloud.size());
  PixelScale scale;
  const Plane wall = run_filters(cloud, cfg, ws, &scale);
  LineModel line{true, Eigen::Vector3f(0, 0, static_cast<float>(kWall)), Eigen::Vector3f(0, 1, 0),
                 0.0f, 0};
  project_to_wall(cloud, wall, ws);
  collect_line_inliers(cloud, cfg, wall, ws, line, ws.side, ws.line[0]);
  const std::size_t before = ws.line[0].size();
  const Cluster c = cluster_along_line(cloud, cfg, line, ws.line[0], ws.line_t_m.get());
  assert_true(c.count < before);
  assert_near(c.length_m(), 0.12, 0.02);
  assert_true(c.t_min_m < -0.1f);
}

void test_handrail_frame_is_eq5(void**) {
  const Eigen::Vector3f n = Eigen::Vector3f(-0.3f, 0.1f, -1.0f).normalized();
  const Eigen::Vector3f line = Eigen::Vector3f(0.1f, 1.0f, 0.2f).normalized();
  const Eigen::Matrix3f R = handrail_frame(n, line);
  assert_near((R.transpose() * R - Eigen::Matrix3f::Identity()).norm(), 0.0, 1e-5);
  assert_near(R.determinant(), 1.0, 1e-5);
  assert_near((R.col(0) - n).norm(), 0.0, 1e-5);
  assert_near(R.col(2).dot(n), 0.0, 1e-5);
  // Sign: a bar nearer vertical points up the image (-y).
  assert_true(R.col(2).y() < 0.0f);
  assert_near((R.col(1) - R.col(2).cross(R.col(0))).norm(), 0.0, 1e-5);
  // The projection of the line keeps its direction.
  const Eigen::Vector3f proj = (line - line.dot(n) * n).normalized();
  assert_near(std::fabs(proj.dot(R.col(2))), 1.0, 1e-5);
}

void test_target_pose(void**) {
  DetectorConfig cfg = test_config();
  cfg.target_standoff_m = 0.4f;
  const Eigen::Matrix3f R = handrail_frame(Eigen::Vector3f(0, 0, -1), Eigen::Vector3f(0, 1, 0));
  Eigen::Vector3f p;
  Eigen::Matrix3f Rt;
  target_pose(cfg, Eigen::Vector3f(0.1f, 0.0f, 0.5f), R, &p, &Rt);
  assert_near(p.z(), 0.1, 1e-6);
  assert_near(p.x(), 0.1, 1e-6);
  assert_near((Rt - R).norm(), 0.0, 1e-9);
  // [v_P v_o v_L] with v_o = v_L x v_P.
  assert_near((Rt.col(1) - Rt.col(2).cross(Rt.col(0))).norm(), 0.0, 1e-6);
}

void test_handrail_state(void**) {
  const bool both[2] = {true, true}, one[2] = {false, true}, none[2] = {false, false};
  assert_int_equal(static_cast<int>(handrail_state(both)),
                   static_cast<int>(HandrailState::kBothEnds));
  assert_int_equal(static_cast<int>(handrail_state(one)), static_cast<int>(HandrailState::kOneEnd));
  assert_int_equal(static_cast<int>(handrail_state(none)), static_cast<int>(HandrailState::kNoEnd));
  assert_string_equal(to_string(HandrailState::kBothEnds), "BE");
  assert_string_equal(to_string(HandrailState::kNoHandrail), "NH");
  assert_string_equal(to_string(DetectStatus::kDeadlineMissed), "DEADLINE_MISSED");
}

void test_config_validation_names_the_field(void**) {
  DetectorConfig cfg = test_config();
  assert_null(validate(cfg));
  cfg.line_iterations = 0;
  assert_string_equal(validate(cfg), "line_iterations");
  cfg = test_config();
  cfg.handrail.bar_center_offset_m = 0.01f;
  assert_string_equal(validate(cfg), "handrail.bar_center_offset_m");
  cfg = test_config();
  cfg.max_range_m = 0.05f;
  assert_string_equal(validate(cfg), "max_range_m");
}

}  // namespace

int main() {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_gap_pass_judges_each_pixel_including_the_tail),
      cmocka_unit_test(test_gap_pass_matches_a_scalar_reference),
      cmocka_unit_test(test_pixel_scale_recovers_projection),
      cmocka_unit_test(test_filters_keep_the_bar_and_drop_a_thin_cable),
      cmocka_unit_test(test_side_width_front_window_allows_deeper_faces_only_when_asked),
      cmocka_unit_test(test_cross_probe_finds_the_wall_past_a_taller_face),
      cmocka_unit_test(test_cross_probe_reaches_past_a_bytes_count),
      cmocka_unit_test(test_candidates_cluster_and_select),
      cmocka_unit_test(test_cluster_splits_at_gaps),
      cmocka_unit_test(test_handrail_frame_is_eq5),
      cmocka_unit_test(test_target_pose),
      cmocka_unit_test(test_handrail_state),
      cmocka_unit_test(test_config_validation_names_the_field),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
