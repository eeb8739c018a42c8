// ValidateContactOptions: the defaults pass; each bad dial is refused with its name in the message.

#include "libs/contact/contact_options.h"

#include <cmath>
#include <functional>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace haptex::contact {
namespace {

struct BadOption {
  std::string name;  // must appear in the error
  std::function<void(ContactOptions*)> spoil;
};

TEST(ContactOptionsTest, DefaultsAreValid) { EXPECT_NO_THROW(ValidateContactOptions(ContactOptions{})); }

TEST(ContactOptionsTest, EachBadDialIsNamed) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<BadOption> cases = {
      {"thumb.radius_m", [](ContactOptions* o) { o->thumb.radius_m = 0.0; }},
      {"index.length_m", [](ContactOptions* o) { o->index.length_m = -0.001; }},
      {"fabric_half_thickness_m", [nan](ContactOptions* o) { o->fabric_half_thickness_m = nan; }},
      {"finger_fabric.mu_dynamic",
       [](ContactOptions* o) {
         o->finger_fabric = {0.2, 0.4};
       }},
      {"finger_finger.mu_static",
       [](ContactOptions* o) {
         o->finger_finger = {-0.1, 0.0};
       }},
      {"pad_stiffness_N_per_m3", [](ContactOptions* o) { o->pad_stiffness_N_per_m3 = 0.0; }},
      {"pinch_samples_per_edge", [](ContactOptions* o) { o->pinch_samples_per_edge = 0; }},
      {"dynamic_leave_fraction", [](ContactOptions* o) { o->dynamic_leave_fraction = 0.7; }},
      {"dynamic_leave_fraction", [nan](ContactOptions* o) { o->dynamic_enter_fraction = nan; }},
      {"textile_contact_force_N", [](ContactOptions* o) { o->textile_contact_force_N = -0.01; }},
      {"state_filter_s", [](ContactOptions* o) { o->state_filter_s = -0.001; }},
      {"state_filter_s", [nan](ContactOptions* o) { o->state_filter_s = nan; }},
      {"state_filter_s", [](ContactOptions* o) { o->state_filter_s = 5.0; }},
      {"max_finger_force_N",
       [](ContactOptions* o) { o->max_finger_force_N = std::numeric_limits<double>::infinity(); }},
      {"stiffness_filter_s", [](ContactOptions* o) { o->stiffness_filter_s = 0.0; }},
  };
  for (const BadOption& c : cases) {
    ContactOptions o;
    c.spoil(&o);
    try {
      ValidateContactOptions(o);
      ADD_FAILURE() << c.name << ": accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(c.name), std::string::npos) << e.what();
    }
  }
}

TEST(ContactOptionsTest, NoStateFilterIsAllowed) {
  ContactOptions o;
  o.state_filter_s = 0.0;
  EXPECT_NO_THROW(ValidateContactOptions(o));
}

}  // namespace
}  // namespace haptex::contact
