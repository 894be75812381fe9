#include <thread>
#include <vector>

#include "cmocka_cpp.hpp"
#include "fsw_app/frame_ring.hpp"

namespace {

std::vector<hal::DepthPoint> frame_points(float z) {
  return std::vector<hal::DepthPoint>(6, hal::DepthPoint{0, 0, z, 0, 0, 255});
}

void test_newest_wins_and_old_frames_are_dropped(void**) {
  fsw_app::FrameRing ring(3, 3, 2);
  std::vector<hal::DepthPoint> out(6);
  hal::DepthFrame got;
  assert_int_equal(static_cast<int>(ring.pop_newest(&got, out.data())),
                   static_cast<int>(fsw_app::RingStatus::kEmpty));
  for (int k = 1; k <= 5; ++k) {
    const std::vector<hal::DepthPoint> pts = frame_points(static_cast<float>(k));
    assert_int_equal(
        static_cast<int>(ring.push({static_cast<std::uint64_t>(k), k * 100, 3, 2, pts.data()})),
        static_cast<int>(fsw_app::RingStatus::kOk));
  }
  assert_int_equal(static_cast<int>(ring.pop_newest(&got, out.data())),
                   static_cast<int>(fsw_app::RingStatus::kOk));
  assert_int_equal(got.frame_id, 5);
  assert_int_equal(got.capture_time_us, 500);
  assert_true(got.points[0].z_m == 5.0f);
  // Frames 1..4 were never read: two overwritten, two skipped.
  assert_int_equal(ring.dropped(), 4);
  assert_int_equal(ring.pushed(), 5);
  assert_int_equal(static_cast<int>(ring.pop_newest(&got, out.data())),
                   static_cast<int>(fsw_app::RingStatus::kEmpty));
  const std::vector<hal::DepthPoint> big(12);
  assert_int_equal(static_cast<int>(ring.push({6, 0, 4, 3, big.data()})),
                   static_cast<int>(fsw_app::RingStatus::kFrameTooLarge));
}

// Popping into another point type converts while copying out, with the
// same bookkeeping as a plain pop.
void test_pop_converts_into_the_consumers_type(void**) {
  fsw_app::FrameRing ring(2, 3, 2);
  for (int k = 1; k <= 3; ++k) {
    const std::vector<hal::DepthPoint> pts = frame_points(static_cast<float>(k));
    ring.push({static_cast<std::uint64_t>(k), k * 10, 3, 2, pts.data()});
  }
  std::vector<double> depth_mm(6, -1.0);
  hal::DepthFrame got;
  assert_int_equal(
      static_cast<int>(ring.pop_newest_as(&got, depth_mm.data(),
                                          [](const hal::DepthPoint& p) { return 1000.0 * p.z_m; })),
      static_cast<int>(fsw_app::RingStatus::kOk));
  assert_int_equal(got.frame_id, 3);
  assert_null(got.points);  // not a DepthPoint buffer
  for (double d : depth_mm) assert_true(d == 3000.0);
  assert_int_equal(ring.dropped(), 2);
  assert_int_equal(static_cast<int>(ring.pop_newest_as(&got, depth_mm.data(),
                                                       [](const hal::DepthPoint&) { return 0.0; })),
                   static_cast<int>(fsw_app::RingStatus::kEmpty));
}

void test_producer_and_consumer_threads(void**) {
  fsw_app::FrameRing ring(4, 3, 2);
  constexpr int kFrames = 2000;
  std::thread producer([&ring] {
    for (int k = 1; k <= kFrames; ++k) {
      const std::vector<hal::DepthPoint> pts = frame_points(static_cast<float>(k));
      (void)ring.push({static_cast<std::uint64_t>(k), k, 3, 2, pts.data()});
    }
  });
  std::vector<hal::DepthPoint> out(6);
  std::uint64_t last = 0, read = 0;
  while (last < kFrames) {
    hal::DepthFrame got;
    if (ring.pop_newest(&got, out.data()) != fsw_app::RingStatus::kOk) continue;
    assert_true(got.frame_id > last);                             // never older, never twice
    assert_true(out[5].z_m == static_cast<float>(got.frame_id));  // whole frame, not torn
    last = got.frame_id;
    ++read;
  }
  producer.join();
  assert_int_equal(read + ring.dropped(), kFrames);
}

}  // namespace

int main() {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_newest_wins_and_old_frames_are_dropped),
      cmocka_unit_test(test_pop_converts_into_the_consumers_type),
      cmocka_unit_test(test_producer_and_consumer_threads),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
