#pragma once
// The emulated camera's frames from the simulated world: the raw-frame
// renderer (tof_raw_renderer.hpp) at the camera's pose when the frame is
// made, so that the raw frames the USB driver reads are the simulator's.
#include <cstdint>

#include "hal/clock.hpp"
#include "sim_hal/emulated_pico_flexx.hpp"
#include "sim_hal/scene.hpp"
#include "sim_hal/simulated_camera.hpp"
#include "sim_hal/tof_raw_renderer.hpp"

namespace sim_hal {

class RenderedFrameSource final : public RawFrameSource {
 public:
  // None owned; all must outlive this. `seed` seeds the renderer's noise.
  RenderedFrameSource(const Scene& scene, CameraPoseSource& poses, RawRenderer& renderer,
                      const hal::Clock& clock, std::uint64_t seed)
      : scene_(scene), poses_(poses), renderer_(renderer), clock_(clock), seed_(seed) {}

  void fill(std::uint64_t frame_index, const hal::UseCase& use_case, std::uint32_t exposure_us,
            tof::RawFrame* out) override {
    const tof::Mode mode = use_case.raw_frames == 9 ? tof::Mode::kMode9 : tof::Mode::kMode5;
    // A commanded exposure is the renderer's manual one; 0 is automatic.
    renderer_.settings().auto_exposure = exposure_us == 0;
    if (exposure_us != 0) renderer_.settings().manual_exposure_us = exposure_us;
    renderer_.render(scene_, poses_.T_world_cam(clock_.now_us()), mode, use_case.max_exposure_us,
                     seed_, frame_index, out);
  }

 private:
  const Scene& scene_;
  CameraPoseSource& poses_;
  RawRenderer& renderer_;
  const hal::Clock& clock_;
  std::uint64_t seed_;
};

}  // namespace sim_hal
