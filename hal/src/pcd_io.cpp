#include "hal/pcd_io.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>

namespace hal {
namespace {

constexpr std::uint32_t kMaxSide = 8192;

struct Field {
  std::string name;
  int size = 4;
  char type = 'F';
  int count = 1;
  std::size_t offset = 0;  // within a binary record
};

bool fail(std::string* error, const std::string& path, const std::string& what) {
  *error = path + ": " + what;
  return false;
}

std::vector<std::string> split_words(const std::string& line) {
  std::vector<std::string> words;
  std::istringstream in(line);
  std::string w;
  while (in >> w) words.push_back(w);
  return words;
}

bool parse_uint(const std::string& s, std::uint64_t* out) {
  if (s.empty() || s[0] == '-') return false;
  char* end = nullptr;
  const unsigned long long v = std::strtoull(s.c_str(), &end, 10);
  if (*end != '\0') return false;
  *out = v;
  return true;
}

double read_binary_value(const unsigned char* p, const Field& f) {
  switch (f.type) {
    case 'F':
      if (f.size == 4) {
        float v;
        std::memcpy(&v, p, 4);
        return v;
      }
      {
        double v;
        std::memcpy(&v, p, 8);
        return v;
      }
    case 'U':
      if (f.size == 1) return *p;
      if (f.size == 2) {
        std::uint16_t v;
        std::memcpy(&v, p, 2);
        return v;
      }
      if (f.size == 4) {
        std::uint32_t v;
        std::memcpy(&v, p, 4);
        return v;
      }
      {
        std::uint64_t v;
        std::memcpy(&v, p, 8);
        return static_cast<double>(v);
      }
    default:
      if (f.size == 1) {
        std::int8_t v;
        std::memcpy(&v, p, 1);
        return v;
      }
      if (f.size == 2) {
        std::int16_t v;
        std::memcpy(&v, p, 2);
        return v;
      }
      if (f.size == 4) {
        std::int32_t v;
        std::memcpy(&v, p, 4);
        return v;
      }
      {
        std::int64_t v;
        std::memcpy(&v, p, 8);
        return static_cast<double>(v);
      }
  }
}

bool valid_type(char type, int size) {
  if (type == 'F') return size == 4 || size == 8;
  if (type == 'U' || type == 'I') return size == 1 || size == 2 || size == 4 || size == 8;
  return false;
}

// Sets a point from the values of the known fields (NaN where absent).
void assign_point(DepthPoint* p, double x, double y, double z, double gray, double noise,
                  double conf, bool has_conf) {
  const bool finite = std::isfinite(x) && std::isfinite(y) && std::isfinite(z);
  const bool valid = finite && z > 0.0 && (!has_conf || conf > 0.0);
  if (!valid) {
    *p = DepthPoint{0.0f, 0.0f, 0.0f, 0.0f, 0, 0};
  } else {
    p->x_m = static_cast<float>(x);
    p->y_m = static_cast<float>(y);
    p->z_m = static_cast<float>(z);
    p->noise_m = std::isfinite(noise) && noise > 0.0 ? static_cast<float>(noise) : 0.0f;
    p->confidence = has_conf ? static_cast<std::uint8_t>(std::fmin(conf, 255.0)) : 255;
  }
  p->gray_value =
      std::isfinite(gray) && gray > 0.0 ? static_cast<std::uint16_t>(std::fmin(gray, 65535.0)) : 0;
}

}  // namespace

bool parse_pcd(const std::string& bytes, const std::string& path, PcdFrame* out,
               std::string* error) {
  std::vector<Field> fields;
  std::uint64_t width = 0, height = 0, points = 0;
  bool have_points = false, have_width = false, have_height = false;
  std::vector<int> sizes, counts;
  std::vector<char> types;
  std::string data_kind;
  std::size_t pos = 0;
  int line_no = 0;
  while (data_kind.empty()) {
    if (pos >= bytes.size()) return fail(error, path, "header ends before a DATA line");
    std::size_t eol = bytes.find('\n', pos);
    if (eol == std::string::npos) eol = bytes.size();
    std::string line = bytes.substr(pos, eol - pos);
    pos = eol + 1;
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty() || line[0] == '#') continue;
    const std::vector<std::string> w = split_words(line);
    if (w.empty()) continue;
    const std::string where = "header line " + std::to_string(line_no) + " (" + w[0] + ")";
    const std::string& key = w[0];
    if (key == "VERSION") continue;
    if (key == "FIELDS") {
      for (std::size_t k = 1; k < w.size(); ++k) fields.push_back(Field{w[k]});
    } else if (key == "SIZE") {
      for (std::size_t k = 1; k < w.size(); ++k) {
        std::uint64_t v;
        if (!parse_uint(w[k], &v) || v > 8)
          return fail(error, path, where + ": bad size '" + w[k] + "'");
        sizes.push_back(static_cast<int>(v));
      }
    } else if (key == "TYPE") {
      for (std::size_t k = 1; k < w.size(); ++k) {
        if (w[k].size() != 1) return fail(error, path, where + ": bad type '" + w[k] + "'");
        types.push_back(w[k][0]);
      }
    } else if (key == "COUNT") {
      for (std::size_t k = 1; k < w.size(); ++k) {
        std::uint64_t v;
        if (!parse_uint(w[k], &v) || v == 0 || v > 1024)
          return fail(error, path, where + ": bad count '" + w[k] + "'");
        counts.push_back(static_cast<int>(v));
      }
    } else if (key == "WIDTH" || key == "HEIGHT" || key == "POINTS") {
      std::uint64_t v;
      if (w.size() != 2 || !parse_uint(w[1], &v))
        return fail(error, path, where + ": expected one non-negative integer");
      if (key == "WIDTH") {
        width = v;
        have_width = true;
      }
      if (key == "HEIGHT") {
        height = v;
        have_height = true;
      }
      if (key == "POINTS") {
        points = v;
        have_points = true;
      }
    } else if (key == "VIEWPOINT") {
      if (w.size() != 8) return fail(error, path, where + ": expected 7 numbers");
    } else if (key == "DATA") {
      if (w.size() != 2) return fail(error, path, where + ": expected ascii or binary");
      data_kind = w[1];
    } else {
      return fail(error, path, where + ": unknown header keyword");
    }
  }
  if (fields.empty()) return fail(error, path, "no FIELDS line in the header");
  if (sizes.size() != fields.size())
    return fail(error, path,
                "SIZE has " + std::to_string(sizes.size()) + " entries for " +
                    std::to_string(fields.size()) + " fields");
  if (types.size() != fields.size())
    return fail(error, path,
                "TYPE has " + std::to_string(types.size()) + " entries for " +
                    std::to_string(fields.size()) + " fields");
  if (!counts.empty() && counts.size() != fields.size())
    return fail(error, path,
                "COUNT has " + std::to_string(counts.size()) + " entries for " +
                    std::to_string(fields.size()) + " fields");
  if (!have_width || !have_height) return fail(error, path, "WIDTH and HEIGHT are required");
  if (height <= 1)
    return fail(error, path,
                "not an organized cloud (HEIGHT " + std::to_string(height) +
                    "); depth frames are organized");
  if (width == 0 || width > kMaxSide || height > kMaxSide)
    return fail(error, path,
                "WIDTH x HEIGHT " + std::to_string(width) + " x " + std::to_string(height) +
                    " is out of range");
  if (have_points && points != width * height)
    return fail(error, path,
                "POINTS " + std::to_string(points) + " does not equal WIDTH x HEIGHT " +
                    std::to_string(width * height));

  std::size_t record = 0;
  int ix = -1, iy = -1, iz = -1, igray = -1, inoise = -1, iconf = -1;
  for (std::size_t k = 0; k < fields.size(); ++k) {
    Field& f = fields[k];
    f.size = sizes[k];
    f.type = types[k];
    f.count = counts.empty() ? 1 : counts[k];
    if (!valid_type(f.type, f.size))
      return fail(error, path,
                  "field '" + f.name + "' has unsupported TYPE " + f.type + " with SIZE " +
                      std::to_string(f.size));
    f.offset = record;
    record += static_cast<std::size_t>(f.size) * static_cast<std::size_t>(f.count);
    const int i = static_cast<int>(k);
    if (f.name == "x")
      ix = i;
    else if (f.name == "y")
      iy = i;
    else if (f.name == "z")
      iz = i;
    else if (f.name == "intensity" || f.name == "gray" || f.name == "grayValue")
      igray = i;
    else if (f.name == "noise")
      inoise = i;
    else if (f.name == "confidence" || f.name == "depthConfidence")
      iconf = i;
  }
  if (ix < 0 || iy < 0 || iz < 0) return fail(error, path, "FIELDS must include x, y and z");

  const std::size_t n = static_cast<std::size_t>(width * height);
  out->width = static_cast<std::uint32_t>(width);
  out->height = static_cast<std::uint32_t>(height);
  out->points.assign(n, DepthPoint{});
  const double nan = std::numeric_limits<double>::quiet_NaN();

  if (data_kind == "binary") {
    if (bytes.size() - std::min(pos, bytes.size()) < n * record) {
      return fail(error, path,
                  "binary data truncated: " +
                      std::to_string(bytes.size() - std::min(pos, bytes.size())) + " bytes for " +
                      std::to_string(n) + " points of " + std::to_string(record) + " bytes");
    }
    const unsigned char* base = reinterpret_cast<const unsigned char*>(bytes.data()) + pos;
    for (std::size_t i = 0; i < n; ++i) {
      const unsigned char* r = base + i * record;
      auto get = [&](int k) {
        return k < 0 ? nan
                     : read_binary_value(r + fields[static_cast<std::size_t>(k)].offset,
                                         fields[static_cast<std::size_t>(k)]);
      };
      assign_point(&out->points[i], get(ix), get(iy), get(iz), get(igray), get(inoise), get(iconf),
                   iconf >= 0);
    }
    return true;
  }
  if (data_kind != "ascii")
    return fail(error, path, "DATA " + data_kind + " is not supported (ascii or binary)");

  std::size_t columns = 0;
  std::vector<std::size_t> first_column(fields.size());
  for (std::size_t k = 0; k < fields.size(); ++k) {
    first_column[k] = columns;
    columns += static_cast<std::size_t>(fields[k].count);
  }
  std::vector<double> values(columns);
  for (std::size_t i = 0; i < n; ++i) {
    // Skip blank lines between points.
    while (pos < bytes.size() && (bytes[pos] == '\n' || bytes[pos] == '\r')) {
      if (bytes[pos] == '\n') ++line_no;
      ++pos;
    }
    if (pos >= bytes.size())
      return fail(
          error, path,
          "ascii data truncated: " + std::to_string(i) + " of " + std::to_string(n) + " points");
    std::size_t eol = bytes.find('\n', pos);
    if (eol == std::string::npos) eol = bytes.size();
    ++line_no;
    const char* c = bytes.c_str() + pos;
    const char* end_of_line = bytes.c_str() + eol;
    for (std::size_t k = 0; k < columns; ++k) {
      while (c < end_of_line && (*c == ' ' || *c == '\t')) ++c;
      char* next = nullptr;
      const double v = std::strtod(c, &next);
      if (next == c || next > end_of_line) {
        return fail(error, path,
                    "line " + std::to_string(line_no) + ": expected " + std::to_string(columns) +
                        " numbers, found " + std::to_string(k));
      }
      values[k] = v;
      c = next;
    }
    auto get = [&](int k) {
      return k < 0 ? nan : values[first_column[static_cast<std::size_t>(k)]];
    };
    assign_point(&out->points[i], get(ix), get(iy), get(iz), get(igray), get(inoise), get(iconf),
                 iconf >= 0);
    pos = eol + 1;
  }
  return true;
}

bool read_pcd(const std::string& path, PcdFrame* out, std::string* error) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return fail(error, path, "cannot open file");
  std::ostringstream bytes;
  bytes << in.rdbuf();
  return parse_pcd(bytes.str(), path, out, error);
}

std::string encode_pcd(const DepthFrame& frame, PcdEncoding encoding) {
  const std::size_t n = static_cast<std::size_t>(frame.width) * frame.height;
  std::ostringstream out;
  out << "# .PCD v0.7 - Point Cloud Data file format\n"
      << "VERSION 0.7\nFIELDS x y z intensity noise confidence\nSIZE 4 4 4 4 4 1\n"
      << "TYPE F F F F F U\nCOUNT 1 1 1 1 1 1\nWIDTH " << frame.width << "\nHEIGHT " << frame.height
      << "\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS " << n << "\nDATA "
      << (encoding == PcdEncoding::kBinary ? "binary" : "ascii") << "\n";
  std::string s = out.str();
  const float nan = std::numeric_limits<float>::quiet_NaN();
  if (encoding == PcdEncoding::kBinary) {
    s.reserve(s.size() + n * 21);
    for (std::size_t i = 0; i < n; ++i) {
      const DepthPoint& p = frame.points[i];
      const bool valid = is_valid(p);
      const float v[5] = {valid ? p.x_m : nan, valid ? p.y_m : nan, valid ? p.z_m : nan,
                          static_cast<float>(p.gray_value), valid ? p.noise_m : nan};
      s.append(reinterpret_cast<const char*>(v), sizeof v);
      s.push_back(static_cast<char>(valid ? p.confidence : 0));
    }
    return s;
  }
  char line[160];
  for (std::size_t i = 0; i < n; ++i) {
    const DepthPoint& p = frame.points[i];
    if (is_valid(p)) {
      std::snprintf(line, sizeof line, "%.9g %.9g %.9g %u %.9g %u\n", p.x_m, p.y_m, p.z_m,
                    static_cast<unsigned>(p.gray_value), p.noise_m,
                    static_cast<unsigned>(p.confidence));
    } else {
      std::snprintf(line, sizeof line, "nan nan nan %u nan 0\n",
                    static_cast<unsigned>(p.gray_value));
    }
    s += line;
  }
  return s;
}

bool write_pcd(const std::string& path, const DepthFrame& frame, PcdEncoding encoding,
               std::string* error) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) return fail(error, path, "cannot create file");
  const std::string bytes = encode_pcd(frame, encoding);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (!out) return fail(error, path, "write failed");
  return true;
}

}  // namespace hal
