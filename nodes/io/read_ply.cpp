// PLY reader (Turk's format): ASCII, binary_little_endian and binary_big_endian; CRLF line endings; any elements.
// Only vertex (x y z [nx ny nz | normal_x ...] [red green blue | diffuse_red ... | r g b] [intensity |
// scalar_intensity]) and face (vertex_indices | vertex_index) are kept, and the first camera record's view_px view_py
// view_pz (the sensor position, as PCL's PLY writer gives it) becomes the viewpoint; other elements such as range_grid
// are read past. Colours of 8-bit types are kept as they are, 16-bit ones scaled by 1/257, other integers clamped to
// [0, 255]; float colours are read as [0, 1] (scaled by 255) unless one exceeds 1, when the file is taken to hold
// [0, 255] floats (with a warning).
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <sstream>

#include "nodes/io/raw_mesh.h"
#include "nodes/io/read_part_labels.h"
#include "nodes/io/read_ply_chunks.h"

namespace scanfill::io {
namespace {

enum class Type { kInt8, kUint8, kInt16, kUint16, kInt32, kUint32, kFloat32, kFloat64 };

bool parse_type(const std::string& s, Type& t) {
  static const std::pair<const char*, Type> kNames[] = {
      {"char", Type::kInt8},     {"int8", Type::kInt8},       {"uchar", Type::kUint8},    {"uint8", Type::kUint8},
      {"short", Type::kInt16},   {"int16", Type::kInt16},     {"ushort", Type::kUint16},  {"uint16", Type::kUint16},
      {"int", Type::kInt32},     {"int32", Type::kInt32},     {"uint", Type::kUint32},    {"uint32", Type::kUint32},
      {"float", Type::kFloat32}, {"float32", Type::kFloat32}, {"double", Type::kFloat64}, {"float64", Type::kFloat64}};
  for (const auto& [name, type] : kNames) {
    if (s == name) {
      t = type;
      return true;
    }
  }
  return false;
}

size_t type_size(Type t) {
  switch (t) {
    case Type::kInt8:
    case Type::kUint8:
      return 1;
    case Type::kInt16:
    case Type::kUint16:
      return 2;
    case Type::kInt32:
    case Type::kUint32:
    case Type::kFloat32:
      return 4;
    case Type::kFloat64:
      return 8;
  }
  return 0;
}

struct Property {
  std::string name;
  Type type = Type::kFloat32;
  bool is_list = false;
  Type count_type = Type::kUint8;
};

struct Element {
  std::string name;
  std::int64_t count = 0;
  std::vector<Property> properties;
};

enum class Encoding { kAscii, kLittle, kBig };

const char* encoding_name(Encoding e) {
  return e == Encoding::kAscii ? "ascii" : e == Encoding::kLittle ? "binary_little_endian" : "binary_big_endian";
}

struct PlyHeader {
  Encoding encoding = Encoding::kAscii;
  std::vector<Element> elements;
  size_t body = 0;  // offset of the first byte after end_header
  int lines = 0;    // header lines
};

const char* type_name(Type t) {
  static const char* kNames[] = {"char", "uchar", "short", "ushort", "int", "uint", "float", "double"};
  return kNames[int(t)];
}

// Reads one binary scalar at p (bounds checked by the caller) as double.
double read_binary(const char* p, Type t, bool swap) {
  char b[8];
  const size_t n = type_size(t);
  std::memcpy(b, p, n);
  if (swap) std::reverse(b, b + n);
  switch (t) {
    case Type::kInt8: {
      std::int8_t v;
      std::memcpy(&v, b, 1);
      return v;
    }
    case Type::kUint8: {
      std::uint8_t v;
      std::memcpy(&v, b, 1);
      return v;
    }
    case Type::kInt16: {
      std::int16_t v;
      std::memcpy(&v, b, 2);
      return v;
    }
    case Type::kUint16: {
      std::uint16_t v;
      std::memcpy(&v, b, 2);
      return v;
    }
    case Type::kInt32: {
      std::int32_t v;
      std::memcpy(&v, b, 4);
      return v;
    }
    case Type::kUint32: {
      std::uint32_t v;
      std::memcpy(&v, b, 4);
      return v;
    }
    case Type::kFloat32: {
      float v;
      std::memcpy(&v, b, 4);
      return v;
    }
    case Type::kFloat64: {
      double v;
      std::memcpy(&v, b, 8);
      return v;
    }
  }
  return 0;
}

// Where a vertex/face/camera property goes: a slot of xyz (0-2), normals (3-5), the face list (6), colour (7-9),
// intensity (10), the camera's position (11-13), or nowhere (-1).
constexpr int kFaceSlot = 6, kColourSlot = 7, kIntensitySlot = 10, kViewSlot = 11, kValueSlots = 14;
int slot_of(const std::string& element, const Property& p) {
  if (element == "camera" && !p.is_list) {
    static const char* kNames[] = {"view_px", "view_py", "view_pz"};
    for (int k = 0; k < 3; ++k)
      if (p.name == kNames[k]) return kViewSlot + k;
  }
  if (element == "vertex" && !p.is_list) {
    static const char* kNames[][4] = {{"x"},
                                      {"y"},
                                      {"z"},
                                      {"nx", "normal_x"},
                                      {"ny", "normal_y"},
                                      {"nz", "normal_z"},
                                      {},
                                      {"red", "diffuse_red", "r"},
                                      {"green", "diffuse_green", "g"},
                                      {"blue", "diffuse_blue", "b"},
                                      {"intensity", "scalar_intensity", "scalar_Intensity", "Intensity"}};
    for (int s = 0; s < int(std::size(kNames)); ++s)
      for (const char* name : kNames[s])
        if (name && p.name == name) return s;
  }
  if (element == "face" && p.is_list && (p.name == "vertex_indices" || p.name == "vertex_index")) return kFaceSlot;
  return -1;
}

bool is_float(Type t) {
  return t == Type::kFloat32 || t == Type::kFloat64;
}

// An integer colour value in [0, 255]: 8-bit as it is, 16-bit scaled by 1/257, wider types clamped.
std::uint8_t integer_colour(double v, Type t) {
  if (t == Type::kUint16 || t == Type::kInt16) v = std::round(v / 257.0);
  return std::isfinite(v) ? std::uint8_t(std::clamp(v, 0.0, 255.0)) : 0;  // an ascii file may say "nan"
}

}  // namespace

// The header of a PLY file in `data` (which holds at least the header), checked: the format, elements and properties,
// a vertex element with x, y and z, and the counts against the `file_size` - body offset bytes after the header.
PlyHeader parse_ply_header(const std::filesystem::path& path, std::string_view data, std::uint64_t file_size) {
  // Header: lines up to and including "end_header", each ended by LF or CRLF.
  size_t pos = 0;
  int line_no = 0;
  auto next_line = [&](std::string& line) {
    if (pos >= data.size()) return false;
    size_t eol = data.find('\n', pos);
    if (eol == std::string::npos) eol = data.size();
    line.assign(data, pos, eol - pos);
    if (!line.empty() && line.back() == '\r') line.pop_back();
    pos = eol + 1;
    ++line_no;
    return true;
  };
  std::string line;
  if (!next_line(line) || line != "ply") fail(path, "not a PLY file (first line is not 'ply')");
  Encoding encoding = Encoding::kAscii;
  bool have_format = false, have_end = false;
  std::vector<Element> elements;
  while (next_line(line)) {
    std::istringstream ls(line);
    std::string word;
    if (!(ls >> word)) continue;
    const std::string where = "header line " + std::to_string(line_no) + ": ";
    if (word == "format") {
      std::string enc, version;
      ls >> enc >> version;
      if (enc == "ascii")
        encoding = Encoding::kAscii;
      else if (enc == "binary_little_endian")
        encoding = Encoding::kLittle;
      else if (enc == "binary_big_endian")
        encoding = Encoding::kBig;
      else
        fail(path, where + "unknown PLY format '" + enc + "'");
      have_format = true;
    } else if (word == "element") {
      Element e;
      std::string count;
      ls >> e.name >> count;
      if (!parse_int(count, e.count) || e.count < 0)
        fail(path, where + "element '" + e.name + "' has an invalid count '" + count + "'");
      elements.push_back(std::move(e));
    } else if (word == "property") {
      if (elements.empty()) fail(path, where + "property before any element");
      Property p;
      std::string type;
      ls >> type;
      if (type == "list") {
        std::string ct, it;
        ls >> ct >> it >> p.name;
        p.is_list = true;
        if (!parse_type(ct, p.count_type) || !parse_type(it, p.type))
          fail(path, where + "unknown list property types '" + ct + " " + it + "'");
      } else {
        ls >> p.name;
        if (!parse_type(type, p.type)) fail(path, where + "unknown property type '" + type + "'");
      }
      if (p.name.empty()) fail(path, where + "property without a name");
      elements.back().properties.push_back(std::move(p));
    } else if (word == "end_header") {
      have_end = true;
      break;
    } else if (word != "comment" && word != "obj_info") {
      fail(path, where + "unexpected '" + word + "'");
    }
  }
  if (!have_end) fail(path, "PLY header has no end_header (truncated?)");
  if (!have_format) fail(path, "PLY header has no format line");

  const Element* vertex = nullptr;
  for (const Element& e : elements)
    if (e.name == "vertex") vertex = &e;
  if (!vertex) fail(path, "PLY has no vertex element");
  // The counts against the bytes after the header, before anything is allocated: a binary record takes at least its
  // scalars and list counts, an ascii value at least one character and a separator (the last may lack it).
  const std::uint64_t body = file_size - std::min<std::uint64_t>(pos, file_size);
  std::uint64_t need = 0;  // bytes (binary) or values (ascii) the header implies, at the least
  for (const Element& e : elements) {
    std::uint64_t record = 0;
    for (const Property& prop : e.properties)
      record += encoding == Encoding::kAscii ? 1 : type_size(prop.is_list ? prop.count_type : prop.type);
    if (e.count == 0) continue;
    const std::uint64_t limit = encoding == Encoding::kAscii ? (body + 1) / 2 : body;
    if (record == 0 || std::uint64_t(e.count) > (limit - std::min(need, limit)) / record)
      fail(path, std::string(record == 0 ? "" : "truncated: ") + "element '" + e.name + "' declares " +
                     std::to_string(e.count) + " records" +
                     (record == 0 ? " without properties"
                                  : ", more than the " + std::to_string(body) + " bytes after the header can hold"));
    need += std::uint64_t(e.count) * record;
  }
  return {encoding, std::move(elements), pos, line_no};
}

// Whether a PLY header read so far is complete: a line "end_header" has ended (a comment may mention end_header).
bool header_complete(std::string_view d) {
  for (size_t at = d.find("\nend_header"); at != std::string_view::npos; at = d.find("\nend_header", at + 1)) {
    const size_t after = at + std::strlen("\nend_header");
    if (d.substr(after).starts_with("\n") || d.substr(after).starts_with("\r\n")) return true;
  }
  return false;
}

FileHeader read_ply_header(const std::filesystem::path& path) {
  std::uint64_t file_size = 0;
  const std::string head = read_head(path, header_complete, file_size);
  const PlyHeader h = parse_ply_header(path, head, file_size);
  FileHeader out;
  out.format = "ply";
  out.encoding = encoding_name(h.encoding);
  out.header_bytes = Index(h.body);
  for (const Element& e : h.elements) {
    if (e.name == "vertex") out.points = e.count;
    if (e.name == "face") out.faces = e.count;
    out.elements.push_back(e.name + " " + std::to_string(e.count));
    for (const Property& p : e.properties)
      out.properties.push_back(e.name + "." + p.name + " " +
                               (p.is_list ? std::string("list ") + type_name(p.count_type) + " " : std::string()) +
                               type_name(p.type));
  }
  return out;
}

namespace {

// The sensor position a camera record holds (view_px, view_py, view_pz); a non-finite one is bad input.
Eigen::Vector3d camera_position(const std::filesystem::path& path, const double* view) {
  if (!std::isfinite(view[0]) || !std::isfinite(view[1]) || !std::isfinite(view[2]))
    fail(path, "the camera's position (view_px, view_py, view_pz) is not finite");
  return {view[0], view[1], view[2]};
}

}  // namespace

RawMesh read_ply(const std::filesystem::path& path) {
  const std::string data = read_file(path);
  const PlyHeader header = parse_ply_header(path, data, data.size());
  const Encoding encoding = header.encoding;
  const std::vector<Element>& elements = header.elements;
  const size_t pos = header.body;
  const int line_no = header.lines;
  RawMesh mesh;
  mesh.encoding = encoding_name(encoding);
  const Element* vertex = nullptr;
  for (const Element& e : elements)
    if (e.name == "vertex") vertex = &e;
  bool has[kValueSlots] = {};
  Type colour_type[3] = {};
  for (const Property& p : vertex->properties) {
    const int s = slot_of("vertex", p);
    if (s >= 0) has[s] = true;
    if (s >= kColourSlot && s < kColourSlot + 3) colour_type[s - kColourSlot] = p.type;
  }
  if (!has[0] || !has[1] || !has[2]) fail(path, "PLY vertex element lacks x, y or z");
  const bool want_normals = has[3] && has[4] && has[5];
  const bool want_colours = has[kColourSlot] && has[kColourSlot + 1] && has[kColourSlot + 2];
  const bool want_intensity = has[kIntensitySlot];
  // Float colours: their range is known only at the end ([0, 1] or [0, 255]), so they are kept as read until then.
  std::vector<float> float_colours;
  float max_float_colour = 0;

  mesh.xyz.reserve(size_t(vertex->count) * 3);
  if (want_normals) mesh.normals.reserve(size_t(vertex->count) * 3);
  if (want_colours) mesh.colours.reserve(size_t(vertex->count) * 3);
  if (want_intensity) mesh.intensity.reserve(size_t(vertex->count));

  const bool swap = (encoding == Encoding::kLittle) != (std::endian::native == std::endian::little);
  const char* p = data.data() + std::min(pos, data.size());
  const char* end = data.data() + data.size();
  Tokenizer tok(p, end);
  std::int64_t corners[256];
  std::vector<std::int64_t> big_polygon;
  std::int64_t skipped_faces = 0;
  double values[kValueSlots] = {};

  for (const Element& e : elements) {
    const bool is_vertex = &e == vertex;
    const bool is_face = e.name == "face";
    const bool is_camera = e.name == "camera";
    std::vector<int> slots;
    for (const Property& prop : e.properties)
      slots.push_back(is_vertex || is_face || is_camera ? slot_of(e.name, prop) : -1);
    int view_mask = 0;  // which of view_px, view_py, view_pz the element has
    for (const int s : slots)
      if (s >= kViewSlot) view_mask |= 1 << (s - kViewSlot);
    const bool has_view = view_mask == 7;
    for (std::int64_t r = 0; r < e.count; ++r) {
      auto truncated = [&] {
        fail(path, "truncated: element '" + e.name + "' declares " + std::to_string(e.count) +
                       " records, the data ends at record " + std::to_string(r));
      };
      for (size_t pi = 0; pi < e.properties.size(); ++pi) {
        const Property& prop = e.properties[pi];
        const int slot = slots[pi];
        if (!prop.is_list) {
          double v = 0;
          if (encoding == Encoding::kAscii) {
            const std::string_view t = tok.next();
            if (t.empty()) truncated();
            if (!parse_double(t, v))
              fail(path, "line " + std::to_string(line_no + tok.line()) + ": '" + std::string(t) +
                             "' is not a number (element '" + e.name + "', property '" + prop.name + "')");
          } else {
            const size_t n = type_size(prop.type);
            if (size_t(end - p) < n) truncated();
            v = read_binary(p, prop.type, swap);
            p += n;
          }
          if (slot >= 0 && slot != kFaceSlot) values[slot] = v;
          continue;
        }
        // A list property: count, then that many items.
        double count_d = 0;
        if (encoding == Encoding::kAscii) {
          const std::string_view t = tok.next();
          if (t.empty()) truncated();
          std::int64_t count_i = 0;
          if (!parse_int(t, count_i))
            fail(path, "element '" + e.name + "' record " + std::to_string(r) + ": '" + std::string(t) +
                           "' is not a list count");
          count_d = double(count_i);
        } else {
          const size_t n = type_size(prop.count_type);
          if (size_t(end - p) < n) truncated();
          count_d = read_binary(p, prop.count_type, swap);
          p += n;
        }
        if (count_d < 0 || count_d != std::floor(count_d))
          fail(path, "element '" + e.name + "' record " + std::to_string(r) + " has an invalid list count");
        // Each item takes at least its size (binary), or one character and a separator (ascii; the last may lack it).
        const bool fits = encoding == Encoding::kAscii ? count_d * 2 <= double(tok.remaining()) + 1
                                                       : count_d * double(type_size(prop.type)) <= double(end - p);
        if (!fits)
          fail(path, "element '" + e.name + "' record " + std::to_string(r) + " declares a list of " +
                         std::to_string(std::uint64_t(std::min(count_d, 1e19))) + " items, more than the file holds");
        const auto count = static_cast<size_t>(count_d);
        std::int64_t* dst = corners;
        if (slot == kFaceSlot && count > 256) {
          big_polygon.resize(count);
          dst = big_polygon.data();
        }
        for (size_t k = 0; k < count; ++k) {
          double v = 0;
          if (encoding == Encoding::kAscii) {
            const std::string_view t = tok.next();
            if (t.empty()) truncated();
            if (!parse_double(t, v)) fail(path, "'" + std::string(t) + "' is not a number in a list");
          } else {
            const size_t n = type_size(prop.type);
            if (size_t(end - p) < n) truncated();
            if (slot == kFaceSlot) v = read_binary(p, prop.type, swap);
            p += n;
          }
          if (slot == kFaceSlot) {
            if (!(v >= -9e15 && v <= 9e15) || v != std::floor(v))  // NaN, fractions and the unrepresentable
              fail(path, "element '" + e.name + "' record " + std::to_string(r) + " has the vertex index '" +
                             short_number(v) + "', not an integer");
            dst[k] = static_cast<std::int64_t>(v);
          }
        }
        if (slot == kFaceSlot && !add_polygon(mesh.faces, dst, count)) ++skipped_faces;
      }
      if (is_vertex) {
        mesh.xyz.insert(mesh.xyz.end(), values, values + 3);
        if (want_normals) mesh.normals.insert(mesh.normals.end(), values + 3, values + 6);
        if (want_intensity) mesh.intensity.push_back(float(values[kIntensitySlot]));
        for (int k = 0; want_colours && k < 3; ++k) {
          const double c = values[kColourSlot + k];
          if (is_float(colour_type[k])) {
            float_colours.push_back(float(c));
            max_float_colour = std::max(max_float_colour, float(c));
          } else {
            mesh.colours.push_back(integer_colour(c, colour_type[k]));
          }
        }
      }
      if (is_camera && r == 0 && has_view && !mesh.viewpoint)
        mesh.viewpoint = camera_position(path, values + kViewSlot);
    }
  }
  if (encoding == Encoding::kAscii) {
    if (!tok.at_end())
      fail(path, "data continues after the last declared element (header counts do not match the data)");
  } else if (p != end) {
    mesh.warnings.push_back(path.string() + ": " + std::to_string(end - p) +
                            " bytes after the last declared element were ignored");
  }
  if (want_colours && !float_colours.empty()) {
    // Interleaved with any integer channels: rebuild the three channels in order.
    const bool scaled = max_float_colour > 1.0f;
    if (scaled)
      mesh.warnings.push_back(path.string() + ": float colours above 1 (up to " + short_number(max_float_colour) +
                              ") were read as [0, 255], not [0, 1]");
    std::vector<std::uint8_t> colours;
    colours.reserve(size_t(vertex->count) * 3);
    size_t next_float = 0, next_int = 0;
    for (std::int64_t i = 0; i < vertex->count; ++i)
      for (int k = 0; k < 3; ++k) {
        if (!is_float(colour_type[k])) {
          colours.push_back(mesh.colours[next_int++]);
          continue;
        }
        const double c = float_colours[next_float++];
        colours.push_back(std::isfinite(c) ? std::uint8_t(std::clamp(std::round(scaled ? c : 255.0 * c), 0.0, 255.0))
                                           : 0);
      }
    mesh.colours = std::move(colours);
  }
  if (skipped_faces > 0)
    mesh.warnings.push_back(std::to_string(skipped_faces) + " faces with fewer than 3 vertices were skipped");
  return mesh;
}

}  // namespace scanfill::io

namespace scanfill {

PlyChunkReader::PlyChunkReader(const std::filesystem::path& path) : path_(path) {
  using namespace io;
  std::uint64_t file_size = 0;
  const std::string head = read_head(path, header_complete, file_size);
  const PlyHeader h = parse_ply_header(path, head, file_size);
  if (h.encoding == Encoding::kAscii) fail(path, "chunked reading needs a binary PLY, this one is ascii");
  const Element& vertex = h.elements.front();
  if (vertex.name != "vertex") fail(path, "chunked reading needs the vertex element first, not '" + vertex.name + "'");
  offset_.assign(6, -1);
  type_.assign(6, 0);
  for (const Property& p : vertex.properties) {
    if (p.is_list) fail(path, "chunked reading needs a vertex element without list properties ('" + p.name + "')");
    const int s = slot_of("vertex", p);
    if (s >= 0 && s < 6) {
      offset_[size_t(s)] = int(record_);
      type_[size_t(s)] = int(p.type);
    }
    record_ += type_size(p.type);
  }
  if (offset_[0] < 0 || offset_[1] < 0 || offset_[2] < 0) fail(path, "PLY vertex element lacks x, y or z");
  normals_ = offset_[3] >= 0 && offset_[4] >= 0 && offset_[5] >= 0;
  swap_ = (h.encoding == Encoding::kLittle) != (std::endian::native == std::endian::little);
  body_ = h.body;
  rows_ = vertex.count;
  in_.open(path, std::ios::binary);
  if (!in_) fail(path, "cannot open");
  rewind();
}

void PlyChunkReader::rewind() {
  in_.clear();
  in_.seekg(std::streamoff(body_));
  row_ = 0;
  dropped_ = 0;
}

bool PlyChunkReader::next(Index max_points, PointSet& out) {
  using namespace io;
  const Index n = std::min(std::max<Index>(max_points, 1), rows_ - row_);
  if (n <= 0) return false;
  buffer_.resize(size_t(n) * record_);
  if (!in_.read(buffer_.data(), std::streamsize(buffer_.size())))
    fail(path_, "truncated: the vertex data ends before record " + std::to_string(row_ + n));
  const auto value = [&](Index r, int slot) {
    return read_binary(buffer_.data() + size_t(r) * record_ + size_t(offset_[size_t(slot)]), Type(type_[size_t(slot)]),
                       swap_);
  };
  Index kept = 0;
  for (Index r = 0; r < n; ++r)
    kept += std::isfinite(value(r, 0)) && std::isfinite(value(r, 1)) && std::isfinite(value(r, 2));
  Eigen::Matrix3Xd P(3, kept), N(3, normals_ ? kept : 0);
  VectorXi64 source(kept);
  for (Index r = 0, j = 0; r < n; ++r) {
    const Eigen::Vector3d p(value(r, 0), value(r, 1), value(r, 2));
    if (!p.allFinite()) continue;
    P.col(j) = p;
    source(j) = row_ + r;
    if (normals_) {
      Eigen::Vector3d v(value(r, 3), value(r, 4), value(r, 5));
      const double len = v.norm();
      if (!(len > 1e-12) || !std::isfinite(len))
        v.setZero();
      else if (std::abs(len - 1) > 1e-12)
        v /= len;  // as read_point_set: normals unit to rounding are kept as stored
      N.col(j) = v;
    }
    ++j;
  }
  dropped_ += n - kept;
  row_ += n;
  out = PointSet(std::move(P));
  if (normals_) out.set_normals(std::move(N));
  out.set_source_index(std::move(source));
  return true;
}

namespace {

// One scalar or list property of a record: its value (a list's count), or, for a list, its items skipped.
double read_property(const io::Property& prop, io::Encoding encoding, bool swap, io::Tokenizer& tok, const char*& p,
                     const char* end, const std::filesystem::path& path) {
  const auto value = [&](io::Type type) {
    if (encoding == io::Encoding::kAscii) {
      const std::string_view t = tok.next();
      double v = 0;
      if (t.empty() || !io::parse_double(t, v)) io::fail(path, "truncated or not a number in property " + prop.name);
      return v;
    }
    const size_t n = io::type_size(type);
    if (size_t(end - p) < n) io::fail(path, "truncated in property " + prop.name);
    const double v = io::read_binary(p, type, swap);
    p += n;
    return v;
  };
  if (!prop.is_list) return value(prop.type);
  const double count = value(prop.count_type);
  if (count < 0 || count > double(end - p) + double(tok.remaining()))
    io::fail(path, "invalid list count in property " + prop.name);
  for (std::int64_t k = 0; k < std::int64_t(count); ++k) value(prop.type);
  return count;
}

}  // namespace

PartLabels read_ply_part_labels(const std::filesystem::path& path, const std::vector<std::string>& names) {
  const std::string data = io::read_file(path);
  const io::PlyHeader header = io::parse_ply_header(path, data, data.size());
  std::vector<std::string> present;
  for (const io::Element& e : header.elements)
    if (e.name == "vertex")
      for (const io::Property& prop : e.properties) present.push_back(prop.name);
  int xyz[3] = {-1, -1, -1}, label = -1;
  PartLabels out;
  const auto it = std::find_first_of(names.begin(), names.end(), present.begin(), present.end());
  if (it == names.end()) {
    std::string wanted, has;
    for (const auto& n : names) wanted += (wanted.empty() ? "'" : " or '") + n + "'";
    for (const auto& n : present) has += (has.empty() ? "" : " ") + n;
    io::fail(path, "no vertex property " + wanted + " with the parts (the vertices have " + has + ")");
  }
  out.property = *it;
  bool started = false;
  const bool swap = (header.encoding == io::Encoding::kLittle) != (std::endian::native == std::endian::little);
  const char* p = data.data() + std::min(header.body, data.size());
  const char* end = data.data() + data.size();
  io::Tokenizer tok(p, end);
  for (const io::Element& e : header.elements) {
    const bool vertex = e.name == "vertex";
    if (vertex) {
      for (size_t k = 0; k < e.properties.size(); ++k) {
        const std::string& n = e.properties[k].name;
        if (n == "x" || n == "y" || n == "z") xyz[n[0] - 'x'] = int(k);
        if (n == out.property && !e.properties[k].is_list) label = int(k);
      }
      if (label < 0) io::fail(path, "vertex property '" + out.property + "' is a list, expected one integer");
      if (std::min({xyz[0], xyz[1], xyz[2]}) < 0) io::fail(path, "PLY vertex element lacks x, y or z");
      started = true;
    }
    std::vector<double> values(e.properties.size());
    for (std::int64_t r = 0; r < e.count; ++r) {
      for (size_t k = 0; k < e.properties.size(); ++k)
        values[k] = read_property(e.properties[k], header.encoding, swap, tok, p, end, path);
      if (!vertex) continue;
      const double l = values[size_t(label)];
      if (l != std::floor(l) || std::abs(l) > 2e9)
        io::fail(path, "vertex " + std::to_string(r) + " has the part '" + io::short_number(l) + "' in property '" +
                           out.property + "', not an integer");
      const Eigen::Vector3d x(values[size_t(xyz[0])], values[size_t(xyz[1])], values[size_t(xyz[2])]);
      if (!x.allFinite()) continue;
      out.positions.push_back(x);
      out.labels.push_back(int(l));
    }
    if (started) break;  // nothing after the vertices is needed
  }
  return out;
}

}  // namespace scanfill
