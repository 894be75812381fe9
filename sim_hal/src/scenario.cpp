#include "sim_hal/scenario.hpp"

#include <cmath>
#include <map>
#include <memory>
#include <sstream>

#include "formats/json.hpp"
#include "formats/text_file.hpp"
#include "scenario_reader.hpp"

namespace sim_hal {
namespace {

using formats::JsonValue;

constexpr double kDegToRad = 3.14159265358979323846 / 180.0;
constexpr std::size_t kMaxFrames = 100000;

using scenario_detail::read_rack_wall;
using scenario_detail::Reader;

Eigen::Matrix3d rotation_rpy_deg(const Eigen::Vector3d& rpy) {
  return (Eigen::AngleAxisd(rpy.z() * kDegToRad, Eigen::Vector3d::UnitZ()) *
          Eigen::AngleAxisd(rpy.y() * kDegToRad, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(rpy.x() * kDegToRad, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

void read_sensor(Reader& r, const JsonValue& s, ToFSettings* t) {
  r.unknown_keys(
      s,
      {"noise", "flying_pixels", "flying_filter", "invalid_pixels", "multipath", "noise_ref_m",
       "flying_probability", "multipath_gain_m", "amplitude_min", "range_min_m", "range_max_m"},
      "sensor");
  r.flag(s, "noise", &t->noise);
  r.flag(s, "flying_pixels", &t->flying_pixels);
  r.flag(s, "flying_filter", &t->flying_filter);
  r.flag(s, "invalid_pixels", &t->invalid_pixels);
  r.flag(s, "multipath", &t->multipath);
  r.number(s, "noise_ref_m", 0.0, 0.1, &t->noise_ref_m, false);
  r.number(s, "flying_probability", 0.0, 1.0, &t->flying_probability, false);
  r.number(s, "multipath_gain_m", 0.0, 0.1, &t->multipath_gain_m, false);
  r.number(s, "amplitude_min", 0.0, 4095.0, &t->amplitude_min, false);
  r.number(s, "range_min_m", 0.0, 10.0, &t->range_min_m, false);
  r.number(s, "range_max_m", 0.1, 20.0, &t->range_max_m, false);
}

using MeshCache = std::map<std::string, std::shared_ptr<const TriangleMesh>>;

// A mesh file named relative to the scenario file's folder, loaded once per
// scenario. Null (and the reader failed) when it cannot be read.
std::shared_ptr<const TriangleMesh> load_mesh(Reader& r, const JsonValue& at, MeshCache* meshes,
                                              std::string* file_out) {
  std::string file = at.text;
  const std::size_t slash = r.path().find_last_of('/');
  if (!file.empty() && file[0] != '/' && slash != std::string::npos) {
    file = r.path().substr(0, slash + 1) + file;
  }
  if (file_out) *file_out = file;
  auto cached = meshes->find(file);
  if (cached == meshes->end()) {
    std::vector<Eigen::Vector3d> vertices;
    std::vector<Eigen::Vector3i> triangles;
    std::string error;
    if (!load_collada_mesh(file, &vertices, &triangles, &error)) {
      r.fail(at, error);
      return nullptr;
    }
    cached = meshes
                 ->emplace(file, std::make_shared<const TriangleMesh>(std::move(vertices),
                                                                      std::move(triangles)))
                 .first;
  }
  return cached->second;
}

// A mesh's "handrails": [{"ends": [[x, y, z], [x, y, z]], "normal": [x, y, z]}, ...],
// in the mesh's frame; the normal perpendicular to the centre line.
bool read_mesh_handrails(Reader& r, const JsonValue& list, std::vector<MeshHandrail>* out) {
  for (const JsonValue& h : list.items) {
    if (!h.is_object()) return r.fail(h, "a mesh handrail must be an object");
    r.unknown_keys(h, {"ends", "normal", "length_m", "bar_section_m"}, "a mesh handrail");
    MeshHandrail rail;
    const JsonValue* ends = r.member(h, "ends", JsonValue::Type::kArray, true);
    if (!r.vec3(h, "normal", &rail.normal, true, true) || !ends) return false;
    if (ends->items.size() != 2) return r.fail(*ends, "\"ends\" must be two points");
    for (int e = 0; e < 2; ++e) {
      const JsonValue& p = ends->items[static_cast<std::size_t>(e)];
      if (!p.is_array() || p.items.size() != 3 || !p.items[0].is_number() ||
          !p.items[1].is_number() || !p.items[2].is_number()) {
        return r.fail(p, "each of \"ends\" must be [x, y, z]");
      }
      rail.ends[e] = Eigen::Vector3d(p.items[0].number, p.items[1].number, p.items[2].number);
    }
    const Eigen::Vector3d along = rail.ends[1] - rail.ends[0];
    if (!(along.norm() >= 0.05 && along.norm() <= 2.0)) {
      return r.fail(*ends, "\"ends\" must be 0.05 to 2 m apart");
    }
    if (std::fabs(along.normalized().dot(rail.normal)) > 1e-3) {
      return r.fail(h, "\"normal\" must be perpendicular to the line between \"ends\"");
    }
    out->push_back(rail);
  }
  return r.ok();
}

void read_scene(Reader& r, const JsonValue& sc, Scene* scene, MeshCache* meshes) {
  r.unknown_keys(sc, {"walls", "rack_walls", "meshes", "handrails", "cables", "boxes", "pipes"},
                 "scene");
  // Something to stand handrails on: plain walls, rack walls or a mesh
  // (a module's interior).
  const bool other_structure = sc.find("rack_walls") != nullptr || sc.find("meshes") != nullptr;
  if (const JsonValue* walls = r.member(sc, "walls", JsonValue::Type::kArray, !other_structure)) {
    if (walls->items.empty() && !other_structure)
      r.fail(*walls, "\"walls\" must hold at least one wall");
    for (const JsonValue& w : walls->items) {
      if (!w.is_object()) {
        r.fail(w, "a wall must be an object");
        return;
      }
      r.unknown_keys(w, {"center", "normal", "up", "size", "reflectivity"}, "a wall");
      Eigen::Vector3d c, n, up(0, 0, 1);
      double refl = 0.6;
      r.vec3(w, "center", &c, true);
      r.vec3(w, "normal", &n, true, true);
      r.vec3(w, "up", &up, false, true);
      r.number(w, "reflectivity", 0.01, 1.0, &refl, false);
      const JsonValue* size = r.member(w, "size", JsonValue::Type::kArray, true);
      if (!r.ok()) return;
      if (size->items.size() != 2 || !size->items[0].is_number() || !size->items[1].is_number() ||
          size->items[0].number <= 0 || size->items[1].number <= 0) {
        r.fail(*size, "\"size\" must be [width_m, height_m], both positive");
        return;
      }
      if (std::fabs(up.dot(n)) > 0.99) {
        r.fail(w, "\"up\" must not be parallel to \"normal\"");
        return;
      }
      scene->add_wall(c, n, up, size->items[0].number, size->items[1].number, refl);
    }
  }
  if (const JsonValue* racks = r.member(sc, "rack_walls", JsonValue::Type::kArray, false)) {
    for (const JsonValue& rw : racks->items) {
      if (!rw.is_object()) {
        r.fail(rw, "a rack wall must be an object");
        return;
      }
      read_rack_wall(r, rw, scene);
      if (!r.ok()) return;
    }
  }
  // The handrails meshes model, made the scene's after its own handrails
  // (so that a scenario's first handrail stays its first).
  struct PendingMeshHandrails {
    std::size_t mesh_index = 0;
    const JsonValue* list = nullptr;
    std::vector<MeshHandrail> rails;
  };
  std::vector<PendingMeshHandrails> pending;
  if (const JsonValue* list = r.member(sc, "meshes", JsonValue::Type::kArray, false)) {
    for (const JsonValue& m : list->items) {
      if (!m.is_object()) {
        r.fail(m, "a mesh must be an object");
        return;
      }
      r.unknown_keys(m, {"path", "position", "rpy_deg", "reflectivity", "handrails"}, "a mesh");
      Eigen::Vector3d rpy = Eigen::Vector3d::Zero();
      SceneMesh placed;
      double refl = 0.5;
      r.vec3(m, "position", &placed.t, false);
      r.vec3(m, "rpy_deg", &rpy, false);
      r.number(m, "reflectivity", 0.01, 1.0, &refl, false);
      const JsonValue* path = r.member(m, "path", JsonValue::Type::kString, true);
      if (!r.ok()) return;
      placed.mesh = load_mesh(r, *path, meshes, &placed.path);
      if (!placed.mesh) return;
      placed.R = rotation_rpy_deg(rpy);
      scene->add_mesh(placed, refl);
      if (const JsonValue* rails = r.member(m, "handrails", JsonValue::Type::kArray, false)) {
        PendingMeshHandrails p;
        p.mesh_index = scene->meshes.size() - 1;
        p.list = rails;
        if (!read_mesh_handrails(r, *rails, &p.rails)) return;
        pending.push_back(std::move(p));
      }
      if (!r.ok()) return;
    }
  }
  if (const JsonValue* rails = r.member(sc, "handrails", JsonValue::Type::kArray, false)) {
    for (const JsonValue& h : rails->items) {
      if (!h.is_object()) {
        r.fail(h, "a handrail must be an object");
        return;
      }
      r.unknown_keys(h, {"kind", "foot", "normal", "axis", "length", "mesh", "reflectivity"},
                     "a handrail");
      Handrail rail{};
      const JsonValue* kind = r.member(h, "kind", JsonValue::Type::kString, true);
      if (!r.ok()) return;
      if (kind->text == "round") {
        rail.kind = HandrailKind::kPaperRound;
      } else if (kind->text == "iss") {
        rail.kind = HandrailKind::kIss;
      } else if (kind->text == "iss_mesh") {
        rail.kind = HandrailKind::kIssMesh;
      } else if (kind->text == "module_rail") {
        rail.kind = HandrailKind::kModuleRail;
      } else {
        r.fail(*kind,
               "\"kind\" must be \"round\", \"iss\", \"iss_mesh\" or \"module_rail\", not \"" +
                   kind->text + "\"");
        return;
      }
      rail.reflectivity = 0.5;
      r.vec3(h, "foot", &rail.foot_center, true);
      r.vec3(h, "normal", &rail.normal, true, true);
      r.vec3(h, "axis", &rail.axis, true, true);
      if (rail.kind == HandrailKind::kIssMesh) {
        if (const JsonValue* length = h.find("length")) {
          r.fail(*length,
                 "an \"iss_mesh\" handrail takes its length from the mesh: drop \"length\"");
          return;
        }
        const JsonValue* mesh = r.member(h, "mesh", JsonValue::Type::kString, true);
        if (!r.ok()) return;
        std::string file;
        rail.mesh = load_mesh(r, *mesh, meshes, &file);
        if (!rail.mesh) return;
        // Above the legs' tops (the bar's underside is ~4.4 cm off the wall).
        rail.mesh_bar = measure_bar(*rail.mesh, 0.046);
        rail.bar_length_m = rail.mesh_bar.length_m();
        if (!(rail.bar_length_m > 0.05 && rail.mesh_bar.center_offset_m() > 0.02)) {
          r.fail(*mesh, file + " does not look like an ISS handrail model (no bar found)");
          return;
        }
      } else {
        if (const JsonValue* mesh = h.find("mesh")) {
          r.fail(*mesh, "\"mesh\" is for \"iss_mesh\" handrails only");
          return;
        }
        r.number(h, "length", 0.1, 2.0, &rail.bar_length_m, true);
      }
      r.number(h, "reflectivity", 0.01, 1.0, &rail.reflectivity, false);
      if (!r.ok()) return;
      if (std::fabs(rail.axis.dot(rail.normal)) > 1e-3) {
        r.fail(h, "\"axis\" must be perpendicular to \"normal\"");
        return;
      }
      scene->add_handrail(rail);
    }
  }
  for (const PendingMeshHandrails& p : pending) {
    const int refused = scene->add_mesh_handrails(p.mesh_index, p.rails);
    if (refused >= 0) {
      const std::size_t k = static_cast<std::size_t>(refused);
      r.fail(p.list->items[k], "mesh handrail " + std::to_string(k) + " has no legs of " +
                                   scene->meshes[p.mesh_index].path +
                                   " behind its centre line: check its \"ends\" and "
                                   "\"normal\" (toward the room; mesh_handrails.py prints them)");
      return;
    }
  }
  for (const char* key : {"cables", "pipes"}) {
    const JsonValue* list = r.member(sc, key, JsonValue::Type::kArray, false);
    if (!list) continue;
    for (const JsonValue& c : list->items) {
      if (!c.is_object()) {
        r.fail(c, "a cable must be an object");
        return;
      }
      r.unknown_keys(c, {"points", "diameter", "reflectivity"}, key);
      double diameter = 0.0, refl = 0.3;
      r.number(c, "diameter", 0.002, 0.2, &diameter, true);
      r.number(c, "reflectivity", 0.01, 1.0, &refl, false);
      const JsonValue* pts = r.member(c, "points", JsonValue::Type::kArray, true);
      if (!r.ok()) return;
      if (pts->items.size() < 2) {
        r.fail(*pts, "\"points\" needs at least 2 points");
        return;
      }
      std::vector<Eigen::Vector3d> points;
      for (const JsonValue& p : pts->items) {
        if (!p.is_array() || p.items.size() != 3 || !p.items[0].is_number() ||
            !p.items[1].is_number() || !p.items[2].is_number()) {
          r.fail(p, "each point must be [x, y, z]");
          return;
        }
        points.emplace_back(p.items[0].number, p.items[1].number, p.items[2].number);
      }
      scene->add_cable(points, diameter, refl);
    }
  }
  if (const JsonValue* boxes = r.member(sc, "boxes", JsonValue::Type::kArray, false)) {
    for (const JsonValue& b : boxes->items) {
      if (!b.is_object()) {
        r.fail(b, "a box must be an object");
        return;
      }
      r.unknown_keys(b, {"center", "size", "rpy_deg", "reflectivity"}, "a box");
      Eigen::Vector3d c, size, rpy = Eigen::Vector3d::Zero();
      double refl = 0.5;
      r.vec3(b, "center", &c, true);
      r.vec3(b, "size", &size, true);
      r.vec3(b, "rpy_deg", &rpy, false);
      r.number(b, "reflectivity", 0.01, 1.0, &refl, false);
      if (!r.ok()) return;
      if (size.minCoeff() <= 0.0) {
        r.fail(b, "box \"size\" must be positive");
        return;
      }
      scene->add_box(c, rotation_rpy_deg(rpy), size, refl);
    }
  }
}

bool read_pose(Reader& r, const JsonValue& p, Eigen::Vector3d* pos, Eigen::Vector3d* facing,
               Eigen::Vector3d* up, Eigen::Vector3d* rpy) {
  *facing = Eigen::Vector3d(-1, 0, 0);
  *up = Eigen::Vector3d(0, 0, 1);
  *rpy = Eigen::Vector3d::Zero();
  r.vec3(p, "position", pos, true);
  r.vec3(p, "facing", facing, false, true);
  r.vec3(p, "up", up, false, true);
  r.vec3(p, "rpy_deg", rpy, false);
  if (r.ok() && std::fabs(facing->dot(*up)) > 0.99)
    return r.fail(p, "\"up\" must not be parallel to \"facing\"");
  return r.ok();
}

void read_poses(Reader& r, const JsonValue& root, Scenario* s) {
  const JsonValue* poses = r.member(root, "poses", JsonValue::Type::kArray, true);
  if (!poses) return;
  if (poses->items.empty()) {
    r.fail(*poses, "\"poses\" must hold at least one pose");
    return;
  }
  for (const JsonValue& p : poses->items) {
    if (!p.is_object()) {
      r.fail(p, "a pose must be an object");
      return;
    }
    r.unknown_keys(p, {"label", "position", "facing", "up", "rpy_deg", "frames", "to"}, "a pose");
    double frames = 1;
    r.number(p, "frames", 1, kMaxFrames, &frames, false);
    Eigen::Vector3d pos, facing, up, rpy;
    if (!read_pose(r, p, &pos, &facing, &up, &rpy)) return;
    std::string label;
    if (const JsonValue* l = r.member(p, "label", JsonValue::Type::kString, false)) label = l->text;
    // With "to", the camera moves linearly from this pose to that one over
    // the frames; without it, it holds still.
    Eigen::Vector3d pos1 = pos, rpy1 = rpy, facing1, up1;
    if (const JsonValue* to = r.member(p, "to", JsonValue::Type::kObject, false)) {
      r.unknown_keys(*to, {"position", "rpy_deg", "facing", "up"}, "\"to\"");
      if (!read_pose(r, *to, &pos1, &facing1, &up1, &rpy1)) return;
    }
    if (!r.ok()) return;
    const int n = static_cast<int>(frames);
    if (s->T_world_cam.size() + static_cast<std::size_t>(n) > kMaxFrames) {
      r.fail(p, "too many frames in the scenario (limit 100000)");
      return;
    }
    for (int k = 0; k < n; ++k) {
      const double f = n > 1 ? static_cast<double>(k) / (n - 1) : 0.0;
      s->T_world_cam.push_back(
          camera_pose(pos + f * (pos1 - pos), facing, up, rpy + f * (rpy1 - rpy)));
      s->pose_labels.push_back(label);
    }
  }
}

}  // namespace

Eigen::Isometry3d camera_pose(const Eigen::Vector3d& position, const Eigen::Vector3d& facing,
                              const Eigen::Vector3d& up, const Eigen::Vector3d& rpy_deg) {
  const Eigen::Vector3d x = facing.normalized();
  const Eigen::Vector3d z = (up - up.dot(x) * x).normalized();
  Eigen::Matrix3d R_world_base;
  R_world_base.col(0) = x;
  R_world_base.col(1) = z.cross(x);
  R_world_base.col(2) = z;
  const Eigen::Matrix3d R_world_body = R_world_base * rotation_rpy_deg(rpy_deg);
  Eigen::Matrix3d R_body_cam;
  R_body_cam.col(0) = Eigen::Vector3d(0, -1, 0);  // camera x = body right
  R_body_cam.col(1) = Eigen::Vector3d(0, 0, -1);  // camera y = body down
  R_body_cam.col(2) = Eigen::Vector3d(1, 0, 0);   // camera z = body forward
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = R_world_body * R_body_cam;
  T.translation() = position;
  return T;
}

bool parse_scenario(const std::string& text, const std::string& path, Scenario* out,
                    std::string* error) {
  *out = Scenario{};
  JsonValue root;
  std::string json_error;
  if (!formats::parse_json(text, &root, &json_error)) {
    *error = path + ":" + json_error.substr(5);  // "line N: ..." -> "N: ..."
    return false;
  }
  Reader r(path);
  if (!root.is_object()) {
    *error = path + ":" + std::to_string(root.line) + ": a scenario must be a JSON object";
    return false;
  }
  r.unknown_keys(root,
                 {"name", "description", "seed", "frame_rate_hz", "gripper_angle_deg", "sensor",
                  "scene", "poses"},
                 "the scenario");
  if (const JsonValue* name = r.member(root, "name", JsonValue::Type::kString, true))
    out->name = name->text;
  if (const JsonValue* d = r.member(root, "description", JsonValue::Type::kString, false))
    out->description = d->text;
  double seed = 1;
  r.number(root, "seed", 0, 9007199254740991.0, &seed, false);
  out->seed = static_cast<std::uint64_t>(seed);
  r.number(root, "frame_rate_hz", 0.1, 1000.0, &out->frame_rate_hz, false);
  r.number(root, "gripper_angle_deg", 0.0, 90.0, &out->gripper_angle_deg, false);
  if (const JsonValue* s = r.member(root, "sensor", JsonValue::Type::kObject, false))
    read_sensor(r, *s, &out->sensor);
  if (const JsonValue* sc = r.member(root, "scene", JsonValue::Type::kObject, true)) {
    MeshCache meshes;
    read_scene(r, *sc, &out->scene, &meshes);
  }
  if (r.ok()) read_poses(r, root, out);
  if (!r.ok()) {
    *error = r.error();
    return false;
  }
  return true;
}

bool load_scenario(const std::string& path, Scenario* out, std::string* error) {
  std::string text;
  if (formats::read_file_bounded(path, formats::kMaxTextFileBytes, &text, error) !=
      formats::FileStatus::kOk) {
    return false;
  }
  return parse_scenario(text, path, out, error);
}

}  // namespace sim_hal
