// The detector on the simulator's ISS rack walls: a handrail on
// a seat track 1.3 cm proud of the rack face that fills the view, found,
// seated on the track and, seen end to end, named as the ISS type it is;
// rack walls and corners without a handrail give nothing. The flat-wall
// detector found none of these handrails (its front-height test measured
// the bar 7.4 cm off the face, not 6.1 cm).
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "allocation_counter.hpp"
#include "cmocka_cpp.hpp"
#include "common/frame_convert.hpp"
#include "estimator/handrail_detector.hpp"
#include "estimator/handrail_types.hpp"
#include "rack_test_scenes.hpp"
#include "sim_hal/ground_truth.hpp"
#include "sim_hal/scenario.hpp"
#include "sim_hal/tof_raw_renderer.hpp"
#include "sim_hal/tof_sensor.hpp"
#include "tof/processor.hpp"

namespace {

using racktest::render_scene;
using racktest::Rendered;

std::string scenario_path(const char* name) {
  const char* root = std::getenv("HRP_SOURCE_DIR");
  return std::string(root ? root : ".") + "/sim_hal/scenarios/" + name;
}

// A scenario written in the test, its relative paths (meshes) taken from
// the scenario folder as if it were the file `name` there.
sim_hal::Scenario parse_inline(const char* json, const char* name) {
  sim_hal::Scenario sc;
  std::string error;
  if (!sim_hal::parse_scenario(json, scenario_path(name), &sc, &error)) {
    print_error("%s\n", error.c_str());
    fail();
  }
  return sc;
}

sim_hal::Scenario load(const char* name) {
  sim_hal::Scenario sc;
  std::string error;
  if (!sim_hal::load_scenario(scenario_path(name), &sc, &error)) {
    print_error("%s\n", error.c_str());
    fail();
  }
  return sc;
}

void render(const sim_hal::Scenario& sc, std::size_t f, Rendered* r) {
  const sim_hal::CameraIntrinsics cam = sim_hal::pico_flexx_intrinsics();
  sim_hal::DepthRenderer renderer(cam, sc.sensor);
  renderer.render(sc.scene, sc.T_world_cam[f], sc.seed, f, &r->points);
  r->truth = sim_hal::compute_truth(sc.scene, cam, sc.T_world_cam[f], f);
  const hal::DepthFrame frame{f, static_cast<std::int64_t>(f) * 200000, cam.width, cam.height,
                              r->points.data()};
  r->cloud = tools::to_estimator_cloud(frame, &r->buffer);
}

// The same frame on the raw path: the raw renderer's MODE_9 phase frames
// (2 ms exposure at most) through the robot's ToF processing, on the
// unit's calibration. Its noise is about a third of the depth renderer's.
class RawPath {
 public:
  explicit RawPath(const sim_hal::Scenario& sc)
      : cam_(sim_hal::pico_flexx_intrinsics()),
        calibration_(sim_hal::simulated_calibration(cam_, 7)),
        renderer_(cam_, sc.sensor, {}, calibration_),
        processor_(calibration_, tof::ProcessingConfig{}) {
    assert_int_equal(static_cast<int>(processor_.init_status()), 0);
  }
  void render(const sim_hal::Scenario& sc, std::size_t f, Rendered* r) {
    renderer_.render(sc.scene, sc.T_world_cam[f], tof::Mode::kMode9, 2000, sc.seed, f, &raw_);
    hal::DepthFrame frame;
    assert_int_equal(static_cast<int>(processor_.process(raw_, &frame)), 0);
    r->truth = sim_hal::compute_truth(sc.scene, cam_, sc.T_world_cam[f], f);
    r->cloud = tools::to_estimator_cloud(frame, &r->buffer);
  }

 private:
  sim_hal::CameraIntrinsics cam_;
  tof::Calibration calibration_;
  sim_hal::RawRenderer renderer_;
  tof::Processor processor_;
  tof::RawFrame raw_;
};

// Distance from a point to the true centre line, and the angle between axes.
double off_line_m(const estimator::HandrailDetection& d, const sim_hal::HandrailTruth& t) {
  const Eigen::Vector3d p = d.p_cam_center.cast<double>() - t.center_cam;
  return (p - p.dot(t.axis_cam) * t.axis_cam).norm();
}
double axis_error_deg(const estimator::HandrailDetection& d, const sim_hal::HandrailTruth& t) {
  return std::acos(std::fmin(1.0, std::fabs(d.axis().cast<double>().dot(t.axis_cam)))) * 180.0 /
         M_PI;
}

void test_handrail_on_a_seat_track_is_found_and_seated(void**) {
  const sim_hal::Scenario sc = load("rack-control-track-only.json");
  estimator::DetectorConfig cfg;
  cfg.gripper_angle_rad = static_cast<float>(sc.gripper_angle_deg * M_PI / 180.0);
  estimator::HandrailDetector detector(cfg);
  Rendered r;
  int found = 0, named = 0, both_ends = 0, frames = 0;
  for (std::size_t f = 0; f < sc.T_world_cam.size(); f += 10) {
    render(sc, f, &r);
    assert_false(r.truth.handrails.empty());
    const sim_hal::HandrailTruth& t = r.truth.handrails[0];
    const estimator::HandrailDetection d = detector.detect(r.cloud);
    ++frames;
    if (d.status != estimator::DetectStatus::kFound) continue;
    ++found;
    assert_true(off_line_m(d, t) < 0.01);
    assert_true(axis_error_deg(d, t) < 2.0);
    // Seated on the track, not on the face that fills the view.
    assert_near(d.mount_offset_m, 0.013, 0.004);
    if (d.state == estimator::HandrailState::kBothEnds) {
      ++both_ends;
      if (d.handrail_type_name != nullptr) {
        assert_string_equal(d.handrail_type_name, "21.5 in");
        assert_near(d.length_m, 0.531, 1e-6);
        ++named;
      }
    }
  }
  print_message("found %d of %d frames; %d of %d end-to-end views named\n", found, frames, named,
                both_ends);
  assert_true(found >= frames - 1);
  assert_true(both_ends > 0);
  assert_int_equal(named, both_ends);
}

// A cable crossing the view on the rack face passes every test there, with
// many inliers; the rail on its seat track, along the gripper's angle (90
// deg: horizontal in the image), must still be the one found, as Algorithm 1
// selects by the gripper's angle.
void test_cable_across_the_gripper_does_not_hide_the_rail(void**) {
  const sim_hal::Scenario sc = load("rack-clutter-horizontal-21-5.json");
  estimator::DetectorConfig cfg;
  cfg.gripper_angle_rad = static_cast<float>(sc.gripper_angle_deg * M_PI / 180.0);
  assert_near(cfg.gripper_angle_rad, M_PI / 2, 1e-6);
  estimator::HandrailDetector detector(cfg);
  Rendered r;
  for (std::size_t f = 1; f <= 18; f += 3) {
    render(sc, f, &r);
    assert_false(r.truth.handrails.empty());
    const estimator::HandrailDetection d = detector.detect(r.cloud);
    assert_int_equal(static_cast<int>(d.status), static_cast<int>(estimator::DetectStatus::kFound));
    assert_true(off_line_m(d, r.truth.handrails[0]) < 0.02);
    assert_true(axis_error_deg(d, r.truth.handrails[0]) < 5.0);
  }
}

void test_rack_walls_without_a_handrail_give_nothing(void**) {
  const sim_hal::Scenario sc = load("rack-no-handrail-corner.json");
  estimator::HandrailDetector detector{estimator::DetectorConfig{}};
  Rendered r;
  for (std::size_t f = 0; f < sc.T_world_cam.size(); f += 4) {
    render(sc, f, &r);
    const estimator::HandrailDetection d = detector.detect(r.cloud);
    assert_int_not_equal(static_cast<int>(d.status),
                         static_cast<int>(estimator::DetectStatus::kFound));
    assert_true(d.counts.mounts_tried >= 1);
  }
}

// The 8.5 in rail approached with its rack's frame seen obliquely: the
// frame, 1 to 2 cm proud of the face that fills the view, makes no surface
// peak of its own in these frames, and no surface mount seats the bar
// (it was once NO_CANDIDATES). The bar's front makes a peak where
// the track over that frame puts it, and the mount read off it holds the
// rail; with front_peak_mounts 0 the frames are missed as before.
void test_a_mount_read_off_the_bars_front_holds_the_rail(void**) {
  const sim_hal::Scenario sc = load("rack-approach-vertical-8-5.json");
  estimator::DetectorConfig cfg;
  cfg.gripper_angle_rad = static_cast<float>(sc.gripper_angle_deg * M_PI / 180.0);
  estimator::DetectorConfig surfaces_only = cfg;
  surfaces_only.front_peak_mounts = 0;
  estimator::HandrailDetector detector(cfg), without(surfaces_only);
  Rendered r;
  int found = 0, found_without = 0, frames = 0;
  for (std::size_t f = 40; f <= 48; ++f) {
    render(sc, f, &r);
    assert_false(r.truth.handrails.empty());
    const sim_hal::HandrailTruth& t = r.truth.handrails[0];
    ++frames;
    const estimator::HandrailDetection d = detector.detect(r.cloud);
    if (d.status == estimator::DetectStatus::kFound && off_line_m(d, t) < 0.05) ++found;
    const estimator::HandrailDetection w = without.detect(r.cloud);
    if (w.status == estimator::DetectStatus::kFound && off_line_m(w, t) < 0.05) ++found_without;
  }
  std::printf("8.5 in rail over an oblique frame: found %d of %d (%d with surface mounts alone)\n",
              found, frames, found_without);
  assert_true(found >= frames - 1);
  assert_true(found_without <= 2);
}

// The station's shortest bar (8.5 in, 0.20 m) running out of the image
// with 35 to 50 % of its centre line in view (the simulator's truth): a
// handrail in reach by the evaluation's definition. The 8 cm clutter floor
// alone refused a fifth of these views; 35 % of the shortest configured
// bar (7 cm), where the image's edge cuts the bar, accepts them.
void test_the_shortest_bar_partly_in_view_is_found(void**) {
  constexpr double kBar_m = 0.20;
  const sim_hal::CameraIntrinsics cam = sim_hal::pico_flexx_intrinsics();
  estimator::DetectorConfig cfg;
  cfg.gripper_angle_rad = static_cast<float>(M_PI / 2);
  estimator::DetectorConfig floor_only = cfg;
  floor_only.min_visible_fraction = 1.0f;  // min(8 cm, 0.20 m): the floor alone
  estimator::HandrailDetector detector(cfg), with_floor_only(floor_only);
  Rendered r;
  int found = 0, found_floor_only = 0, frames = 0;
  // At three ranges, slide the bar out past the image's edge along +y,
  // 3 mm at a time, and keep the views with 35 to 50 % in view.
  for (double range_m : {0.45, 0.55, 0.65}) {
    const Eigen::Isometry3d T =
        sim_hal::camera_pose(Eigen::Vector3d(range_m, 0.0, 0.0), -Eigen::Vector3d::UnitX(),
                             Eigen::Vector3d::UnitZ(), Eigen::Vector3d::Zero());
    for (int k = 0; k < 100; ++k) {
      sim_hal::Scene scene;
      scene.add_wall(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitZ(),
                     4.0, 3.0);
      sim_hal::Handrail rail;
      rail.kind = sim_hal::HandrailKind::kIss;
      rail.axis = Eigen::Vector3d::UnitY();
      rail.bar_length_m = kBar_m;
      rail.foot_center = Eigen::Vector3d(0.0, 0.15 + 0.003 * k, 0.0);
      scene.add_handrail(rail);
      const sim_hal::FrameTruth truth = sim_hal::compute_truth(scene, cam, T, 0);
      if (truth.handrails.empty()) continue;
      const double visible = truth.handrails[0].visible_fraction;
      if (visible < 0.35 || visible > 0.50) continue;
      render_scene(scene, T, static_cast<std::size_t>(frames), &r);
      ++frames;
      found += detector.detect(r.cloud).status == estimator::DetectStatus::kFound ? 1 : 0;
      found_floor_only +=
          with_floor_only.detect(r.cloud).status == estimator::DetectStatus::kFound ? 1 : 0;
    }
  }
  std::printf(
      "0.20 m bar 35 to 50 %% in view: found %d of %d (%d with the 8 cm floor alone); "
      "shortest partial bar %.3f m\n",
      found, frames, found_floor_only, static_cast<double>(estimator::shortest_partial_bar_m(cfg)));
  assert_true(frames >= 20);
  assert_true(found * 10 >= frames * 9);
  assert_true(found >= found_floor_only + 3);
}

// The shortest bar seen as in Table 2's steepest pose (camera 60 cm out,
// 15 cm up and across, rolled, pitched and yawed 30 deg each), slid along
// the wall in 5 mm steps toward and under the image's top edge. The wall's
// tilt widens the cross test's upward probe (eq. 2) to 4 or 5 cm, more rows
// than lie between the bar and the top edge; searched there whole, the
// probe found no wall and refused the bar's middle. Between the bar and the
// edge the wall still shows: the probe searches at the plain distance
// instead. And where an end lies a pixel or two inside the border, the end
// walk's band (+-2 px across) reaches past the edge; a band pixel past it
// says nothing of the end, so the wall in the band's pixels in view shows
// the end seen. Views with both true ends at least a pixel inside the image
// are counted: the bar found, and found with both ends and its length.
void test_a_bar_along_the_image_top_edge_is_found_end_to_end(void**) {
  constexpr double kBar_m = 0.20;
  const sim_hal::CameraIntrinsics cam = sim_hal::pico_flexx_intrinsics();
  const Eigen::Isometry3d T =
      sim_hal::camera_pose(Eigen::Vector3d(0.60, 0.15, 0.15), -Eigen::Vector3d::UnitX(),
                           Eigen::Vector3d::UnitZ(), Eigen::Vector3d(30.0, 30.0, 30.0));
  estimator::DetectorConfig cfg;
  cfg.gripper_angle_rad = static_cast<float>(M_PI / 2);
  estimator::HandrailDetector detector(cfg);
  Rendered r;
  int views = 0, found = 0, both_ends = 0;
  for (int k = 0; k < 60; ++k) {
    sim_hal::Scene scene = racktest::flat_wall_scene();
    sim_hal::Handrail rail;
    rail.kind = sim_hal::HandrailKind::kIss;
    rail.axis = Eigen::Vector3d::UnitY();
    rail.bar_length_m = kBar_m;
    rail.foot_center = Eigen::Vector3d(0.0, 0.0, -0.06 + 0.002 * k);
    scene.add_handrail(rail);
    const sim_hal::FrameTruth truth = sim_hal::compute_truth(scene, cam, T, 0);
    if (truth.handrails.empty()) continue;
    const sim_hal::HandrailTruth& t = truth.handrails[0];
    bool inside = true;
    double top_row = 1e9;
    for (const Eigen::Vector3d& end : t.ends_cam) {
      Eigen::Vector2d px = Eigen::Vector2d::Constant(-1.0);
      if (!sim_hal::project(cam, end, &px)) inside = false;
      inside = inside && px.x() >= 1.0 && px.y() >= 1.0 && px.x() <= cam.width - 2.0 &&
               px.y() <= cam.height - 2.0;
      top_row = std::fmin(top_row, px.y());
    }
    if (!inside || top_row > 12.0) continue;   // only views with an end near the top edge
    for (int noise = 0; noise < 4; ++noise) {  // four noise draws and RANSAC streams each
      render_scene(scene, T, static_cast<std::size_t>(4 * k + noise), &r);
      ++views;
      const estimator::HandrailDetection d = detector.detect(r.cloud);
      if (d.status != estimator::DetectStatus::kFound || off_line_m(d, t) > 0.02 ||
          axis_error_deg(d, t) > 5.0) {
        continue;
      }
      ++found;
      if (d.state == estimator::HandrailState::kBothEnds &&
          std::fabs(d.visible_length_m - kBar_m) < 0.02) {
        ++both_ends;
      }
    }
  }
  print_message(
      "0.20 m bar with an end 1 to 12 rows from the top edge: found %d of %d views, "
      "%d with both ends and its length\n",
      found, views, both_ends);
  // Before: 61 of 64 found, 57 with both ends; the probe alone: 64, but 37
  // (the walk's band met the edge); the end rule alone: 61, 59.
  assert_true(views >= 48);
  assert_true(found >= views - 1);
  assert_true(both_ends * 10 >= views * 9);
}

// A seat track on a narrow rack face (12 cm tall, 1.85 cm deep) between a
// face 2 cm proud above it, which fills most of the view, and a deeper one
// below. The bar's front stands 5.3 cm off the proud face: in the gap
// window of that face's search, but short of a handrail's height above it.
// No surface peak of the frame is the narrow face, so no other search
// passes the bar's front. The plane's search seats it on the face measured
// beside it, with a seat track (the same layout as the development set's
// rack approach, frame 10, where the detector before said WRONG_HEIGHT).
const char* const kRailBesideTheDominantFace = R"({
    "name": "rail-beside-the-dominant-face", "seed": 31, "frame_rate_hz": 5, "gripper_angle_deg": 90,
    "scene": {
      "rack_walls": [{"center": [0, 0, 0], "normal": [1, 0, 0], "up": [0, 0, 1],
        "faces": [{"u": [-0.64, 0.63], "v": [-0.087, 0.03], "depth": -0.0185, "reflectivity": 0.6},
                  {"u": [-1.4, 1.4], "v": [-1.4, -0.087], "depth": -0.029, "reflectivity": 0.63},
                  {"u": [-1.4, 1.4], "v": [0.03, 1.4], "depth": 0.0203, "reflectivity": 0.52}],
        "seat_tracks": [{"from": [-0.63, 0.0], "to": [0.62, 0.0], "depth": -0.0185}]}],
      "handrails": [{"kind": "iss_mesh", "foot": [-0.0055, 0.0, 0.0], "normal": [1, 0, 0],
                     "axis": [0, 1, 0], "mesh": "../assets/handrails/handrail_30.dae"}]},
    "poses": [{"label": "back-off", "position": [0.65, 0.12, 0.06], "facing": [-1, 0, 0],
               "up": [0, 0, 1], "rpy_deg": [0, 0, 0], "frames": 8,
               "to": {"position": [0.95, 0.1, 0.1], "rpy_deg": [0, 0, 0]}}]})";

// Detects every frame of the scene above, rendered by `render_frame`, and
// checks each find is the rail seated on its track, and that it is found
// in all frames but one at most.
template <typename RenderFrame>
void detect_rail_beside_the_dominant_face(const char* path_name, RenderFrame render_frame) {
  const sim_hal::Scenario sc = parse_inline(kRailBesideTheDominantFace, "rail-beside.json");
  estimator::DetectorConfig cfg;
  cfg.gripper_angle_rad = static_cast<float>(M_PI / 2);
  estimator::HandrailDetector detector(cfg);
  Rendered r;
  int found = 0;
  for (std::size_t f = 0; f < sc.T_world_cam.size(); ++f) {
    render_frame(sc, f, &r);
    assert_false(r.truth.handrails.empty());
    const estimator::HandrailDetection d = detector.detect(r.cloud);
    if (d.status != estimator::DetectStatus::kFound) continue;
    ++found;
    assert_true(off_line_m(d, r.truth.handrails[0]) < 0.01);
    assert_true(axis_error_deg(d, r.truth.handrails[0]) < 2.0);
    // On the track (0.0055 m behind the wall's reference), measured from
    // the proud face (0.0203 m in front of it).
    assert_near(d.mount_offset_m, -0.0055 - 0.0203, 0.004);
  }
  print_message("rail beside the dominant face (%s path): found %d of %zu frames\n", path_name,
                found, sc.T_world_cam.size());
  assert_true(found >= static_cast<int>(sc.T_world_cam.size()) - 1);
}

void test_rail_on_a_face_beside_the_dominant_plane_is_seated_there(void**) {
  detect_rail_beside_the_dominant_face("depth", render);
}

// The same on the raw path, whose pixels are quieter: the bar's front,
// 2.6 cm below a handrail's height above the dominant face, must not be
// refused by the side width test before the plane's search can seat it
// (noise had widened that test's window enough on the depth path alone).
void test_rail_beside_the_dominant_plane_is_found_on_the_raw_path(void**) {
  const sim_hal::Scenario sc = parse_inline(kRailBesideTheDominantFace, "rail-beside.json");
  RawPath raw(sc);
  detect_rail_beside_the_dominant_face(
      "raw", [&](const sim_hal::Scenario& s, std::size_t f, Rendered* r) { raw.render(s, f, r); });
}

// A seat track on a narrow rack face (14 cm wide) between a face 1.8 cm
// proud of it, which fills most of the view and is the dominant plane, and
// a face 4.5 cm proud of it, 3.4 cm beside the track (the layout of the
// third development set's `dev-rack-clutter-vertical-30`, frames 76 to 88 on
// the raw path). The rail's mount, the track's top, lies 5 mm below the
// plane; the cross test's probe toward the tall face lands on it, 3.2 cm
// over that mount: not the wall the plane's tolerance allows, and the rail
// failed the test. The tall face is a surface in view (a peak of the
// frame's heights) below the bar's back, and is wall to the probes.
const char* const kRailBesideATallFace = R"({
    "name": "rail-beside-a-tall-face", "seed": 47, "frame_rate_hz": 5, "gripper_angle_deg": 0,
    "scene": {
      "rack_walls": [{"center": [0, 0, 0], "normal": [1, 0, 0], "up": [0, 0, 1],
        "faces": [{"u": [-0.105, 0.034], "v": [-1.4, 1.4], "depth": -0.0065, "reflectivity": 0.7},
                  {"u": [-1.4, -0.105], "v": [-1.4, 1.4], "depth": 0.0111, "reflectivity": 0.46},
                  {"u": [0.034, 1.4], "v": [-1.4, 1.4], "depth": 0.0384, "reflectivity": 0.47}],
        "seat_tracks": [{"from": [0.0, -1.39], "to": [0.0, 1.39], "depth": -0.0065}]}],
      "handrails": [{"kind": "iss_mesh", "foot": [0.0065, 0.0, 0.0], "normal": [1, 0, 0],
                     "axis": [0, 0, 1], "mesh": "../assets/handrails/handrail_30.dae"}]},
    "poses": [{"label": "pass", "position": [0.55, -0.16, 0.05], "facing": [-1, 0, 0],
               "up": [0, 0, 1], "rpy_deg": [0, 0, 0], "frames": 10,
               "to": {"position": [0.5, -0.12, -0.05], "rpy_deg": [0, 0, 0]}}]})";

// Finds of the rail in the scene above, depth and raw paths, with the
// faces in view taken as the probes' wall or not.
int finds_beside_a_tall_face(bool faces_wall, bool raw_path) {
  const sim_hal::Scenario sc = parse_inline(kRailBesideATallFace, "rail-beside-tall.json");
  estimator::DetectorConfig cfg;
  cfg.cross_faces_wall = faces_wall;
  estimator::HandrailDetector detector(cfg);
  RawPath raw(sc);
  Rendered r;
  int found = 0;
  for (std::size_t f = 0; f < sc.T_world_cam.size(); ++f) {
    if (raw_path) {
      raw.render(sc, f, &r);
    } else {
      render(sc, f, &r);
    }
    assert_false(r.truth.handrails.empty());
    const estimator::HandrailDetection d = detector.detect(r.cloud);
    if (d.status != estimator::DetectStatus::kFound) continue;
    assert_true(off_line_m(d, r.truth.handrails[0]) < 0.01);
    assert_true(axis_error_deg(d, r.truth.handrails[0]) < 2.0);
    ++found;
  }
  print_message("rail beside a tall face (%s path, faces %s): found %d of %zu frames\n",
                raw_path ? "raw" : "depth", faces_wall ? "wall" : "not wall", found,
                sc.T_world_cam.size());
  return found;
}

void test_a_tall_face_in_view_is_wall_to_the_probes(void**) {
  // Measured: depth 10 of 10 (2 with the faces not wall), raw 7 of 10 (0).
  assert_true(finds_beside_a_tall_face(true, false) >= 9);
  assert_true(finds_beside_a_tall_face(false, false) <= 3);
  assert_true(finds_beside_a_tall_face(true, true) >= 6);
  assert_true(finds_beside_a_tall_face(false, true) <= 2);
}

// In Columbus a fin at a rack's edge (about a centimetre wide, 7 cm proud
// of the recessed face beside it) runs past both sides of the view beside a
// groove, and the first mount searched takes it for a handrail with no end
// in view (NE) and a few hundred inliers. The starboard rail, its top end in view,
// stands on a mount searched later. A find with no end in view has not had
// its ends looked at (no leg test), so it must not end the search over
// mounts; the rail, better supported, wins. Before that rule the search
// stopped at the strip in 7 of these 10 frames (found 3).
void test_a_find_with_no_end_in_view_does_not_end_the_mount_search(void**) {
  const sim_hal::Scenario sc = load("columbus-approaches.json");
  estimator::DetectorConfig cfg;
  cfg.gripper_angle_rad = static_cast<float>(sc.gripper_angle_deg * M_PI / 180.0);
  estimator::HandrailDetector detector(cfg);
  Rendered r;
  int found = 0, frames = 0, with_end = 0;
  for (std::size_t f = 12; f < 22; ++f) {
    render(sc, f, &r);
    assert_false(r.truth.handrails.empty());
    const sim_hal::HandrailTruth& t = r.truth.handrails[0];
    const estimator::HandrailDetection d = detector.detect(r.cloud);
    ++frames;
    if (d.status != estimator::DetectStatus::kFound || off_line_m(d, t) > 0.05 ||
        axis_error_deg(d, t) > 15.0) {
      continue;
    }
    ++found;
    with_end += d.state == estimator::HandrailState::kOneEnd ? 1 : 0;
  }
  print_message("the starboard rail found in %d of %d frames, %d with its end seen\n", found,
                frames, with_end);
  assert_true(found >= 7);
  assert_true(with_end >= found - 1);
}

// A line that crosses a bar at an angle (Algorithm 2 ranks lines by the
// candidate pixels near them, and a diagonal through a bar collects the
// patch under it) is refused (CROSSES_BAR): measured as it stood, the end
// walk found the bar's sides as two ends a few centimetres apart, and the
// 0.55 m round rail of the paper's Table 2 scene passed as a 0.20 m (8.5 in)
// handrail with both ends seen. A HIL run met it from its start
// pose, 1.2 m out, with the gripper's angle across the bar (fsw_app's
// configuration): the short find won on the gripper's angle, and its first
// updates kicked the filter. Seen from there over 30 frames (each its own
// RANSAC stream) the rail is found every time at its whole length; with
// the test off (the front's turn allowed up to 90 deg) the short find
// comes back.
void test_a_line_across_the_bar_is_refused(void**) {
  const sim_hal::Scenario sc = load("table2-round.json");
  const Eigen::Isometry3d T =
      sim_hal::camera_pose(Eigen::Vector3d(1.27, -0.11, 0.02), -Eigen::Vector3d::UnitX(),
                           Eigen::Vector3d::UnitZ(), Eigen::Vector3d(0.0, 2.0, 7.5));
  estimator::DetectorConfig cfg;
  cfg.handrail = estimator::paper_round_handrail(0.55f);
  cfg.gripper_angle_rad = 0.0f;  // along the image's y: across this bar
  estimator::DetectorConfig test_off = cfg;
  test_off.line_max_turn_deg = 90.0f;
  estimator::HandrailDetector detector(cfg), old_rule(test_off);
  const sim_hal::CameraIntrinsics cam = sim_hal::pico_flexx_intrinsics();
  Rendered r;
  int whole = 0, short_finds = 0, short_finds_old = 0;
  constexpr int kFrames = 30;
  for (std::size_t f = 0; f < kFrames; ++f) {
    render_scene(sc.scene, T, f, &r);
    r.truth = sim_hal::compute_truth(sc.scene, cam, T, f);
    assert_false(r.truth.handrails.empty());
    const estimator::HandrailDetection d = detector.detect(r.cloud);
    const bool found = d.status == estimator::DetectStatus::kFound;
    if (found && d.visible_length_m < 0.45f) ++short_finds;
    if (found && d.state == estimator::HandrailState::kBothEnds &&
        std::fabs(d.visible_length_m - 0.55f) < 0.03f &&
        off_line_m(d, r.truth.handrails[0]) < 0.01 &&
        axis_error_deg(d, r.truth.handrails[0]) < 1.0) {
      ++whole;
    }
    const estimator::HandrailDetection o = old_rule.detect(r.cloud);
    if (o.status == estimator::DetectStatus::kFound && o.visible_length_m < 0.45f) {
      ++short_finds_old;
    }
  }
  std::printf(
      "round rail across the gripper, %d frames: whole length %d, short %d (test off: %d)\n",
      kFrames, whole, short_finds, short_finds_old);
  assert_int_equal(short_finds, 0);
  assert_int_equal(whole, kFrames);
  assert_true(short_finds_old >= 1);
}

// The search over mounts (every surface in view, each searched in turn)
// allocates nothing: the frames are rendered first, then detected with the
// counter armed.
void test_searching_mounts_allocates_nothing(void**) {
  const sim_hal::Scenario sc = load("rack-table2-iss-mesh-21-5.json");
  constexpr int kFrames = 12;
  std::vector<Rendered> frames(kFrames);
  for (int k = 0; k < kFrames; ++k) render(sc, static_cast<std::size_t>(k) * 33, &frames[k]);
  estimator::HandrailDetector detector{estimator::DetectorConfig{}};
  std::uint32_t searched_beyond_plane = 0;
  alloc_counter::arm();
  for (int round = 0; round < 3; ++round) {
    for (const Rendered& r : frames) {
      const estimator::HandrailDetection d = detector.detect(r.cloud);
      searched_beyond_plane += d.counts.mounts_tried > 1 ? 1u : 0u;
    }
  }
  const long allocations = alloc_counter::disarm();
  assert_int_equal(allocations, 0);
  // The frames did exercise the search beyond the dominant plane.
  assert_true(searched_beyond_plane > 0);
}

}  // namespace

int main() {
  const CMUnitTest tests[] = {
      cmocka_unit_test(test_handrail_on_a_seat_track_is_found_and_seated),
      cmocka_unit_test(test_cable_across_the_gripper_does_not_hide_the_rail),
      cmocka_unit_test(test_rack_walls_without_a_handrail_give_nothing),
      cmocka_unit_test(test_a_mount_read_off_the_bars_front_holds_the_rail),
      cmocka_unit_test(test_the_shortest_bar_partly_in_view_is_found),
      cmocka_unit_test(test_a_bar_along_the_image_top_edge_is_found_end_to_end),
      cmocka_unit_test(test_rail_on_a_face_beside_the_dominant_plane_is_seated_there),
      cmocka_unit_test(test_rail_beside_the_dominant_plane_is_found_on_the_raw_path),
      cmocka_unit_test(test_a_tall_face_in_view_is_wall_to_the_probes),
      cmocka_unit_test(test_a_find_with_no_end_in_view_does_not_end_the_mount_search),
      cmocka_unit_test(test_a_line_across_the_bar_is_refused),
      cmocka_unit_test(test_searching_mounts_allocates_nothing),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
