#include "formats/pcd_io.hpp"

#include <lzf.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>
#include <utility>

#include "formats/text_file.hpp"

namespace formats {
namespace {

constexpr std::uint32_t kMaxSide = 8192;

// binary_compressed data starts with two little-endian uint32: the size of
// the LZF stream, then the size of the payload once decompressed.
constexpr std::size_t kCompressedSizesBytes = 8;
constexpr std::uint64_t kLzfMaxExpansion = 264 / 3;

struct Field {
  std::string name;
  int size = 4;
  char type = 'F';
  int count = 1;
  std::uint64_t offset = 0;  // within a binary record

  std::uint64_t bytes() const {
    return static_cast<std::uint64_t>(size) * static_cast<std::uint64_t>(count);
  }
  // PCL names padding "_". Binary records include its bytes; PCL leaves it
  // out of binary_compressed payloads (its writer drops it from the header,
  // its reader skips it), so it holds no bytes there.
  bool is_padding() const { return name == "_"; }
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

std::uint32_t read_le_u32(const unsigned char* p) {
  return static_cast<std::uint32_t>(p[0]) | static_cast<std::uint32_t>(p[1]) << 8 |
         static_cast<std::uint32_t>(p[2]) << 16 | static_cast<std::uint32_t>(p[3]) << 24;
}

void append_le_u32(std::string* s, std::uint32_t v) {
  for (int shift = 0; shift < 32; shift += 8) s->push_back(static_cast<char>((v >> shift) & 0xff));
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
void assign_point(hal::DepthPoint* p, double x, double y, double z, double gray, double noise,
                  double conf, bool has_conf) {
  const bool finite = std::isfinite(x) && std::isfinite(y) && std::isfinite(z);
  const bool valid = finite && z > 0.0 && (!has_conf || conf > 0.0);
  if (!valid) {
    *p = hal::DepthPoint{0.0f, 0.0f, 0.0f, 0.0f, 0, 0};
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

// Indices into the header's fields of the ones a depth point is made of.
struct KnownFields {
  int x = -1, y = -1, z = -1, gray = -1, noise = -1, conf = -1;
};

// Where each field's values lie in memory: point i's value of field k starts
// at first[k] + i * stride[k]. One record after another for binary data,
// one field's values after another for binary_compressed.
struct BinaryLayout {
  std::vector<const unsigned char*> first;
  std::vector<std::uint64_t> stride;
};

void assign_binary_points(const std::vector<Field>& fields, const KnownFields& known,
                          const BinaryLayout& layout, std::vector<hal::DepthPoint>* points) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (std::size_t i = 0; i < points->size(); ++i) {
    auto get = [&](int k) {
      if (k < 0) return nan;
      const std::size_t kk = static_cast<std::size_t>(k);
      return read_binary_value(layout.first[kk] + i * layout.stride[kk], fields[kk]);
    };
    assign_point(&(*points)[i], get(known.x), get(known.y), get(known.z), get(known.gray),
                 get(known.noise), get(known.conf), known.conf >= 0);
  }
}

// The payload after `DATA binary_compressed`, checked against the file and
// the header before the decompression buffer is allocated.
bool read_compressed_points(const std::string& bytes, std::size_t pos, const std::string& path,
                            const std::vector<Field>& fields, const KnownFields& known,
                            std::uint64_t n, std::vector<hal::DepthPoint>* points,
                            std::string* error) {
  const std::size_t left = bytes.size() - std::min(pos, bytes.size());
  if (left < kCompressedSizesBytes)
    return fail(error, path,
                "binary_compressed data truncated: " + std::to_string(left) +
                    " bytes after the header, need 8 for the compressed and uncompressed sizes");
  const unsigned char* base = reinterpret_cast<const unsigned char*>(bytes.data()) + pos;
  const std::uint32_t compressed_bytes = read_le_u32(base);
  const std::uint32_t uncompressed_bytes = read_le_u32(base + 4);
  const std::size_t stream_left = left - kCompressedSizesBytes;

  std::uint64_t point_bytes = 0;
  for (const Field& f : fields)
    if (!f.is_padding()) point_bytes += f.bytes();
  const std::uint64_t expected_bytes = n * point_bytes;
  if (uncompressed_bytes > kMaxPcdUncompressedBytes)
    return fail(error, path,
                "binary_compressed uncompressed size " + std::to_string(uncompressed_bytes) +
                    " bytes is over the limit of " + std::to_string(kMaxPcdUncompressedBytes) +
                    " bytes");
  if (uncompressed_bytes != expected_bytes)
    return fail(error, path,
                "binary_compressed uncompressed size " + std::to_string(uncompressed_bytes) +
                    " bytes does not equal " + std::to_string(n) + " points x " +
                    std::to_string(point_bytes) + " bytes = " + std::to_string(expected_bytes));
  // Bytes after the stream are ignored: PCL 1.13 pads its files with zeros
  // to a whole 4096-byte page.
  if (compressed_bytes > stream_left)
    return fail(error, path,
                "binary_compressed compressed size " + std::to_string(compressed_bytes) +
                    " bytes is more than the " + std::to_string(stream_left) +
                    " bytes left in the file");

  // An LZF back reference of 3 bytes copies at most 264, so a stream can
  // grow 88 times at most: a tiny file cannot make room for a huge payload.
  if (uncompressed_bytes > kLzfMaxExpansion * static_cast<std::uint64_t>(compressed_bytes))
    return fail(error, path,
                "binary_compressed uncompressed size " + std::to_string(uncompressed_bytes) +
                    " bytes is more than LZF can expand " + std::to_string(compressed_bytes) +
                    " compressed bytes to (" + std::to_string(kLzfMaxExpansion) +
                    " times as many)");

  points->assign(static_cast<std::size_t>(n), hal::DepthPoint{});
  std::vector<unsigned char> payload(uncompressed_bytes);
  errno = 0;
  const unsigned int got_bytes = lzf_decompress(base + kCompressedSizesBytes, compressed_bytes,
                                                payload.data(), uncompressed_bytes);
  if (got_bytes == 0) {
    // liblzf reports why through errno: E2BIG when the stream holds more
    // than the buffer, EINVAL when it is corrupt.
    return fail(error, path,
                errno == E2BIG ? "LZF data decompresses to more than the uncompressed size " +
                                     std::to_string(uncompressed_bytes) + " bytes"
                               : std::string("LZF decompression failed: corrupt compressed data"));
  }
  if (got_bytes != uncompressed_bytes)
    return fail(error, path,
                "LZF data decompressed to " + std::to_string(got_bytes) +
                    " bytes, not the uncompressed size " + std::to_string(uncompressed_bytes) +
                    " bytes");

  BinaryLayout layout;
  std::uint64_t plane = 0;
  for (const Field& f : fields) {
    // Padding has no plane; no known field is named "_", so it is never read.
    layout.first.push_back(payload.data() + plane);
    layout.stride.push_back(f.bytes());
    if (!f.is_padding()) plane += n * f.bytes();
  }
  assign_binary_points(fields, known, layout, points);
  return true;
}

// The values our writer stores for one point, in FIELDS order but the last.
struct EncodedPoint {
  float values[5];
  std::uint8_t confidence;
};

EncodedPoint encode_point(const hal::DepthPoint& p) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const bool valid = is_valid(p);
  return EncodedPoint{{valid ? p.x_m : nan, valid ? p.y_m : nan, valid ? p.z_m : nan,
                       static_cast<float>(p.gray_value), valid ? p.noise_m : nan},
                      static_cast<std::uint8_t>(valid ? p.confidence : 0)};
}

const char* data_keyword(PcdEncoding encoding) {
  switch (encoding) {
    case PcdEncoding::kBinary:
      return "binary";
    case PcdEncoding::kBinaryCompressed:
      return "binary_compressed";
    case PcdEncoding::kAscii:
      break;
  }
  return "ascii";
}

// Appends the sizes and the LZF stream of the frame's fields, each field's
// values for all points in turn (as PCL lays them out: similar values side
// by side compress better). False if LZF fails.
bool append_compressed(const hal::DepthFrame& frame, std::size_t n, std::string* s) {
  constexpr std::size_t kFloatFields = 5;
  const std::size_t float_plane_bytes = n * sizeof(float);
  std::vector<unsigned char> payload(n * (kFloatFields * sizeof(float) + 1));
  for (std::size_t i = 0; i < n; ++i) {
    const EncodedPoint e = encode_point(frame.points[i]);
    for (std::size_t k = 0; k < kFloatFields; ++k)
      std::memcpy(&payload[k * float_plane_bytes + i * sizeof(float)], &e.values[k], sizeof(float));
    payload[kFloatFields * float_plane_bytes + i] = e.confidence;
  }
  if (payload.empty()) {
    append_le_u32(s, 0);
    append_le_u32(s, 0);
    return true;
  }
  // LZF output may exceed its input by up to about 1/32 on incompressible
  // data; lzf_compress returns 0 when the buffer is too small.
  std::vector<unsigned char> stream(payload.size() + payload.size() / 16 + 64);
  const unsigned int compressed_bytes =
      lzf_compress(payload.data(), static_cast<unsigned int>(payload.size()), stream.data(),
                   static_cast<unsigned int>(stream.size()));
  if (compressed_bytes == 0) return false;
  append_le_u32(s, compressed_bytes);
  append_le_u32(s, static_cast<std::uint32_t>(payload.size()));
  s->append(reinterpret_cast<const char*>(stream.data()), compressed_bytes);
  return true;
}

}  // namespace

bool parse_pcd(const std::string& bytes, const std::string& path, PcdFrame* out, std::string* error,
               std::uint64_t max_points) {
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
      if (w.size() != 2)
        return fail(error, path, where + ": expected ascii, binary or binary_compressed");
      data_kind = w[1];
    } else {
      return fail(error, path, where + ": unknown header keyword");
    }
  }
  if (data_kind != "ascii" && data_kind != "binary" && data_kind != "binary_compressed")
    return fail(error, path,
                "DATA " + data_kind + " is not supported (ascii, binary or binary_compressed)");
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
  if (width * height > std::min(max_points, kMaxPcdPoints))
    return fail(error, path,
                "WIDTH x HEIGHT " + std::to_string(width) + " x " + std::to_string(height) +
                    " is " + std::to_string(width * height) + " points, over the limit of " +
                    std::to_string(std::min(max_points, kMaxPcdPoints)));
  if (have_points && points != width * height)
    return fail(error, path,
                "POINTS " + std::to_string(points) + " does not equal WIDTH x HEIGHT " +
                    std::to_string(width * height));

  // 64-bit sizes: on the robot's 32-bit ARM a size_t product of a hostile
  // header's counts could wrap past the checks below.
  std::uint64_t record = 0;
  KnownFields known;
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
    record += f.bytes();
    const int i = static_cast<int>(k);
    if (f.name == "x")
      known.x = i;
    else if (f.name == "y")
      known.y = i;
    else if (f.name == "z")
      known.z = i;
    else if (f.name == "intensity" || f.name == "gray" || f.name == "grayValue")
      known.gray = i;
    else if (f.name == "noise")
      known.noise = i;
    else if (f.name == "confidence" || f.name == "depthConfidence")
      known.conf = i;
  }
  if (known.x < 0 || known.y < 0 || known.z < 0)
    return fail(error, path, "FIELDS must include x, y and z");

  const std::uint64_t n = width * height;
  const std::size_t left = bytes.size() - std::min(pos, bytes.size());
  PcdFrame frame;
  frame.width = static_cast<std::uint32_t>(width);
  frame.height = static_cast<std::uint32_t>(height);

  if (data_kind == "binary") {
    // The points must all be in the file before room is made for them.
    if (left < n * record) {
      return fail(error, path,
                  "binary data truncated: " + std::to_string(left) + " bytes for " +
                      std::to_string(n) + " points of " + std::to_string(record) + " bytes");
    }
    frame.points.assign(static_cast<std::size_t>(n), hal::DepthPoint{});
    const unsigned char* base = reinterpret_cast<const unsigned char*>(bytes.data()) + pos;
    BinaryLayout layout;
    for (const Field& f : fields) {
      layout.first.push_back(base + f.offset);
      layout.stride.push_back(record);
    }
    assign_binary_points(fields, known, layout, &frame.points);
    *out = std::move(frame);
    return true;
  }
  if (data_kind == "binary_compressed") {
    if (!read_compressed_points(bytes, pos, path, fields, known, n, &frame.points, error))
      return false;
    *out = std::move(frame);
    return true;
  }

  std::size_t columns = 0;
  std::vector<std::size_t> first_column(fields.size());
  for (std::size_t k = 0; k < fields.size(); ++k) {
    first_column[k] = columns;
    columns += static_cast<std::size_t>(fields[k].count);
  }
  // A point takes at least one character and one separator per column, so
  // a short file cannot make room for the header's point count.
  frame.points.reserve(
      static_cast<std::size_t>(std::min<std::uint64_t>(n, left / (2 * columns) + 1)));
  const double nan = std::numeric_limits<double>::quiet_NaN();
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
    hal::DepthPoint p{};
    assign_point(&p, get(known.x), get(known.y), get(known.z), get(known.gray), get(known.noise),
                 get(known.conf), known.conf >= 0);
    frame.points.push_back(p);
    pos = eol + 1;
  }
  *out = std::move(frame);
  return true;
}

bool read_pcd(const std::string& path, PcdFrame* out, std::string* error,
              std::uint64_t max_points) {
  // Bounded: the header's sizes are checked against what was read, and a
  // runaway file or a device is refused before it fills memory.
  std::string bytes;
  if (read_file_bounded(path, kMaxPcdFileBytes, &bytes, error) != FileStatus::kOk) return false;
  return parse_pcd(bytes, path, out, error, max_points);
}

std::string encode_pcd(const hal::DepthFrame& frame, PcdEncoding encoding) {
  const std::size_t n = static_cast<std::size_t>(frame.width) * frame.height;
  std::ostringstream out;
  out << "# .PCD v0.7 - Point Cloud Data file format\n"
      << "VERSION 0.7\nFIELDS x y z intensity noise confidence\nSIZE 4 4 4 4 4 1\n"
      << "TYPE F F F F F U\nCOUNT 1 1 1 1 1 1\nWIDTH " << frame.width << "\nHEIGHT " << frame.height
      << "\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS " << n << "\nDATA " << data_keyword(encoding) << "\n";
  std::string s = out.str();
  if (encoding == PcdEncoding::kBinaryCompressed) {
    if (!append_compressed(frame, n, &s)) return std::string();
    return s;
  }
  if (encoding == PcdEncoding::kBinary) {
    s.reserve(s.size() + n * 21);
    for (std::size_t i = 0; i < n; ++i) {
      const EncodedPoint e = encode_point(frame.points[i]);
      s.append(reinterpret_cast<const char*>(e.values), sizeof e.values);
      s.push_back(static_cast<char>(e.confidence));
    }
    return s;
  }
  char line[160];
  for (std::size_t i = 0; i < n; ++i) {
    const hal::DepthPoint& p = frame.points[i];
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

bool write_pcd(const std::string& path, const hal::DepthFrame& frame, PcdEncoding encoding,
               std::string* error) {
  const std::string bytes = encode_pcd(frame, encoding);
  if (bytes.empty()) return fail(error, path, "LZF compression failed");
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) return fail(error, path, "cannot create file");
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (!out) return fail(error, path, "write failed");
  return true;
}

}  // namespace formats
