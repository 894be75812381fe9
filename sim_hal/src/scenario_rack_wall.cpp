#include <cmath>
#include <string>

#include "scenario_reader.hpp"

namespace sim_hal {
namespace scenario_detail {
namespace {

// Rack-wall coordinates are bounded so that a typo (centimetres for metres)
// is an error rather than a 60 m wall.
constexpr double kWallExtentM = 20.0;

// The front-most face containing (u, v), 1 mm of slack at its edges; false
// when no face does.
bool face_depth_at(const RackWall& w, double u, double v, double* depth_m) {
  bool found = false;
  for (const RackWall::Face& f : w.faces) {
    if (u < f.rect.u0 - 1e-3 || u > f.rect.u1 + 1e-3 || v < f.rect.v0 - 1e-3 ||
        v > f.rect.v1 + 1e-3)
      continue;
    if (!found || f.depth_m > *depth_m) *depth_m = f.depth_m;
    found = true;
  }
  return found;
}

bool read_wall_rect(Reader& r, const JsonValue& obj, WallRect* rect) {
  r.range(obj, "u", -kWallExtentM, kWallExtentM, &rect->u0, &rect->u1, true);
  r.range(obj, "v", -kWallExtentM, kWallExtentM, &rect->v0, &rect->v1, true);
  return r.ok();
}

// The depth a track or strip stands on: given, or the face under its centre.
bool base_depth(Reader& r, const JsonValue& obj, const RackWall& w, double u, double v,
                const char* what, double* depth_m) {
  if (obj.find("depth")) return r.number(obj, "depth", -1.0, 0.5, depth_m, true);
  if (face_depth_at(w, u, v, depth_m)) return true;
  return r.fail(obj,
                std::string("no rack face under the ") + what + "'s centre: give its \"depth\"");
}

}  // namespace

void read_rack_wall(Reader& r, const JsonValue& rw, Scene* scene) {
  r.unknown_keys(rw,
                 {"center", "normal", "up", "back_depth", "reflectivity", "faces", "seat_tracks",
                  "gaps", "bays", "strips"},
                 "a rack wall");
  RackWall w;
  double refl = 0.6;
  r.vec3(rw, "center", &w.center, true);
  r.vec3(rw, "normal", &w.normal, true, true);
  r.vec3(rw, "up", &w.up, false, true);
  r.number(rw, "back_depth", -2.0, -0.01, &w.back_depth_m, false);
  r.number(rw, "reflectivity", 0.01, 1.0, &refl, false);
  if (!r.ok()) return;
  if (std::fabs(w.up.dot(w.normal)) > 0.99) {
    r.fail(rw, "\"up\" must not be parallel to \"normal\"");
    return;
  }
  const JsonValue* faces = r.member(rw, "faces", JsonValue::Type::kArray, true);
  if (!r.ok()) return;
  if (faces->items.empty()) {
    r.fail(*faces, "\"faces\" must hold at least one rack face");
    return;
  }
  for (const JsonValue& f : faces->items) {
    if (!f.is_object()) {
      r.fail(f, "a rack face must be an object");
      return;
    }
    r.unknown_keys(f, {"u", "v", "depth", "reflectivity"}, "a rack face");
    RackWall::Face face;
    face.reflectivity = refl;
    read_wall_rect(r, f, &face.rect);
    r.number(f, "depth", -1.0, 0.5, &face.depth_m, false);
    r.number(f, "reflectivity", 0.01, 1.0, &face.reflectivity, false);
    if (!r.ok()) return;
    if (face.depth_m < w.back_depth_m + 0.01) {
      r.fail(f, "a rack face's \"depth\" must be at least 1 cm in front of \"back_depth\"");
      return;
    }
    w.faces.push_back(face);
  }
  if (const JsonValue* tracks = r.member(rw, "seat_tracks", JsonValue::Type::kArray, false)) {
    for (const JsonValue& t : tracks->items) {
      if (!t.is_object()) {
        r.fail(t, "a seat track must be an object");
        return;
      }
      r.unknown_keys(t, {"from", "to", "depth", "width", "height", "reflectivity"}, "a seat track");
      RackWall::SeatTrack track;
      track.reflectivity = 0.5;
      r.vec2(t, "from", -kWallExtentM, kWallExtentM, &track.from, true);
      r.vec2(t, "to", -kWallExtentM, kWallExtentM, &track.to, true);
      r.number(t, "width", 0.005, 0.1, &track.width_m, false);
      r.number(t, "height", 0.002, 0.05, &track.height_m, false);
      r.number(t, "reflectivity", 0.01, 1.0, &track.reflectivity, false);
      if (!r.ok()) return;
      if ((track.to - track.from).norm() < 0.05) {
        r.fail(t, "a seat track must be at least 5 cm long");
        return;
      }
      const Eigen::Vector2d mid = 0.5 * (track.from + track.to);
      if (!base_depth(r, t, w, mid.x(), mid.y(), "seat track", &track.base_depth_m)) return;
      w.seat_tracks.push_back(track);
    }
  }
  for (const char* key : {"gaps", "bays"}) {
    const bool bay = std::string(key) == "bays";
    const JsonValue* list = r.member(rw, key, JsonValue::Type::kArray, false);
    if (!list) continue;
    for (const JsonValue& g : list->items) {
      if (!g.is_object()) {
        r.fail(g, std::string("a ") + (bay ? "bay" : "gap") + " must be an object");
        return;
      }
      RackWall::Recess rec;
      read_wall_rect(r, g, &rec.rect);
      r.number(g, "reflectivity", 0.01, 1.0, &rec.reflectivity, false);
      if (bay) {
        // An empty rack bay: a box recess about 35 cm deep.
        r.unknown_keys(g, {"u", "v", "depth", "rim", "reflectivity"}, "a bay");
        rec.depth_m = -0.35;
        rec.side_walls = true;
        r.number(g, "depth", -1.5, -0.01, &rec.depth_m, false);
        r.number(g, "rim", -1.0, 0.5, &rec.rim_depth_m, false);
        if (r.ok() && rec.rim_depth_m < rec.depth_m + 0.01) {
          r.fail(g, "a bay's \"rim\" must be at least 1 cm in front of its \"depth\"");
          return;
        }
      } else {
        // A gap between racks: a surface about 12 cm back, or, without
        // "depth", an opening that returns nothing.
        r.unknown_keys(g, {"u", "v", "depth", "reflectivity"}, "a gap");
        rec.has_back = g.find("depth") != nullptr;
        r.number(g, "depth", -1.5, 0.5, &rec.depth_m, false);
      }
      if (!r.ok()) return;
      w.recesses.push_back(rec);
    }
  }
  if (const JsonValue* strips = r.member(rw, "strips", JsonValue::Type::kArray, false)) {
    for (const JsonValue& st : strips->items) {
      if (!st.is_object()) {
        r.fail(st, "a strip must be an object");
        return;
      }
      r.unknown_keys(st, {"u", "v", "depth", "height", "reflectivity"}, "a strip");
      RackWall::Strip strip;
      read_wall_rect(r, st, &strip.rect);
      r.number(st, "height", 0.001, 0.05, &strip.height_m, false);
      r.number(st, "reflectivity", 0.01, 1.0, &strip.reflectivity, false);
      if (!r.ok()) return;
      if (!base_depth(r, st, w, 0.5 * (strip.rect.u0 + strip.rect.u1),
                      0.5 * (strip.rect.v0 + strip.rect.v1), "strip", &strip.base_depth_m))
        return;
      w.strips.push_back(strip);
    }
  }
  scene->add_rack_wall(w);
}

}  // namespace scenario_detail
}  // namespace sim_hal
