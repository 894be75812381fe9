#include "sim_hal/ground_truth.hpp"

#include <cstdio>

namespace sim_hal {
namespace {

constexpr int kVisibilitySamples = 101;

// A centre-line point is visible when it projects into the image and the
// first surface on the ray toward it belongs to its own handrail (the
// centre line is inside the bar, so that surface is the bar's skin).
bool centre_point_visible(const Scene& scene, const CameraIntrinsics& cam,
                          const Eigen::Isometry3d& T_world_cam, int handrail,
                          const Eigen::Vector3d& p_world) {
  const Eigen::Vector3d p_cam = T_world_cam.inverse() * p_world;
  Eigen::Vector2d px;
  if (!project(cam, p_cam, &px)) return false;
  if (px.x() < 0.0 || px.y() < 0.0 || px.x() > cam.width - 1.0 || px.y() > cam.height - 1.0)
    return false;
  const Eigen::Vector3d origin = T_world_cam.translation();
  const Eigen::Vector3d dir = (p_world - origin).normalized();
  Hit hit;
  if (!intersect_scene(scene, origin, dir, 1e-4, (p_world - origin).norm(), &hit)) return true;
  return scene.surfaces[static_cast<std::size_t>(hit.surface)].object_id == handrail;
}

void append_vec(std::string* s, const Eigen::Vector3d& v) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "[%.6f,%.6f,%.6f]", v.x(), v.y(), v.z());
  *s += buf;
}

}  // namespace

FrameTruth compute_truth(const Scene& scene, const CameraIntrinsics& cam,
                         const Eigen::Isometry3d& T_world_cam, std::uint64_t frame) {
  FrameTruth truth;
  truth.frame = frame;
  truth.T_world_cam = T_world_cam;
  const Eigen::Isometry3d T_cam_world = T_world_cam.inverse();
  for (std::size_t k = 0; k < scene.handrails.size(); ++k) {
    const Handrail& h = scene.handrails[k];
    const int id = static_cast<int>(k);
    int visible = 0;
    Eigen::Vector3d visible_sum = Eigen::Vector3d::Zero();
    for (int s = 0; s < kVisibilitySamples; ++s) {
      const double f = static_cast<double>(s) / (kVisibilitySamples - 1);
      const Eigen::Vector3d p = h.end_point(0) + f * (h.end_point(1) - h.end_point(0));
      if (centre_point_visible(scene, cam, T_world_cam, id, p)) {
        ++visible;
        visible_sum += p;
      }
    }
    if (visible == 0) continue;
    HandrailTruth t;
    t.index = id;
    t.kind = h.kind;
    for (int e = 0; e < 2; ++e) {
      t.ends_cam[e] = T_cam_world * h.end_point(e);
      // Pull the probe just inside the bar so that its own end cap does not
      // hide it.
      const Eigen::Vector3d inside =
          h.end_point(e) - (e == 0 ? -0.005 : 0.005) * h.axis.normalized();
      t.end_in_view[e] = centre_point_visible(scene, cam, T_world_cam, id, inside);
    }
    t.center_cam = 0.5 * (t.ends_cam[0] + t.ends_cam[1]);
    t.axis_cam = (t.ends_cam[1] - t.ends_cam[0]).normalized();
    t.normal_cam = T_cam_world.rotation() * h.normal.normalized();
    t.length_m = h.bar_length_m;
    t.visible_fraction = static_cast<double>(visible) / kVisibilitySamples;
    t.visible_center_cam = T_cam_world * (visible_sum / visible);
    truth.handrails.push_back(t);
  }
  return truth;
}

std::string truth_to_json(const FrameTruth& truth, const std::string& frame_file) {
  std::string s = "{\"frame\":" + std::to_string(truth.frame) + ",\"file\":\"" + frame_file + "\"";
  const Eigen::Quaterniond q(truth.T_world_cam.rotation());
  char buf[160];
  s += ",\"camera_position\":";
  append_vec(&s, truth.T_world_cam.translation());
  std::snprintf(buf, sizeof buf, ",\"camera_quaternion_wxyz\":[%.8f,%.8f,%.8f,%.8f]", q.w(), q.x(),
                q.y(), q.z());
  s += buf;
  s += ",\"handrails\":[";
  for (std::size_t k = 0; k < truth.handrails.size(); ++k) {
    const HandrailTruth& h = truth.handrails[k];
    if (k) s += ",";
    s += "{\"index\":" + std::to_string(h.index) + ",\"kind\":\"" + to_string(h.kind) +
         "\",\"ends\":[";
    append_vec(&s, h.ends_cam[0]);
    s += ",";
    append_vec(&s, h.ends_cam[1]);
    s += "],\"center\":";
    append_vec(&s, h.center_cam);
    s += ",\"axis\":";
    append_vec(&s, h.axis_cam);
    s += ",\"normal\":";
    append_vec(&s, h.normal_cam);
    std::snprintf(buf, sizeof buf,
                  ",\"length\":%.4f,\"visible_fraction\":%.3f,\"end_in_view\":[%s,%s]}", h.length_m,
                  h.visible_fraction, h.end_in_view[0] ? "true" : "false",
                  h.end_in_view[1] ? "true" : "false");
    s += buf;
  }
  s += "]}";
  return s;
}

}  // namespace sim_hal
