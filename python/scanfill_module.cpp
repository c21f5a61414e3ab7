// The `scanfill` Python module (issue 14): read, complete, transfer and analogy on numpy arrays or files.
//
// A thin client of the engine, like the CLI. The keyword options become the CLI's `--set KEY=VALUE` texts over a
// generated config that holds only the mode and the output folder, so every key and value is read and checked by
// load_config exactly as in a config file or on the command line, and a bad one raises ValueError with the CLI's own
// message. Arrays are written to temporary PLY files and given to the run as input paths; the results are read back
// from the files the run wrote (output.ply, analogy.ply, report.json), so they are the CLI's results to the bit. The
// run and the file work release the GIL; the Python objects are converted before and after, with the GIL held.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <tbb/global_control.h>
#include <tbb/info.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include "engine/config.h"
#include "engine/console.h"
#include "engine/pipeline.h"
#include "nodes/core/errors.h"
#include "nodes/input/input.h"
#include "nodes/io/read_point_set.h"
#include "nodes/io/write_ply.h"

namespace py = pybind11;

namespace {

using namespace scanfill;

// A folder of its own under the system's temporary folder, removed with its content when the call ends.
class TempFolder {
 public:
  TempFolder() {
    std::string name = (std::filesystem::temp_directory_path() / "scanfill-py-XXXXXX").string();
    if (!::mkdtemp(name.data())) throw IoError(name + ": cannot make a temporary folder");
    path_ = name;
  }
  ~TempFolder() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  TempFolder(const TempFolder&) = delete;
  TempFolder& operator=(const TempFolder&) = delete;
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

// ---------------------------------------------------------------------------------------------------------------------
// Python values -> YAML texts of --set

std::string type_name(const py::handle& obj) {
  if (py::isinstance<py::array>(obj)) return "an array of shape " + py::str(obj.attr("shape")).cast<std::string>();
  return py::str(py::type::handle_of(obj).attr("__name__")).cast<std::string>();
}

std::string double_quoted(const std::string& s) {
  std::string out = "\"";
  for (const char c : s) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      char hex[8];
      std::snprintf(hex, sizeof hex, "\\x%02x", static_cast<unsigned char>(c));
      out += hex;
    } else {
      out += c;
    }
  }
  return out + "\"";
}

// A string option as YAML: plain when it is a word, a number or a path (as one writes it in a config or after --set,
// so the messages show it the same way), double-quoted otherwise.
std::string yaml_string(const std::string& s) {
  const bool plain = !s.empty() && (std::isalnum(static_cast<unsigned char>(s[0])) || std::strchr("/._-+", s[0])) &&
                     std::all_of(s.begin(), s.end(), [](char c) {
                       return std::isalnum(static_cast<unsigned char>(c)) || std::strchr("/._-+:", c);
                     });
  return plain ? s : double_quoted(s);
}

// A Python value as the YAML text of one config value: bool, int, float, str, path, None, and lists (also arrays) of
// them. `key` names the option in the TypeError of anything else.
std::string yaml_value(py::handle value, const std::string& key) {
  static const py::handle numpy_generic =
      py::object(py::module_::import("numpy").attr("generic")).release();  // kept to the end
  if (py::isinstance(value, numpy_generic)) return yaml_value(value.attr("item")(), key);
  if (py::isinstance<py::array>(value)) return yaml_value(value.attr("tolist")(), key);
  if (value.is_none()) return "~";
  if (py::isinstance<py::bool_>(value)) return value.cast<bool>() ? "true" : "false";
  if (py::isinstance<py::int_>(value)) return py::str(value).cast<std::string>();
  if (py::isinstance<py::float_>(value)) {
    const double v = value.cast<double>();
    if (std::isnan(v)) return ".nan";
    if (std::isinf(v)) return v > 0 ? ".inf" : "-.inf";
    return py::repr(value).cast<std::string>();  // the shortest text that reads back as the same double
  }
  if (py::isinstance<py::str>(value)) return yaml_string(value.cast<std::string>());
  if (py::hasattr(value, "__fspath__"))
    return yaml_string(py::module_::import("os").attr("fsdecode")(value).cast<std::string>());
  if (py::isinstance<py::list>(value) || py::isinstance<py::tuple>(value)) {
    std::string out = "[";
    for (const py::handle item : value) out += (out.size() > 1 ? ", " : "") + yaml_value(item, key);
    return out + "]";
  }
  throw py::type_error(key + ": expected a bool, number, string, path or list, got " + type_name(value));
}

// Options as --set texts: a dict value is a section (sample={'count': 20000} is sample.count=20000), a dotted name is
// a key of a section (**{'sample.count': 20000}). Nesting deeper than that is passed on for load_config to refuse.
void flatten_option(const std::string& key, py::handle value, std::vector<std::string>& out) {
  const std::string top = key.substr(0, key.find('.'));
  if (top == "mode") throw py::value_error("mode: set by the function called (complete, transfer or analogy)");
  if (top == "inputs") throw py::value_error(key + ": the inputs are the function's arguments");
  if (py::isinstance<py::dict>(value)) {
    for (const auto& [k, v] : value.cast<py::dict>())
      flatten_option(key + "." + py::str(k).cast<std::string>(), v, out);
    return;
  }
  out.push_back(key + "=" + yaml_value(value, key));
}

// ---------------------------------------------------------------------------------------------------------------------
// Inputs: paths and input texts as they are, arrays written to PLY files

// `text` with a relative file made absolute: the generated config lives in a temporary folder and a config's relative
// paths are relative to its folder, a Python caller's to the working directory.
std::string absolute_input(const std::string& text) {
  const InputSpec spec = parse_input(text, std::filesystem::current_path());
  if (!spec.procedural.empty()) return text;
  return (spec.revolution ? "revolution:" : spec.box ? "box:" : "") + spec.path.string();
}

// A C-contiguous copy of an N x 3 array as a 3 x N matrix (row-major N x 3 is column-major 3 x N).
template <class T>
Eigen::Matrix<T, 3, Eigen::Dynamic> rows_of_three(py::handle obj, const std::string& what) {
  const auto a = py::array_t<T, py::array::c_style | py::array::forcecast>::ensure(obj);
  if (!a || a.ndim() != 2 || a.shape(1) != 3)
    throw py::value_error(what + ": expected an N x 3 array, got " + type_name(obj));
  Eigen::Matrix<T, 3, Eigen::Dynamic> m(3, a.shape(0));
  if (a.size() > 0) std::memcpy(m.data(), a.data(), sizeof(T) * size_t(a.size()));
  return m;
}

// An array input: N x 3 points, or a dict with 'points' and optionally 'normals' (N x 3) and 'faces' (F x 3 vertex
// indices). The other keys of read()'s and the runs' results are allowed and ignored, so a result can be an input.
PointSet point_set_from(py::handle obj, const std::string& name) {
  py::object points = py::reinterpret_borrow<py::object>(obj), normals, faces;
  if (py::isinstance<py::dict>(obj)) {
    const auto d = py::reinterpret_borrow<py::dict>(obj);
    static const std::vector<std::string> known{"points", "normals", "faces",      "origin",     "label",
                                                "colors", "report",  "curvatures", "directions", "analogy"};
    for (const auto& [k, v] : d) {
      const std::string key = py::str(k).cast<std::string>();
      if (std::find(known.begin(), known.end(), key) == known.end())
        throw py::value_error(name + "['" + key + "']: unknown key (an input dict has points, normals, faces)");
    }
    if (!d.contains("points")) throw py::value_error(name + ": a dict input needs 'points' (an N x 3 array)");
    points = d["points"];
    if (d.contains("normals") && !d["normals"].is_none()) normals = d["normals"];
    if (d.contains("faces") && !d["faces"].is_none()) faces = d["faces"];
  }
  PointSet ps(rows_of_three<double>(points, name + " points"));
  if (ps.empty()) throw py::value_error(name + ": no points");
  if (normals) {
    Eigen::Matrix3Xd n = rows_of_three<double>(normals, name + " normals");
    if (n.cols() != ps.size())
      throw py::value_error(name + " normals: " + std::to_string(n.cols()) + " rows for " + std::to_string(ps.size()) +
                            " points");
    ps.set_normals(std::move(n));
  }
  if (faces) {
    const auto f = rows_of_three<std::int64_t>(faces, name + " faces");
    if (f.size() > 0 && (f.minCoeff() < 0 || f.maxCoeff() >= ps.size()))
      throw py::value_error(name + " faces: vertex indices must be in [0, " + std::to_string(ps.size()) + ")");
    ps.set_faces(f.cast<std::int32_t>());
  }
  return ps;
}

// The YAML value of one input: a file, procedural:NAME or revolution:... as given (str or path), an array or dict
// written to a PLY file in `folder`, or (scan and exemplar) a list of fragments.
std::string input_value(py::handle obj, const std::string& name, bool fragments, const std::filesystem::path& folder,
                        int& files) {
  if (py::isinstance<py::str>(obj) || py::hasattr(obj, "__fspath__"))
    return double_quoted(absolute_input(py::module_::import("os").attr("fsdecode")(obj).cast<std::string>()));
  if (py::isinstance<py::list>(obj) || py::isinstance<py::tuple>(obj)) {
    if (!fragments)
      throw py::value_error(name +
                            ": expected a path, procedural:NAME, an N x 3 numpy array or a dict with 'points', " +
                            "got a list (a list is a list of fragments, taken by scan and exemplar only)");
    if (py::len(obj) == 0) throw py::value_error(name + ": an empty list of fragments");
    std::string out = "[";
    int i = 0;
    for (const py::handle item : obj) {
      const std::string value = input_value(item, name + "[" + std::to_string(i) + "]", false, folder, files);
      out += (i++ ? ", " : "") + value;
    }
    return out + "]";
  }
  if (!py::isinstance<py::dict>(obj) && !py::array::ensure(obj))
    throw py::value_error(name + ": expected a path, procedural:NAME, an N x 3 array or a dict with 'points', got " +
                          type_name(obj));
  const PointSet ps = point_set_from(obj, name);
  const std::filesystem::path file = folder / ("input" + std::to_string(files++) + ".ply");
  {
    py::gil_scoped_release release;
    write_ply(file, ps);
  }
  return double_quoted(file.string());
}

// ---------------------------------------------------------------------------------------------------------------------
// Results: our own binary PLY read back whole, every vertex property kept

struct PlyColumn {
  std::string name;
  char kind = 'f';  // numpy's: 'f' float, 'i' signed, 'u' unsigned
  int bytes = 4;
  std::vector<double> values;
};

struct PlyData {
  std::vector<PlyColumn> columns;
  std::vector<std::int32_t> faces;  // 3 per triangle
  const PlyColumn* find(const std::string& name) const {
    for (const PlyColumn& c : columns)
      if (c.name == name) return &c;
    return nullptr;
  }
};

bool ply_type(const std::string& t, char& kind, int& bytes) {
  static const std::vector<std::tuple<std::string, char, int>> types{
      {"char", 'i', 1},  {"int8", 'i', 1},    {"uchar", 'u', 1},  {"uint8", 'u', 1},
      {"short", 'i', 2}, {"int16", 'i', 2},   {"ushort", 'u', 2}, {"uint16", 'u', 2},
      {"int", 'i', 4},   {"int32", 'i', 4},   {"uint", 'u', 4},   {"uint32", 'u', 4},
      {"float", 'f', 4}, {"float32", 'f', 4}, {"double", 'f', 8}, {"float64", 'f', 8}};
  for (const auto& [name, k, b] : types)
    if (name == t) {
      kind = k;
      bytes = b;
      return true;
    }
  return false;
}

double ply_value(const char* p, char kind, int bytes) {
  auto get = [p]<class T>(T) {
    T v;
    std::memcpy(&v, p, sizeof v);
    return double(v);
  };
  if (kind == 'f') return bytes == 4 ? get(float{}) : get(double{});
  if (kind == 'u') return bytes == 1 ? get(std::uint8_t{}) : bytes == 2 ? get(std::uint16_t{}) : get(std::uint32_t{});
  return bytes == 1 ? get(std::int8_t{}) : bytes == 2 ? get(std::int16_t{}) : get(std::int32_t{});
}

// Reads a binary little-endian PLY as write_ply writes it (vertex properties, then optional triangles), which
// read_point_set does not keep whole (origin, label and colours are not point-set attributes).
PlyData read_own_ply(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::string data((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (!in.good() && !in.eof()) throw IoError(path.string() + ": cannot be read");
  const auto bad = [&](const std::string& what) { return IoError(path.string() + ": " + what); };
  const size_t end = data.find("end_header\n");
  if (end == std::string::npos) throw bad("no PLY header");
  std::istringstream header(data.substr(0, end));
  PlyData ply;
  Index vertices = 0, faces = 0;
  std::string element, line;
  while (std::getline(header, line)) {
    std::istringstream words(line);
    std::string word, type, name;
    words >> word;
    if (word == "format" && line != "format binary_little_endian 1.0") throw bad("not a binary little-endian PLY");
    if (word == "element") {
      Index n = -1;
      words >> element >> n;
      if ((element != "vertex" && element != "face") || n < 0) throw bad("unexpected element '" + line + "'");
      (element == "vertex" ? vertices : faces) = n;
    } else if (word == "property" && element == "vertex") {
      PlyColumn c;
      words >> type >> c.name;
      if (!ply_type(type, c.kind, c.bytes)) throw bad("unknown property type '" + type + "'");
      ply.columns.push_back(std::move(c));
    } else if (word == "property" && line != "property list uchar int vertex_indices") {
      throw bad("faces other than 'list uchar int vertex_indices'");
    }
  }
  int stride = 0;
  for (const PlyColumn& c : ply.columns) stride += c.bytes;
  size_t at = end + std::strlen("end_header\n");
  if (data.size() < at + size_t(vertices) * size_t(stride) + size_t(faces) * 13) throw bad("truncated");
  for (PlyColumn& c : ply.columns) c.values.resize(size_t(vertices));
  for (Index i = 0; i < vertices; ++i)
    for (PlyColumn& c : ply.columns) {
      c.values[size_t(i)] = ply_value(data.data() + at, c.kind, c.bytes);
      at += size_t(c.bytes);
    }
  ply.faces.resize(size_t(faces) * 3);
  for (Index f = 0; f < faces; ++f) {
    if (data[at] != 3) throw bad("a face that is not a triangle");
    std::memcpy(ply.faces.data() + 3 * f, data.data() + at + 1, 12);
    at += 13;
  }
  return ply;
}

template <class T>
py::array_t<T> array_of(const std::vector<const std::vector<double>*>& columns) {
  const size_t n = columns.empty() ? 0 : columns[0]->size(), k = columns.size();
  py::array_t<T> a(k == 1 ? std::vector<py::ssize_t>{py::ssize_t(n)}
                          : std::vector<py::ssize_t>{py::ssize_t(n), py::ssize_t(k)});
  T* out = a.mutable_data();
  for (size_t i = 0; i < n; ++i)
    for (size_t j = 0; j < k; ++j) out[i * k + j] = T((*columns[j])[i]);
  return a;
}

// The arrays of a PLY read back: points, normals, colors, curvatures, directions (N x k, as their PLY properties are
// grouped), faces (F x 3), and every other vertex property by its name (origin, label) with the file's type.
py::dict arrays_of(const PlyData& ply) {
  py::dict out;
  std::vector<std::string> grouped;
  const auto group = [&]<class T>(const char* key, std::vector<std::string> names, T) {
    std::vector<const std::vector<double>*> columns;
    for (const std::string& name : names)
      if (const PlyColumn* c = ply.find(name)) columns.push_back(&c->values);
    if (columns.size() != names.size()) return;
    out[key] = array_of<T>(columns);
    grouped.insert(grouped.end(), names.begin(), names.end());
  };
  group("points", {"x", "y", "z"}, double{});
  group("normals", {"nx", "ny", "nz"}, double{});
  group("colors", {"red", "green", "blue"}, std::uint8_t{});
  group("curvatures", {"k1", "k2"}, double{});
  group("directions", {"d1x", "d1y", "d1z"}, double{});
  for (const PlyColumn& c : ply.columns) {
    if (std::find(grouped.begin(), grouped.end(), c.name) != grouped.end()) continue;
    const std::vector<const std::vector<double>*> column{&c.values};
    if (c.kind == 'f')
      out[c.name.c_str()] = array_of<double>(column);
    else if (c.kind == 'u' && c.bytes == 1)
      out[c.name.c_str()] = array_of<std::uint8_t>(column);
    else
      out[c.name.c_str()] = array_of<std::int64_t>(column);
  }
  if (!ply.faces.empty()) {
    py::array_t<std::int32_t> f({py::ssize_t(ply.faces.size() / 3), py::ssize_t(3)});
    std::memcpy(f.mutable_data(), ply.faces.data(), ply.faces.size() * sizeof(std::int32_t));
    out["faces"] = f;
  }
  return out;
}

// ---------------------------------------------------------------------------------------------------------------------
// The calls

struct RunFiles {
  std::optional<PlyData> output, analogy;
  std::string report;
};

py::dict run_mode(RunMode mode, const std::vector<std::pair<Role, py::handle>>& inputs, const py::kwargs& options) {
  TempFolder temp;  // the arrays' PLY files, the generated config and, unless output.dir is given, the outputs
  std::vector<std::string> overrides;
  int files = 0;
  for (const auto& [role, obj] : inputs) {
    const std::string name = role_name(role);
    overrides.push_back("inputs." + name + "=" + input_value(obj, name, takes_fragments(role), temp.path(), files));
  }
  for (const auto& [key, value] : options) flatten_option(py::str(key).cast<std::string>(), value, overrides);
  RunFiles got;
  {
    py::gil_scoped_release release;
    const std::filesystem::path config_path = temp.path() / "config.yaml";
    write_file_atomic(config_path, "mode: " + mode_name(mode) +
                                       "\noutput:\n  dir: " + double_quoted((temp.path() / "out").string()) + "\n");
    const RunConfig config = load_config(config_path, overrides);
    {
      const int threads = config.threads > 0 ? config.threads : tbb::info::default_concurrency();
      const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(threads));
      run(config);
    }
    const std::filesystem::path dir = config.output_dir;
    if (std::filesystem::exists(dir / "output.ply")) got.output = read_own_ply(dir / "output.ply");
    if (std::filesystem::exists(dir / "analogy.ply")) got.analogy = read_own_ply(dir / "analogy.ply");
    std::ifstream report(dir / "report.json");
    got.report.assign(std::istreambuf_iterator<char>(report), std::istreambuf_iterator<char>());
  }
  py::dict result;
  if (got.output) {
    result = arrays_of(*got.output);
    if (got.analogy) result["analogy"] = arrays_of(*got.analogy);
  } else if (got.analogy) {
    result = arrays_of(*got.analogy);
  }
  result["report"] = py::module_::import("json").attr("loads")(got.report);
  return result;
}

py::dict read_shape(py::handle path) {
  const std::string text = py::module_::import("os").attr("fsdecode")(path).cast<std::string>();
  LoadResult loaded;
  {
    py::gil_scoped_release release;
    // File order, as the file has it: Morton ordering is the pipeline's business.
    loaded = load_input(parse_input(text), LoadOptions{.morton_sort = false});
  }
  const PointSet& p = loaded.points;
  py::dict out;
  const auto rows = [](const Eigen::Matrix3Xd& m) {
    py::array_t<double> a({py::ssize_t(m.cols()), py::ssize_t(3)});
    std::memcpy(a.mutable_data(), m.data(), sizeof(double) * size_t(m.size()));
    return a;
  };
  out["points"] = rows(p.positions());
  if (p.has_normals()) out["normals"] = rows(p.normals());
  if (p.has_colours()) {
    py::array_t<std::uint8_t> c({py::ssize_t(p.size()), py::ssize_t(3)});
    std::memcpy(c.mutable_data(), p.colours().data(), size_t(p.colours().size()));
    out["colors"] = c;
  }
  if (p.has_intensity()) {
    py::array_t<float> v(py::ssize_t(p.size()));
    std::memcpy(v.mutable_data(), p.intensity().data(), sizeof(float) * size_t(p.size()));
    out["intensity"] = v;
  }
  if (p.has_faces()) {
    py::array_t<std::int32_t> f({py::ssize_t(p.faces().cols()), py::ssize_t(3)});
    std::memcpy(f.mutable_data(), p.faces().data(), sizeof(std::int32_t) * size_t(p.faces().size()));
    out["faces"] = f;
  }
  return out;
}

}  // namespace

PYBIND11_MODULE(scanfill, m) {
  m.doc() =
      "scanfill: complete partial 3D scans and transfer geometric style by shape analogies (Ma et al. 2014).\n\n"
      "Inputs are paths (any format scanfill reads), 'procedural:NAME', 'revolution:...', N x 3 numpy arrays of\n"
      "points, or dicts {'points': N x 3, 'normals': N x 3, 'faces': F x 3}; scan and exemplar also take a list of\n"
      "fragments. Options are the config's YAML keys: sample={'count': 20000} or **{'sample.count': 20000};\n"
      "scanfill.default_config() lists them all. Results are dicts of numpy arrays with the run's report.";
  m.attr("__version__") = SCANFILL_VERSION;

  // Error is a RuntimeError; ConfigError (a bad option or input) is also a ValueError. Registered base first: the
  // translators are tried latest first.
  auto& error = py::register_exception<Error>(m, "Error", PyExc_RuntimeError);
  py::register_exception<ConfigError>(m, "ConfigError", py::make_tuple(error, py::handle(PyExc_ValueError)));

  // Warnings and errors only unless SPDLOG_LEVEL says otherwise: a library call should not chatter.
  setup_logging(false, std::getenv("SPDLOG_LEVEL") == nullptr);

  m.def("read", &read_shape, py::arg("path"),
        "read(path) -> dict\n\n"
        "Reads a point cloud or mesh (.ply .pcd .obj .off .stl .xyz, procedural:NAME, revolution:...) in file order:\n"
        "{'points': N x 3 float64, 'normals': N x 3 (when the file has them), 'colors': N x 3 uint8 and\n"
        "'intensity': N float32 (when the file has them), 'faces': F x 3 int32 (meshes)}.");
  m.def(
      "complete",
      [](py::handle scan, py::handle template_shape, const py::kwargs& options) {
        return run_mode(RunMode::kCompletion, {{Role::kScan, scan}, {Role::kTemplate, template_shape}}, options);
      },
      py::arg("scan"), py::arg("template"),
      "complete(scan, template, **options) -> dict\n\n"
      "Completes a partial scan with the structure of a template (mode: completion). Returns output.ply's arrays:\n"
      "'points', 'normals', 'origin' (0 scan, 1 synthesised, 2 copied), 'label' (the transform), 'colors' (N x 3\n"
      "uint8, as output.colour says), 'intensity' (when the scan has it), 'faces' when meshed; 'analogy' "
      "(analogy.ply's arrays) and 'report' (report.json as a dict).\n"
      "output={'dir': PATH} keeps the files; otherwise they are written to a temporary folder and removed.");
  m.def(
      "transfer",
      [](py::handle source, py::handle target, py::handle exemplar, const py::kwargs& options) {
        return run_mode(RunMode::kTransfer,
                        {{Role::kSource, source}, {Role::kTarget, target}, {Role::kExemplar, exemplar}}, options);
      },
      py::arg("source"), py::arg("target"), py::arg("exemplar"),
      "transfer(source, target, exemplar, **options) -> dict\n\n"
      "Transfers the exemplar's style by the analogy source -> target (mode: transfer). Returns what complete() does.");
  m.def(
      "analogy",
      [](py::handle source, py::handle target, const py::kwargs& options) {
        return run_mode(RunMode::kAnalogy, {{Role::kSource, source}, {Role::kTarget, target}}, options);
      },
      py::arg("source"), py::arg("target"),
      "analogy(source, target, **options) -> dict\n\n"
      "The analogy source -> target alone (mode: analogy). Returns analogy.ply's arrays, the target's samples:\n"
      "'points', 'normals', 'curvatures', 'directions', 'label' (the transform of each), 'colors'; and 'report'.");
  m.def("default_config", &default_config_yaml,
        "default_config() -> str\n\nEvery option with its default and meaning, as `scanfill --print-defaults`.");
}
