// What shows beside a bar (mount_beside): its mount in the band across
// from it, the seat track's foot there, the levels a front-height test may
// seat it on, and the mount found under it from those levels
// (mount_surfaces' find_mount_under_bar).
#include <cmath>
#include <cstddef>
#include <vector>

#include "cmocka_cpp.hpp"
#include "estimator/handrail_filters.hpp"
#include "estimator/mount_beside.hpp"
#include "estimator/mount_surfaces.hpp"
#include "estimator/plane_estimation.hpp"
#include "estimator/track_past_end.hpp"

using namespace estimator;

namespace {

constexpr float kFront = 0.061f + 0.0175f;  // the ISS bar's front face above its mount

// A frame for the mount-beside step: a fronto-parallel grid of points 4 mm
// apart, 1 m away (the wall z = 1, its normal toward the camera), a bar's
// centre line along image y through the middle. `height_beside` gives each
// pixel's height above the wall from its distance across the bar (x); NAN
// leaves it invalid.
struct BesideFrame {
  std::vector<CloudPoint> points;
  OrganizedCloud cloud;
  Workspace ws{224 * 171};
  Plane wall;
  CenterLine line;
  template <typename F>
  explicit BesideFrame(F height_beside) : points(224 * 171) {
    for (int r = 0; r < 171; ++r) {
      for (int c = 0; c < 224; ++c) {
        const float x = 0.004f * static_cast<float>(c - 112),
                    y = 0.004f * static_cast<float>(r - 85);
        const float h = height_beside(x);
        CloudPoint& p = points[static_cast<std::size_t>(r) * 224 + c];
        p = CloudPoint{x,      y,   1.0f - (std::isnan(h) ? 0.0f : h),
                       0.001f, 100, static_cast<std::uint8_t>(std::isnan(h) ? 0 : 255)};
      }
    }
    cloud.width = 224;
    cloud.height = 171;
    cloud.points = points.data();
    sample_valid_points(cloud, DetectorConfig{}, ws);
    wall.normal = Eigen::Vector3f(0, 0, -1);
    wall.d = 1.0f;
    line.point = Eigen::Vector3f(0, 0, 1.0f - 0.074f);
    line.axis = Eigen::Vector3f(0, 1, 0);
    line.t_min_m = -0.25f;
    line.t_max_m = 0.25f;
  }
  bool shows(float mount_m) const {
    const DetectorConfig cfg;
    return mount_shows_beside(measure_mount_beside(cloud, cfg, ws, wall, line, mount_m), cfg);
  }
};

// The bar's own pixels (within 1 cm across) stand at its front; beside it,
// what each case puts there.
float bar_or(float x, float beside) {
  return std::fabs(x) < 0.01f ? 0.078f : beside;
}

void test_the_mount_shows_beside_a_handrail(void**) {
  // A seat track's foot (the rack face 1.3 cm below the track) beside it:
  // the bar stands on the track, 1.3 cm above the wall.
  const BesideFrame on_track([](float x) { return bar_or(x, 0.0f); });
  assert_true(on_track.shows(0.013f));
  // A flat wall: the bar stands on it.
  assert_true(on_track.shows(0.0f));
  // A gap 12 cm deep on one side, the face on the other: still standing.
  const BesideFrame gap_one_side([](float x) { return bar_or(x, x > 0.0f ? -0.12f : 0.0f); });
  assert_true(gap_one_side.shows(0.013f));
  const MountBeside m = measure_mount_beside(gap_one_side.cloud, DetectorConfig{}, gap_one_side.ws,
                                             gap_one_side.wall, gap_one_side.line, 0.013f);
  assert_true(m.band_pixels[0] >= 20 && m.band_pixels[1] >= 20);
  assert_true(m.at_mount(0) == 0 || m.at_mount(1) == 0);
}

void test_no_mount_beside_is_no_handrail(void**) {
  // Something a handrail's height above a surface 3.8 cm behind the wall,
  // with nothing at that depth beside it (a rack's edge strip over a deep
  // groove, seen as a bar on a mount elsewhere in view).
  const BesideFrame strip([](float x) { return bar_or(x, -0.12f); });
  assert_false(strip.shows(-0.038f));
  // ... nor is the wall it was measured from a mount 3.8 cm off.
  const BesideFrame wall_beside([](float x) { return bar_or(x, 0.0f); });
  assert_false(wall_beside.shows(-0.038f));
  // Nothing valid beside it at all: no evidence, no refusal.
  const BesideFrame nothing([](float x) { return std::fabs(x) < 0.01f ? 0.078f : NAN; });
  assert_true(nothing.shows(-0.038f));
}

// The seat-track reading (track_shows_beside, NOT_ON_TRACK when on): a bar
// on a track shows the track's foot beside it; a handrail-like cable
// seated on the face under it shows that face, its mount's own level,
// running on beside it.
void test_a_bar_on_a_track_shows_the_foot_beside_it(void**) {
  const DetectorConfig cfg;
  auto split = [&](const BesideFrame& f, float mount_m) {
    return measure_mount_beside(f.cloud, cfg, f.ws, f.wall, f.line, mount_m);
  };
  // The track 1.3 cm proud of the wall, the bar on it: the wall beside.
  const BesideFrame on_track([](float x) { return bar_or(x, 0.0f); });
  const MountBeside track = split(on_track, 0.013f);
  assert_true(track.at_foot[0] > 20 && track.at_foot[1] > 20);
  assert_int_equal(track.at_level[0] + track.at_level[1], 0);
  assert_true(track_shows_beside(track, cfg));
  // The cable on the face: the same face beside it, at the mount's level.
  const MountBeside cable = split(on_track, 0.0f);
  assert_true(cable.at_level[0] > 20 && cable.at_level[1] > 20);
  assert_false(track_shows_beside(cable, cfg));
  // One side a gap 12 cm deep, the other the face at the mount's level:
  // the level still runs on where it shows.
  const BesideFrame gap_one_side([](float x) { return bar_or(x, x > 0.0f ? -0.12f : 0.0f); });
  assert_false(track_shows_beside(split(gap_one_side, 0.0f), cfg));
  assert_true(track_shows_beside(split(gap_one_side, 0.013f), cfg));
  // Nothing valid beside it: no evidence, no refusal.
  const BesideFrame nothing([](float x) { return std::fabs(x) < 0.01f ? 0.078f : NAN; });
  assert_true(track_shows_beside(split(nothing, 0.0f), cfg));
  // A neighbouring face flush with the track's top on one side (1.3 cm
  // above the track's face, 3 mm off the mount's level), the track's own
  // face on the other: the level runs on where the
  // neighbour is, the foot shows where the face is, and the bar stands on
  // its track. The neighbour beginning 2 cm out on that side, the track's
  // face between: still standing.
  const BesideFrame flush([](float x) { return bar_or(x, x > 0.0f ? 0.016f : 0.0f); });
  const MountBeside beside_flush = split(flush, 0.013f);
  // (x > 0 is side 0: across the bar is its axis times the wall's normal.)
  assert_true(beside_flush.at_level[0] > 20 && beside_flush.at_foot[1] > 20);
  assert_true(track_shows_beside(beside_flush, cfg));
  const BesideFrame flush_past_face([](float x) { return bar_or(x, x > 0.02f ? 0.016f : 0.0f); });
  assert_true(track_shows_beside(split(flush_past_face, 0.013f), cfg));
  // The foot must outnumber the level on its side: a few pixels of some
  // face 1.3 cm lower among the level's are no track.
  const BesideFrame level_with_foot_patch(
      [](float x) { return bar_or(x, x < -0.045f ? 0.0f : 0.013f); });
  const MountBeside patch = split(level_with_foot_patch, 0.013f);
  assert_true(patch.at_foot[1] > 0 && patch.at_level[1] > patch.at_foot[1]);
  assert_false(track_shows_beside(patch, cfg));
}

// On the dominant plane's own face among rack faces (open_face_both_sides):
// the plane may be a neighbouring face flush with the track's top, so a
// real handrail shows its mount's level on one side, and the track's own
// face a step below (or a gap) on the other; a cable lying over a face has
// that face at its mount's level on both sides.
void test_an_open_face_on_both_sides_is_no_seat_track(void**) {
  const DetectorConfig cfg;
  auto split = [&](const BesideFrame& f, float mount_m) {
    return measure_mount_beside(f.cloud, cfg, f.ws, f.wall, f.line, mount_m);
  };
  // The cable over the face: the face on both sides.
  const BesideFrame face([](float x) { return bar_or(x, 0.0f); });
  assert_true(open_face_both_sides(split(face, 0.0f), cfg));
  // The rail on a track whose top is flush with the plane's face on one
  // side, the track's own face 1.3 cm below on the other.
  const BesideFrame flush_one_side([](float x) { return bar_or(x, x > 0.0f ? -0.013f : 0.0f); });
  assert_false(open_face_both_sides(split(flush_one_side, 0.0f), cfg));
  // ... or a gap 12 cm deep on the other.
  const BesideFrame gap_one_side([](float x) { return bar_or(x, x > 0.0f ? -0.12f : 0.0f); });
  assert_false(open_face_both_sides(split(gap_one_side, 0.0f), cfg));
  // A side too thin to judge (seen obliquely, the bar hides it): no
  // refusal on the other side alone.
  const BesideFrame sliver([](float x) { return bar_or(x, x > 0.0135f ? NAN : 0.0f); });
  const MountBeside m = split(sliver, 0.0f);
  assert_true(m.band_pixels[0] < cfg.track_beside_min_pixels ||
              m.band_pixels[1] < cfg.track_beside_min_pixels);
  assert_false(open_face_both_sides(m, cfg));
  // The track's foot on both sides: a bar on a track, not an open face.
  assert_false(open_face_both_sides(split(face, 0.013f), cfg));
}

// The hidden track's verdict past a seen end (track_runs_past_end): the
// strip under the centre line against its flanks.
void test_a_hidden_track_stands_proud_past_the_end(void**) {
  const DetectorConfig cfg;
  const bool seen[2] = {true, false};
  // The hidden track's top: a step over the face the strip lies on.
  const float face = cfg.mount_step_m;
  TrackPastEnd m;
  m.strip_pixels[0] = 40;
  m.flank_pixels[0][0] = m.flank_pixels[0][1] = 40;
  // The face level with the strip on both sides: no track, refused.
  m.strip_m[0] = 0.0f;
  m.flank_m[0][0] = 0.001f;
  m.flank_m[0][1] = -0.002f;
  assert_false(track_runs_past_end(m, seen, face, cfg));
  // The same past an end not seen (the image cuts it): nothing said.
  const bool unseen[2] = {false, false};
  assert_true(track_runs_past_end(m, unseen, face, cfg));
  // A track's step (1.3 cm) over one flank, the other a face flush with
  // its top: a track.
  m.flank_m[0][1] = -0.013f;
  assert_true(track_runs_past_end(m, seen, face, cfg));
  // Less than half a step: the face, refused.
  m.flank_m[0][1] = -0.006f;
  assert_false(track_runs_past_end(m, seen, face, cfg));
  // One flank too thin to judge and the other level: a flush neighbour may
  // be all that shows; nothing said.
  m.flank_pixels[0][1] = kPastEndMinPixels - 1;
  assert_true(track_runs_past_end(m, seen, face, cfg));
  // Too little strip: nothing said.
  m.flank_pixels[0][1] = 40;
  m.strip_pixels[0] = kPastEndMinPixels - 1;
  assert_true(track_runs_past_end(m, seen, face, cfg));
  // Level across, but 6 cm over the track's top (a box across the end, the
  // third development set's rack clutter): something at the bar's own
  // height stands over where the track would run; nothing said. A face
  // 1.2 cm over the track's top running on in line with it (Columbus) is
  // still refused: no track runs on under it.
  m.strip_pixels[0] = 40;
  m.strip_m[0] = 0.06f;
  m.flank_m[0][0] = 0.061f;
  m.flank_m[0][1] = 0.059f;
  assert_true(track_runs_past_end(m, seen, 0.0f, cfg));
  assert_true(track_runs_past_end(m, seen, 0.06f - gap_min_m(cfg), cfg));
  assert_false(track_runs_past_end(m, seen, 0.06f - 0.012f, cfg));
}

// The levels beside the bar, for the front-height test: what each side
// shows, measured there rather than taken from the frame's surface peaks.
void test_the_levels_beside_a_bar(void**) {
  const DetectorConfig cfg;
  // A rack frame 2.2 cm behind the wall on one side (the track's foot: too
  // narrow a strip to be a peak of the whole frame), a gap on the other.
  const BesideFrame frame_strip([](float x) { return bar_or(x, x > 0.0f ? -0.022f : -0.12f); });
  LevelsBeside near = find_levels_beside(frame_strip.cloud, cfg, frame_strip.ws, frame_strip.wall,
                                         frame_strip.line, -0.06f, 0.01f);
  assert_int_equal(near.count, 1);
  assert_near(near.level_m[0], -0.022f, 0.0005f);
  // The same surface on both sides: two levels, both it.
  const BesideFrame both([](float x) { return bar_or(x, -0.022f); });
  near = find_levels_beside(both.cloud, cfg, both.ws, both.wall, both.line, -0.06f, 0.01f);
  assert_int_equal(near.count, 2);
  assert_near(near.level_m[0], -0.022f, 0.0005f);
  assert_near(near.level_m[1], -0.022f, 0.0005f);
  // Outside the range looked in: nothing.
  near = find_levels_beside(both.cloud, cfg, both.ws, both.wall, both.line, -0.015f, 0.01f);
  assert_int_equal(near.count, 0);
  // Nothing valid beside the bar, or an empty range: nothing, and no NaN.
  const BesideFrame nothing([](float x) { return std::fabs(x) < 0.01f ? 0.078f : NAN; });
  near =
      find_levels_beside(nothing.cloud, cfg, nothing.ws, nothing.wall, nothing.line, -0.06f, 0.01f);
  assert_int_equal(near.count, 0);
  near = find_levels_beside(both.cloud, cfg, both.ws, both.wall, both.line, 0.01f, -0.06f);
  assert_int_equal(near.count, 0);
  near = find_levels_beside(both.cloud, cfg, both.ws, both.wall, both.line, NAN, 0.01f);
  assert_int_equal(near.count, 0);
}

void test_the_mount_under_a_bar_beside_it(void**) {
  const DetectorConfig cfg;
  // The frame's surfaces: the dominant face and one 5 cm behind it; the
  // bar's front 7.3 cm above the dominant plane fits neither (nor a track
  // on either).
  MountHypotheses m;
  m.surface_count = 2;
  m.surface_m[0] = 0.0f;
  m.surface_m[1] = -0.05f;
  const float front = -0.018f + 0.013f + kFront;
  float mount = 99.0f;
  assert_false(find_mount_under_bar(m, cfg, front, 0.004f, &mount));
  // Beside it, a strip 1.8 cm behind the plane: the bar is on a seat track
  // on that strip.
  const float near_levels[1] = {-0.018f};
  assert_true(find_mount_under_bar(m, cfg, front, 0.004f, &mount, near_levels, 1));
  assert_near(mount, -0.018f + 0.013f, 1e-6f);
  // A level beside it that is the dominant plane is still the flat-wall
  // search's to judge.
  const float plane_level[1] = {0.0f};
  assert_false(find_mount_under_bar(m, cfg, kFront, 0.004f, &mount, plane_level, 1));
  // A seat track on a strip 1.64 cm behind the plane tops out 3.4 mm
  // under it, nearer the plane than a face of its own could be: the bar
  // 5.5 mm lower than a flat-wall bar stands on that track.
  const float frame_level[1] = {-0.0164f};
  assert_true(find_mount_under_bar(m, cfg, kFront - 0.0055f, 0.004f, &mount, frame_level, 1));
  assert_near(mount, -0.0164f + 0.013f, 1e-6f);
  // A face that near the plane is the plane's own: not a mount.
  const float near_face[1] = {-0.0034f};
  assert_false(find_mount_under_bar(m, cfg, kFront - 0.0034f, 0.004f, &mount, near_face, 1));
}

}  // namespace

int main() {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_the_mount_shows_beside_a_handrail),
      cmocka_unit_test(test_a_bar_on_a_track_shows_the_foot_beside_it),
      cmocka_unit_test(test_an_open_face_on_both_sides_is_no_seat_track),
      cmocka_unit_test(test_a_hidden_track_stands_proud_past_the_end),
      cmocka_unit_test(test_no_mount_beside_is_no_handrail),
      cmocka_unit_test(test_the_levels_beside_a_bar),
      cmocka_unit_test(test_the_mount_under_a_bar_beside_it),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
