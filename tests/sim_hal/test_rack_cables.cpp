// Handrail-like cables against the handrail on the simulator's walls:
// each test of what a handrail is beyond its height (ramps at
// the ends, whether the view's edge cuts them or not, and the side face seen
// from across the bar) refuses the cable, only that test refuses it, and the
// ISS handrail on its seat track seen the same way is still found.
#include <cmath>
#include <cstdio>

#include "cmocka_cpp.hpp"
#include "estimator/handrail_detector.hpp"
#include "rack_test_scenes.hpp"

namespace {

using racktest::flat_wall_scene;
using racktest::rail_on_seat_track_scene;
using racktest::render_scene;
using racktest::Rendered;

// The 0.55 m ISS handrail along the world's y (horizontal in these views),
// its mounting footprint's centre at foot.
void add_rail_along_y(sim_hal::Scene* scene, const Eigen::Vector3d& foot) {
  sim_hal::Handrail rail;
  rail.kind = sim_hal::HandrailKind::kIss;
  rail.axis = Eigen::Vector3d::UnitY();
  rail.foot_center = foot;
  scene->add_handrail(rail);
}

// The detector's defaults, for bars horizontal in the image.
estimator::DetectorConfig horizontal_bars_config() {
  estimator::DetectorConfig cfg;
  cfg.gripper_angle_rad = static_cast<float>(M_PI / 2);
  return cfg;
}

// A handrail-like cable's frames: how often the detector takes it, how
// often its best line is refused for `verdict`, and how often a detector
// without that test takes it.
struct CableCounts {
  int found = 0, refused = 0, found_lenient = 0;
  void add(const estimator::OrganizedCloud& cloud, estimator::HandrailDetector& detector,
           estimator::HandrailDetector& lenient, estimator::LineVerdict verdict) {
    const estimator::HandrailDetection d = detector.detect(cloud);
    found += d.status == estimator::DetectStatus::kFound ? 1 : 0;
    refused += d.counts.first_rejection == verdict ? 1 : 0;
    found_lenient += lenient.detect(cloud).status == estimator::DetectStatus::kFound ? 1 : 0;
  }
};

// Renders the scene from T_world_cam and says whether the detector finds a
// handrail there with both ends seen.
bool found_with_both_ends(const sim_hal::Scene& scene, const Eigen::Isometry3d& T_world_cam,
                          std::size_t f, estimator::HandrailDetector& detector, Rendered* r) {
  render_scene(scene, T_world_cam, f, r);
  const estimator::HandrailDetection h = detector.detect(r->cloud);
  return h.status == estimator::DetectStatus::kFound &&
         h.state == estimator::HandrailState::kBothEnds;
}

// The cable scene and the rail scene seen from the same poses: the cable
// counted for one test's verdict, the rail found or not (with both ends
// seen, when asked); then that test alone refuses the cable (in at least
// `min_refused` views, every view but one unless given) and the rail is
// found in every view.
struct CableAgainstRail {
  bool rail_with_both_ends = false;
  CableCounts cable;
  int rail_found = 0, frames = 0;
  void view(const sim_hal::Scene& cable_scene, const sim_hal::Scene& rail_scene,
            const Eigen::Isometry3d& T, std::size_t f, estimator::HandrailDetector& detector,
            estimator::HandrailDetector& lenient, estimator::LineVerdict verdict, Rendered* r) {
    ++frames;
    render_scene(cable_scene, T, f, r);
    cable.add(r->cloud, detector, lenient, verdict);
    if (rail_with_both_ends) {
      rail_found += found_with_both_ends(rail_scene, T, f, detector, r) ? 1 : 0;
      return;
    }
    render_scene(rail_scene, T, f, r);
    rail_found += detector.detect(r->cloud).status == estimator::DetectStatus::kFound ? 1 : 0;
  }
  void report_and_check(const char* what, const char* refused_as, const char* test,
                        int min_refused = -1) const {
    std::printf(
        "%s: found %d of %d (%d refused %s; %d found without the %s); the handrail there: "
        "%d of %d%s\n",
        what, cable.found, frames, cable.refused, refused_as, cable.found_lenient, test, rail_found,
        frames, rail_with_both_ends ? ", both ends" : "");
    const int least = min_refused >= 0 ? min_refused : frames - 1;
    assert_int_equal(cable.found, 0);
    assert_true(cable.refused >= least);
    assert_true(cable.found_lenient >= least);
    assert_int_equal(rail_found, frames);
  }
};

// A handrail-like cable (2 cm thick, straight over 0.4 m at a handrail's
// height, 7 cm off a flat wall) comes down to the wall in 15 cm ramps; a
// handrail's front holds to its legs. With both ends in view the cable is
// refused for its ramps (RAMP_END), and only that refuses it: with the
// ramp allowance opened up it is taken for a handrail. The handrail in the
// same place is found, both ends seen.
void test_handrail_like_cable_is_refused_for_its_ramps(void**) {
  sim_hal::Scene cable_scene = flat_wall_scene(), rail_scene = flat_wall_scene();
  // Centre 7 cm off the wall, front 8 cm: the bar's front is 7.85 cm.
  cable_scene.add_cable({Eigen::Vector3d(0.01, -0.35, 0.0), Eigen::Vector3d(0.07, -0.2, 0.0),
                         Eigen::Vector3d(0.07, 0.2, 0.0), Eigen::Vector3d(0.01, 0.35, 0.0)},
                        0.02);
  sim_hal::Handrail rail;
  rail.kind = sim_hal::HandrailKind::kIss;
  rail.axis = Eigen::Vector3d::UnitY();
  rail_scene.add_handrail(rail);
  const estimator::DetectorConfig cfg = horizontal_bars_config();
  estimator::DetectorConfig no_ramp_test = cfg;
  no_ramp_test.end_drop_max_m = 1.0f;
  estimator::HandrailDetector detector(cfg), lenient(no_ramp_test);
  Rendered r;
  CableAgainstRail seen;
  seen.rail_with_both_ends = true;
  for (std::size_t f = 0; f < 5; ++f) {
    const Eigen::Isometry3d T = sim_hal::camera_pose(
        Eigen::Vector3d(0.65 + 0.03 * static_cast<double>(f), 0.02 * static_cast<double>(f), 0.0),
        -Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitZ(), Eigen::Vector3d::Zero());
    seen.view(cable_scene, rail_scene, T, f, detector, lenient, estimator::LineVerdict::kRampEnd,
              &r);
  }
  seen.report_and_check("handrail-like cable", "for a ramp end", "ramp test", 3);
}

// The same cable with the clutter's short ramps (8 cm, as the station's
// facts give a handrail-like cable): most of each ramp lies below the gap
// window's floor, so only the raised structure counted down to the wall
// shows it for a ramp. A handrail standing on a seat track that runs on
// 15 cm past both its ends is still found with both ends (a guard: in
// these views the track's noise stays under 2 cm even counted from the
// wall; the development frames where it did not, and why the count now
// starts at the bar's mount, are in sim_hal/README.md).
void test_short_ramps_are_refused_and_a_seat_track_is_no_ramp(void**) {
  sim_hal::Scene cable_scene = flat_wall_scene(), rail_scene = rail_on_seat_track_scene();
  cable_scene.add_cable({Eigen::Vector3d(0.01, -0.28, 0.0), Eigen::Vector3d(0.07, -0.2, 0.0),
                         Eigen::Vector3d(0.07, 0.2, 0.0), Eigen::Vector3d(0.01, 0.28, 0.0)},
                        0.02);
  const estimator::DetectorConfig cfg = horizontal_bars_config();
  estimator::HandrailDetector detector(cfg);
  Rendered r;
  int cable_found = 0, cable_found_straight_on = 0, ramp_refusals = 0, rail_found = 0, frames = 0;
  for (std::size_t f = 0; f < 10; ++f) {
    // Straight on, then from about 30 deg off the normal both along and
    // across the bar, where the track beside and past the bar shows most.
    const double k = static_cast<double>(f % 5);
    const Eigen::Vector3d position = f < 5 ? Eigen::Vector3d(0.65 + 0.03 * k, 0.02 * k, 0.0)
                                           : Eigen::Vector3d(0.5 + 0.03 * k, 0.3, 0.25);
    const Eigen::Vector3d facing = f < 5 ? Eigen::Vector3d(-Eigen::Vector3d::UnitX())
                                         : Eigen::Vector3d(-position.normalized());
    const Eigen::Isometry3d T =
        sim_hal::camera_pose(position, facing, Eigen::Vector3d::UnitZ(), Eigen::Vector3d::Zero());
    ++frames;
    render_scene(cable_scene, T, f, &r);
    const estimator::HandrailDetection d = detector.detect(r.cloud);
    cable_found += d.status == estimator::DetectStatus::kFound ? 1 : 0;
    cable_found_straight_on += d.status == estimator::DetectStatus::kFound && f < 5 ? 1 : 0;
    ramp_refusals += d.counts.first_rejection == estimator::LineVerdict::kRampEnd ? 1 : 0;
    rail_found += found_with_both_ends(rail_scene, T, f, detector, &r) ? 1 : 0;
  }
  std::printf(
      "cable with 8 cm ramps: found %d of %d (%d straight on; %d refused for a ramp end); the "
      "handrail on a seat track: %d of %d, both ends\n",
      cable_found, frames, cable_found_straight_on, ramp_refusals, rail_found, frames);
  // Seen obliquely one ramp can hide behind the cable itself; straight on
  // both show, and the measure before this one passed all five.
  assert_int_equal(cable_found_straight_on, 0);
  assert_true(cable_found <= 1);
  assert_true(ramp_refusals >= 8);
  assert_int_equal(rail_found, frames);
}

// The image's edge cuts a handrail-like cable part way down its ramp (2 cm
// thick, centre 7 cm off a flat wall, coming down to the wall over 15 cm),
// and its other end lies far out of view: no end is seen, but the part of
// the ramp in view runs on below the front's height for 6.5 to 8 cm, more
// than a leg's allowance (5 cm at this range). The cable is refused for its ramp (RAMP_END), and
// only that refuses it (with the allowance opened up it is taken for a
// handrail with no end in view). The 0.55 m rail on its seat track, its end
// at the same cuts of the view, is found in every frame.
void test_a_ramp_the_image_edge_cuts_is_still_a_ramp(void**) {
  sim_hal::Scene cable_scene = flat_wall_scene(), rail_scene = rail_on_seat_track_scene();
  cable_scene.add_cable({Eigen::Vector3d(0.07, -1.5, 0.0), Eigen::Vector3d(0.07, 0.2, 0.0),
                         Eigen::Vector3d(0.01, 0.35, 0.0)},
                        0.02);
  const estimator::DetectorConfig cfg = horizontal_bars_config();
  estimator::DetectorConfig no_ramp_test = cfg;
  no_ramp_test.end_drop_max_m = 1.0f;
  estimator::HandrailDetector detector(cfg), lenient(no_ramp_test);
  Rendered r;
  CableAgainstRail seen;
  const double tan_half_fov = std::tan(31.0 * M_PI / 180.0);
  for (std::size_t f = 0; f < 5; ++f) {
    // Face-on, 0.60 to 0.68 m out; the view's edge on the wall at y = 0.335
    // to 0.345 m, short of the ramp's foot (0.35 m), and on the cable's
    // front about 5 cm nearer the ramp's top (0.2 m). The front's height,
    // with its noise allowance, gives out about 3 cm down the ramp.
    const double k = static_cast<double>(f);
    const double out_m = 0.6 + 0.02 * k, wall_cut_y_m = 0.335 + 0.0025 * k;
    const Eigen::Vector3d position(out_m, wall_cut_y_m - out_m * tan_half_fov, 0.0);
    const Eigen::Isometry3d T = sim_hal::camera_pose(
        position, -Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitZ(), Eigen::Vector3d::Zero());
    seen.view(cable_scene, rail_scene, T, f, detector, lenient, estimator::LineVerdict::kRampEnd,
              &r);
  }
  seen.report_and_check("cable ramp cut by the image's edge", "for a ramp end", "ramp test");
}

// A handrail-like cable (2 cm thick, centre 7 cm off a flat wall, front 8
// cm, as high as the ISS bar's 7.85 cm front) running out of the view both
// ways: no end to test, and face-on nothing tells it from the bar. Seen 25
// to 30 deg across from the side, the bar shows its side face down to its
// back, the cable only its upper half: the cable is refused for its shallow
// profile (SHALLOW_PROFILE), and only that refuses it (with the test off it
// is taken for a handrail). An ISS handrail on a seat track seen the same
// way is found.
void test_a_cable_seen_from_its_side_is_too_shallow_for_a_bar(void**) {
  sim_hal::Scene cable_scene = flat_wall_scene(), rail_scene = rail_on_seat_track_scene();
  cable_scene.add_cable({Eigen::Vector3d(0.07, -1.5, 0.0), Eigen::Vector3d(0.07, 1.5, 0.0)}, 0.02);
  const estimator::DetectorConfig cfg = horizontal_bars_config();
  estimator::DetectorConfig no_profile_test = cfg;
  no_profile_test.profile_min_spread_m = 0.0f;
  estimator::HandrailDetector detector(cfg), lenient(no_profile_test);
  Rendered r;
  CableAgainstRail seen;
  for (std::size_t f = 0; f < 6; ++f) {
    // Above or below the bar (across it), 0.55 to 0.65 m out: 25 to 30 deg.
    const double k = static_cast<double>(f % 3), side = f < 3 ? 1.0 : -1.0;
    const Eigen::Vector3d position(0.55 + 0.05 * k, 0.03 * k, side * (0.27 + 0.03 * k));
    const Eigen::Isometry3d T = sim_hal::camera_pose(
        position, -position.normalized(), Eigen::Vector3d::UnitZ(), Eigen::Vector3d::Zero());
    seen.view(cable_scene, rail_scene, T, f, detector, lenient,
              estimator::LineVerdict::kShallowProfile, &r);
  }
  seen.report_and_check("handrail-like cable seen from its side", "as too shallow", "profile test");
}

// A handrail-like cable (2 cm thick) running out of the view both ways over
// a rack face 2.5 cm proud of the wall, its front a bar's height (7.9 cm)
// above that face, seen face-on: neither ends, ramps nor a side face show.
// It is seated on the face, off the dominant plane (the wall), and that face
// runs on beside it at the mount's own level, where beside a handrail's
// seat track lies the face a track step lower: refused (NOT_ON_TRACK, in
// the searches of the mounts off the plane; the plane's own search refuses
// its first line for the flat-wall height, so the first rejection is not
// counted here), and only that refuses it. The ISS handrail on a seat
// track on the same face, seen the same way, is found.
void test_a_cable_over_a_rack_face_stands_on_no_track(void**) {
  constexpr double kFaceProud_m = 0.025, kTrackProud_m = 0.013;
  auto rack_face = [&]() {
    sim_hal::Scene s = flat_wall_scene();
    // 3 m along the bar, 22 cm across it: the wall stays the dominant plane.
    s.add_box(Eigen::Vector3d(0.5 * kFaceProud_m, 0.0, 0.0), Eigen::Matrix3d::Identity(),
              Eigen::Vector3d(kFaceProud_m, 3.0, 0.22));
    return s;
  };
  sim_hal::Scene cable_scene = rack_face(), rail_scene = rack_face();
  const double cable_centre_m = kFaceProud_m + 0.079 - 0.01;
  cable_scene.add_cable(
      {Eigen::Vector3d(cable_centre_m, -1.5, 0.0), Eigen::Vector3d(cable_centre_m, 1.5, 0.0)},
      0.02);
  rail_scene.add_box(Eigen::Vector3d(kFaceProud_m + 0.5 * kTrackProud_m, 0.0, 0.0),
                     Eigen::Matrix3d::Identity(), Eigen::Vector3d(kTrackProud_m, 0.85, 0.026));
  add_rail_along_y(&rail_scene, Eigen::Vector3d(kFaceProud_m + kTrackProud_m, 0.0, 0.0));
  const estimator::DetectorConfig cfg = horizontal_bars_config();
  estimator::DetectorConfig no_track_test = cfg;
  no_track_test.track_beside = false;
  estimator::HandrailDetector detector(cfg), lenient(no_track_test);
  Rendered r;
  CableAgainstRail seen;
  for (std::size_t f = 0; f < 6; ++f) {
    // Face-on within 5 deg, 0.6 to 0.7 m out, above and below the bar.
    const double k = static_cast<double>(f % 3), side = f < 3 ? 1.0 : -1.0;
    const Eigen::Vector3d position(0.6 + 0.05 * k, 0.04 * k, side * 0.02 * (k + 1.0));
    const Eigen::Isometry3d T = sim_hal::camera_pose(
        position, -Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitZ(), Eigen::Vector3d::Zero());
    seen.view(cable_scene, rail_scene, T, f, detector, lenient, estimator::LineVerdict::kNotOnTrack,
              &r);
  }
  seen.report_and_check("handrail-like cable over a rack face", "first as on no track",
                        "track test", 0);
  // With min_refused 0 the check above asks nothing of the lenient
  // detector: here it must take the cable in every view, so that the track
  // test is what refuses it.
  assert_int_equal(seen.cable.found_lenient, seen.frames);
}

// The same cable over the dominant plane's own face. That is
// the flat-wall case, where a handrail stands on the plane itself, and the
// seat-track test above is not asked; but among rack faces (the plane's
// faces a step or more apart) a handrail's seat track shows a step beside
// it on at least one side, even where its top lies flush with the plane's
// face and the bar is seated on the plane. Here the plane is a rack face
// 1.3 cm proud; below it a strip of the deeper face with the track on it
// (3 cm above the track's centre line to 10 cm below it), its top flush with
// the plane; below that a face 2.5 cm prouder.
// The cable over the plane's face has that face on both sides and is
// refused; the rail on the flush track, seated on the plane, is found.
void test_a_cable_over_the_planes_own_face_among_rack_faces_is_refused(void**) {
  constexpr double kFaceProud_m = 0.013, kTrackProud_m = 0.013;
  constexpr double kStripAbove_m = 0.03, kStripBelow_m = 0.10;
  auto rack_faces = [&]() {
    sim_hal::Scene s = flat_wall_scene();
    s.add_box(Eigen::Vector3d(0.5 * kFaceProud_m, 0.0, 0.5 * (kStripAbove_m + 1.5)),
              Eigen::Matrix3d::Identity(), Eigen::Vector3d(kFaceProud_m, 3.0, 1.5 - kStripAbove_m));
    const double lower_proud_m = kFaceProud_m + 0.025;
    s.add_box(Eigen::Vector3d(0.5 * lower_proud_m, 0.0, -0.5 * (kStripBelow_m + 1.5)),
              Eigen::Matrix3d::Identity(),
              Eigen::Vector3d(lower_proud_m, 3.0, 1.5 - kStripBelow_m));
    return s;
  };
  sim_hal::Scene cable_scene = rack_faces(), rail_scene = rack_faces();
  constexpr double kCableZ_m = 0.10;  // its band beside it all on the plane's face
  const double cable_centre_m = kFaceProud_m + 0.079 - 0.01;
  cable_scene.add_cable({Eigen::Vector3d(cable_centre_m, -1.5, kCableZ_m),
                         Eigen::Vector3d(cable_centre_m, 1.5, kCableZ_m)},
                        0.02);
  rail_scene.add_box(Eigen::Vector3d(0.5 * kTrackProud_m, 0.0, 0.0), Eigen::Matrix3d::Identity(),
                     Eigen::Vector3d(kTrackProud_m, 0.85, 0.026));
  add_rail_along_y(&rail_scene, Eigen::Vector3d(kTrackProud_m, 0.0, 0.0));
  const estimator::DetectorConfig cfg = horizontal_bars_config();
  estimator::DetectorConfig no_track_test = cfg;
  no_track_test.track_beside = false;
  estimator::HandrailDetector detector(cfg), lenient(no_track_test);
  Rendered r;
  CableCounts cable;
  int rail_found = 0, rail_found_lenient = 0, rail_on_plane = 0, frames = 0;
  for (std::size_t f = 0; f < 6; ++f) {
    // Face-on within 5 deg, 0.6 to 0.7 m out, the rail 5 to 9 cm below the
    // view's centre (the cable 1 to 5 cm above it): the plane's face fills
    // most of the view, the deeper strip and the prouder face below it
    // show too.
    const double k = static_cast<double>(f % 3), tilt = f < 3 ? 0.0 : 4.0;
    const Eigen::Vector3d off(0.6 + 0.05 * k, 0.04 * k, 0.05 + 0.02 * k);
    const Eigen::Vector3d tilts(tilt, 0.0, tilt);
    ++frames;
    render_scene(
        cable_scene,
        sim_hal::camera_pose(off, -Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitZ(), tilts), f,
        &r);
    cable.add(r.cloud, detector, lenient, estimator::LineVerdict::kNotOnTrack);
    render_scene(
        rail_scene,
        sim_hal::camera_pose(off, -Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitZ(), tilts), f,
        &r);
    const estimator::HandrailDetection d = detector.detect(r.cloud);
    rail_found_lenient += lenient.detect(r.cloud).status == estimator::DetectStatus::kFound ? 1 : 0;
    if (d.status == estimator::DetectStatus::kFound) {
      ++rail_found;
      rail_on_plane += std::fabs(d.mount_offset_m) < 1e-6f ? 1 : 0;
    }
  }
  std::printf(
      "cable over the plane's own face among rack faces: found %d of %d (%d found without the "
      "track test); the rail on its flush track: %d of %d (%d seated on the plane; %d without "
      "the track test)\n",
      cable.found, frames, cable.found_lenient, rail_found, frames, rail_on_plane,
      rail_found_lenient);
  assert_int_equal(cable.found, 0);
  assert_int_equal(cable.found_lenient, frames);
  // The test costs the rail nothing.
  assert_int_equal(rail_found, rail_found_lenient);
  assert_int_equal(rail_found, frames);
  assert_int_equal(rail_on_plane, rail_found);
  // Seen from below, the prouder face below the strip is the dominant
  // plane and the rail is seated off it, on its track 2.5 cm behind: the
  // face above runs on at the mount's level on that side, the track's own
  // face shows on the other. Refused as on no track before the
  // second development set showed such layouts.
  int below_found = 0, below_off_plane = 0;
  for (std::size_t f = 0; f < 3; ++f) {
    const double k = static_cast<double>(f);
    const Eigen::Isometry3d T = sim_hal::camera_pose(
        Eigen::Vector3d(0.6 + 0.05 * k, 0.04 * k, -0.05 - 0.025 * k), -Eigen::Vector3d::UnitX(),
        Eigen::Vector3d::UnitZ(), Eigen::Vector3d::Zero());
    render_scene(rail_scene, T, 10 + f, &r);
    const estimator::HandrailDetection d = detector.detect(r.cloud);
    if (d.status != estimator::DetectStatus::kFound) continue;
    ++below_found;
    below_off_plane += std::fabs(d.mount_offset_m + 0.025f) < 0.005f ? 1 : 0;
  }
  std::printf("the rail seen from below: found %d of 3, %d seated on its track off the plane\n",
              below_found, below_off_plane);
  assert_int_equal(below_found, 3);
  assert_int_equal(below_off_plane, 3);
}

// A handrail-like cable a track step higher than a handrail over a face:
// its front stands where a bar's would on a seat track hidden under it
// (seen face-on the track does not show beside a bar), and its end in
// view drops straight down (no ramp: into a connector flush with the
// face). Past that end the face runs on under where the track would be,
// level with the face on both sides, and the cable is refused
// (NO_TRACK_PAST_END); a detector that does not ask takes it.
// The ISS handrail on a real track, the track running on 30 cm past its
// end, seen the same way, is found.
void test_a_hidden_track_must_run_on_past_the_end(void**) {
  constexpr double kTrackProud_m = 0.013;
  // The ISS bar's front 7.85 cm over its track, so the 2 cm cable's centre
  // 1 cm below that over the face.
  const double cable_centre_m = kTrackProud_m + 0.0785 - 0.01;
  sim_hal::Scene cable_scene = flat_wall_scene(), rail_scene = flat_wall_scene();
  cable_scene.add_cable(
      {Eigen::Vector3d(cable_centre_m, -1.5, 0.0), Eigen::Vector3d(cable_centre_m, 0.1, 0.0)},
      0.02);
  rail_scene.add_box(Eigen::Vector3d(0.5 * kTrackProud_m, -0.2, 0.0), Eigen::Matrix3d::Identity(),
                     Eigen::Vector3d(kTrackProud_m, 1.2, 0.026));
  add_rail_along_y(&rail_scene, Eigen::Vector3d(kTrackProud_m, -0.175, 0.0));  // its end at y 0.1
  const estimator::DetectorConfig cfg = horizontal_bars_config();
  estimator::HandrailDetector detector(cfg);
  detector.set_line_trace(true);
  Rendered r;
  int cable_found = 0, cable_refused = 0, rail_found = 0, rail_end_seen = 0, frames = 0;
  for (std::size_t f = 0; f < 6; ++f) {
    // Face-on within 6 deg, 0.6 to 0.7 m out, the end 5 to 15 cm right of
    // the view's centre, a little above or below the bar.
    const double k = static_cast<double>(f % 3), side = f < 3 ? 1.0 : -1.0;
    const Eigen::Isometry3d T = sim_hal::camera_pose(
        Eigen::Vector3d(0.6 + 0.05 * k, -0.05 * k, side * 0.03), -Eigen::Vector3d::UnitX(),
        Eigen::Vector3d::UnitZ(), Eigen::Vector3d(0.0, 0.0, 3.0 * k * side));
    ++frames;
    render_scene(cable_scene, T, f, &r);
    const estimator::HandrailDetection c = detector.detect(r.cloud);
    cable_found += c.status == estimator::DetectStatus::kFound ? 1 : 0;
    // The trace says which test refused its lines: this one, for some.
    const estimator::LineTrace& trace = detector.last_line_trace();
    bool refused_here = false;
    for (std::uint32_t e = 0; e < trace.count; ++e) {
      refused_here =
          refused_here || trace.entries[e].verdict == estimator::LineVerdict::kNoTrackPastEnd;
    }
    cable_refused += refused_here ? 1 : 0;
    render_scene(rail_scene, T, f, &r);
    const estimator::HandrailDetection d = detector.detect(r.cloud);
    if (d.status == estimator::DetectStatus::kFound) {
      ++rail_found;
      rail_end_seen += d.state == estimator::HandrailState::kNoEnd ? 0 : 1;
    }
  }
  std::printf(
      "cable on a hidden track: found %d of %d (%d with a line refused for no track past its end); "
      "the "
      "rail on its track: %d of %d, %d with its end seen\n",
      cable_found, frames, cable_refused, rail_found, frames, rail_end_seen);
  assert_int_equal(cable_found, 0);
  assert_true(cable_refused >= frames - 1);
  assert_int_equal(rail_found, frames);
  assert_true(rail_end_seen >= frames - 1);
}

// The found bar's largest extent along the world's y (its ends, in the
// world frame).
double largest_y_of_ends(const estimator::HandrailDetection& d, const Eigen::Isometry3d& T) {
  double y_max = -1e9;
  for (int e = 0; e < 2; ++e) y_max = std::fmax(y_max, (T * d.ends_cam[e].cast<double>()).y());
  return y_max;
}

// A handrail-like cable that runs out of the view one way and, the other
// way, up to a box 6 cm proud of the wall, whose top lies in the gap
// window. The end walk used to run on along the box's top, whose far edge
// then passed for the bar's end: a "handrail" as long as the cable and the
// box together (found in 7 of these 9 views, every time so). Across the walk a bar's raised run is
// a bar's width wide; over the box it goes on for the box's width, and the
// walk does not take it for the bar. The cable is now refused: the box's
// raised ground past its front counts in the ramp test's drop. A handrail
// ending 2.5 cm short of the same box never reaches over it either, and is
// found, that end seen where it is, in all views but one: there, seen
// across the gap, the box's side face rises right past the rail's end, and
// the rail is refused as the cable is (RAMP_END).
void test_the_end_walk_does_not_run_on_over_a_box(void**) {
  constexpr double kBoxStart_m = 0.05, kRailEnd_m = 0.025;
  sim_hal::Scene cable_scene = flat_wall_scene(), rail_scene = flat_wall_scene();
  for (sim_hal::Scene* scene : {&cable_scene, &rail_scene}) {
    scene->add_box(Eigen::Vector3d(0.03, kBoxStart_m + 0.15, 0.0), Eigen::Matrix3d::Identity(),
                   Eigen::Vector3d(0.06, 0.30, 0.12));
  }
  cable_scene.add_cable(
      {Eigen::Vector3d(0.068, -0.8, 0.0), Eigen::Vector3d(0.068, kBoxStart_m, 0.0)}, 0.02);
  add_rail_along_y(&rail_scene, Eigen::Vector3d(0.0, kRailEnd_m - 0.275, 0.0));  // 0.55 m
  const estimator::DetectorConfig cfg = horizontal_bars_config();  // along the image's rows
  estimator::HandrailDetector detector(cfg);
  Rendered r;
  int cable_found = 0, onto_box = 0, rail_found = 0, rail_onto_box = 0, rail_end_right = 0,
      frames = 0;
  for (const double range_m : {0.60, 0.65, 0.70}) {
    for (const double shift_m : {-0.03, 0.0, 0.03}) {
      const Eigen::Isometry3d T =
          sim_hal::camera_pose(Eigen::Vector3d(range_m, shift_m, 0.02), -Eigen::Vector3d::UnitX(),
                               Eigen::Vector3d::UnitZ(), Eigen::Vector3d(0.0, shift_m, 0.02));
      const std::size_t f = static_cast<std::size_t>(frames++);
      render_scene(cable_scene, T, f, &r);
      const estimator::HandrailDetection cable = detector.detect(r.cloud);
      if (cable.status == estimator::DetectStatus::kFound) {
        ++cable_found;
        onto_box += largest_y_of_ends(cable, T) > kBoxStart_m + 0.03 ? 1 : 0;
      }
      render_scene(rail_scene, T, f, &r);
      const estimator::HandrailDetection found = detector.detect(r.cloud);
      if (found.status != estimator::DetectStatus::kFound) continue;
      ++rail_found;
      rail_onto_box += largest_y_of_ends(found, T) > kBoxStart_m + 0.03 ? 1 : 0;
      const int toward_box =
          (T * found.ends_cam[1].cast<double>()).y() > (T * found.ends_cam[0].cast<double>()).y()
              ? 1
              : 0;
      rail_end_right +=
          found.end_seen[toward_box] && std::fabs(largest_y_of_ends(found, T) - kRailEnd_m) < 0.03
              ? 1
              : 0;
    }
  }
  std::printf(
      "cable up to a box: found %d of %d views, %d of them running on over the box; the rail "
      "ending short of it: found %d (%d running on over the box), that end seen where it is "
      "%d\n",
      cable_found, frames, onto_box, rail_found, rail_onto_box, rail_end_right);
  assert_int_equal(onto_box, 0);
  assert_int_equal(cable_found, 0);
  assert_true(rail_found >= frames - 1);
  assert_int_equal(rail_onto_box, 0);
  assert_true(rail_end_right >= frames - 1);
}

}  // namespace

int main() {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_handrail_like_cable_is_refused_for_its_ramps),
      cmocka_unit_test(test_short_ramps_are_refused_and_a_seat_track_is_no_ramp),
      cmocka_unit_test(test_a_ramp_the_image_edge_cuts_is_still_a_ramp),
      cmocka_unit_test(test_a_cable_seen_from_its_side_is_too_shallow_for_a_bar),
      cmocka_unit_test(test_a_cable_over_a_rack_face_stands_on_no_track),
      cmocka_unit_test(test_a_cable_over_the_planes_own_face_among_rack_faces_is_refused),
      cmocka_unit_test(test_the_end_walk_does_not_run_on_over_a_box),
      cmocka_unit_test(test_a_hidden_track_must_run_on_past_the_end),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
