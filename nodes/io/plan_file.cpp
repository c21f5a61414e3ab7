#include "nodes/io/plan_file.h"

#include <bit>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <string>
#include <type_traits>

#include "nodes/core/errors.h"
#include "nodes/io/write_ply.h"

namespace scanfill {
namespace {

static_assert(std::endian::native == std::endian::little, "big-endian hosts would need byte swapping here");

constexpr char kMagic[8] = {'S', 'C', 'N', 'F', 'P', 'L', 'A', 'N'};
constexpr size_t kHeaderBytes = 32;

std::uint64_t fnv1a(const char* data, size_t n) {
  std::uint64_t h = 14695981039346656037ull;
  for (size_t i = 0; i < n; ++i) h = (h ^ std::uint8_t(data[i])) * 1099511628211ull;
  return h;
}

// Appends to a payload.
class Writer {
 public:
  template <class T>
  void put(T v) {
    static_assert(std::is_trivially_copyable_v<T>);
    buf.append(reinterpret_cast<const char*>(&v), sizeof(T));
  }
  void put_matrix(const Eigen::Matrix3Xd& m) {
    put(std::uint64_t(m.cols()));
    buf.append(reinterpret_cast<const char*>(m.data()), size_t(m.size()) * sizeof(double));
  }
  template <class T>
  void put_vector(const std::vector<T>& v) {
    put(std::uint64_t(v.size()));
    buf.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
  }
  std::string buf;
};

// Reads a payload; any read past its end means the counts in it are wrong.
class Reader {
 public:
  Reader(const std::string& buf, size_t pos, const std::string& file) : buf_(buf), pos_(pos), file_(file) {}
  template <class T>
  T get() {
    T v;
    std::memcpy(&v, take(sizeof(T)), sizeof(T));
    return v;
  }
  // A count of items of `bytes` each, checked against what is left before anything is allocated.
  size_t count(size_t bytes) {
    const auto n = get<std::uint64_t>();
    if (n > (buf_.size() - pos_) / bytes) corrupt("an array longer than the file");
    return size_t(n);
  }
  Eigen::Matrix3Xd get_matrix() {
    Eigen::Matrix3Xd m(3, Index(count(3 * sizeof(double))));
    std::memcpy(m.data(), take(size_t(m.size()) * sizeof(double)), size_t(m.size()) * sizeof(double));
    return m;
  }
  template <class T>
  std::vector<T> get_vector() {
    std::vector<T> v(count(sizeof(T)));
    std::memcpy(v.data(), take(v.size() * sizeof(T)), v.size() * sizeof(T));
    return v;
  }
  bool at_end() const { return pos_ == buf_.size(); }
  [[noreturn]] void corrupt(const std::string& what) const {
    throw IoError(file_ + ": not a valid scanfill plan (" + what + ")");
  }

 private:
  const char* take(size_t n) {
    if (n > buf_.size() - pos_) corrupt("it ends inside a field");
    const char* p = buf_.data() + pos_;
    pos_ += n;
    return p;
  }
  const std::string& buf_;
  size_t pos_;
  std::string file_;
};

void put_similarity(Writer& w, const Similarity& s) {
  for (Index i = 0; i < 9; ++i) w.put(s.rotation.data()[i]);
  for (int i = 0; i < 3; ++i) w.put(s.translation[i]);
  w.put(s.scale);
}

Similarity get_similarity(Reader& r) {
  Similarity s;
  for (Index i = 0; i < 9; ++i) s.rotation.data()[i] = r.get<double>();
  for (int i = 0; i < 3; ++i) s.translation[i] = r.get<double>();
  s.scale = r.get<double>();
  return s;
}

std::string payload_of(const PlanFile& f) {
  const TransferPlan& p = f.plan;
  Writer w;
  w.put(std::int32_t(f.self_label));
  w.put(std::uint8_t(f.colour));
  w.put(std::uint8_t(p.mesh_output));
  w.put(std::uint8_t(p.colours));
  w.put(std::uint8_t(p.intensity));
  w.put(std::int64_t(p.exemplar_points));
  for (int i = 0; i < 3; ++i) w.put(p.exemplar_bounds.min[i]);
  for (int i = 0; i < 3; ++i) w.put(p.exemplar_bounds.max[i]);
  w.put_matrix(p.exemplar_samples);
  w.put_matrix(p.target_samples);
  w.put(std::uint64_t(p.patches.size()));
  for (const PlanPatch& q : p.patches) {
    w.put(std::int32_t(q.label));
    w.put(std::uint8_t(q.origin));
    w.put(std::uint8_t(q.from_target));
    put_similarity(w, q.whole);
  }
  w.put_vector(p.patch);
  w.put_vector(p.base);
  w.put_vector(p.shift);
  w.put_matrix(p.normal);
  return std::move(w.buf);
}

PlanFile plan_of(Reader& r) {
  PlanFile f;
  TransferPlan& p = f.plan;
  f.self_label = r.get<std::int32_t>();
  const auto colour = r.get<std::uint8_t>();
  if (colour > std::uint8_t(PlanColour::kScan)) r.corrupt("an unknown output colour");
  f.colour = PlanColour(colour);
  p.mesh_output = r.get<std::uint8_t>() != 0;
  p.colours = r.get<std::uint8_t>() != 0;
  p.intensity = r.get<std::uint8_t>() != 0;
  if (f.colour == PlanColour::kScan && !p.colours) r.corrupt("the scan's own colours asked for, but it has none");
  p.exemplar_points = r.get<std::int64_t>();
  for (int i = 0; i < 3; ++i) p.exemplar_bounds.min[i] = r.get<double>();
  for (int i = 0; i < 3; ++i) p.exemplar_bounds.max[i] = r.get<double>();
  p.exemplar_samples = r.get_matrix();
  p.target_samples = r.get_matrix();
  p.patches.resize(r.count(2 + 4 + 13 * sizeof(double)));
  for (PlanPatch& q : p.patches) {
    q.label = r.get<std::int32_t>();
    const auto origin = r.get<std::uint8_t>();
    if (origin > std::uint8_t(Origin::kTarget)) r.corrupt("a patch of unknown origin");
    q.origin = Origin(origin);
    q.from_target = r.get<std::uint8_t>() != 0;
    q.whole = get_similarity(r);
  }
  p.patch = r.get_vector<std::int32_t>();
  p.base = r.get_vector<std::int32_t>();
  p.shift = r.get_vector<double>();
  p.normal = r.get_matrix();
  if (!r.at_end()) r.corrupt("bytes after the plan");
  if (const std::string what = plan_inconsistency(p); !what.empty()) r.corrupt(what);
  return f;
}

std::string read_whole(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError(path.string() + ": cannot be opened (" + std::strerror(errno) + ")");
  std::string buf((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) throw IoError(path.string() + ": read failed");
  return buf;
}

}  // namespace

void write_plan(const std::filesystem::path& path, const PlanFile& plan) {
  const std::string payload = payload_of(plan);
  Writer header;
  header.buf.append(kMagic, sizeof(kMagic));
  header.put(kPlanFormatVersion);
  header.put(std::uint32_t(0));
  header.put(std::uint64_t(payload.size()));
  header.put(fnv1a(payload.data(), payload.size()));
  write_file_atomic(path, header.buf + payload);
}

PlanFile read_plan(const std::filesystem::path& path) {
  const std::string file = path.string();
  const std::string buf = read_whole(path);
  if (buf.size() < sizeof(kMagic) || std::memcmp(buf.data(), kMagic, sizeof(kMagic)) != 0)
    throw IoError(file + ": not a scanfill plan (no SCNFPLAN magic; make one with scanfill plan)");
  Reader header(buf, sizeof(kMagic), file);
  if (buf.size() < kHeaderBytes)
    throw IoError(file + ": truncated scanfill plan (" + std::to_string(buf.size()) +
                  " bytes, shorter than its header)");
  const auto version = header.get<std::uint32_t>();
  if (version != kPlanFormatVersion)
    throw IoError(file + ": a plan of format version " + std::to_string(version) + "; this scanfill reads version " +
                  std::to_string(kPlanFormatVersion) + " (make the plan again with this scanfill)");
  header.get<std::uint32_t>();
  const auto length = header.get<std::uint64_t>();
  const auto hash = header.get<std::uint64_t>();
  if (length != buf.size() - kHeaderBytes)
    throw IoError(file + ": " + (length > buf.size() - kHeaderBytes ? "truncated" : "overlong") + " scanfill plan (" +
                  std::to_string(buf.size()) + " bytes, the header says " + std::to_string(length + kHeaderBytes) +
                  ")");
  if (fnv1a(buf.data() + kHeaderBytes, buf.size() - kHeaderBytes) != hash)
    throw IoError(file + ": corrupt scanfill plan (its content does not match the header's hash)");
  Reader r(buf, kHeaderBytes, file);
  return plan_of(r);
}

}  // namespace scanfill
