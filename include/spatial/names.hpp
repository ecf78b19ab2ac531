#pragma once
/// \file names.hpp
/// "Did you mean …?" for unknown joint, body, link and frame names in error messages (reduce.hpp, urdf.hpp).
///
/// The suggestion is the candidate closest to the given name by optimal-string-alignment distance (insertions,
/// deletions, substitutions and swaps of two neighbouring characters count 1: 'jiont' is 1 from 'joint'), accepted
/// when the distance is at most max(2, length / 3); a candidate that the name contains or that contains the name
/// (≥ 3 characters, e.g. 'R_SFE' in 'R_SFE_link') is accepted too, scored by the difference in length. Ties go to
/// the first candidate. Only error paths call this; it allocates.

#include <algorithm>
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace spatial {
namespace detail {

/// Optimal string alignment distance (Levenshtein plus transpositions of neighbouring characters).
inline std::size_t edit_distance(std::string_view a, std::string_view b) {
  const std::size_t n = a.size(), m = b.size();
  std::vector<std::size_t> d((n + 1) * (m + 1));
  auto at = [&](std::size_t i, std::size_t j) -> std::size_t& { return d[i * (m + 1) + j]; };
  for (std::size_t i = 0; i <= n; ++i) at(i, 0) = i;
  for (std::size_t j = 0; j <= m; ++j) at(0, j) = j;
  for (std::size_t i = 1; i <= n; ++i) {
    for (std::size_t j = 1; j <= m; ++j) {
      const std::size_t cost = a[i - 1] == b[j - 1] ? 0 : 1;
      std::size_t v = std::min({at(i - 1, j) + 1, at(i, j - 1) + 1, at(i - 1, j - 1) + cost});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1]) v = std::min(v, at(i - 2, j - 2) + 1);
      at(i, j) = v;
    }
  }
  return at(n, m);
}

/// The candidate closest to `name` (see the file comment), or "" when none is close enough. `Range`: any range of
/// things convertible to std::string_view.
template <class Range>
std::string closest_name(std::string_view name, const Range& candidates) {
  std::string best;
  std::size_t best_score = static_cast<std::size_t>(-1);
  const std::size_t limit = std::max<std::size_t>(2, name.size() / 3);
  for (const auto& c : candidates) {
    const std::string_view cand(c);
    if (cand.empty() || cand == name) continue;
    std::size_t score = static_cast<std::size_t>(-1);
    const std::size_t dist = edit_distance(name, cand);
    if (dist <= limit) score = dist;
    const std::string_view shorter = cand.size() < name.size() ? cand : name;
    const std::string_view longer = cand.size() < name.size() ? name : cand;
    if (shorter.size() >= 3 && longer.find(shorter) != std::string_view::npos)
      score = std::min(score, longer.size() - shorter.size());
    if (score < best_score) {
      best_score = score;
      best = std::string(cand);
    }
  }
  return best;
}

/// " (did you mean 'X'?)" with the closest candidate, or "" when none is close.
template <class Range>
std::string did_you_mean(std::string_view name, const Range& candidates) {
  const std::string best = closest_name(name, candidates);
  return best.empty() ? std::string() : " (did you mean '" + best + "'?)";
}

/// The keys of a map (for `did_you_mean` over a name → index map).
template <class Map>
std::vector<std::string> keys_of(const Map& map) {
  std::vector<std::string> out;
  for (const auto& kv : map) out.push_back(kv.first);
  return out;
}

}  // namespace detail
}  // namespace spatial
