#pragma once
// The emulated camera's frames from the simulated world: the raw-frame
// renderer (tof_raw_renderer.hpp) at the camera's pose at the frame's
// capture (as the pose source has it then: the hardware-in-loop world
// gives its current pose), so that the raw frames the USB driver reads are
// the simulator's.
#include <cstdint>

#include "sim_hal/emulated_pico_flexx.hpp"
#include "sim_hal/scene.hpp"
#include "sim_hal/simulated_camera.hpp"
#include "sim_hal/tof_raw_renderer.hpp"

namespace sim_hal {

class RenderedFrameSource final : public RawFrameSource {
 public:
  // None owned; all must outlive this. `seed` seeds the renderer's noise.
  RenderedFrameSource(const Scene& scene, CameraPoseSource& poses, RawRenderer& renderer,
                      std::uint64_t seed)
      : scene_(scene), poses_(poses), renderer_(renderer), seed_(seed) {}

  // The world as the pose source has it at the frame's capture.
  void fill(std::uint64_t frame_index, std::int64_t capture_host_us, const hal::UseCase& use_case,
            std::uint32_t exposure_us, tof::RawFrame* out) override {
    const tof::Mode mode = use_case.raw_frames == 9 ? tof::Mode::kMode9 : tof::Mode::kMode5;
    // A commanded exposure is the renderer's manual one; 0 is automatic.
    renderer_.settings().auto_exposure = exposure_us == 0;
    if (exposure_us != 0) renderer_.settings().manual_exposure_us = exposure_us;
    renderer_.render(scene_, poses_.T_world_cam(capture_host_us), mode, use_case.max_exposure_us,
                     seed_, frame_index, out);
  }

 private:
  const Scene& scene_;
  CameraPoseSource& poses_;
  RawRenderer& renderer_;
  std::uint64_t seed_;
};

}  // namespace sim_hal
