// Names (model.hpp, names.hpp, reduce.hpp, urdf.hpp): index look-ups by name on compile-time, run-time and reduced
// models; "did you mean …?" in the errors for unknown joint, body and link names.

#include <spatial/spatial.hpp>
#include <spatial/models/hoap3_floating.hpp>
#include <spatial/models/hoap3_stance_right.hpp>
#include <spatial/urdf.hpp>

#include <gtest/gtest.h>

#include <functional>
#include <string>
#include <vector>

namespace {

using namespace spatial;
namespace stance = spatial::models::hoap3_stance_right;
namespace uio = spatial::urdf_io;
using Vec = Eigen::VectorXd;

const std::string kHoap3 = std::string(SPATIAL_SOURCE_DIR) + "/urdf/hoap3.urdf";

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const ModelError& e) {
    return e.what();
  }
  return "(no ModelError)";
}

template <class M>
void expect_lookups_match_generated(const M& model) {
  for (int i = 0; i < stance::dof; ++i) {
    EXPECT_EQ(model.joint_index(std::string(stance::joint_names[static_cast<std::size_t>(i)])), i);
    EXPECT_EQ(model.body_index(std::string(stance::body_names[static_cast<std::size_t>(i)])), i);
  }
  for (std::size_t k = 0; k < stance::frame_names.size(); ++k) {
    const int f = model.frame_index(std::string(stance::frame_names[k]));
    ASSERT_GE(f, 0) << stance::frame_names[k];
    EXPECT_EQ(model.frames()[static_cast<std::size_t>(f)].name, stance::frame_names[k]);
    EXPECT_EQ(f, stance::frame_index(stance::frame_names[k]));
  }
  EXPECT_EQ(model.frame_index("R_SOLE_typo"), -1);
  EXPECT_EQ(model.joint_index("R_KN"), -1);  // a body name is not a joint name
  EXPECT_EQ(model.body_index("R_LFE_R_KN_joint"), -1);
}

TEST(Names, FrameJointAndBodyIndexOnEveryModel) {
  expect_lookups_match_generated(stance::model());                       // compile-time
  uio::LoadOptions opt;
  opt.root = "R_SOLE";
  for (const auto& j : stance::locked_joints) opt.locked.emplace_back(std::string(j), 0.0);
  expect_lookups_match_generated(uio::load_file(kHoap3, opt).model);      // run-time, from the URDF
}

TEST(Names, FrameIndexOnReducedModels) {
  const auto model = stance::model();
  const ReducedModel<double> arms = keep_branches(model, {"R_SFE", "L_SFE"}, Vec::Zero(stance::dof));
  EXPECT_EQ(arms.model.size(), 8);
  // Frames of the full model are kept, and each locked body leaves a frame of its own name.
  for (const char* f : {"R_SOLE", "R_HAND", "L_HAND", "HEAD", "CHEST", "R_KN"}) {
    const int k = arms.model.frame_index(f);
    ASSERT_GE(k, 0) << f;
    EXPECT_EQ(arms.model.frames()[static_cast<std::size_t>(k)].name, f);
  }
  EXPECT_EQ(arms.model.joint_index("CHEST_R_SFE_joint"), 0);
  EXPECT_EQ(arms.model.body_index("L_EB"), 7);
  EXPECT_EQ(arms.model.joint_index("R_LFE_R_KN_joint"), -1);  // locked
}

// FloatingModel forwards the look-ups to its tree (q index 7 + i, v index 6 + i); the root body is not a tree body.
TEST(Names, IndexLookupsOnFloatingModels) {
  namespace fb = spatial::models::hoap3_floating;
  uio::LoadOptions opt;
  opt.floating = true;
  for (const auto& j : fb::locked_joints) opt.locked.emplace_back(std::string(j), 0.0);
  const auto loaded = uio::load_file(kHoap3, opt);
  const FloatingModel<double> rt = uio::floating_model(loaded);
  const auto ct = fb::floating_model();
  for (int i = 0; i < fb::dof; ++i) {
    const std::string j(fb::joint_names[static_cast<std::size_t>(i)]), b(fb::body_names[static_cast<std::size_t>(i)]);
    EXPECT_EQ(rt.joint_index(j), i) << j;
    EXPECT_EQ(ct.joint_index(j), i) << j;
    EXPECT_EQ(rt.body_index(b), i) << b;
    EXPECT_EQ(ct.body_index(b), i) << b;
  }
  for (std::size_t k = 0; k < fb::frame_names.size(); ++k) {
    const std::string f(fb::frame_names[k]);
    EXPECT_EQ(rt.frame_index(f), fb::frame_index(f)) << f;
    EXPECT_EQ(ct.frame_index(f), fb::frame_index(f)) << f;
    EXPECT_EQ(rt.tree().frames()[static_cast<std::size_t>(rt.frame_index(f))].body, fb::frame_bodies[k]) << f;
  }
  EXPECT_EQ(rt.body_index(rt.root_name()), -1);
  EXPECT_EQ(rt.joint_index(kFreeFlyerName), -1);
  EXPECT_EQ(rt.frame_index("R_SOLE_typo"), -1);
}

TEST(Names, EditDistanceAndClosestName) {
  EXPECT_EQ(detail::edit_distance("joint", "jiont"), 1u);  // one swap
  EXPECT_EQ(detail::edit_distance("kitten", "sitting"), 3u);
  EXPECT_EQ(detail::edit_distance("", "abc"), 3u);
  const std::vector<std::string> names{"R_LFE_R_KN_joint", "L_LFE_L_KN_joint", "R_KN_R_AFE_joint"};
  EXPECT_EQ(detail::closest_name("R_LFE_R_KN_jiont", names), "R_LFE_R_KN_joint");
  EXPECT_EQ(detail::closest_name("l_lfe_l_kn_joint", names), "");  // too far (case counts)
  EXPECT_EQ(detail::closest_name("completely_else", names), "");
  EXPECT_EQ(detail::did_you_mean("R_LFE_R_KN_jiont", names), " (did you mean 'R_LFE_R_KN_joint'?)");
  const std::vector<std::string> bodies{"R_SAA", "R_SFE", "L_SFE"};
  EXPECT_EQ(detail::closest_name("R_SFE_link", bodies), "R_SFE");  // contained
}

TEST(Names, ReductionErrorsSuggestTheRightName) {
  const auto model = stance::model();
  const Vec q = Vec::Zero(stance::dof);
  EXPECT_EQ(error_of([&] { lock_joints(model, {{"R_LFE_R_KN_jiont", 0.0}}); }),
            "lock_joints: the model has no joint 'R_LFE_R_KN_jiont' (did you mean 'R_LFE_R_KN_joint'?)");
  EXPECT_EQ(error_of([&] { keep_joints(model, {"CHEST_R_SFE_joint", "CHEST_L_SFE_jont"}, q); }),
            "keep_joints: the model has no joint 'CHEST_L_SFE_jont' (did you mean 'CHEST_L_SFE_joint'?)");
  EXPECT_EQ(error_of([&] { keep_joints(model, {"R_KN"}, q); }),
            "keep_joints: the model has no joint 'R_KN' ('R_KN' is a body (link) name: the joint that moves it is "
            "'R_KN_R_AFE_joint')");
  EXPECT_EQ(error_of([&] { keep_branches(model, {"R_SFE_link"}, q); }),
            "keep_branches: the model has no body 'R_SFE_link' (it takes body (link) names, the first body of each "
            "branch) (did you mean 'R_SFE'?)");
  EXPECT_EQ(error_of([&] { keep_branches(model, {"CHEST_R_SFE_joint"}, q); }),
            "keep_branches: the model has no body 'CHEST_R_SFE_joint' (it takes body (link) names, the first body "
            "of each branch; 'CHEST_R_SFE_joint' is a joint: the body it moves is 'R_SFE')");
  EXPECT_EQ(error_of([&] { lock_joints(model, {{"NO_SUCH_THING", 0.0}}); }),
            "lock_joints: the model has no joint 'NO_SUCH_THING'");
  // The comment of reduce.hpp, as written there, works.
  EXPECT_EQ(keep_branches(model, {"R_SFE", "L_SFE"}, q).model.size(), 8);
}

TEST(Names, UrdfLoaderErrorsSuggestTheRightName) {
  uio::LoadOptions opt;
  opt.root = "R_SOEL";
  EXPECT_NE(error_of([&] { uio::load_file(kHoap3, opt); }).find("root: unknown link 'R_SOEL' (did you mean 'R_SOLE'?)"),
            std::string::npos)
      << error_of([&] { uio::load_file(kHoap3, opt); });
  opt = {};
  opt.subtree = "CHST";
  EXPECT_NE(error_of([&] { uio::load_file(kHoap3, opt); }).find("subtree: unknown link 'CHST' (did you mean 'CHEST'?)"),
            std::string::npos)
      << error_of([&] { uio::load_file(kHoap3, opt); });
  opt = {};
  opt.locked = {{"R_EB_R_WR_jiont", 0.0}};
  const std::string e = error_of([&] { uio::load_file(kHoap3, opt); });
  EXPECT_NE(e.find("locked: unknown joint 'R_EB_R_WR_jiont' (did you mean 'R_EB_R_WR_joint'?)"), std::string::npos) << e;
}

}  // namespace
