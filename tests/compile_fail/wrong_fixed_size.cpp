// Compile-fail test (tests/CMakeLists.txt, ctest "compile_fail.wrong_fixed_size"): a fixed-size q with one entry
// too few for a compile-time tree must not compile, and the error must be the static_assert of sizes.hpp. With
// SPATIAL_RIGHT_SIZE the same program has the right size and must compile (ctest "compile_fail.control").
// With SPATIAL_FLOATING the same for a floating base on that tree (q: nq = 3 + 7 entries; the static_assert of
// floating.hpp; ctest "compile_fail.floating_wrong_fixed_size" and "compile_fail.floating_control").
#include <spatial/spatial.hpp>

using Tree3 = spatial::Tree<spatial::Parents<-1, 0, 1>,
                            spatial::Joints<spatial::JointType::RevoluteZ, spatial::JointType::RevoluteY,
                                            spatial::JointType::RevoluteY>>;

#ifdef SPATIAL_FLOATING
constexpr int kRight = 3 + 7;  // nq
#else
constexpr int kRight = 3;
#endif
#ifdef SPATIAL_RIGHT_SIZE
constexpr int kSize = kRight;
#else
constexpr int kSize = kRight - 1;  // one entry too few
#endif

int main() {
  spatial::ModelBuilder<double> b;
  const auto I = spatial::Inertia<double>::from_com(1.0, Eigen::Vector3d(0, 0, 0.1), Eigen::Matrix3d::Identity() * 1e-3);
  b.add_body("a", -1, spatial::JointType::RevoluteZ, spatial::Transform<double>::Identity(), I);
  b.add_body("b", 0, spatial::JointType::RevoluteY, spatial::Transform<double>::Identity(), I);
  b.add_body("c", 1, spatial::JointType::RevoluteY, spatial::Transform<double>::Identity(), I);
  const auto model = spatial::Model<double, Tree3>::from(b.build());
  Eigen::Matrix<double, kSize, 1> q = Eigen::Matrix<double, kSize, 1>::Zero();
#ifdef SPATIAL_FLOATING
  const spatial::FloatingModel<double, Tree3> fmodel(model, I, "root");
  spatial::FloatingData<double, Tree3> data(fmodel);
  q[kSize - 1] = 1.0;  // with the right size: the quaternion's w
  const Eigen::Matrix<double, 3 + 6, 1> v = Eigen::Matrix<double, 3 + 6, 1>::Zero();
  return spatial::rnea(fmodel, data, q, v, v).allFinite() ? 0 : 1;
#else
  spatial::Data<double, Tree3> data(model);
  const Eigen::Matrix<double, 3, 1> qd = Eigen::Matrix<double, 3, 1>::Zero();
  return spatial::rnea(model, data, q, qd, qd).allFinite() ? 0 : 1;
#endif
}
