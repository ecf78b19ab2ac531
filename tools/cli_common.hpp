#pragma once
// Shared by the command-line tools (spatial-dyn, spatial-gen): strict number parsing, the model options that both
// accept (--root, --subtree, --lock, --gravity, --gravity-frame, --strict-inertia), turning them into
// urdf_io::LoadOptions, and printing the loader's warnings.
// Not part of the installed library.

#include <spatial/urdf.hpp>

#include <charconv>
#include <cmath>
#include <iostream>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <system_error>
#include <utility>
#include <vector>

namespace spatial::cli {

/// A bad command line (exit status 2).
class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A problem with the inputs (exit status 1).
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

inline std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) s.remove_suffix(1);
  return s;
}

inline std::vector<std::string_view> split(std::string_view s, char sep) {
  std::vector<std::string_view> out;
  std::size_t start = 0;
  for (;;) {
    const std::size_t k = s.find(sep, start);
    out.push_back(s.substr(start, k == std::string_view::npos ? std::string_view::npos : k - start));
    if (k == std::string_view::npos) break;
    start = k + 1;
  }
  return out;
}

/// The whole of `s` (spaces around it allowed) as a finite double, or nothing. Locale-independent.
inline std::optional<double> parse_double(std::string_view s) {
  s = trim(s);
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);  // from_chars does not take a leading '+'
  if (s.empty()) return std::nullopt;
  double x = 0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), x);
  if (ec != std::errc() || end != s.data() + s.size() || !std::isfinite(x)) return std::nullopt;
  return x;
}

/// Shortest decimal text that reads back as exactly the same double (at most 17 significant digits).
inline std::string format_double(double x) {
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, x);
  return std::string(buf, r.ptr);
}

/// Message text on one line (urdfdom's messages may contain line breaks).
inline std::string one_line(std::string s) {
  for (char& c : s)
    if (c == '\n' || c == '\r') c = ' ';
  return s;
}

/// "J1=0,J2=0.5" -> {(J1, 0), (J2, 0.5)}.
inline std::vector<std::pair<std::string, double>> parse_lock_list(std::string_view text) {
  std::vector<std::pair<std::string, double>> out;
  for (std::string_view item : split(text, ',')) {
    item = trim(item);
    if (item.empty()) continue;
    const std::size_t eq = item.find('=');
    if (eq == std::string_view::npos)
      throw UsageError("--lock: '" + std::string(item) + "' is not JOINT=ANGLE");
    const std::string name(trim(item.substr(0, eq)));
    const auto value = parse_double(item.substr(eq + 1));
    if (name.empty()) throw UsageError("--lock: '" + std::string(item) + "' has no joint name");
    if (!value)
      throw UsageError("--lock: '" + std::string(trim(item.substr(eq + 1))) + "' (joint '" + name +
                       "') is not a finite number");
    out.emplace_back(name, *value);
  }
  return out;
}

/// "gx,gy,gz" -> a vector.
inline Eigen::Vector3d parse_vector3(std::string_view text, const std::string& option) {
  const auto parts = split(text, ',');
  if (parts.size() != 3) throw UsageError(option + ": expected three numbers gx,gy,gz, got '" + std::string(text) + "'");
  Eigen::Vector3d v;
  for (int k = 0; k < 3; ++k) {
    const auto x = parse_double(parts[static_cast<std::size_t>(k)]);
    if (!x)
      throw UsageError(option + ": '" + std::string(trim(parts[static_cast<std::size_t>(k)])) +
                       "' is not a finite number");
    v[k] = *x;
  }
  return v;
}

/// Command-line options: `--name value` pairs and `--flag`s, after an optional subcommand.
class Options {
 public:
  /// `with_value`: options that take a value; `flags`: options that do not. Anything else is an error.
  Options(int argc, char** argv, int first, const std::vector<std::string>& with_value,
          const std::vector<std::string>& flags) {
    for (int i = first; i < argc; ++i) {
      std::string arg = argv[i];
      std::optional<std::string> inline_value;
      if (arg.rfind("--", 0) == 0) {
        const std::size_t eq = arg.find('=');
        if (eq != std::string::npos) {
          inline_value = arg.substr(eq + 1);
          arg = arg.substr(0, eq);
        }
      }
      if (contains(flags, arg)) {
        if (inline_value) throw UsageError(arg + " takes no value");
        flags_.push_back(arg);
      } else if (contains(with_value, arg)) {
        if (values_.count(arg)) throw UsageError(arg + " given twice");
        if (inline_value) {
          values_[arg] = *inline_value;
        } else {
          if (i + 1 >= argc) throw UsageError(arg + " needs a value");
          values_[arg] = argv[++i];
        }
      } else {
        throw UsageError("unknown argument '" + std::string(argv[i]) + "' (try --help)");
      }
    }
  }
  bool has(const std::string& name) const { return values_.count(name) > 0 || contains(flags_, name); }
  std::optional<std::string> get(const std::string& name) const {
    const auto it = values_.find(name);
    if (it == values_.end()) return std::nullopt;
    return it->second;
  }
  std::string required(const std::string& name) const {
    const auto v = get(name);
    if (!v) throw UsageError(name + " is required");
    return *v;
  }

 private:
  static bool contains(const std::vector<std::string>& list, const std::string& s) {
    for (const auto& x : list)
      if (x == s) return true;
    return false;
  }
  std::map<std::string, std::string> values_;
  std::vector<std::string> flags_;
};

/// The options that choose the model, shared by the tools.
inline const std::vector<std::string>& model_option_names() {
  static const std::vector<std::string> names = {"--urdf", "--root", "--subtree", "--lock", "--gravity",
                                                 "--gravity-frame"};
  return names;
}
/// The model options that take no value: `--floating` (the base link becomes free-flying, LoadOptions::floating)
/// and `--strict-inertia` (LoadOptions::strict_inertia).
inline const std::vector<std::string>& model_flag_names() {
  static const std::vector<std::string> names = {"--floating", "--strict-inertia"};
  return names;
}

inline urdf_io::LoadOptions load_options(const Options& o) {
  urdf_io::LoadOptions opt;
  opt.floating = o.has("--floating");
  opt.strict_inertia = o.has("--strict-inertia");
  if (auto v = o.get("--root")) opt.root = *v;
  if (auto v = o.get("--subtree")) opt.subtree = *v;
  if (auto v = o.get("--lock")) opt.locked = parse_lock_list(*v);
  if (auto v = o.get("--gravity")) opt.gravity = parse_vector3(*v, "--gravity");
  if (auto v = o.get("--gravity-frame")) {
    if (*v == "root") opt.gravity_frame = urdf_io::GravityFrame::Root;
    else if (*v == "urdf") opt.gravity_frame = urdf_io::GravityFrame::UrdfRoot;
    else throw UsageError("--gravity-frame: expected 'root' or 'urdf', got '" + *v + "'");
  }
  return opt;
}

/// Prints the loader's warnings (each already starts with the file name) to stderr, one line each:
/// "TOOL: warning: FILE: MESSAGE".
inline void print_warnings(const urdf_io::LoadedModel& loaded, const std::string& tool) {
  for (const std::string& w : loaded.warnings) std::cerr << tool << ": warning: " << one_line(w) << "\n";
}

}  // namespace spatial::cli
