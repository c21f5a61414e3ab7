#include "engine/config.h"

#include <yaml-cpp/yaml.h>

#include <iomanip>
#include <map>
#include <sstream>

#include "engine/fields.h"
#include "nodes/core/errors.h"
#include "nodes/procedural/shapes.h"

namespace scanfill {
namespace {

constexpr const char* kProcedural = "procedural:";
constexpr const char* kRevolution = "revolution:";

std::string join(const std::vector<std::string>& v, const char* sep = ", ") {
  std::string out;
  for (const auto& s : v) out += (out.empty() ? "" : sep) + s;
  return out;
}

// Collects problems, each tied to a position in the file when one is known.
class Problems {
 public:
  explicit Problems(std::filesystem::path file) : file_(std::move(file)) {}
  void add(const YAML::Mark& mark, const std::string& key, const std::string& what) {
    std::ostringstream s;
    s << file_.string();
    if (mark.line >= 0) s << ":" << mark.line + 1 << ":" << mark.column + 1;
    s << ": " << key << ": " << what;
    lines_.push_back(s.str());
  }
  void remember(const std::string& key, const YAML::Mark& mark) { marks_[key] = mark; }
  YAML::Mark mark_of(const std::string& key) const {
    const auto it = marks_.find(key);
    return it == marks_.end() ? YAML::Mark::null_mark() : it->second;
  }
  bool empty() const { return lines_.empty(); }
  std::string message() const { return join(lines_, "\n"); }

 private:
  std::filesystem::path file_;
  std::vector<std::string> lines_;
  std::map<std::string, YAML::Mark> marks_;
};

std::string describe(const YAML::Node& n) {
  if (n.IsMap()) return "a map";
  if (n.IsSequence()) return "a list";
  if (n.IsNull()) return "nothing";
  return "'" + n.Scalar() + "'";
}

// Checks that `node` is a map whose keys are all in `valid`; reports the others, listing the valid ones.
bool check_map(const YAML::Node& node, const std::string& key, const std::vector<std::string>& valid,
               Problems& problems) {
  if (!node.IsMap()) {
    problems.add(node.Mark(), key, "expected a map with keys " + join(valid) + ", got " + describe(node));
    return false;
  }
  for (auto it = node.begin(); it != node.end(); ++it) {
    if (!it->first.IsScalar()) {  // a map or list used as a key (`? [a, b]`, `{a: 1}: x`)
      problems.add(it->first.Mark(), key.empty() ? "(top level)" : key,
                   "a key must be a name, got " + describe(it->first));
      continue;
    }
    const std::string k = it->first.as<std::string>();
    if (std::find(valid.begin(), valid.end(), k) == valid.end())
      problems.add(it->first.Mark(), key.empty() ? k : key + "." + k, "unknown key (valid: " + join(valid) + ")");
  }
  return true;
}

template <class T>
bool scalar_as(const YAML::Node& n, T& out) {
  if (!n.IsScalar()) return false;
  try {
    out = n.as<T>();
    return true;
  } catch (const YAML::Exception&) {
    return false;
  }
}

// Reads one field's value from YAML into the config.
void read_field(const YAML::Node& n, const std::string& key, Field& field, Problems& problems) {
  auto bad = [&](const std::string& expected) {
    problems.add(n.Mark(), key, "expected " + expected + ", got " + describe(n));
  };
  std::visit(
      [&](auto* p) {
        using T = std::remove_pointer_t<decltype(p)>;
        if constexpr (std::is_same_v<T, bool>) {
          if (!scalar_as(n, *p)) bad("true or false");
        } else if constexpr (std::is_same_v<T, double>) {
          if (!scalar_as(n, *p)) bad("a number");
        } else if constexpr (std::is_same_v<T, int>) {
          if (!scalar_as(n, *p)) bad("an integer");
        } else if constexpr (std::is_same_v<T, Index>) {
          long long v;
          if (scalar_as(n, v))
            *p = v;
          else
            bad("an integer");
        } else if constexpr (std::is_same_v<T, std::uint64_t>) {
          unsigned long long v;
          if (n.IsScalar() && !n.Scalar().empty() && n.Scalar()[0] != '-' && scalar_as(n, v))
            *p = v;
          else
            bad("a non-negative integer");
        } else if constexpr (std::is_same_v<T, NormalOrientation>) {
          std::string v;
          std::vector<std::string> names;
          for (const auto& [name, value] : orientation_names()) names.push_back(name);
          bool found = false;
          if (scalar_as(n, v))
            for (const auto& [name, value] : orientation_names())
              if (name == v) {
                *p = value;
                found = true;
              }
          if (!found) bad("one of " + join(names));
        } else if constexpr (std::is_same_v<T, std::optional<Eigen::Vector3d>>) {
          if (n.IsNull()) {
            p->reset();
            return;
          }
          Eigen::Vector3d v;
          bool ok = n.IsSequence() && n.size() == 3;
          for (int i = 0; ok && i < 3; ++i) ok = scalar_as(n[i], v(i)) && std::isfinite(v(i));
          if (ok)
            *p = v;
          else
            bad("a list of 3 finite numbers [x, y, z] or ~");
        } else if constexpr (std::is_same_v<T, std::vector<Landmark>>) {
          p->clear();
          const auto point = [&](const YAML::Node& q, Eigen::Vector3d& v) {
            bool ok = q.IsSequence() && q.size() == 3;
            for (int i = 0; ok && i < 3; ++i) ok = scalar_as(q[i], v(i)) && std::isfinite(v(i));
            return ok;
          };
          bool ok = n.IsSequence() || n.IsNull();
          for (size_t i = 0; ok && n.IsSequence() && i < n.size(); ++i) {
            Landmark l;
            ok = n[i].IsSequence() && n[i].size() == 2 && point(n[i][0], l.exemplar) && point(n[i][1], l.source);
            if (ok) p->push_back(l);
          }
          if (!ok) bad("a list of landmark pairs [[x, y, z], [x, y, z]] (exemplar point, source point)");
        }
      },
      field.ref);
}

std::string yaml_value(const FieldRef& ref) {
  return std::visit(
      [](auto* p) -> std::string {
        using T = std::remove_pointer_t<decltype(p)>;
        std::ostringstream s;
        if constexpr (std::is_same_v<T, bool>) {
          s << (*p ? "true" : "false");
        } else if constexpr (std::is_same_v<T, double>) {
          s << std::setprecision(15) << *p;
        } else if constexpr (std::is_same_v<T, NormalOrientation>) {
          s << to_string(*p);
        } else if constexpr (std::is_same_v<T, std::vector<Landmark>>) {
          s << "[";
          for (size_t i = 0; i < p->size(); ++i) {
            const Landmark& l = (*p)[i];
            s << (i ? ", " : "") << "[[" << l.exemplar(0) << ", " << l.exemplar(1) << ", " << l.exemplar(2) << "], ["
              << l.source(0) << ", " << l.source(1) << ", " << l.source(2) << "]]";
          }
          s << "]";
        } else if constexpr (std::is_same_v<T, std::optional<Eigen::Vector3d>>) {
          if (!*p)
            s << "~";
          else
            s << "[" << (**p)(0) << ", " << (**p)(1) << ", " << (**p)(2) << "]";
        } else {
          s << *p;
        }
        return s.str();
      },
      ref);
}

}  // namespace

const std::vector<std::string>& mode_names() {
  static const std::vector<std::string> modes{"completion", "transfer", "analogy"};
  return modes;
}

const std::vector<std::string>& roles_for_mode(const std::string& mode) {
  static const std::map<std::string, std::vector<std::string>> roles{{"completion", {"scan", "template"}},
                                                                     {"transfer", {"source", "target", "exemplar"}},
                                                                     {"analogy", {"source", "target"}}};
  static const std::vector<std::string> none;
  const auto it = roles.find(mode);
  return it == roles.end() ? none : it->second;
}

std::vector<std::pair<std::string, std::string>> validate(const RunConfig& config) {
  std::vector<std::pair<std::string, std::string>> problems;
  RunConfig copy = config;  // field tables take non-const references; validation reads only
  for (const Section& section : option_sections(copy))
    for (const Field& field : section.fields)
      if (auto problem = field.check())
        problems.push_back({section.key + "." + field.key, *problem + ", got " + yaml_value(field.ref)});
  if (std::find(mode_names().begin(), mode_names().end(), config.mode) == mode_names().end())
    problems.push_back({"mode", "expected one of " + join(mode_names()) + ", got '" + config.mode + "'"});
  if (config.threads < 0)
    problems.push_back({"threads", "expected an integer >= 0 (0 = all cores), got " + std::to_string(config.threads)});
  if (config.output_dir.empty()) problems.push_back({"output.dir", "expected a folder path"});
  const auto& roles = roles_for_mode(config.mode);
  for (const std::string& role : roles) {
    const auto it =
        std::find_if(config.inputs.begin(), config.inputs.end(), [&](const InputSpec& s) { return s.role == role; });
    if (it == config.inputs.end()) {
      problems.push_back(
          {"inputs", "mode '" + config.mode + "' needs input '" + role + "' (inputs: " + join(roles) + ")"});
      continue;
    }
    const std::string key = "inputs." + role;
    if (!it->procedural.empty()) {
      const auto& names = shape_names();
      if (std::find(names.begin(), names.end(), it->procedural) == names.end())
        problems.push_back({key, "unknown procedural shape '" + it->procedural + "' (valid: " + join(names) + ")"});
      continue;
    }
    std::error_code ec;
    if (!std::filesystem::exists(it->path, ec))
      problems.push_back({key, "no such file: " + it->path.string()});
    else if (!std::filesystem::is_regular_file(it->path, ec))
      problems.push_back({key, "not a regular file: " + it->path.string()});
    else if (!is_supported_extension(it->path))
      problems.push_back({key, "unknown format '" + it->path.extension().string() + "' of " + it->path.string() +
                                   " (expected .ply, .pcd, .obj, .off, .stl or .xyz)"});
  }
  return problems;
}

RunConfig load_config(const std::filesystem::path& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) throw ConfigError(path.string() + ": no such config file");
  YAML::Node root;
  try {
    root = YAML::LoadFile(path.string());
  } catch (const YAML::Exception& e) {
    std::ostringstream s;
    s << path.string() << ":" << e.mark.line + 1 << ":" << e.mark.column + 1 << ": invalid YAML: " << e.msg;
    throw ConfigError(s.str());
  }
  RunConfig config;
  config.config_path = path;
  Problems problems(path);
  if (!root.IsMap()) {
    problems.add(root.Mark(), "(top level)", "expected a map of settings, got " + describe(root));
    throw ConfigError(problems.message());
  }
  std::vector<std::string> top{"mode", "inputs", "output", "threads"};
  for (const Section& section : option_sections(config)) top.push_back(section.key);
  check_map(root, "", top, problems);

  if (const YAML::Node n = root["mode"]) {
    problems.remember("mode", n.Mark());
    if (!scalar_as(n, config.mode))
      problems.add(n.Mark(), "mode", "expected one of " + join(mode_names()) + ", got " + describe(n));
  } else {
    problems.add(root.Mark(), "mode", "missing (expected one of " + join(mode_names()) + ")");
  }
  if (const YAML::Node n = root["threads"]) {
    problems.remember("threads", n.Mark());
    if (!scalar_as(n, config.threads))
      problems.add(n.Mark(), "threads", "expected an integer >= 0, got " + describe(n));
  }
  if (const YAML::Node n = root["output"]; n && check_map(n, "output", {"dir"}, problems)) {
    if (const YAML::Node d = n["dir"]) {
      std::string dir;
      problems.remember("output.dir", d.Mark());
      if (scalar_as(d, dir) && !dir.empty())
        config.output_dir = dir;
      else
        problems.add(d.Mark(), "output.dir", "expected a folder path, got " + describe(d));
    }
  }
  const std::vector<std::string> all_roles{"scan", "template", "source", "target", "exemplar"};
  const std::filesystem::path base = path.parent_path();
  if (const YAML::Node n = root["inputs"]) {
    problems.remember("inputs", n.Mark());
    const auto& roles = roles_for_mode(config.mode);
    if (check_map(n, "inputs", roles.empty() ? all_roles : roles, problems)) {
      for (auto it = n.begin(); it != n.end(); ++it) {
        if (!it->first.IsScalar()) continue;  // reported by check_map
        InputSpec spec;
        spec.role = it->first.as<std::string>();
        if (!roles.empty() && std::find(roles.begin(), roles.end(), spec.role) == roles.end()) continue;
        const std::string key = "inputs." + spec.role;
        problems.remember(key, it->second.Mark());
        if (!scalar_as(it->second, spec.text) || spec.text.empty()) {
          problems.add(it->second.Mark(), key, "expected a file path or procedural:NAME, got " + describe(it->second));
          continue;
        }
        std::string file = spec.text;
        if (file.rfind(kRevolution, 0) == 0) {
          spec.revolution = true;
          file = file.substr(std::string(kRevolution).size());
        }
        if (file.rfind(kProcedural, 0) == 0)
          spec.procedural = file.substr(std::string(kProcedural).size());
        else
          spec.path = std::filesystem::path(file).is_absolute() ? std::filesystem::path(file) : base / file;
        config.inputs.push_back(spec);
      }
      std::stable_sort(config.inputs.begin(), config.inputs.end(), [&](const InputSpec& a, const InputSpec& b) {
        return std::find(roles.begin(), roles.end(), a.role) < std::find(roles.begin(), roles.end(), b.role);
      });
    }
  } else {
    problems.remember("inputs", root.Mark());
  }
  for (Section& section : option_sections(config)) {
    const YAML::Node n = root[section.key];
    if (!n) continue;
    std::vector<std::string> keys;
    for (const Field& f : section.fields) keys.push_back(f.key);
    if (!check_map(n, section.key, keys, problems)) continue;
    for (Field& field : section.fields) {
      const std::string key = section.key + "." + field.key;
      if (const YAML::Node v = n[field.key]) {
        problems.remember(key, v.Mark());
        read_field(v, key, field, problems);
      }
    }
  }
  // Ranges and inputs of every value that parsed (one that did not keeps its valid default): all problems at once.
  for (const auto& [key, what] : validate(config)) problems.add(problems.mark_of(key), key, what);
  if (!problems.empty()) throw ConfigError(problems.message());
  config.support.allow_scale = config.vote.allow_scale;
  return config;
}

std::string default_config_yaml() {
  RunConfig config;
  std::ostringstream s;
  s << "# scanfill configuration: every option with its default. Relative input paths are relative to this file.\n"
    << "mode: completion            # " << join(mode_names(), " | ") << "\n"
    << "inputs:                     # completion: scan, template; transfer: source, target, exemplar;\n"
    << "                            # analogy: source, target. A file (.ply .pcd .obj .off .stl .xyz)\n"
    << "                            # or procedural:NAME (" << join(shape_names()) << "),\n"
    << "                            # or revolution:FILE (the body of revolution about z of a model: a template)\n"
    << "  scan: procedural:vase\n"
    << "  template: procedural:vase_template\n"
    << "output:\n"
    << "  dir: out                  # created if missing; relative to the working directory\n"
    << "threads: 0                  # worker threads; 0 = all cores (the --threads option overrides it)\n";
  for (const Section& section : option_sections(config)) {
    s << section.key << ":" << std::string(std::max<int>(1, 28 - int(section.key.size()) - 1), ' ') << "# "
      << section.doc << "\n";
    for (const Field& f : section.fields) {
      std::string line = "  " + f.key + ": " + yaml_value(f.ref);
      line += std::string(std::max<int>(1, 28 - int(line.size())), ' ');
      s << line << "# " << f.doc << "\n";
    }
  }
  return s.str();
}

}  // namespace scanfill
