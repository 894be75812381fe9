// A royale application in the SDK samples' style, written against the
// royale API only: it builds unchanged against the vendor's SDK. It finds
// the first camera, initializes it, prints what the camera reports (id,
// name, use cases, exposure limits, lens parameters), then captures for a
// few seconds and prints how many frames came and the centre pixel's mean depth.
//
//   royale_sample_camera_info [seconds]    (default 3)
#include <royale.hpp>

#include <chrono>
#include <cstdlib>
#include <iostream>
#include <memory>
#include <mutex>
#include <thread>

namespace {

// Counts frames and averages the centre point's depth over the frames where
// it is valid. Called on the camera's thread, so the state is behind a
// mutex.
class CentreDepthListener : public royale::IDepthDataListener {
 public:
  void onNewData(const royale::DepthData* data) override {
    std::lock_guard<std::mutex> lock(mutex_);
    ++frames_;
    const royale::DepthPoint& p =
        data->points[static_cast<size_t>(data->height / 2) * data->width + data->width / 2];
    if (p.depthConfidence > 0) {
      centreSum_ += p.z;
      ++centreFrames_;
    }
    exposure_ = data->exposureTimes.empty() ? 0 : data->exposureTimes[0];
  }

  void print() {
    std::lock_guard<std::mutex> lock(mutex_);
    std::cout << "Frames received: " << frames_ << std::endl;
    std::cout << "Last exposure time: " << exposure_ << " us" << std::endl;
    if (centreFrames_ > 0) {
      std::cout << "Centre depth: " << centreSum_ / centreFrames_ << " m (mean of " << centreFrames_
                << " frames)" << std::endl;
    } else {
      std::cout << "Centre depth: no valid point" << std::endl;
    }
  }

  long frames() {
    std::lock_guard<std::mutex> lock(mutex_);
    return frames_;
  }

 private:
  std::mutex mutex_;
  long frames_ = 0;
  double centreSum_ = 0.0;
  long centreFrames_ = 0;
  uint32_t exposure_ = 0;
};

int printError(const char* what, royale::CameraStatus status) {
  std::cerr << what << ": " << royale::getStatusString(status) << std::endl;
  return 1;
}

}  // namespace

int main(int argc, char* argv[]) {
  const int seconds = argc > 1 ? std::atoi(argv[1]) : 3;
  if (seconds < 1 || seconds > 600) {
    std::cerr << "usage: " << argv[0] << " [seconds, 1 .. 600]" << std::endl;
    return 2;
  }

  std::unique_ptr<royale::ICameraDevice> cameraDevice;
  {
    royale::CameraManager manager;
    royale::Vector<royale::String> camlist = manager.getConnectedCameraList();
    std::cout << "Detected " << camlist.size() << " camera(s)." << std::endl;
    if (camlist.empty()) {
      std::cerr << "No camera connected." << std::endl;
      return 1;
    }
    cameraDevice = manager.createCamera(camlist[0]);
  }
  if (cameraDevice == nullptr) {
    std::cerr << "Cannot create the camera device." << std::endl;
    return 1;
  }

  royale::CameraStatus status = cameraDevice->initialize();
  if (status != royale::CameraStatus::SUCCESS)
    return printError("Cannot initialize the camera", status);

  royale::String id;
  royale::String name;
  cameraDevice->getId(id);
  cameraDevice->getCameraName(name);
  std::cout << "Camera ID: " << id << std::endl;
  std::cout << "Camera name: " << name << std::endl;

  royale::Vector<royale::String> useCases;
  status = cameraDevice->getUseCases(useCases);
  if (status != royale::CameraStatus::SUCCESS || useCases.empty()) {
    return printError("No use cases", status);
  }
  std::cout << "Use cases: " << useCases.size() << std::endl;
  for (size_t i = 0; i < useCases.size(); ++i) {
    std::cout << "    " << useCases[i] << std::endl;
  }
  royale::String current;
  uint16_t frameRate = 0;
  cameraDevice->getCurrentUseCase(current);
  cameraDevice->getFrameRate(frameRate);
  std::cout << "Current use case: " << current << " (" << frameRate << " fps)" << std::endl;

  royale::Pair<uint32_t, uint32_t> limits;
  status = cameraDevice->getExposureLimits(limits);
  if (status != royale::CameraStatus::SUCCESS) return printError("No exposure limits", status);
  std::cout << "Exposure limits: " << limits.first << " .. " << limits.second << " us" << std::endl;

  royale::LensParameters lens;
  status = cameraDevice->getLensParameters(lens);
  if (status != royale::CameraStatus::SUCCESS) return printError("No lens parameters", status);
  std::cout << "Lens parameters:" << std::endl;
  std::cout << "    cx/cy " << lens.principalPoint.first << " " << lens.principalPoint.second
            << std::endl;
  std::cout << "    fx/fy " << lens.focalLength.first << " " << lens.focalLength.second
            << std::endl;
  std::cout << "    tangential " << lens.distortionTangential.first << " "
            << lens.distortionTangential.second << std::endl;
  std::cout << "    radial";
  for (float k : lens.distortionRadial) std::cout << " " << k;
  std::cout << std::endl;

  CentreDepthListener listener;
  status = cameraDevice->registerDataListener(&listener);
  if (status != royale::CameraStatus::SUCCESS)
    return printError("Cannot register a listener", status);
  status = cameraDevice->startCapture();
  if (status != royale::CameraStatus::SUCCESS) return printError("Cannot start capturing", status);
  std::cout << "Capturing for " << seconds << " s" << std::endl;
  std::this_thread::sleep_for(std::chrono::seconds(seconds));
  status = cameraDevice->stopCapture();
  if (status != royale::CameraStatus::SUCCESS) return printError("Cannot stop capturing", status);
  cameraDevice->unregisterDataListener();

  listener.print();
  return listener.frames() > 0 ? 0 : 1;
}
