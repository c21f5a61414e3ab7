#include "engine/config.h"

#include <yaml-cpp/yaml.h>

#include <iomanip>
#include <map>
#include <sstream>

#include "engine/fields.h"
#include "nodes/core/errors.h"
#include "nodes/procedural/castle.h"
#include "nodes/procedural/shapes.h"

namespace scanfill {
namespace {

const std::vector<std::pair<std::string, Role>>& role_names() {
  static const std::vector<std::pair<std::string, Role>> names{{"scan", Role::kScan},
                                                               {"template", Role::kTemplate},
                                                               {"source", Role::kSource},
                                                               {"target", Role::kTarget},
                                                               {"exemplar", Role::kExemplar}};
  return names;
}

std::vector<std::string> mode_list() {
  std::vector<std::string> out;
  for (const auto& [name, mode] : mode_names()) out.push_back(name);
  return out;
}

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
    if (const auto it = overridden_.find(key); it != overridden_.end()) {
      s << "--set " << it->second;  // a value from the command line: no place in the file
    } else {
      s << file_.string();
      if (mark.line >= 0) s << ":" << mark.line + 1 << ":" << mark.column + 1;
    }
    s << ": " << key << ": " << what;
    lines_.push_back(s.str());
  }
  void overridden(const std::string& key, const std::string& text) { overridden_[key] = text; }
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
  std::map<std::string, std::string> overridden_;  // key -> "KEY=VALUE" as given to --set
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
        } else if constexpr (std::is_same_v<T, std::string>) {
          if (!scalar_as(n, *p) || p->empty()) bad("a name");
        } else if constexpr (std::is_same_v<T, LandmarkFiles>) {
          std::string exemplar, source;
          if (n.IsNull() || (n.IsSequence() && n.size() == 0)) {
            *p = {};
          } else if (n.IsSequence() && n.size() == 2 && scalar_as(n[0], exemplar) && scalar_as(n[1], source) &&
                     !exemplar.empty() && !source.empty()) {
            *p = {exemplar, source};
          } else {
            bad("two MeshLab picked-points files [SCAN.pp, TEMPLATE.pp] or []");
          }
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
        } else if constexpr (std::is_same_v<T, LandmarkFiles>) {
          if (p->exemplar.empty())
            s << "[]";
          else
            s << "[" << p->exemplar.string() << ", " << p->source.string() << "]";
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

const std::vector<std::pair<std::string, RunMode>>& mode_names() {
  static const std::vector<std::pair<std::string, RunMode>> modes{{"completion", RunMode::kCompletion},
                                                                  {"transfer", RunMode::kTransfer},
                                                                  {"analogy", RunMode::kAnalogy},
                                                                  {"curves", RunMode::kCurves},
                                                                  {"exchange", RunMode::kExchange}};
  return modes;
}

std::string mode_name(RunMode mode) {
  for (const auto& [name, value] : mode_names())
    if (value == mode) return name;
  throw InvariantError("unnamed mode");
}

std::string role_name(Role role) {
  for (const auto& [name, value] : role_names())
    if (value == role) return name;
  throw InvariantError("unnamed role");
}

const std::vector<Role>& roles_for_mode(RunMode mode) {
  static const std::vector<Role> completion{Role::kScan, Role::kTemplate},
      transfer{Role::kSource, Role::kTarget, Role::kExemplar}, analogy{Role::kSource, Role::kTarget},
      exchange{Role::kExemplar, Role::kTarget};
  switch (mode) {
    case RunMode::kExchange:
      return exchange;
    case RunMode::kCompletion:
      return completion;
    case RunMode::kTransfer:
    case RunMode::kCurves:
      return transfer;
    case RunMode::kAnalogy:
      break;
  }
  return analogy;
}

const std::vector<std::pair<std::string, SurfaceChoice>>& surface_choice_names() {
  static const std::vector<std::pair<std::string, SurfaceChoice>> names{
      {"auto", SurfaceChoice::kAuto}, {"none", SurfaceChoice::kNone}, {"poisson", SurfaceChoice::kPoisson}};
  return names;
}

const std::vector<std::pair<std::string, ColourChoice>>& colour_choice_names() {
  static const std::vector<std::pair<std::string, ColourChoice>> names{{"auto", ColourChoice::kAuto},
                                                                       {"origin", ColourChoice::kOrigin},
                                                                       {"label", ColourChoice::kLabel},
                                                                       {"scan", ColourChoice::kScan}};
  return names;
}

bool makes_surface(const RunConfig& config) {
  if (config.mode == RunMode::kAnalogy || config.mode == RunMode::kCurves || config.mode == RunMode::kExchange)
    return false;
  if (config.output_surface == SurfaceChoice::kAuto) return config.mode == RunMode::kCompletion;
  return config.output_surface == SurfaceChoice::kPoisson;
}

std::vector<const Input*> inputs_for(const RunConfig& config, Role role) {
  std::vector<const Input*> out;
  for (const Input& input : config.inputs)
    if (input.role == role) out.push_back(&input);
  return out;
}

const Input& input_for(const RunConfig& config, Role role) {
  for (const Input& input : config.inputs)
    if (input.role == role) return input;
  throw InvariantError("no input '" + role_name(role) + "' in mode " + mode_name(config.mode));
}

namespace {

std::string box_text(const PartBox& b) {
  std::ostringstream s;
  s << "[[" << b.min.x() << ", " << b.min.y() << ", " << b.min.z() << "], [" << b.max.x() << ", " << b.max.y() << ", "
    << b.max.z() << "]]";
  return s.str();
}

// Where an exchange input's parts come from when the config gives no boxes: a castle's layout, or a PLY's part
// property; nothing else has them.
std::optional<std::string> check_part_source(const Input& input) {
  if (!input.spec.procedural.empty())
    return castle_part_boxes(input.spec.procedural)
               ? std::nullopt
               : std::optional<std::string>("procedural:" + input.spec.procedural +
                                            " has no parts: give its boxes (boxes: [[[x, y, z], [x, y, z]], ...])");
  if (input.spec.revolution || input.spec.path.extension() != ".ply")
    return input_name(input.spec) + ": parts come from a PLY's per-vertex part property or from boxes in the config";
  return std::nullopt;
}

// Mode exchange: every exemplar and target, named once, each with a shape or parts it can have.
void validate_exchange(const RunConfig& config, std::vector<std::pair<std::string, std::string>>& problems) {
  for (const Role role : {Role::kExemplar, Role::kTarget}) {
    const std::vector<const Input*> inputs = inputs_for(config, role);
    if (inputs.empty())
      problems.push_back({"inputs", "mode 'exchange' needs at least one " + role_name(role) +
                                        " (inputs: exemplar, "
                                        "target, each a list)"});
    std::map<std::string, size_t> names;
    for (size_t i = 0; i < inputs.size(); ++i) {
      const Input& in = *inputs[i];
      const std::string key = "inputs." + role_name(role) + "[" + std::to_string(i) + "]";
      if (!in.spec.text.empty()) {
        if (const auto problem = check_input(in.spec)) problems.push_back({key, *problem});
      } else if (role == Role::kExemplar) {
        problems.push_back({key, "an exemplar needs its shape: path: FILE or procedural:NAME"});
      }
      if (!in.boxes && in.spec.text.empty())
        problems.push_back({key, "a target needs its parts: boxes: [[[x, y, z], [x, y, z]], ...] or a path"});
      else if (!in.boxes)
        if (const auto problem = check_part_source(in)) problems.push_back({key, *problem});
      if (in.boxes && in.boxes->empty()) problems.push_back({key + ".boxes", "no parts: expected at least one box"});
      for (size_t b = 0; in.boxes && b < in.boxes->size(); ++b)
        if (!((*in.boxes)[b].size().array() > 0).all())
          problems.push_back(
              {key + ".boxes[" + std::to_string(b) + "]",
               "a box with zero volume: " + box_text((*in.boxes)[b]) + " (expected min < max on x, y, z)"});
      if (const auto [it, fresh] = names.emplace(in.name, i); !fresh)
        problems.push_back({key + ".name", "'" + in.name + "' is also " + role_name(role) + "[" +
                                               std::to_string(it->second) + "]'s: give each its own name"});
    }
  }
}

// Completion votes within [1 / completion_scale, completion_scale] of vote's own range (engine/stages.cpp): the two
// must overlap in more than a point, or no transform survives support's refinement. Each key's own range is checked by
// its field; this only where both hold.
void check_completion_scale(const VoteOptions& v, std::vector<std::pair<std::string, std::string>>& problems) {
  if (!(v.completion_scale > 1 && v.min_scale > 0 && v.min_scale <= v.max_scale)) return;
  if (v.min_scale < v.completion_scale && v.max_scale > 1 / v.completion_scale) return;
  std::ostringstream s;  // the fuzz build links config.cpp without fmt
  s << "completion votes for scales in [1 / " << v.completion_scale << ", " << v.completion_scale
    << "], which [vote.min_scale, vote.max_scale] = [" << v.min_scale << ", " << v.max_scale
    << "] does not overlap: raise vote.completion_scale or widen [vote.min_scale, vote.max_scale]";
  problems.push_back({"vote.completion_scale", s.str()});
}

}  // namespace

std::vector<std::pair<std::string, std::string>> validate(const RunConfig& config) {
  std::vector<std::pair<std::string, std::string>> problems;
  RunConfig copy = config;  // field tables take non-const references; validation reads only
  for (const Section& section : option_sections(copy))
    for (const Field& field : section.fields)
      if (auto problem = field.check())
        problems.push_back({section.key + "." + field.key, *problem + ", got " + yaml_value(field.ref)});
  if (config.threads < 0)
    problems.push_back({"threads", "expected an integer >= 0 (0 = all cores), got " + std::to_string(config.threads)});
  if (config.output_dir.empty()) problems.push_back({"output.dir", "expected a folder path"});
  for (const auto& file : {config.correspond.landmarks_file.exemplar, config.correspond.landmarks_file.source}) {
    std::error_code ec;
    if (!file.empty() && !std::filesystem::is_regular_file(file, ec))
      problems.push_back({"correspond.landmarks_file", "no such file: " + file.string()});
  }
  if (config.mode == RunMode::kAnalogy && config.output_surface == SurfaceChoice::kPoisson)
    problems.push_back({"output.surface", "mode analogy writes no output.ply to mesh: expected auto or none"});
  if (config.mode == RunMode::kCompletion) check_completion_scale(config.vote, problems);
  if (config.mode == RunMode::kCurves && config.output_surface == SurfaceChoice::kPoisson)
    problems.push_back({"output.surface", "mode curves writes curves, not a surface: expected auto or none"});
  if (config.mode == RunMode::kExchange) {
    if (config.output_surface == SurfaceChoice::kPoisson)
      problems.push_back({"output.surface", "mode exchange writes points: expected auto or none"});
    validate_exchange(config, problems);
    return problems;
  }
  std::vector<std::string> roles;
  for (const Role role : roles_for_mode(config.mode)) roles.push_back(role_name(role));
  for (const Role role : roles_for_mode(config.mode)) {
    const auto it =
        std::find_if(config.inputs.begin(), config.inputs.end(), [&](const Input& s) { return s.role == role; });
    if (it == config.inputs.end()) {
      problems.push_back({"inputs", "mode '" + mode_name(config.mode) + "' needs input '" + role_name(role) +
                                        "' (inputs: " + join(roles) + ")"});
      continue;
    }
    const bool drawing = config.mode == RunMode::kCurves;
    if (const auto problem = drawing ? check_drawing_input(it->spec) : check_input(it->spec))
      problems.push_back({"inputs." + role_name(role), *problem});
    if (drawing && !it->fragments.empty())
      problems.push_back({"inputs." + role_name(role), "mode curves takes one drawing per input, not a list"});
    if (!it->fragments.empty() && role == Role::kScan && config.virtual_scan.eye)
      problems.push_back({"virtual_scan.eye",
                          "a scan given as fragments is not scanned again: remove virtual_scan.eye "
                          "or give one input"});
    for (size_t i = 0; i < it->fragments.size(); ++i)
      if (const auto problem = check_input(it->fragments[i]))
        problems.push_back({"inputs." + role_name(role) + "[" + std::to_string(i + 1) + "]", *problem});
  }
  return problems;
}

namespace {

// mode: one of the modes; false when given but unknown (its inputs then cannot be checked).
bool read_mode(const YAML::Node& root, RunConfig& config, Problems& problems) {
  const YAML::Node n = root["mode"];
  if (!n) {
    problems.add(root.Mark(), "mode", "missing (expected one of " + join(mode_list()) + ")");
    return true;
  }
  problems.remember("mode", n.Mark());
  std::string name;
  const bool scalar = scalar_as(n, name);
  const auto& modes = mode_names();
  const auto it = std::find_if(modes.begin(), modes.end(), [&](const auto& m) { return m.first == name; });
  if (scalar && it != modes.end()) {
    config.mode = it->second;
    return true;
  }
  problems.add(n.Mark(), "mode", "expected one of " + join(mode_list()) + ", got " + describe(n));
  return false;
}

// output.surface: auto | none | poisson.
// output.KEY, one of `choices` by name.
template <class Choice>
void read_choice(const YAML::Node& output, const std::string& key,
                 const std::vector<std::pair<std::string, Choice>>& choices, Choice& out, Problems& problems) {
  const YAML::Node n = output[key];
  if (!n) return;
  problems.remember("output." + key, n.Mark());
  std::string name;
  std::vector<std::string> names;
  for (const auto& [choice_name, choice] : choices) {
    names.push_back(choice_name);
    if (scalar_as(n, name) && name == choice_name) {
      out = choice;
      return;
    }
  }
  problems.add(n.Mark(), "output." + key, "expected one of " + join(names) + ", got " + describe(n));
}

void read_threads_and_output(const YAML::Node& root, RunConfig& config, Problems& problems) {
  if (const YAML::Node n = root["threads"]) {
    problems.remember("threads", n.Mark());
    if (!scalar_as(n, config.threads))
      problems.add(n.Mark(), "threads", "expected an integer >= 0, got " + describe(n));
  }
  if (const YAML::Node n = root["output"]; n && check_map(n, "output", {"dir", "colour", "surface"}, problems)) {
    read_choice(n, "surface", surface_choice_names(), config.output_surface, problems);
    read_choice(n, "colour", colour_choice_names(), config.output_colour, problems);
    if (const YAML::Node d = n["dir"]) {
      std::string dir;
      problems.remember("output.dir", d.Mark());
      if (scalar_as(d, dir) && !dir.empty())
        config.output_dir = dir;
      else
        problems.add(d.Mark(), "output.dir", "expected a folder path, got " + describe(d));
    }
  }
}

// preset: the parameter set the sections start from (their keys override it).
void read_preset(const YAML::Node& root, RunConfig& config, Problems& problems) {
  const YAML::Node n = root["preset"];
  if (!n) return;
  problems.remember("preset", n.Mark());
  std::string name;
  if (scalar_as(n, name) && (name == "scanfill" || name == "paper")) {
    config.preset = name;
    if (name == "paper") use_paper_parameters(config);
  } else {
    problems.add(n.Mark(), "preset", "expected scanfill or paper, got " + describe(n));
  }
}

// One input's text: a scalar, or (for a role that takes fragments) a list of scalars. Empty when malformed.
std::vector<std::string> input_texts(const YAML::Node& n, const std::string& key, bool fragments, Problems& problems) {
  const std::string expected =
      fragments ? "a file path, procedural:NAME or a list of scan fragments (files)" : "a file path or procedural:NAME";
  std::vector<std::string> texts;
  std::string text;
  if (scalar_as(n, text) && !text.empty()) return {text};
  if (fragments && n.IsSequence() && n.size() > 0) {
    for (size_t i = 0; i < n.size(); ++i) {
      if (!scalar_as(n[i], text) || text.empty()) {
        problems.add(n[i].Mark(), key + "[" + std::to_string(i) + "]",
                     "expected a file path or procedural:NAME, got " + describe(n[i]));
        return {};
      }
      texts.push_back(text);
    }
    return texts;
  }
  problems.add(n.Mark(), key, "expected " + expected + ", got " + describe(n));
  return {};
}

// A box [[x, y, z], [x, y, z]] (its min and max corners); false when malformed.
bool read_box(const YAML::Node& n, PartBox& box) {
  bool ok = n.IsSequence() && n.size() == 2;
  for (int c = 0; ok && c < 2; ++c) {
    ok = n[c].IsSequence() && n[c].size() == 3;
    for (int k = 0; ok && k < 3; ++k)
      ok = scalar_as(n[c][k], (c == 0 ? box.min : box.max)(k)) && std::isfinite((c == 0 ? box.min : box.max)(k));
  }
  return ok;
}

// A name for output files: letters, digits, '.', '-' and '_'.
bool file_safe(const std::string& name) {
  return !name.empty() && std::all_of(name.begin(), name.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '-' || c == '_';
  });
}

// The default name of an exchange input: its procedural name or file stem, made file-safe.
std::string default_name(const InputSpec& spec, const std::string& fallback) {
  std::string name = !spec.procedural.empty() ? spec.procedural : spec.path.stem().string();
  for (char& c : name)
    if (!file_safe(std::string(1, c))) c = '_';
  return name.empty() ? fallback : name;
}

// One exchange input: FILE | procedural:NAME | {path: ..., name: ..., boxes: [[[x, y, z], [x, y, z]], ...]}.
void read_exchange_entry(const YAML::Node& n, const std::string& key, Role role, size_t index,
                         const std::filesystem::path& path, RunConfig& config, Problems& problems) {
  problems.remember(key, n.Mark());
  Input input{role, {}, {}, {}, std::nullopt};
  std::string text;
  if (scalar_as(n, text) && !text.empty()) {
    input.spec = parse_input(text, path.parent_path());
  } else if (n.IsMap() && check_map(n, key, {"path", "name", "boxes"}, problems)) {
    if (const YAML::Node p = n["path"]) {
      if (scalar_as(p, text) && !text.empty())
        input.spec = parse_input(text, path.parent_path());
      else
        problems.add(p.Mark(), key + ".path", "expected a file path or procedural:NAME, got " + describe(p));
    }
    if (const YAML::Node nm = n["name"]) {
      if (!scalar_as(nm, input.name) || !file_safe(input.name))
        problems.add(nm.Mark(), key + ".name",
                     "expected a name of letters, digits, '.', '-', '_', got " + describe(nm));
    }
    if (const YAML::Node b = n["boxes"]) {
      problems.remember(key + ".boxes", b.Mark());
      input.boxes = PartBoxes{};
      if (!b.IsSequence())
        problems.add(b.Mark(), key + ".boxes", "expected a list of boxes [[x, y, z], [x, y, z]], got " + describe(b));
      for (size_t i = 0; b.IsSequence() && i < b.size(); ++i) {
        const std::string box_key = key + ".boxes[" + std::to_string(i) + "]";
        problems.remember(box_key, b[i].Mark());
        PartBox box;
        if (read_box(b[i], box))
          input.boxes->push_back(box);
        else
          problems.add(b[i].Mark(), box_key,
                       "expected a box [[x, y, z], [x, y, z]] (min and max corners), got " + describe(b[i]));
      }
    }
  } else {
    if (!n.IsMap())
      problems.add(n.Mark(), key, "expected a file path, procedural:NAME or {path, name, boxes}, got " + describe(n));
    return;
  }
  if (input.name.empty()) input.name = default_name(input.spec, role_name(role) + std::to_string(index));
  problems.remember(key + ".name", n.Mark());
  config.inputs.push_back(std::move(input));
}

// Mode exchange: inputs.exemplar and inputs.target, each one entry or a list of them.
void read_exchange_inputs(const YAML::Node& n, const std::filesystem::path& path, RunConfig& config,
                          Problems& problems) {
  for (const Role role : {Role::kExemplar, Role::kTarget}) {
    const YAML::Node list = n[role_name(role)];
    if (!list) continue;
    const std::string key = "inputs." + role_name(role);
    if (!list.IsSequence()) {
      read_exchange_entry(list, key + "[0]", role, 0, path, config, problems);
      continue;
    }
    for (size_t i = 0; i < list.size(); ++i)
      read_exchange_entry(list[i], key + "[" + std::to_string(i) + "]", role, i, path, config, problems);
  }
}

void read_inputs(const YAML::Node& root, bool mode_known, const std::filesystem::path& path, RunConfig& config,
                 Problems& problems) {
  const YAML::Node n = root["inputs"];
  if (!n) {
    problems.remember("inputs", root.Mark());
    return;
  }
  problems.remember("inputs", n.Mark());
  std::vector<std::string> valid;  // the mode's roles in order; every role when the mode is unknown
  if (mode_known)
    for (const Role role : roles_for_mode(config.mode)) valid.push_back(role_name(role));
  else
    for (const auto& [name, role] : role_names()) valid.push_back(name);
  if (!check_map(n, "inputs", valid, problems)) return;
  if (mode_known && config.mode == RunMode::kExchange) return read_exchange_inputs(n, path, config, problems);
  for (auto it = n.begin(); it != n.end(); ++it) {
    if (!it->first.IsScalar()) continue;  // reported by check_map
    const std::string name = it->first.as<std::string>();
    const auto role = std::find(valid.begin(), valid.end(), name);
    if (!mode_known || role == valid.end()) continue;
    const std::string key = "inputs." + name;
    problems.remember(key, it->second.Mark());
    Input input{roles_for_mode(config.mode)[size_t(role - valid.begin())], {}, {}, {}, std::nullopt};
    const std::vector<std::string> texts = input_texts(it->second, key, takes_fragments(input.role), problems);
    if (texts.empty()) continue;
    input.spec = parse_input(texts[0], path.parent_path());
    for (size_t i = 1; i < texts.size(); ++i) input.fragments.push_back(parse_input(texts[i], path.parent_path()));
    config.inputs.push_back(std::move(input));
  }
  std::stable_sort(config.inputs.begin(), config.inputs.end(), [&](const Input& a, const Input& b) {
    const auto& order = roles_for_mode(config.mode);
    return std::find(order.begin(), order.end(), a.role) < std::find(order.begin(), order.end(), b.role);
  });
}

void read_sections(const YAML::Node& root, RunConfig& config, Problems& problems) {
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
}

}  // namespace

std::vector<InputSpec> all_specs(const Input& input) {
  std::vector<InputSpec> specs{input.spec};
  specs.insert(specs.end(), input.fragments.begin(), input.fragments.end());
  return specs;
}

bool takes_fragments(Role role) {
  return role == Role::kScan || role == Role::kExemplar;
}

namespace {

// --set KEY=VALUE: VALUE (read as YAML: a number, a word, a list [a, b]) replaces or adds the key, one level of
// section at most (sample.count, preset, inputs.scan).
void apply_override(YAML::Node& root, const std::string& text, Problems& problems) {
  const size_t eq = text.find('=');
  const std::string key = text.substr(0, eq);
  const size_t dot = key.find('.');
  const bool well_formed =
      eq != std::string::npos && eq > 0 && eq + 1 < text.size() &&
      (dot == std::string::npos || (dot > 0 && dot + 1 < key.size() && key.find('.', dot + 1) == std::string::npos));
  if (!well_formed) throw ConfigError("--set " + text + ": expected KEY=VALUE with KEY a key or SECTION.KEY");
  YAML::Node value;
  try {
    value = YAML::Load(text.substr(eq + 1));
  } catch (const YAML::Exception& e) {
    throw ConfigError("--set " + text + ": invalid value: " + e.msg);
  }
  problems.overridden(key, text);
  if (dot == std::string::npos) {
    root[key] = value;
    return;
  }
  const std::string section = key.substr(0, dot);
  if (root[section] && !root[section].IsMap())
    throw ConfigError("--set " + text + ": " + section + " is not a section of the config");
  root[section][key.substr(dot + 1)] = value;
}

}  // namespace

RunConfig load_config(const std::filesystem::path& path, const std::vector<std::string>& overrides) {
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
  for (const std::string& text : overrides) apply_override(root, text, problems);
  std::vector<std::string> top{"mode", "inputs", "output", "threads", "preset"};
  for (const Section& section : option_sections(config)) top.push_back(section.key);
  check_map(root, "", top, problems);
  const bool mode_known = read_mode(root, config, problems);
  read_threads_and_output(root, config, problems);
  read_preset(root, config, problems);
  read_inputs(root, mode_known, path, config, problems);
  read_sections(root, config, problems);
  for (std::filesystem::path* file :
       {&config.correspond.landmarks_file.exemplar, &config.correspond.landmarks_file.source})
    if (!file->empty() && file->is_relative()) *file = path.parent_path() / *file;  // as inputs: beside the config
  // Ranges and inputs of every value that parsed (one that did not keeps its valid default): all problems at once.
  for (const auto& [key, what] : validate(config))
    if (mode_known || key.rfind("inputs", 0) != 0) problems.add(problems.mark_of(key), key, what);
  if (!problems.empty()) throw ConfigError(problems.message());
  return config;
}

std::string default_config_yaml() {
  RunConfig config;
  std::ostringstream s;
  s << "# scanfill configuration: every option with its default. Relative input paths are relative to this file.\n"
    << "mode: completion            # " << join(mode_list(), " | ") << "\n"
    << "preset: scanfill            # scanfill | paper: the paper's sigma_n, mu, delta_n, label costs and 5-alpha MRF\n"
    << "                            # ring as the defaults below (label.*, support.normal_angle_deg; keys override)\n"
    << "inputs:                     # completion: scan, template; transfer: source, target, exemplar;\n"
    << "                            # analogy: source, target. A file (.ply .pcd .obj .off .stl .xyz)\n"
    << "                            # curves: source, target, exemplar, each a drawing (.svg .txt .polyline)\n"
    << "                            # or procedural:NAME (" << join(shape_names()) << "),\n"
    << "                            # or revolution:FILE (the body of revolution of a model about its own axis),\n"
    << "                            # or box:FILE (a model's bounding box, square to its faces): plain templates\n"
    << "                            # scan and exemplar may be a list of fragments, registered together,\n"
    << "                            # or a .conf of range scans and their poses (Stanford's bun.conf)\n"
    << "                            # exchange: exemplar and target, each a list of entries FILE, procedural:NAME\n"
    << "                            # or {path: FILE, name: NAME, boxes: [[[x, y, z], [x, y, z]], ...]}: the parts\n"
    << "                            # as boxes (min, max corners), else a PLY's exchange.part_property, else a\n"
    << "                            # castle's layout; a target may be boxes alone. One output per pair.\n"
    << "  scan: procedural:vase\n"
    << "  template: procedural:vase_template\n"
    << "output:\n"
    << "  dir: out                  # created if missing; relative to the working directory\n"
    << "  colour: auto              # output.ply's RGB: origin (scan grey, synthesised orange, copied blue),\n"
    << "                            # label (one colour per transform, as analogy.ply), scan (the scan's or\n"
    << "                            # exemplar's own colours, copied points grey; the scan must have them)\n"
    << "                            # or auto (scan when the scan has colours, else origin)\n"
    << "  surface: auto             # output_mesh.ply, a surface of the completed shape: poisson | none |\n"
    << "                            # auto (poisson in completion, none otherwise); its options: surface below\n"
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
