// The rack-wall parts of the detector on their own: the surfaces in view
// and the mounts they offer (mount_surfaces) and the surface found under a
// bar from its front face's height. What shows beside a bar is in
// test_mount_beside.cpp; the ISS handrail lengths and the settings'
// validation in test_handrail_types.cpp.
#include <cmath>
#include <vector>

#include "cmocka_cpp.hpp"
#include "estimator/handrail_filters.hpp"
#include "estimator/mount_surfaces.hpp"
#include "estimator/plane_estimation.hpp"
#include "synthetic_cloud.hpp"

using namespace estimator;

namespace {

constexpr float kFront = 0.061f + 0.0175f;  // the ISS bar's front face above its mount

// A frame's distances from the dominant plane, as the gap distance pass
// leaves them: `share` of the pixels at each height (+- 1 mm of spread,
// deterministic), the rest invalid (-infinity).
struct Heights {
  float height_m;
  float share;
};
struct DistanceFrame {
  OrganizedCloud cloud;
  Workspace ws{224 * 171};
  explicit DistanceFrame(const std::vector<Heights>& layers) {
    cloud.width = 224;
    cloud.height = 171;
    const std::size_t n = cloud.size();
    std::size_t i = 0;
    for (const Heights& h : layers) {
      const std::size_t count = static_cast<std::size_t>(h.share * static_cast<float>(n));
      for (std::size_t k = 0; k < count && i < n; ++k, ++i) {
        ws.signed_distance_m[i] = h.height_m + 0.0005f * (static_cast<float>(k % 5) - 2.0f);
      }
    }
    for (; i < n; ++i) ws.signed_distance_m[i] = -INFINITY;
  }
};

bool has_surface(const MountHypotheses& m, float height_m) {
  for (std::uint32_t k = 0; k < m.surface_count; ++k) {
    if (std::fabs(m.surface_m[k] - height_m) < 0.0015f) return true;
  }
  return false;
}

bool has_mount(const MountHypotheses& m, float height_m) {
  for (std::uint32_t k = 0; k < m.count; ++k) {
    if (std::fabs(m.offset_m[k] - height_m) < 0.0015f) return true;
  }
  return false;
}

void test_surfaces_of_a_rack_wall(void**) {
  // The dominant face, a face 3 cm back, a seat track 1.3 cm proud of the
  // dominant face and a bar standing on the track.
  const DistanceFrame f({{0.0f, 0.5f}, {-0.03f, 0.25f}, {0.013f, 0.04f}, {0.013f + kFront, 0.03f}});
  const DetectorConfig cfg;
  const MountHypotheses m = find_mount_hypotheses(f.cloud, cfg, f.ws);
  assert_true(has_surface(m, 0.0f));
  assert_true(has_surface(m, -0.03f));
  assert_true(has_surface(m, 0.013f));
  // The bar's front is where the track (or the face under it, plus the
  // seat track's step) puts it: that mount comes first.
  assert_true(m.count >= 1);
  assert_near(m.offset_m[0], 0.013f, 0.0015f);
  assert_true(m.front_pixels[0] >= static_cast<std::uint32_t>(0.02f * 224 * 171));
  // The 3 cm deeper face has no bar over it: not a mount worth searching.
  assert_false(has_mount(m, -0.03f));
  assert_false(has_mount(m, -0.03f + cfg.mount_step_m));
}

void test_surfaces_too_far_from_the_plane_are_not_mounts(void**) {
  // Box tops 10 and 20 cm proud with something at a bar's height above
  // them: rack faces differ by at most 5 cm and boxes are not mounts.
  for (const float box : {0.10f, 0.20f}) {
    const DistanceFrame f({{0.0f, 0.6f}, {box, 0.2f}, {box + kFront, 0.05f}});
    const DetectorConfig cfg;
    const MountHypotheses m = find_mount_hypotheses(f.cloud, cfg, f.ws);
    assert_false(has_surface(m, box));
    assert_false(has_mount(m, box));
  }
}

// Faces closer than a rack's least face step (1 cm) merge into one peak
// under the depth noise of a metre's range, at a level between them: a
// face 5 cm proud (the most a face stands off the plane) beside one 5.9 cm
// proud made one peak at 5.9 cm, past mount_search_m, and the seat track
// on the 5 cm face (a rail on it) was never searched
// (`dev-rack-approach-vertical-8-5`, second development set, depth path,
// 1.0 to 1.15 m: 6 frames of 120). Such a peak is a surface up to a face
// step past mount_search_m; a surface further out is not (the test above).
void test_a_face_merged_past_the_search_range_is_a_surface(void**) {
  const DetectorConfig cfg;
  const float merged = 0.059f, track_top = 0.0627f;
  const DistanceFrame f({{0.0f, 0.4f}, {merged, 0.25f}, {track_top + kFront, 0.01f}});
  const MountHypotheses m = find_mount_hypotheses(f.cloud, cfg, f.ws);
  assert_true(merged > cfg.mount_search_m);
  assert_true(has_surface(m, merged));
  assert_true(has_mount(m, merged));
  float mount = 0.0f;
  assert_true(find_mount_under_bar(m, cfg, track_top + kFront, 0.005f, &mount));
  assert_near(mount, merged, 0.0015f);
  // A bump on a slope of heights there is no face: it does not fall to
  // half within a face step (clutter-only's flat wall).
  std::vector<Heights> slope = {{0.0f, 0.5f}, {0.058f, 0.004f}};
  for (int k = 0; k < 14; ++k) {
    slope.push_back({0.04f + kMountBinM * static_cast<float>(k), 0.004f});
  }
  const DistanceFrame s(slope);
  const MountHypotheses on_slope = find_mount_hypotheses(s.cloud, cfg, s.ws);
  for (std::uint32_t k = 0; k < on_slope.surface_count; ++k) {
    assert_true(on_slope.surface_m[k] <= cfg.mount_search_m);
  }
  // A step and more past the range: no surface (a box's top).
  const float beyond = cfg.mount_search_m + kRackFaceStepM + 2.0f * kMountBinM;
  const DistanceFrame g({{0.0f, 0.4f}, {beyond, 0.25f}, {beyond + kFront, 0.01f}});
  assert_false(has_surface(find_mount_hypotheses(g.cloud, cfg, g.ws), beyond));
}

// In a bay view seen obliquely the faces in front of the bay's back make a
// ramp of heights, and a mount whose bar front would fall on it collects
// the ramp's pixels: five such mounts outranked a rail's own face, whose
// window holds the bar's front and little else, and the bay's five slots
// were full before it (`dev-rack-table2-iss-0-53`, second development set,
// raw path, 7 frames of its 30/30/30 deg pose). In a bay view mounts rank
// by their window's pixels less those in as wide a window just above it,
// where nothing of a bar on that mount lies: a ramp gives as many there as
// in the window, a bar's front none.
void test_a_bay_view_ranks_a_bar_front_over_a_ramp_of_faces(void**) {
  const DetectorConfig cfg;
  const float rail_face = 0.355f;
  std::vector<Heights> layers = {{0.0f, 0.3f}};
  for (int k = 0; k < 4; ++k) {
    layers.push_back({0.2925f + 0.0125f * static_cast<float>(k), 0.04f});
  }
  // The ramp: from below the rail's face to above every other mount's
  // window.
  for (int k = 0; k < 29; ++k) {
    layers.push_back({0.36f + kMountBinM * static_cast<float>(k), 0.007f});
  }
  layers.push_back({rail_face, 0.04f});
  layers.push_back({rail_face + kFront, 0.012f});
  const DistanceFrame f(layers);
  const MountHypotheses m = find_mount_hypotheses(f.cloud, cfg, f.ws);
  assert_true(has_surface(m, rail_face));
  assert_true(m.count - m.front_peak_count <= cfg.max_mount_hypotheses_bay);
  // Among the mounts searched, though more than the bay's five slots show
  // more front pixels.
  std::uint32_t rail = kMaxMountHypotheses;
  for (std::uint32_t k = 0; k < m.count; ++k) {
    if (std::fabs(m.offset_m[k] - rail_face) < 0.0015f) rail = k;
  }
  assert_true(rail < m.count);
  std::uint32_t more = 0;
  for (std::uint32_t k = 0; k < m.count; ++k) more += m.front_pixels[k] > m.front_pixels[rail];
  assert_true(more >= 3);
}

void test_rack_faces_in_front_of_an_empty_bay_are_mounts(void**) {
  // The dominant plane is the back of an empty bay; the rack faces stand
  // 35 and 33.5 cm in front of it, a seat track on the nearer one, and a
  // bar on the track: the track is the mount, though far from the plane.
  const float face = 0.35f, track = face + 0.013f;
  const DistanceFrame f({{0.0f, 0.45f},
                         {face, 0.2f},
                         {face - 0.015f, 0.15f},
                         {track, 0.03f},
                         {track + kFront, 0.03f}});
  const DetectorConfig cfg;
  const MountHypotheses m = find_mount_hypotheses(f.cloud, cfg, f.ws);
  assert_true(has_surface(m, face));
  assert_true(has_surface(m, face - 0.015f));
  assert_true(m.count >= 1);
  assert_near(m.offset_m[0], track, 0.0015f);
  // ... and a bar whose front stands there is seated on it.
  float mount = 0.0f;
  assert_true(find_mount_under_bar(m, cfg, track + kFront, 0.004f, &mount));
  assert_near(mount, track, 0.0015f);
  // Without the bay's range (a configuration that turns it off) the faces
  // are not surfaces.
  DetectorConfig no_bay;
  no_bay.mount_bay_min_m = no_bay.mount_bay_max_m = 0.0f;
  assert_false(has_surface(find_mount_hypotheses(f.cloud, no_bay, f.ws), face));
}

// A bay view with faces at a bar front's height over other faces (the
// development set's `dev-rack-approach-vertical-8-5`, third offset, on the
// raw path): a face standing 7.85 cm over another gives that one's mount
// more front pixels than the track the handrail stands on, so ranked by
// front pixels the track comes fourth. Three searches missed it; in a bay
// view five are made.
void test_a_bay_view_searches_past_faces_at_a_bar_fronts_height(void**) {
  const float face_a = 0.26f, face_c = 0.30f, track = face_a + kFront + 0.013f;
  const DistanceFrame f({{0.0f, 0.3f},
                         {face_a, 0.1f},
                         {face_a + kFront, 0.1f},  // over face a
                         {0.28f, 0.06f},
                         {0.28f + 0.013f + kFront, 0.08f},  // over a track's top on 0.28
                         {face_c, 0.05f},
                         {face_c + kFront, 0.05f},  // over face c
                         {track, 0.02f},
                         {track + kFront, 0.03f}});  // the bar, on a track on a + kFront
  const DetectorConfig cfg;
  const MountHypotheses m = find_mount_hypotheses(f.cloud, cfg, f.ws);
  assert_true(has_surface(m, track));
  assert_true(m.count > cfg.max_mount_hypotheses);
  assert_true(has_mount(m, track));
  // The old budget, three mounts: the distractors fill it.
  DetectorConfig three = cfg;
  three.max_mount_hypotheses_bay = cfg.max_mount_hypotheses;
  const MountHypotheses m3 = find_mount_hypotheses(f.cloud, three, f.ws);
  assert_false(has_mount(m3, track));
  // Off the bay the budget is the plain one: a rack wall's view with more
  // than three mounts on offer (faces 4 and 2 cm back with something at a
  // bar front's height over each, a track on the plane's face) searches
  // three of them, as before.
  const DistanceFrame wall({{0.0f, 0.4f},
                            {-0.04f, 0.1f},
                            {-0.04f + kFront, 0.05f},
                            {-0.02f, 0.1f},
                            {-0.02f + kFront, 0.04f},
                            {0.013f, 0.04f},
                            {0.013f + kFront, 0.03f}});
  const MountHypotheses on_wall = find_mount_hypotheses(wall.cloud, cfg, wall.ws);
  assert_int_equal(on_wall.count - on_wall.front_peak_count, cfg.max_mount_hypotheses);
  DetectorConfig five = cfg;
  five.max_mount_hypotheses = 5;
  const MountHypotheses more = find_mount_hypotheses(wall.cloud, five, wall.ws);
  assert_true(more.count - more.front_peak_count > cfg.max_mount_hypotheses);
}

// A face seen obliquely through noise breaks into a comb of histogram
// maxima a few millimetres apart (the development set's
// `dev-rack-table2-iss-0-53`, second offset, last pose, on the raw path:
// seven maxima 5 mm apart in front of an empty bay). Taken in order of
// distance they filled the surface list, and the face the rail stands on,
// behind them, was never a surface: the rail was missed in 29 of its 50
// frames. A maximum within a face step of a better supported one is no
// surface of its own.
void test_a_comb_of_weak_maxima_leaves_room_for_a_stronger_face(void**) {
  const float rail_face = 0.37f;
  const DetectorConfig cfg;
  // Eight spikes 5 mm apart, each within one histogram bin (at its centre;
  // the frame spreads a height by +- 1 mm), make seven maxima between them.
  const float lo_m = -(cfg.mount_search_m + 2.0f * kMountBinM);
  const int first_bin = static_cast<int>((0.29f - lo_m) / kMountBinM);
  std::vector<Heights> layers = {{0.0f, 0.3f}};
  for (int k = 0; k < 8; ++k) {
    const float centre_m = lo_m + (static_cast<float>(first_bin + 2 * k) + 0.5f) * kMountBinM;
    layers.push_back({centre_m, k == 4 ? 0.04f : 0.02f});
  }
  layers.push_back({rail_face, 0.1f});
  layers.push_back({rail_face + kFront, 0.03f});
  const DistanceFrame f(layers);
  const MountHypotheses m = find_mount_hypotheses(f.cloud, cfg, f.ws);
  assert_true(has_surface(m, 0.0f));
  assert_true(has_surface(m, rail_face));
  // In order of distance, and the comb reduced to teeth a face step apart
  // (before: the plane and seven teeth, the list full).
  for (std::uint32_t k = 1; k < m.surface_count; ++k) {
    assert_true(m.surface_m[k] - m.surface_m[k - 1] > kRackFaceStepM - kMountBinM);
  }
  assert_true(m.surface_count < kMaxSurfacePeaks);
  float mount = 0.0f;
  assert_true(find_mount_under_bar(m, cfg, rail_face + kFront, 0.004f, &mount));
  assert_near(mount, rail_face, 0.0015f);
}

// The plane's own face offers a mount too, and a face standing a bar
// front's height over the plane gives it the most front pixels. It is the
// plane, searched on its own, so it must not take one of the slots: there
// it pushed the seat track a rail stood on out of the list and was never
// searched itself (the development sets' `dev-rack-approach-vertical-21-5`
// at 1.1 to 1.25 m, 7 frames of 120 on one path or the other).
void test_the_plane_takes_no_mount_slot(void**) {
  const DistanceFrame f({{0.0f, 0.3f},
                         {kFront, 0.1f},  // a face over the plane, at a front's height
                         {-0.04f, 0.1f},
                         {-0.04f + kFront, 0.05f},
                         {-0.02f, 0.1f},
                         {-0.02f + kFront, 0.04f},
                         {0.013f + kFront, 0.025f}});  // a bar on a track on the plane
  const DetectorConfig cfg;
  const MountHypotheses m = find_mount_hypotheses(f.cloud, cfg, f.ws);
  // Three surface mounts, none the plane, the track among them (not left
  // to a bar-front peak's mount, searched only while nothing is found).
  const std::uint32_t surface_mounts = m.count - m.front_peak_count;
  assert_int_equal(surface_mounts, cfg.max_mount_hypotheses);
  bool track = false;
  for (std::uint32_t k = 0; k < surface_mounts; ++k) {
    assert_true(std::fabs(m.offset_m[k]) >= kSameMountM);
    track |= std::fabs(m.offset_m[k] - 0.013f) < 0.0015f;
  }
  assert_true(track);
  // The plane's front pixels are still reported, for the order of search.
  assert_true(m.dominant_front_pixels >= static_cast<std::uint32_t>(0.09f * 224 * 171));
}

void test_no_bar_anywhere_leaves_the_plane(void**) {
  const DistanceFrame f({{0.0f, 0.7f}, {-0.02f, 0.2f}});
  const DetectorConfig cfg;
  const MountHypotheses m = find_mount_hypotheses(f.cloud, cfg, f.ws);
  assert_int_equal(m.count, 1);
  assert_near(m.offset_m[0], 0.0f, 1e-6f);
}

void test_a_small_surface_is_no_surface(void**) {
  // Under mount_min_fraction of the valid pixels: noise, a label, an edge.
  const DistanceFrame f({{0.0f, 0.8f}, {-0.025f, 0.004f}});
  const DetectorConfig cfg;
  const MountHypotheses m = find_mount_hypotheses(f.cloud, cfg, f.ws);
  assert_true(has_surface(m, 0.0f));
  assert_false(has_surface(m, -0.025f));
}

// A rack's face seen obliquely can hold too few pixels for a surface peak
// (here 0.4 % of the view, 1.6 cm proud of the plane) while the bar on the
// seat track over it makes a peak of its own: the mount is read off the
// bar's front, past the surface mounts. With front_peak_mounts 0 it is not.
void test_a_face_too_small_for_a_peak_is_found_under_its_bar(void**) {
  const float track_m = 0.016f + 0.013f;
  const DistanceFrame f(
      {{0.0f, 0.6f}, {-0.03f, 0.2f}, {0.016f, 0.004f}, {track_m + kFront, 0.006f}});
  DetectorConfig cfg;
  const MountHypotheses m = find_mount_hypotheses(f.cloud, cfg, f.ws);
  assert_false(has_surface(m, 0.016f));
  bool found = false;
  for (std::uint32_t k = 0; k < m.count; ++k) {
    found |= std::fabs(m.offset_m[k] - track_m) < 0.0025f;
  }
  assert_true(found);
  assert_true(m.count <= cfg.max_mount_hypotheses + cfg.front_peak_mounts);
  cfg.front_peak_mounts = 0;
  const MountHypotheses none = find_mount_hypotheses(f.cloud, cfg, f.ws);
  for (std::uint32_t k = 0; k < none.count; ++k) {
    assert_true(std::fabs(none.offset_m[k] - track_m) >= 0.0025f);
  }
}

// A front peak whose mount would lie farther behind the plane than any
// surface mount may (mount_search_m, 5.2 cm): a structure, not a bar's
// front over a face in view.
void test_a_front_peak_too_far_behind_the_plane_is_no_mount(void**) {
  const float behind_m = -0.06f;
  const DistanceFrame f({{0.0f, 0.7f}, {behind_m + kFront, 0.01f}});
  const MountHypotheses m = find_mount_hypotheses(f.cloud, DetectorConfig{}, f.ws);
  for (std::uint32_t k = 0; k < m.count; ++k) {
    assert_true(std::fabs(m.offset_m[k] - behind_m) >= 0.005f);
  }
}

// A rack face 4.5 cm proud of the plane is a surface, and it is also the
// histogram's strongest peak where a bar's front could stand (over a mount
// 3.3 cm behind the plane). That peak is the face, not a bar: no mount is
// read off it (its search would put the whole face in the gap set).
void test_a_face_at_a_front_height_is_no_front_peak(void**) {
  const float face_m = 0.045f;
  const DistanceFrame f({{0.0f, 0.6f}, {face_m, 0.3f}});
  const MountHypotheses m = find_mount_hypotheses(f.cloud, DetectorConfig{}, f.ws);
  assert_true(has_surface(m, face_m));
  assert_int_equal(m.front_peak_count, 0);
  assert_false(has_mount(m, face_m - kFront));
}

void test_huge_and_not_finite_distances_are_ignored(void**) {
  DistanceFrame f({{0.0f, 0.5f}});
  const std::size_t n = f.cloud.size();
  for (std::size_t i = n / 2; i < n; i += 3) f.ws.signed_distance_m[i] = 1e30f;
  for (std::size_t i = n / 2 + 1; i < n; i += 3) f.ws.signed_distance_m[i] = NAN;
  for (std::size_t i = n / 2 + 2; i < n; i += 3) f.ws.signed_distance_m[i] = -1e30f;
  const MountHypotheses m = find_mount_hypotheses(f.cloud, DetectorConfig{}, f.ws);
  assert_true(has_surface(m, 0.0f));
  assert_int_equal(m.surface_count, 1);
}

void test_the_mount_under_a_bar(void**) {
  const DetectorConfig cfg;
  MountHypotheses m;
  m.surface_count = 2;
  m.surface_m[0] = 0.0f;
  m.surface_m[1] = -0.03f;
  float mount = 99.0f;
  // On the deeper face directly.
  assert_true(find_mount_under_bar(m, cfg, -0.03f + kFront + 0.002f, 0.004f, &mount));
  assert_near(mount, -0.03f, 1e-6f);
  // On a seat track on the deeper face.
  assert_true(find_mount_under_bar(m, cfg, -0.03f + 0.013f + kFront, 0.004f, &mount));
  assert_near(mount, -0.03f + 0.013f, 1e-6f);
  // On a seat track on the dominant face.
  assert_true(find_mount_under_bar(m, cfg, 0.013f + kFront - 0.003f, 0.004f, &mount));
  assert_near(mount, 0.013f, 1e-6f);
  // On the dominant face itself: that is the flat-wall search's to judge.
  assert_false(find_mount_under_bar(m, cfg, kFront, 0.004f, &mount));
  // A cable 2 cm higher than any handrail's front: nothing under it.
  assert_false(find_mount_under_bar(m, cfg, 0.013f + kFront + 0.02f, 0.004f, &mount));
  // Outside the tolerance, by a little.
  assert_false(find_mount_under_bar(m, cfg, -0.03f + kFront + 0.006f, 0.004f, &mount));
}

// The detector's configuration for testing_support's 160 x 120 scenes, and
// their wall (z = 0.6 m, its normal toward the camera).
DetectorConfig synthetic_scene_config() {
  DetectorConfig cfg;
  cfg.max_width = 160;
  cfg.max_height = 120;
  return cfg;
}

Plane synthetic_scene_wall() {
  Plane wall;
  wall.normal = Eigen::Vector3f(0, 0, -1);
  wall.d = 0.6f;
  return wall;
}

// The searches on other mounts shift the first pass's distances instead of
// reading the cloud again: the same flags (the plane's own inliers apart),
// gap list and distances as a full pass against the shifted wall.
void test_shifted_pass_equals_a_full_pass(void**) {
  testing_support::SyntheticScene scene;
  scene.cylinders.push_back(testing_support::vertical_bar(0.6, 0.074, 0.3, 0.0095));
  scene.noise_m = 0.002;
  std::vector<CloudPoint> pts;
  OrganizedCloud cloud = testing_support::render(scene, &pts, 3);
  pts[17].confidence = 0;  // an invalid pixel and a NaN one
  pts[400].z_m = NAN;
  cloud.points = pts.data();
  const DetectorConfig cfg = synthetic_scene_config();
  const Plane wall = synthetic_scene_wall();
  Workspace shifted(cloud.size()), full(cloud.size());
  std::uint32_t valid_shifted = 0, valid_full = 0;
  gap_distance_test(cloud, cfg, wall, shifted, &valid_shifted);
  keep_plane_pass(cloud, shifted);
  const float offset = 0.013f;
  gap_distance_shifted(cloud, cfg, offset, shifted, &valid_shifted);
  Plane moved = wall;
  moved.d -= offset;
  gap_distance_test(cloud, cfg, moved, full, &valid_full);
  assert_int_equal(valid_shifted, valid_full);
  assert_int_equal(shifted.gap.size(), full.gap.size());
  assert_true(full.gap.size() > 100);  // the bar is in the window
  for (std::size_t k = 0; k < full.gap.size(); ++k) assert_int_equal(shifted.gap[k], full.gap[k]);
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const int without_plane = ~static_cast<int>(kFlagPlane) & 0xff;
    assert_int_equal(shifted.flags[i] & without_plane, full.flags[i] & without_plane);
    const float a = shifted.signed_distance_m[i], b = full.signed_distance_m[i];
    if (std::isinf(b)) {
      assert_true(std::isinf(a) && a < 0.0f);
    } else {
      assert_near(a, b, 1e-6);
    }
  }
}

// A search on a face 4 cm deeper than the dominant plane puts the whole
// plane in its gap window. The plane's pixels keep their gap bit (the
// probes read it) but stay out of the list the cross test walks; the bar
// standing on that deeper face stays in it, front and sides.
void test_search_below_the_plane_leaves_the_plane_out_of_the_list(void**) {
  const float kMount = -0.04f;
  testing_support::SyntheticScene scene;
  // The bar's centre 7.4 cm above the deeper face: 3.4 cm above the plane.
  scene.cylinders.push_back(testing_support::vertical_bar(0.6, 0.074 + kMount, 0.3, 0.0095));
  scene.noise_m = 0.002;
  std::vector<CloudPoint> pts;
  OrganizedCloud cloud = testing_support::render(scene, &pts, 5);
  const DetectorConfig cfg = synthetic_scene_config();
  const Plane wall = synthetic_scene_wall();
  assert_true(plane_left_out_of_gap_list(cfg, kMount));
  Workspace ws(cloud.size());
  std::uint32_t valid = 0;
  gap_distance_test(cloud, cfg, wall, ws, &valid);
  keep_plane_pass(cloud, ws);
  gap_distance_shifted(cloud, cfg, kMount, ws, &valid);
  std::vector<char> listed(cloud.size(), 0);
  for (std::int32_t i : ws.gap) listed[static_cast<std::size_t>(i)] = 1;
  std::size_t plane_in_window = 0, bar_listed = 0;
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const bool on_plane = (ws.flags[i] & kFlagPlane) != 0;
    const bool in_window = (ws.flags[i] & kFlagGap) != 0;
    if (on_plane) {
      assert_false(listed[i]);
      plane_in_window += in_window;
    } else {
      // Everything else in the window is listed, as in a full pass.
      assert_int_equal(listed[i], in_window);
      bar_listed += in_window;
    }
  }
  assert_true(plane_in_window > cloud.size() / 2);  // the plane is in the window
  assert_true(bar_listed > 100);                    // and the bar is listed

  // The deepest mount the search looks at still qualifies; a mount so deep
  // that a bar's front would meet the plane's band does not.
  assert_true(plane_left_out_of_gap_list(cfg, -cfg.mount_search_m));
  assert_false(plane_left_out_of_gap_list(cfg, -0.07f));
  // The plane's own search, run again from the kept distances, keeps its
  // list as the full pass makes it.
  assert_false(plane_left_out_of_gap_list(cfg, 0.0f));
}

}  // namespace

int main() {
  const CMUnitTest tests[] = {
      cmocka_unit_test(test_surfaces_of_a_rack_wall),
      cmocka_unit_test(test_surfaces_too_far_from_the_plane_are_not_mounts),
      cmocka_unit_test(test_rack_faces_in_front_of_an_empty_bay_are_mounts),
      cmocka_unit_test(test_a_bay_view_searches_past_faces_at_a_bar_fronts_height),
      cmocka_unit_test(test_a_comb_of_weak_maxima_leaves_room_for_a_stronger_face),
      cmocka_unit_test(test_the_plane_takes_no_mount_slot),
      cmocka_unit_test(test_a_face_merged_past_the_search_range_is_a_surface),
      cmocka_unit_test(test_a_bay_view_ranks_a_bar_front_over_a_ramp_of_faces),
      cmocka_unit_test(test_no_bar_anywhere_leaves_the_plane),
      cmocka_unit_test(test_a_small_surface_is_no_surface),
      cmocka_unit_test(test_a_face_too_small_for_a_peak_is_found_under_its_bar),
      cmocka_unit_test(test_a_front_peak_too_far_behind_the_plane_is_no_mount),
      cmocka_unit_test(test_a_face_at_a_front_height_is_no_front_peak),
      cmocka_unit_test(test_huge_and_not_finite_distances_are_ignored),
      cmocka_unit_test(test_the_mount_under_a_bar),
      cmocka_unit_test(test_shifted_pass_equals_a_full_pass),
      cmocka_unit_test(test_search_below_the_plane_leaves_the_plane_out_of_the_list),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
