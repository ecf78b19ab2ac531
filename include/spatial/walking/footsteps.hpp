#pragma once
/// \file walking/footsteps.hpp
/// Footstep plan, phase timeline, swing-foot trajectories, reference ZMP and support polygons of a biped walk
/// on flat ground (first stage of a ZMP walking pattern generator; see docs/walking.md).
///
/// Frames and units. One **world frame**: x forward (the initial walking direction), y left, z up; the ground is
/// the plane z = `ground_height`. SI units (m, s, rad). A foot's pose is the position of its **foot centre** (the
/// point of the sole that the plan places; the sole rectangle is given around it by `Sole`) and its **yaw** about
/// world z. Horizontal quantities (reference ZMP, polygons) are world (x, y).
///
/// The plan. Both feet start side by side, parallel, at y = ±width/2 (left foot at +width/2), with the pelvis
/// above the origin. A *path frame* C_k = (p_k, ψ_k) advances along the walk: C_0 is the origin with heading 0,
/// and C_k = C_{k−1} moved by `step_length` along the mean heading ψ_{k−1} + θ/2 and turned by θ (`turn`), so the
/// p_k lie on a circle (a straight line when θ = 0). Step k = 1 … N−1 puts its swing foot at C_k offset by
/// ±width/2 along the path frame's y axis, with yaw ψ_k; the last step N puts its swing foot beside the other
/// foot, at C_{N−1}, so the feet end side by side and parallel. The swing foot alternates, starting with
/// `first_swing`. The first and last swings move the foot by one step length (half steps), the others by two; the
/// walk advances (N−1) step lengths and turns by (N−1) θ.
///
/// The timeline (t = 0 is the start of the plan), in this order:
///   standing       [0, T_i]              both feet down, reference ZMP at the middle of the feet
///   for k = 1 … N: double support k      duration r T: the reference ZMP moves from the previous stance point
///                                        (the middle of the feet for k = 1) to step k's stance foot
///                  single support k      duration (1 − r) T: step k's swing foot moves to its new footprint
///   double support N + 1                 duration r T: the reference ZMP moves from the last stance foot to the
///                                        middle of the (now side by side) feet
///   standing       [.., + T_f]           reference ZMP at the middle of the feet
/// with T = `period` (one double + one single support), r = `double_support_ratio`, T_i and T_f the initial and
/// final standing durations. With N = 0 the plan stands for T_i + T_f. Total duration: T_i + N T + r T + T_f
/// (N ≥ 1).
///
/// Swing trajectories (single support k, phase variable s = (t − t_0) / ((1 − r) T) ∈ [0, 1]): horizontal
/// position and yaw follow the quintic q(s) = 10 s³ − 15 s⁴ + 6 s⁵ (q' = q'' = 0 at s = 0 and 1) from the old
/// footprint to the new one; the height above the ground is h b(s) with b(s) = 64 s³ (1 − s)³, which is 1 at
/// s = 1/2 (its only interior maximum) and has b = b' = b'' = 0 at both ends. Feet in stance do not move.
/// Velocities and accelerations are exact derivatives with respect to time.
///
/// Costs. Construction allocates (the footstep and phase lists) and validates the parameters (std::invalid_argument
/// naming the parameter). Queries at a time t do not allocate and do not throw: t < 0 is treated as 0 and
/// t > duration() as duration(); a phase is found by bisection on the phase ends.

#include <Eigen/Core>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace spatial::walking {

/// A foot. `left` is on the +y side at the start.
enum class Foot : int { left = 0, right = 1 };

/// The other foot.
constexpr Foot other(Foot f) noexcept { return f == Foot::left ? Foot::right : Foot::left; }

/// Index of a foot into two-element arrays (left 0, right 1).
constexpr int index(Foot f) noexcept { return static_cast<int>(f); }

template <class S>
using Vec2 = Eigen::Matrix<S, 2, 1>;
template <class S>
using Vec3 = Eigen::Matrix<S, 3, 1>;

/// The sole in contact as a rectangle around the foot centre, in the foot frame (x along the foot's yaw, y to its
/// left): x ∈ [−back, front], y ∈ [−right, left] (metres, all ≥ 0). The defaults are the HOAP-3's 108 × 73 mm
/// sole (/work/shared/hoap3/DATASHEET.md: x ∈ [−40, 68] mm from the ankle, i.e. ±54 mm about its centre; 73 mm
/// wide, ±36.5 mm about its centre), centred on the foot centre.
template <class S = double>
struct Sole {
  S front = S(0.054);
  S back = S(0.054);
  S left = S(0.0365);
  S right = S(0.0365);
};

/// The parameters of a walk. Defaults: a HOAP-3-sized straight walk of 8 steps (see docs/walking.md).
template <class S = double>
struct GaitParameters {
  int steps = 8;                       ///< N ≥ 0: number of steps (swings), the last one closing the feet
  S step_length = S(0.05);             ///< m, distance between consecutive path frames (finite; < 0 walks back)
  S step_width = S(0.088);             ///< m, > 0: lateral distance between the feet's centres
  S turn = S(0);                       ///< rad per step, |turn| < π: the walking direction turns by this each step
  S period = S(1.0);                   ///< s, > 0: one double support + one single support
  S double_support_ratio = S(0.2);     ///< in [0, 1): fraction of `period` in double support
  S swing_height = S(0.02);            ///< m, ≥ 0: swing-foot clearance at mid-swing
  Foot first_swing = Foot::right;      ///< the foot that swings first
  S initial_double_support = S(1.0);   ///< s, ≥ 0: standing before the first step
  S final_double_support = S(1.0);     ///< s, ≥ 0: standing after the last step
  S ground_height = S(0);              ///< m: z of the ground plane (world)
  S zmp_forward_offset = S(0);         ///< m: single-support reference ZMP ahead of the stance foot centre (foot x)
  bool smooth_zmp_transfer = false;    ///< double support: false = linear in time, true = quintic (C² in time)
  Sole<S> left_sole{};                 ///< the left sole around the left foot centre
  Sole<S> right_sole{};                ///< the right sole around the right foot centre
};

/// A footprint: which foot, where (world, the foot centre on the ground) and its yaw about world z.
template <class S = double>
struct Footstep {
  Foot foot = Foot::left;
  Vec3<S> position = Vec3<S>::Zero();
  S yaw = S(0);
};

enum class PhaseKind : int {
  standing,        ///< initial or final standing: both feet down, reference ZMP at their middle
  double_support,  ///< both feet down, reference ZMP moving from `zmp_start` to `zmp_end`
  single_support,  ///< `stance` foot down, `swing` foot moving from `swing_from` to `swing_to`
};

/// One phase of the timeline, [start, end] in seconds.
template <class S = double>
struct Phase {
  PhaseKind kind = PhaseKind::standing;
  int step = 0;                   ///< 0 before the first step; k for step k's double and single support; N + 1 after
  Foot stance = Foot::left;       ///< single support: the foot down; double support k: step k's stance foot
  Foot swing = Foot::right;       ///< single support: the foot moving (meaningless otherwise)
  S start = S(0);
  S end = S(0);
  Vec2<S> zmp_start = Vec2<S>::Zero();  ///< reference ZMP at `start` (world x, y)
  Vec2<S> zmp_end = Vec2<S>::Zero();    ///< reference ZMP at `end`
  std::array<Footstep<S>, 2> feet{};    ///< both feet's footprints at `start` (index(Foot))
  Footstep<S> swing_to{};               ///< single support: the swing foot's new footprint
};

/// A foot's pose and its time derivatives at one instant (world). Yaw is not wrapped: it stays continuous.
template <class S = double>
struct FootState {
  Vec3<S> position = Vec3<S>::Zero();
  Vec3<S> velocity = Vec3<S>::Zero();
  Vec3<S> acceleration = Vec3<S>::Zero();
  S yaw = S(0);
  S yaw_rate = S(0);
  S yaw_acceleration = S(0);
  bool in_contact = true;
};

// ---------------------------------------------------------------------------------------------------------------
// 2-D convex hull and signed distance

/// A convex polygon with at most `Capacity` vertices, counter-clockwise, no repeated vertex, no collinear vertex.
/// `size` 0: empty; 1: a point; 2: a segment.
template <class S, int Capacity>
struct ConvexPolygon {
  std::array<Vec2<S>, Capacity> vertices{};
  int size = 0;
};

namespace detail {
template <class S>
S cross(const Vec2<S>& o, const Vec2<S>& a, const Vec2<S>& b) noexcept {
  return (a.x() - o.x()) * (b.y() - o.y()) - (a.y() - o.y()) * (b.x() - o.x());
}

/// Distance from p to the segment [a, b].
template <class S>
S segment_distance(const Vec2<S>& p, const Vec2<S>& a, const Vec2<S>& b) noexcept {
  const Vec2<S> d = b - a;
  const S len2 = d.squaredNorm();
  S u = len2 > S(0) ? (p - a).dot(d) / len2 : S(0);
  u = std::min(S(1), std::max(S(0), u));
  return (p - (a + u * d)).norm();
}
}  // namespace detail

/// Convex hull of points[0 … n) by Andrew's monotone chain (sort by x then y; lower and upper chains keep left
/// turns only, so collinear points are dropped). Counter-clockwise, starting at the lowest-x (then lowest-y)
/// point. No allocation. Requires 0 ≤ n ≤ Capacity.
template <class S, int Capacity>
ConvexPolygon<S, Capacity> convex_hull(std::array<Vec2<S>, Capacity> points, int n) noexcept {
  ConvexPolygon<S, Capacity> hull;
  n = std::max(0, std::min(n, Capacity));
  std::sort(points.begin(), points.begin() + n, [](const Vec2<S>& a, const Vec2<S>& b) {
    return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
  });
  // drop exact duplicates
  int m = 0;
  for (int i = 0; i < n; ++i)
    if (m == 0 || points[static_cast<std::size_t>(i)] != points[static_cast<std::size_t>(m - 1)])
      points[static_cast<std::size_t>(m++)] = points[static_cast<std::size_t>(i)];
  if (m <= 2) {
    for (int i = 0; i < m; ++i) hull.vertices[static_cast<std::size_t>(i)] = points[static_cast<std::size_t>(i)];
    hull.size = m;
    return hull;
  }
  std::array<Vec2<S>, 2 * Capacity> h{};
  int k = 0;
  for (int i = 0; i < m; ++i) {  // lower chain
    const Vec2<S>& p = points[static_cast<std::size_t>(i)];
    while (k >= 2 && detail::cross(h[static_cast<std::size_t>(k - 2)], h[static_cast<std::size_t>(k - 1)], p) <= S(0))
      --k;
    h[static_cast<std::size_t>(k++)] = p;
  }
  const int lower = k + 1;
  for (int i = m - 2; i >= 0; --i) {  // upper chain
    const Vec2<S>& p = points[static_cast<std::size_t>(i)];
    while (k >= lower &&
           detail::cross(h[static_cast<std::size_t>(k - 2)], h[static_cast<std::size_t>(k - 1)], p) <= S(0))
      --k;
    h[static_cast<std::size_t>(k++)] = p;
  }
  --k;  // the last point repeats the first
  if (k < 2) k = 2;  // all points collinear: the chains meet at the two ends
  hull.size = std::min(k, Capacity);
  for (int i = 0; i < hull.size; ++i) hull.vertices[static_cast<std::size_t>(i)] = h[static_cast<std::size_t>(i)];
  return hull;
}

/// Signed distance from p to the boundary of a convex polygon: positive inside (the distance to the nearest edge),
/// zero on the boundary, negative outside (minus the distance to the polygon). A point or segment polygon has no
/// inside: the result is minus the distance to it. An empty polygon gives −infinity.
template <class S, int Capacity>
S signed_distance(const ConvexPolygon<S, Capacity>& poly, const Vec2<S>& p) noexcept {
  const int n = poly.size;
  if (n == 0) return -std::numeric_limits<S>::infinity();
  const auto& v = poly.vertices;
  if (n == 1) return -(p - v[0]).norm();
  if (n == 2) return -detail::segment_distance(p, v[0], v[1]);
  bool inside = true;
  S inner = std::numeric_limits<S>::infinity();  // min distance to the edge lines (valid inside)
  S outer = std::numeric_limits<S>::infinity();  // min distance to the edge segments
  for (int i = 0; i < n; ++i) {
    const Vec2<S>& a = v[static_cast<std::size_t>(i)];
    const Vec2<S>& b = v[static_cast<std::size_t>((i + 1) % n)];
    const S len = (b - a).norm();
    const S side = detail::cross(a, b, p) / len;  // > 0: p left of a→b, i.e. inside this edge
    if (side < S(0)) inside = false;
    inner = std::min(inner, side);
    outer = std::min(outer, detail::segment_distance(p, a, b));
  }
  return inside ? inner : -outer;
}

/// The support polygon at one instant: the corners of the soles in contact (4 in single support, 8 in double)
/// and their convex hull (world x, y).
template <class S = double>
struct SupportPolygon {
  std::array<Vec2<S>, 8> corners{};
  int corner_count = 0;
  ConvexPolygon<S, 8> hull{};
};

/// The four corners of a sole placed at a footprint (world x, y), counter-clockwise from front-left.
template <class S>
std::array<Vec2<S>, 4> sole_corners(const Sole<S>& sole, const Vec2<S>& centre, S yaw) noexcept {
  const S c = std::cos(yaw), s = std::sin(yaw);
  const auto at = [&](S fx, S fy) { return Vec2<S>(centre.x() + c * fx - s * fy, centre.y() + s * fx + c * fy); };
  return {at(sole.front, sole.left), at(-sole.back, sole.left), at(-sole.back, -sole.right),
          at(sole.front, -sole.right)};
}

// ---------------------------------------------------------------------------------------------------------------
// Footstep plan

/// The footstep plan and timeline of a walk (see the file comment for every convention).
template <class S = double>
class FootstepPlan {
 public:
  explicit FootstepPlan(const GaitParameters<S>& p) : p_(p) {
    validate(p);
    build();
  }

  const GaitParameters<S>& parameters() const noexcept { return p_; }

  /// The feet before the first step (index(Foot)): side by side at y = ±width/2, yaw 0, on the ground.
  const std::array<Footstep<S>, 2>& initial_feet() const noexcept { return initial_; }
  /// The footprints of steps 1 … N (element k − 1 is step k's swing-foot landing).
  const std::vector<Footstep<S>>& footsteps() const noexcept { return steps_; }
  /// The feet after the last step (side by side and parallel).
  const std::array<Footstep<S>, 2>& final_feet() const noexcept { return final_; }
  /// The timeline, in order, contiguous (phase i ends where phase i + 1 starts); phases may have zero length.
  const std::vector<Phase<S>>& phases() const noexcept { return phases_; }
  /// The end of the last phase (s).
  S duration() const noexcept { return phases_.back().end; }

  /// The index of the phase containing t: the first phase with end > t (the last phase for t ≥ duration()).
  std::size_t phase_index(S t) const noexcept {
    const auto it = std::upper_bound(phases_.begin(), phases_.end(), t,
                                     [](S value, const Phase<S>& ph) { return value < ph.end; });
    return it == phases_.end() ? phases_.size() - 1 : static_cast<std::size_t>(it - phases_.begin());
  }
  const Phase<S>& phase_at(S t) const noexcept { return phases_[phase_index(t)]; }

  /// Whether foot f is on the ground at t (always, except the swing foot in single support).
  bool in_contact(Foot f, S t) const noexcept {
    const Phase<S>& ph = phase_at(clamp_time(t));
    return !(ph.kind == PhaseKind::single_support && ph.swing == f);
  }

  /// Pose, velocity and acceleration of foot f at t (world).
  FootState<S> foot(Foot f, S t) const noexcept {
    t = clamp_time(t);
    const Phase<S>& ph = phase_at(t);
    const Footstep<S>& from = ph.feet[static_cast<std::size_t>(index(f))];
    FootState<S> st;
    st.position = from.position;
    st.yaw = from.yaw;
    if (ph.kind != PhaseKind::single_support || ph.swing != f) return st;
    st.in_contact = false;
    const S dur = ph.end - ph.start;  // > 0: a zero-length phase is never found by phase_at
    const S s = std::min(S(1), std::max(S(0), (t - ph.start) / dur));
    const S q = s * s * s * (S(10) + s * (S(-15) + S(6) * s));
    const S dq = S(30) * s * s * (S(1) - s) * (S(1) - s) / dur;
    const S ddq = S(60) * s * (S(1) - s) * (S(1) - S(2) * s) / (dur * dur);
    const S u = S(1) - s;
    const S b = S(64) * s * s * s * u * u * u;
    const S db = S(192) * s * s * u * u * (S(1) - S(2) * s) / dur;
    const S ddb = S(384) * s * u * (S(1) - S(5) * s + S(5) * s * s) / (dur * dur);
    const Vec3<S> d = ph.swing_to.position - from.position;
    const S dyaw = ph.swing_to.yaw - from.yaw;
    st.position = from.position + q * d;
    st.velocity = dq * d;
    st.acceleration = ddq * d;
    const S h = p_.swing_height;
    st.position.z() += h * b;
    st.velocity.z() += h * db;
    st.acceleration.z() += h * ddb;
    st.yaw = from.yaw + q * dyaw;
    st.yaw_rate = dq * dyaw;
    st.yaw_acceleration = ddq * dyaw;
    return st;
  }

  /// The reference ZMP at t (world x, y): the middle of the feet while standing, the stance foot centre (plus
  /// `zmp_forward_offset` along its yaw) in single support, moving between the two in double support (linearly
  /// in time, or along the quintic q of the file comment when `smooth_zmp_transfer`).
  Vec2<S> zmp_reference(S t) const noexcept {
    t = clamp_time(t);
    const Phase<S>& ph = phase_at(t);
    if (ph.kind != PhaseKind::double_support) return ph.zmp_start;
    const S dur = ph.end - ph.start;
    S s = dur > S(0) ? std::min(S(1), std::max(S(0), (t - ph.start) / dur)) : S(1);
    if (p_.smooth_zmp_transfer) s = s * s * s * (S(10) + s * (S(-15) + S(6) * s));
    return ph.zmp_start + s * (ph.zmp_end - ph.zmp_start);
  }

  /// The support polygon at t: the corners of the soles in contact (the feet where the plan puts them) and their
  /// convex hull.
  SupportPolygon<S> support_polygon(S t) const noexcept {
    t = clamp_time(t);
    SupportPolygon<S> sp;
    const Phase<S>& ph = phase_at(t);
    for (Foot f : {Foot::left, Foot::right}) {
      if (ph.kind == PhaseKind::single_support && ph.swing == f) continue;
      const Footstep<S>& fs = ph.feet[static_cast<std::size_t>(index(f))];
      const auto c = sole_corners(f == Foot::left ? p_.left_sole : p_.right_sole,
                                  Vec2<S>(fs.position.x(), fs.position.y()), fs.yaw);
      for (const auto& v : c) sp.corners[static_cast<std::size_t>(sp.corner_count++)] = v;
    }
    sp.hull = convex_hull<S, 8>(sp.corners, sp.corner_count);
    return sp;
  }

  /// Signed distance of the point zmp (world x, y) to the boundary of the support polygon at t (> 0 inside).
  S margin(S t, const Vec2<S>& zmp) const noexcept { return signed_distance(support_polygon(t).hull, zmp); }

  /// Checks the parameters; throws std::invalid_argument naming the first bad one.
  static void validate(const GaitParameters<S>& p) {
    const auto fail = [](const char* name, const std::string& rule, S value) {
      std::ostringstream os;
      os << "spatial::walking::GaitParameters: " << name << " must be " << rule << " (got " << value << ")";
      throw std::invalid_argument(os.str());
    };
    const auto finite = [](S x) { return std::isfinite(static_cast<double>(x)); };
    if (p.steps < 0) fail("steps", ">= 0", S(p.steps));
    if (!finite(p.step_length)) fail("step_length", "finite", p.step_length);
    if (!(p.step_width > S(0)) || !finite(p.step_width)) fail("step_width", "finite and > 0", p.step_width);
    if (!(std::abs(p.turn) < S(EIGEN_PI))) fail("turn", "in (-pi, pi)", p.turn);
    if (!(p.period > S(0)) || !finite(p.period)) fail("period", "finite and > 0", p.period);
    if (!(p.double_support_ratio >= S(0) && p.double_support_ratio < S(1)))
      fail("double_support_ratio", "in [0, 1)", p.double_support_ratio);
    if (!(p.swing_height >= S(0)) || !finite(p.swing_height)) fail("swing_height", "finite and >= 0", p.swing_height);
    if (!(p.initial_double_support >= S(0)) || !finite(p.initial_double_support))
      fail("initial_double_support", "finite and >= 0", p.initial_double_support);
    if (!(p.final_double_support >= S(0)) || !finite(p.final_double_support))
      fail("final_double_support", "finite and >= 0", p.final_double_support);
    if (!finite(p.ground_height)) fail("ground_height", "finite", p.ground_height);
    if (!finite(p.zmp_forward_offset)) fail("zmp_forward_offset", "finite", p.zmp_forward_offset);
    const auto sole_ok = [&](const Sole<S>& s, const char* name) {
      for (S v : {s.front, s.back, s.left, s.right})
        if (!(v >= S(0)) || !finite(v)) fail(name, "finite half-lengths >= 0", v);
      if (!(s.front + s.back > S(0)) || !(s.left + s.right > S(0)))
        fail(name, "a rectangle of non-zero length and width", s.front + s.back);
    };
    sole_ok(p.left_sole, "left_sole");
    sole_ok(p.right_sole, "right_sole");
  }

 private:
  S clamp_time(S t) const noexcept { return std::min(duration(), std::max(S(0), t)); }

  Footstep<S> place(Foot f, const Vec2<S>& c, S psi) const {
    const S side = f == Foot::left ? S(0.5) : S(-0.5);
    Footstep<S> fs;
    fs.foot = f;
    fs.position = Vec3<S>(c.x() - std::sin(psi) * side * p_.step_width, c.y() + std::cos(psi) * side * p_.step_width,
                          p_.ground_height);
    fs.yaw = psi;
    return fs;
  }

  Vec2<S> stance_point(const Footstep<S>& fs) const {
    return Vec2<S>(fs.position.x() + std::cos(fs.yaw) * p_.zmp_forward_offset,
                   fs.position.y() + std::sin(fs.yaw) * p_.zmp_forward_offset);
  }

  static Vec2<S> middle(const std::array<Footstep<S>, 2>& feet) {
    return S(0.5) * Vec2<S>(feet[0].position.x() + feet[1].position.x(), feet[0].position.y() + feet[1].position.y());
  }

  void build() {
    const int n = p_.steps;
    initial_[0] = place(Foot::left, Vec2<S>::Zero(), S(0));
    initial_[1] = place(Foot::right, Vec2<S>::Zero(), S(0));

    // path frames C_0 … C_{N−1} and the landings
    steps_.reserve(static_cast<std::size_t>(n));
    Vec2<S> c = Vec2<S>::Zero();
    S psi = S(0);
    Foot swing = p_.first_swing;
    for (int k = 1; k <= n; ++k, swing = other(swing)) {
      if (k < n) {
        const S mid = psi + S(0.5) * p_.turn;
        c += p_.step_length * Vec2<S>(std::cos(mid), std::sin(mid));
        psi += p_.turn;
      }
      steps_.push_back(place(swing, c, psi));
    }

    // timeline
    const S T = p_.period, r = p_.double_support_ratio;
    std::array<Footstep<S>, 2> feet = initial_;
    Phase<S> ph;
    ph.kind = PhaseKind::standing;
    ph.step = 0;
    ph.stance = other(p_.first_swing);
    ph.swing = p_.first_swing;
    ph.start = S(0);
    ph.end = p_.initial_double_support;
    ph.zmp_start = ph.zmp_end = middle(feet);
    ph.feet = feet;
    phases_.push_back(ph);
    Vec2<S> zmp = ph.zmp_end;
    S t = ph.end;
    for (int k = 1; k <= n; ++k) {
      const Footstep<S>& land = steps_[static_cast<std::size_t>(k - 1)];
      const Foot stance = other(land.foot);
      Phase<S> ds;
      ds.kind = PhaseKind::double_support;
      ds.step = k;
      ds.stance = stance;
      ds.swing = land.foot;
      ds.start = t;
      ds.end = t + r * T;
      ds.zmp_start = zmp;
      ds.zmp_end = stance_point(feet[static_cast<std::size_t>(index(stance))]);
      ds.feet = feet;
      phases_.push_back(ds);
      Phase<S> ss = ds;
      ss.kind = PhaseKind::single_support;
      ss.start = ds.end;
      ss.end = ds.start + T;
      ss.zmp_start = ss.zmp_end = ds.zmp_end;
      ss.swing_to = land;
      phases_.push_back(ss);
      feet[static_cast<std::size_t>(index(land.foot))] = land;
      zmp = ds.zmp_end;
      t = ss.end;
    }
    if (n > 0) {
      Phase<S> ds;
      ds.kind = PhaseKind::double_support;
      ds.step = n + 1;
      ds.stance = other(steps_.back().foot);
      ds.swing = steps_.back().foot;
      ds.start = t;
      ds.end = t + r * T;
      ds.zmp_start = zmp;
      ds.zmp_end = middle(feet);
      ds.feet = feet;
      phases_.push_back(ds);
      t = ds.end;
    }
    final_ = feet;
    Phase<S> fin;
    fin.kind = PhaseKind::standing;
    fin.step = n + 1;
    fin.stance = n > 0 ? other(steps_.back().foot) : other(p_.first_swing);
    fin.swing = other(fin.stance);
    fin.start = t;
    fin.end = t + p_.final_double_support;
    fin.zmp_start = fin.zmp_end = middle(feet);
    fin.feet = feet;
    phases_.push_back(fin);
  }

  GaitParameters<S> p_;
  std::array<Footstep<S>, 2> initial_{};
  std::array<Footstep<S>, 2> final_{};
  std::vector<Footstep<S>> steps_;
  std::vector<Phase<S>> phases_;
};

/// The reference ZMP sampled at t_k = k dt, k = 0 … ⌊duration / dt⌋ (rows; columns world x, y), for the preview
/// controller. Allocates the result. dt must be > 0 (std::invalid_argument otherwise).
template <class S>
Eigen::Matrix<S, Eigen::Dynamic, 2> sample_zmp_reference(const FootstepPlan<S>& plan, S dt) {
  if (!(dt > S(0))) throw std::invalid_argument("spatial::walking::sample_zmp_reference: dt must be > 0");
  const auto n = static_cast<Eigen::Index>(std::floor(plan.duration() / dt + S(1e-9))) + 1;
  Eigen::Matrix<S, Eigen::Dynamic, 2> ref(n, 2);
  for (Eigen::Index k = 0; k < n; ++k) ref.row(k) = plan.zmp_reference(S(k) * dt).transpose();
  return ref;
}

}  // namespace spatial::walking
