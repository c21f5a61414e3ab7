// PCD reader (ascii, binary, binary_compressed), our own: PCL's PCDReader crashed on files of a few bytes (null
// dereferences, reads after free, out-of-bounds reads in readBodyBinary: issue 11), so the whole header is parsed and
// checked here first (fields, SIZE against TYPE, COUNT, WIDTH x HEIGHT against POINTS, the DATA kind, the body size
// the header implies against the bytes in the file) and the body is decoded with bounds checks on every read.
// Fields x y z (any numeric type, 64-bit integers included) and, when present, normal_x normal_y normal_z, the
// packed colour rgb or rgba (4 bytes, 0x00RRGGBB or 0xAARRGGBB, F or U; in ascii files the integer PCL writes, or a
// float whose bits are the packed value) and intensity (any numeric type). The
// VIEWPOINT origin becomes the point set's viewpoint (the sensor position of a single-view scan); (0, 0, 0) without it.
// Values are converted exactly as PCL did: a 4-byte float field is rounded to float in ascii files too.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstring>
#include <limits>

#include "nodes/io/raw_mesh.h"

namespace scanfill::io {
namespace {

struct PcdField {
  std::string name;
  char type = 'F';           // F, I or U
  std::uint64_t size = 4;    // bytes of one value
  std::uint64_t count = 1;   // values per point
  std::uint64_t offset = 0;  // within a point record (binary); value index within a line (ascii)
  std::uint64_t first_value = 0;
};

enum class PcdData { kAscii, kBinary, kCompressed };

struct PcdHeader {
  std::vector<PcdField> fields;
  std::uint64_t width = 0, height = 1, points = 0;
  double viewpoint[7] = {0, 0, 0, 1, 0, 0, 0};
  PcdData kind = PcdData::kAscii;
  std::string kind_name;
  size_t body = 0;  // offset of the data after the DATA line
  int lines = 0;    // header lines
  std::uint64_t point_step = 0, values_per_point = 0;
};

// Decodes one value of a field from little-endian bytes.
double binary_value(const unsigned char* p, const PcdField& f) {
  unsigned char b[8] = {};
  std::memcpy(b, p, f.size);
  std::uint64_t u = 0;
  for (std::uint64_t i = 0; i < f.size; ++i) u |= std::uint64_t(b[i]) << (8 * i);
  if (f.type == 'F') {
    if (f.size == 4) {
      float v;
      const auto u32 = std::uint32_t(u);
      std::memcpy(&v, &u32, 4);
      return v;
    }
    double v;
    std::memcpy(&v, &u, 8);
    return v;
  }
  if (f.type == 'U') return double(u);
  // Signed: sign-extend from size bytes.
  const unsigned bits = unsigned(8 * f.size);
  if (bits < 64 && (u >> (bits - 1)) & 1) u |= ~std::uint64_t(0) << bits;
  return double(std::int64_t(u));
}

// LZF decompression (liblzf's format, as PCL writes binary_compressed). False if the stream is malformed or does not
// fill `out` exactly.
bool lzf_decompress(const unsigned char* in, size_t in_size, std::string& out) {
  const unsigned char* ip = in;
  const unsigned char* const in_end = in + in_size;
  size_t op = 0;
  const size_t out_size = out.size();
  while (ip < in_end) {
    size_t ctrl = *ip++;
    if (ctrl < 32) {  // a literal run of ctrl + 1 bytes
      ++ctrl;
      if (size_t(in_end - ip) < ctrl || out_size - op < ctrl) return false;
      std::memcpy(&out[op], ip, ctrl);
      op += ctrl;
      ip += ctrl;
    } else {  // a back reference
      size_t len = ctrl >> 5;
      if (len == 7) {
        if (ip >= in_end) return false;
        len += *ip++;
      }
      if (ip >= in_end) return false;
      const size_t back = ((ctrl & 0x1f) << 8) + *ip++ + 1;
      len += 2;
      if (back > op || out_size - op < len) return false;
      for (size_t k = 0; k < len; ++k, ++op) out[op] = out[op - back];  // may overlap: byte by byte
    }
  }
  return op == out_size;
}

// A 4-byte float value of an ascii file, parsed straight to float (as PCL did: no double rounding).
bool parse_float(std::string_view t, double& out) {
  if (t.empty()) return false;
  const char* b = t.data();
  if (*b == '+') ++b;
  float v;
  const auto [ptr, ec] = std::from_chars(b, t.data() + t.size(), v);
  if (ec == std::errc::result_out_of_range) {  // denormals and overflow: take strtof's answer (inf or tiny)
    out = std::strtof(std::string(t).c_str(), nullptr);
    return true;
  }
  out = v;
  return ec == std::errc() && ptr == t.data() + t.size();
}

bool parse_count(std::string_view t, std::uint64_t& out) {
  std::int64_t v;
  if (!parse_int(t, v) || v < 0) return false;
  out = std::uint64_t(v);
  return true;
}

}  // namespace

// The header of a PCD file in `data` (which holds at least the header), checked: keywords, fields (SIZE against TYPE,
// x y z present), WIDTH x HEIGHT against POINTS, and the body it implies against the `file_size` - body offset bytes
// after it (a binary_compressed block's own sizes are checked by read_pcd, which has its bytes).
PcdHeader parse_pcd_header(const std::filesystem::path& path, std::string_view data, std::uint64_t file_size) {
  // ---- header: one keyword per line up to and including DATA
  std::vector<PcdField> fields;
  bool have_fields = false, have_size = false, have_type = false, have_count = false, have_version = false;
  std::uint64_t width = 0, height = 1, points = 0;
  bool have_width = false, have_height = false, have_points = false;
  double viewpoint[7] = {0, 0, 0, 1, 0, 0, 0};
  PcdData kind = PcdData::kAscii;
  std::string kind_name;
  bool have_data = false;
  size_t pos = 0;
  int line_no = 0;
  while (pos < data.size() && !have_data) {
    size_t eol = data.find('\n', pos);
    if (eol == std::string::npos) eol = data.size();
    Tokenizer tok(data.data() + pos, data.data() + eol);
    pos = eol + 1;
    ++line_no;
    const std::string_view key = tok.next();
    if (key.empty() || key[0] == '#') continue;
    const std::string where = "header line " + std::to_string(line_no) + ": ";
    std::vector<std::string_view> values;
    for (std::string_view t = tok.next(); !t.empty(); t = tok.next()) values.push_back(t);
    auto per_field = [&](const char* what) {
      if (!have_fields) fail(path, where + what + " before FIELDS");
      if (values.size() != fields.size())
        fail(path, where + what + " has " + std::to_string(values.size()) + " entries for " +
                       std::to_string(fields.size()) + " fields");
    };
    auto one_count = [&](const char* what, std::uint64_t& out) {
      if (values.size() != 1 || !parse_count(values[0], out))
        fail(path, where + what + " expects one non-negative integer, got '" +
                       (values.empty() ? std::string() : std::string(values[0])) + "'");
    };
    if (key == "VERSION") {
      have_version = true;
    } else if (key == "FIELDS" || key == "COLUMNS") {
      if (have_fields) fail(path, where + "a second FIELDS line");
      if (values.empty()) fail(path, where + "FIELDS lists no field");
      for (const auto v : values) fields.push_back(PcdField{.name = std::string(v)});
      have_fields = true;
    } else if (key == "SIZE") {
      per_field("SIZE");
      for (size_t i = 0; i < values.size(); ++i)
        if (!parse_count(values[i], fields[i].size))
          fail(path, where + "SIZE of field '" + fields[i].name + "' is '" + std::string(values[i]) + "'");
      have_size = true;
    } else if (key == "TYPE") {
      per_field("TYPE");
      for (size_t i = 0; i < values.size(); ++i) {
        if (values[i] != "F" && values[i] != "I" && values[i] != "U")
          fail(path, where + "TYPE of field '" + fields[i].name + "' is '" + std::string(values[i]) +
                         "' (expected F, I or U)");
        fields[i].type = values[i][0];
      }
      have_type = true;
    } else if (key == "COUNT") {
      per_field("COUNT");
      for (size_t i = 0; i < values.size(); ++i)
        if (!parse_count(values[i], fields[i].count) || fields[i].count == 0 || fields[i].count > (1u << 20))
          fail(path, where + "COUNT of field '" + fields[i].name + "' is '" + std::string(values[i]) +
                         "' (expected 1 to 1048576)");
      have_count = true;
    } else if (key == "WIDTH") {
      one_count("WIDTH", width);
      have_width = true;
    } else if (key == "HEIGHT") {
      one_count("HEIGHT", height);
      have_height = true;
    } else if (key == "POINTS") {
      one_count("POINTS", points);
      have_points = true;
    } else if (key == "VIEWPOINT") {
      bool ok = values.size() == 7;
      for (size_t i = 0; ok && i < 7; ++i) ok = parse_double(values[i], viewpoint[i]) && std::isfinite(viewpoint[i]);
      if (!ok) fail(path, where + "VIEWPOINT expects 7 finite numbers (tx ty tz qw qx qy qz)");
    } else if (key == "DATA") {
      if (!have_version && !have_fields) fail(path, "not a PCD file (no VERSION or FIELDS header line)");
      if (values.size() != 1) fail(path, where + "DATA expects one of ascii, binary, binary_compressed");
      kind_name = std::string(values[0]);
      if (kind_name == "ascii")
        kind = PcdData::kAscii;
      else if (kind_name == "binary")
        kind = PcdData::kBinary;
      else if (kind_name == "binary_compressed")
        kind = PcdData::kCompressed;
      else
        fail(path, where + "unknown DATA kind '" + kind_name + "' (expected ascii, binary or binary_compressed)");
      have_data = true;
    } else {
      if (!have_version && !have_fields) fail(path, "not a PCD file (no VERSION or FIELDS header line)");
      fail(path, where + "unexpected '" + std::string(key) + "' in the PCD header");
    }
  }
  if (!have_version && !have_fields) fail(path, "not a PCD file (no VERSION or FIELDS header line)");
  if (!have_fields) fail(path, "PCD header has no FIELDS line");
  if (!have_size) fail(path, "PCD header has no SIZE line");
  if (!have_type) fail(path, "PCD header has no TYPE line");
  if (!have_data) fail(path, "PCD header has no DATA line (truncated?)");
  (void)have_count;  // COUNT is optional: 1 per field

  // ---- fields: sizes against types, the record layout
  std::uint64_t point_step = 0, values_per_point = 0;
  for (PcdField& f : fields) {
    const bool ok =
        f.type == 'F' ? (f.size == 4 || f.size == 8) : (f.size == 1 || f.size == 2 || f.size == 4 || f.size == 8);
    if (!ok)
      fail(path, "field '" + f.name + "' has TYPE " + std::string(1, f.type) + " with SIZE " + std::to_string(f.size) +
                     " (expected " + (f.type == 'F' ? "4 or 8" : "1, 2, 4 or 8") + ")");
    f.offset = point_step;
    f.first_value = values_per_point;
    point_step += f.size * f.count;  // at most 2^20 fields of 8 x 2^20 bytes: no overflow
    values_per_point += f.count;
  }
  auto has_field = [&](const char* name) {
    return std::any_of(fields.begin(), fields.end(), [&](const PcdField& f) { return f.name == name; });
  };
  if (!has_field("x") || !has_field("y") || !has_field("z")) fail(path, "PCD has no x, y, z fields");
  for (const PcdField& f : fields)
    if ((f.name == "rgb" || f.name == "rgba") && f.size != 4)
      fail(path, "field '" + f.name + "' has SIZE " + std::to_string(f.size) + " (a packed colour has 4 bytes)");

  // ---- counts: WIDTH x HEIGHT against POINTS (files before v0.7 may give only one of them)
  if (!have_width && !have_points) fail(path, "PCD header has neither WIDTH nor POINTS");
  if (!have_width) width = points, height = have_height ? height : 1;
  if (have_width && !have_height) height = 1;
  if (height != 0 && width > std::numeric_limits<std::uint64_t>::max() / height) fail(path, "WIDTH x HEIGHT overflows");
  if (!have_points) points = width * height;
  if (width * height != points)
    fail(path, "WIDTH x HEIGHT (" + std::to_string(width) + " x " + std::to_string(height) + ") differs from POINTS (" +
                   std::to_string(points) + ")");

  // ---- the body the header implies, against the bytes the file holds (before anything is allocated)
  const std::uint64_t remaining = file_size - std::min<std::uint64_t>(pos, file_size);
  const auto point_bytes = [&](std::uint64_t n) { return n > 0 && point_step > remaining / n; };
  if (kind == PcdData::kAscii) {
    // Each value takes at least one character and one separator.
    if (points > 0 && values_per_point > remaining / points / 2 + 1)
      fail(path, "truncated: " + std::to_string(points) + " points of " + std::to_string(values_per_point) +
                     " values declared, the ascii data has " + std::to_string(remaining) + " bytes");
  } else if (kind == PcdData::kBinary) {
    if (point_bytes(points))
      fail(path, "truncated: " + std::to_string(points) + " points of " + std::to_string(point_step) +
                     " bytes declared, the binary data has " + std::to_string(remaining) + " bytes");
  } else if (remaining < 8) {
    fail(path, "truncated: binary_compressed data without its size header");
  }
  PcdHeader h;
  h.fields = std::move(fields);
  h.width = width;
  h.height = height;
  h.points = points;
  std::copy(viewpoint, viewpoint + 7, h.viewpoint);
  h.kind = kind;
  h.kind_name = kind_name;
  h.body = std::min<std::uint64_t>(pos, file_size);
  h.lines = line_no;
  h.point_step = point_step;
  h.values_per_point = values_per_point;
  return h;
}

FileHeader read_pcd_header(const std::filesystem::path& path) {
  std::uint64_t file_size = 0;
  // Complete once a line starting with DATA has ended.
  const auto complete = [](std::string_view d) {
    for (size_t at = d.find("DATA"); at != std::string_view::npos; at = d.find("DATA", at + 1))
      if ((at == 0 || d[at - 1] == '\n') && d.find('\n', at) != std::string_view::npos) return true;
    return false;
  };
  const std::string head = read_head(path, complete, file_size);
  const PcdHeader h = parse_pcd_header(path, head, file_size);
  FileHeader out;
  out.format = "pcd";
  out.encoding = h.kind_name;
  out.header_bytes = Index(h.body);
  out.points = Index(h.points);
  out.elements.push_back(std::to_string(h.width) + " x " + std::to_string(h.height));
  for (const PcdField& f : h.fields)
    out.properties.push_back(f.name + " " + std::string(1, f.type) + std::to_string(f.size) +
                             (f.count > 1 ? " x " + std::to_string(f.count) : ""));
  out.viewpoint = Eigen::Vector3d(float(h.viewpoint[0]), float(h.viewpoint[1]), float(h.viewpoint[2]));
  return out;
}

RawMesh read_pcd(const std::filesystem::path& path) {
  const std::string data = read_file(path);  // the same "no such file" / "file is empty" messages as the other formats
  const PcdHeader h = parse_pcd_header(path, data, data.size());
  const std::vector<PcdField>& fields = h.fields;
  const std::uint64_t points = h.points, point_step = h.point_step, values_per_point = h.values_per_point;
  const PcdData kind = h.kind;
  const size_t body = h.body, file_size = data.size();
  const std::uint64_t remaining = file_size - body;
  const int line_no = h.lines;
  const double* viewpoint = h.viewpoint;
  auto field = [&](const char* name) -> const PcdField* {
    for (const PcdField& f : fields)
      if (f.name == name) return &f;
    return nullptr;
  };
  const PcdField* fx = field("x");
  const PcdField* fy = field("y");
  const PcdField* fz = field("z");
  const PcdField* fn[3] = {field("normal_x"), field("normal_y"), field("normal_z")};
  const bool normals = fn[0] && fn[1] && fn[2];
  const PcdField* frgb = field("rgb") ? field("rgb") : field("rgba");
  const PcdField* fintensity = field("intensity");

  std::string decompressed;
  const unsigned char* records = reinterpret_cast<const unsigned char*>(data.data()) + body;
  if (kind == PcdData::kCompressed) {
    if (remaining < 8) fail(path, "truncated: binary_compressed data without its size header");
    std::uint32_t sizes[2];
    std::memcpy(sizes, records, 8);
    const std::uint64_t compressed = sizes[0], uncompressed = sizes[1];
    if (compressed > remaining - 8)
      fail(path, "truncated: the compressed block declares " + std::to_string(compressed) + " bytes, the file has " +
                     std::to_string(remaining - 8));
    if (points > 0 &&
        (point_step > std::numeric_limits<std::uint64_t>::max() / points || uncompressed != points * point_step))
      fail(path, "the compressed block holds " + std::to_string(uncompressed) + " bytes, " + std::to_string(points) +
                     " points of " + std::to_string(point_step) + " bytes need " + std::to_string(points * point_step));
    if (uncompressed > 88 * compressed)  // LZF expands 3 bytes to at most 264
      fail(path, "the compressed block (" + std::to_string(compressed) + " bytes) cannot hold " +
                     std::to_string(uncompressed) + " bytes");
    decompressed.resize(uncompressed);
    if (uncompressed > 0 && !lzf_decompress(records + 8, compressed, decompressed))
      fail(path, "corrupt binary_compressed data (LZF stream)");
  }

  RawMesh mesh;
  mesh.encoding = h.kind_name;
  mesh.xyz.resize(3 * points);
  if (normals) mesh.normals.resize(3 * points);
  const PcdField* wanted[6] = {fx, fy, fz, fn[0], fn[1], fn[2]};
  const int n_wanted = normals ? 6 : 3;
  auto store = [&](std::uint64_t i, int k, double v) {
    if (k < 3)
      mesh.xyz[3 * i + k] = v;
    else
      mesh.normals[3 * i + k - 3] = v;
  };
  if (frgb) mesh.colours.resize(3 * points);
  if (fintensity) mesh.intensity.resize(points);
  auto store_rgb = [&](std::uint64_t i, std::uint32_t packed) {
    for (int k = 0; k < 3; ++k) mesh.colours[3 * i + k] = std::uint8_t(packed >> (16 - 8 * k));
  };
  // The packed colour's 4 bytes as they are: a float's bits may be a NaN pattern, which a conversion would change.
  auto packed_bits = [](const unsigned char* p) {
    return std::uint32_t(p[0]) | std::uint32_t(p[1]) << 8 | std::uint32_t(p[2]) << 16 | std::uint32_t(p[3]) << 24;
  };

  if (kind == PcdData::kBinary) {
    for (std::uint64_t i = 0; i < points; ++i) {
      const unsigned char* record = records + i * point_step;
      for (int k = 0; k < n_wanted; ++k) store(i, k, binary_value(record + wanted[k]->offset, *wanted[k]));
      if (frgb) store_rgb(i, packed_bits(record + frgb->offset));
      if (fintensity) mesh.intensity[i] = float(binary_value(record + fintensity->offset, *fintensity));
    }
  } else if (kind == PcdData::kCompressed) {
    // Field by field: all points' values of the first field, then of the second...
    const auto* soa = reinterpret_cast<const unsigned char*>(decompressed.data());
    const auto column = [&](const PcdField& f, std::uint64_t i) {
      return soa + points * f.offset + i * f.size * f.count;
    };
    for (int k = 0; k < n_wanted; ++k)
      for (std::uint64_t i = 0; i < points; ++i) store(i, k, binary_value(column(*wanted[k], i), *wanted[k]));
    for (std::uint64_t i = 0; frgb && i < points; ++i) store_rgb(i, packed_bits(column(*frgb, i)));
    for (std::uint64_t i = 0; fintensity && i < points; ++i)
      mesh.intensity[i] = float(binary_value(column(*fintensity, i), *fintensity));
  } else {
    const char* p = data.data() + body;
    const char* const end = data.data() + file_size;
    std::vector<std::string_view> tokens;
    int line = line_no;
    for (std::uint64_t i = 0; i < points;) {
      if (p >= end)
        fail(path, "truncated: " + std::to_string(points) + " points declared, the ascii data ends after " +
                       std::to_string(i));
      const char* eol = static_cast<const char*>(std::memchr(p, '\n', size_t(end - p)));
      if (!eol) eol = end;
      Tokenizer tok(p, eol);
      p = eol + 1;
      ++line;
      tokens.clear();
      for (std::string_view t = tok.next(); !t.empty() && tokens.size() <= values_per_point; t = tok.next())
        tokens.push_back(t);
      if (tokens.empty()) continue;
      if (tokens.size() != values_per_point)
        fail(path, "line " + std::to_string(line) + ": " + (tokens.size() > values_per_point ? "more than " : "") +
                       std::to_string(tokens.size()) + " values, the header declares " +
                       std::to_string(values_per_point) + " per point");
      for (int k = 0; k < n_wanted; ++k) {
        const PcdField& f = *wanted[k];
        const std::string_view t = tokens[f.first_value];
        double v;
        if (f.type == 'F') {
          if (!(f.size == 4 ? parse_float(t, v) : parse_double(t, v)))
            fail(path, "line " + std::to_string(line) + ": '" + std::string(t) + "' is not a number (field '" + f.name +
                           "')");
        } else {
          std::int64_t iv;
          if (!parse_int(t, iv))
            fail(path, "line " + std::to_string(line) + ": '" + std::string(t) + "' is not an integer (field '" +
                           f.name + "')");
          v = double(iv);
        }
        store(i, k, v);
      }
      if (frgb) {
        // As PCL reads it: an integer (TYPE U or I, as PCL writes it), or a float whose bits are the packed value.
        const std::string_view t = tokens[frgb->first_value];
        std::int64_t iv = 0;
        double fv = 0;
        if (frgb->type != 'F' ? !(parse_int(t, iv) && iv >= 0 && iv <= 0xffffffffLL) : !parse_float(t, fv))
          fail(path, "line " + std::to_string(line) + ": '" + std::string(t) + "' is not a packed colour (field '" +
                         frgb->name + "', TYPE " + std::string(1, frgb->type) + ")");
        std::uint32_t bits = std::uint32_t(iv);
        if (frgb->type == 'F') {
          const float f = float(fv);
          std::memcpy(&bits, &f, 4);
        }
        store_rgb(i, bits);
      }
      if (fintensity) {
        const std::string_view t = tokens[fintensity->first_value];
        double v;
        const bool is_float = fintensity->type == 'F';
        if (!(is_float && fintensity->size == 4 ? parse_float(t, v) : parse_double(t, v)))
          fail(path, "line " + std::to_string(line) + ": '" + std::string(t) + "' is not a number (field '" +
                         fintensity->name + "')");
        mesh.intensity[i] = float(v);
      }
      ++i;
    }
  }
  mesh.viewpoint = Eigen::Vector3d(float(viewpoint[0]), float(viewpoint[1]), float(viewpoint[2]));
  return mesh;
}

}  // namespace scanfill::io
