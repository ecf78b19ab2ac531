#pragma once
// Test helpers for the command-line tool (not part of the installed library): run a program and capture its exit
// status, stdout and stderr; a scratch directory removed on exit; CSV files written and read independently of the
// tool's own code. POSIX (std::system with /bin/sh redirections).

#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <limits>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace spatial::testing {

/// A fresh directory under the system's temporary directory, removed with everything in it on destruction.
class ScratchDir {
 public:
  explicit ScratchDir(const std::string& tag) {
    static std::atomic<int> counter{0};
    path_ = std::filesystem::temp_directory_path() /
            ("spatial_" + tag + "_" + std::to_string(::getpid()) + "_" + std::to_string(counter++));
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~ScratchDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;
  std::string file(const std::string& name) const { return (path_ / name).string(); }

 private:
  std::filesystem::path path_;
};

inline std::string shell_quote(const std::string& s) {
  std::string out = "'";
  for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

inline std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream os;
  os << in.rdbuf();
  return os.str();
}

struct RunResult {
  int status = -1;  ///< exit status (-1: did not exit normally)
  std::string out, err;
};

/// Runs `exe args...` (stdin from `stdin_path` if given, else /dev/null) and captures everything.
inline RunResult run_program(const std::string& exe, const std::vector<std::string>& args,
                             const std::string& stdin_path = "") {
  static std::atomic<int> counter{0};
  const auto base = std::filesystem::temp_directory_path() /
                    ("spatial_run_" + std::to_string(::getpid()) + "_" + std::to_string(counter++));
  const std::string out = base.string() + ".out", err = base.string() + ".err";
  std::string cmd = shell_quote(exe);
  for (const auto& a : args) cmd += " " + shell_quote(a);
  cmd += " <" + shell_quote(stdin_path.empty() ? std::string("/dev/null") : stdin_path);
  cmd += " >" + shell_quote(out) + " 2>" + shell_quote(err);
  const int raw = std::system(cmd.c_str());
  RunResult r;
  r.status = (raw != -1 && WIFEXITED(raw)) ? WEXITSTATUS(raw) : -1;
  r.out = slurp(out);
  r.err = slurp(err);
  std::remove(out.c_str());
  std::remove(err.c_str());
  return r;
}

/// A CSV table: column names and rows of text cells.
struct Csv {
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;

  int column(const std::string& name) const {
    for (std::size_t k = 0; k < header.size(); ++k)
      if (header[k] == name) return static_cast<int>(k);
    return -1;
  }
  /// The number in a cell (throws if the column is missing or the cell is not a number).
  double number(std::size_t row, const std::string& name) const {
    const int k = column(name);
    if (k < 0) throw std::runtime_error("no column " + name);
    const std::string& s = rows.at(row).at(static_cast<std::size_t>(k));
    std::size_t used = 0;
    const double x = std::stod(s, &used);
    if (used != s.size()) throw std::runtime_error("not a number: " + s);
    return x;
  }
  std::string text() const {
    std::string s;
    auto line = [&](const std::vector<std::string>& cells) {
      for (std::size_t k = 0; k < cells.size(); ++k) s += (k ? "," : "") + cells[k];
      s += "\n";
    };
    line(header);
    for (const auto& r : rows) line(r);
    return s;
  }
  void write(const std::string& path) const {
    std::ofstream f(path, std::ios::binary);
    f << text();
  }
};

/// Plain CSV: lines split at commas, nothing else.
inline Csv parse_csv(const std::string& text) {
  Csv c;
  std::istringstream in(text);
  std::string line;
  bool first = true;
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    std::vector<std::string> cells;
    std::size_t start = 0;
    for (;;) {
      const std::size_t k = line.find(',', start);
      cells.push_back(line.substr(start, k == std::string::npos ? std::string::npos : k - start));
      if (k == std::string::npos) break;
      start = k + 1;
    }
    if (first) c.header = cells;
    else c.rows.push_back(cells);
    first = false;
  }
  return c;
}

/// Full precision text of a double (reads back exactly).
inline std::string exact(double x) {
  std::ostringstream os;
  os << std::setprecision(std::numeric_limits<double>::max_digits10) << x;
  return os.str();
}

}  // namespace spatial::testing
